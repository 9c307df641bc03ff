//! `[[load]]`: nodal forces and pressures, with an optional amplitude table.

use super::*;

impl Checker<'_> {
    /// Every `[[load]]` of the scene: on a meshed body, `force` on the nodes of a face (a box
    /// body's), a surface, a node set or a region, or `pressure` on a face or a surface.
    pub(super) fn loads(
        &self,
        raw: &[RawLoad],
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
        rigid: &[RigidBodySpec],
    ) -> Result<Vec<LoadSpec>> {
        let mut out = Vec::with_capacity(raw.len());
        for (i, l) in raw.iter().enumerate() {
            let key = |k: &str| format!("load[{i}].{k}");
            if rigid.iter().any(|b| b.name == l.body) {
                return Err(self.err(
                    key("body"),
                    format!("`{}` is a rigid body: loads act on meshed bodies", l.body),
                ));
            }
            let body = self.body_index(&key("body"), &l.body, raw_bodies)?;
            let kind = match (l.force, l.pressure) {
                (Some(f), None) => LoadKind::Force(self.finite3(&key("force"), f)?),
                (None, Some(p)) if p.is_finite() => LoadKind::Pressure(p),
                (None, Some(p)) => {
                    return Err(self.err(key("pressure"), format!("must be finite, got {p}")))
                }
                _ => return Err(self.err(
                    key("force"),
                    "give exactly one of `force` (on each selected node) or `pressure` (on a face)",
                )),
            };
            let nodes = match &l.surface {
                Some(name) if l.face.is_none() && l.set.is_none() && l.region.is_none() => {
                    NodeSelection::Surface(self.surface_of(&key("surface"), name, &bodies[body])?)
                }
                Some(_) => {
                    return Err(self.err(
                        key("surface"),
                        "give exactly one of `face`, `surface`, `set` or `region`",
                    ))
                }
                None if matches!(kind, LoadKind::Pressure(_)) && l.face.is_none() => {
                    return Err(self.err(
                        key("pressure"),
                        "acts on a face: give `face` (a box body's) or `surface` (a mesh's), not `set` or `region`",
                    ))
                }
                None => self.nodes_of(&key, (&l.face, &l.set, l.region.as_ref()), &bodies[body])?,
            };
            out.push(LoadSpec {
                body,
                nodes,
                kind,
                amplitude: self.amplitude(&key("amplitude"), l.amplitude.as_deref())?,
            });
        }
        Ok(out)
    }

    /// An amplitude table: (time, value) points, finite, times increasing.
    pub(super) fn amplitude(
        &self,
        key: &str,
        points: Option<&[[f64; 2]]>,
    ) -> Result<Vec<[f64; 2]>> {
        let Some(points) = points else {
            return Ok(Vec::new());
        };
        if points.is_empty() {
            return Err(self.err(
                key,
                "has no point: give [time, value] pairs, or leave it out",
            ));
        }
        for (j, p) in points.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(self.err(
                    key,
                    format!("point {j} is {p:?}: times and values must be finite"),
                ));
            }
            if j > 0 && p[0] <= points[j - 1][0] {
                return Err(self.err(
                    key,
                    format!(
                        "point {j}'s time {} does not follow point {}'s ({}): times must increase",
                        p[0],
                        j - 1,
                        points[j - 1][0]
                    ),
                ));
            }
        }
        Ok(points.to_vec())
    }
}
