//! `[[cohesive]]`: interfaces that bond two bodies' faces by a traction-separation law.

use super::*;
use crate::material::CohesiveLaw;

impl Checker<'_> {
    /// Every `[[cohesive]]` of the scene.
    pub(super) fn cohesive(
        &self,
        raw: &[RawCohesive],
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<Vec<CohesiveSpec>> {
        let mut out: Vec<CohesiveSpec> = Vec::new();
        for (i, c) in raw.iter().enumerate() {
            let key = |k: &str| format!("cohesive[{i}].{k} (cohesive `{}`)", c.name);
            let spec = self.one_cohesive(&key, c, raw_bodies, bodies)?;
            let split = |s: &CohesiveSpec| match s.sides {
                CohesiveSides::Laminate { body, .. } => Some(body),
                _ => None,
            };
            if let Some(j) = (split(&spec).is_some())
                .then(|| out.iter().position(|o| split(o) == split(&spec)))
                .flatten()
            {
                return Err(self.err(
                    key("body"),
                    format!("is split at its ply changes by cohesive[{j}] already: one interface per laminate"),
                ));
            }
            out.push(spec);
        }
        Ok(out)
    }

    fn one_cohesive(
        &self,
        key: &dyn Fn(&str) -> String,
        c: &RawCohesive,
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<CohesiveSpec> {
        let sides = match (&c.between, &c.body) {
            (Some(_), Some(_)) => {
                return Err(self.err(
                    key("body"),
                    "give either `between` (two bodies' faces) or `body` with `at` (inside a laminate), not both",
                ))
            }
            (None, Some(b)) => self.laminate(key, c, b, raw_bodies, bodies)?,
            (Some(_), None) if c.at.is_some() => {
                return Err(self.err(
                    key("at"),
                    "goes with `body` (inside a laminate), not with `between`",
                ))
            }
            (Some(between), None) => self.between(key, between, raw_bodies, bodies)?,
            (None, None) => {
                return Err(self.err(
                    key("between"),
                    "is required: the two sides, e.g. [{ body = \"top\", face = \"z-\" }, { body = \"bottom\", face = \"z+\" }], or give `body` and `at = \"ply_changes\"`",
                ))
            }
        };
        let region = self.region(key, c.region.as_ref())?;
        Ok(CohesiveSpec {
            name: c.name.clone(),
            sides,
            region,
            law: self.cohesive_law(key, c)?,
        })
    }

    /// `between`: two sides on two bodies, each a face or surface of a meshed body.
    fn between(
        &self,
        key: &dyn Fn(&str) -> String,
        between: &[RawSurfaceRef],
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<CohesiveSides> {
        let [a, b] = between else {
            return Err(self.err(
                key("between"),
                format!("names {} sides: an interface has two", between.len()),
            ));
        };
        let side = |k: &str, r: &RawSurfaceRef| -> Result<SurfaceRef> {
            if r.rigid_body.is_some() {
                return Err(self.err(
                    key(&format!("{k}.rigid_body")),
                    "a cohesive side is a meshed body's face or surface: a rigid body has no nodes to bond",
                ));
            }
            self.surface_ref(key, k, r, raw_bodies, bodies)
        };
        let sides = [side("between[0]", a)?, side("between[1]", b)?];
        if sides[0].body == sides[1].body {
            return Err(self.err(
                key("between"),
                "both sides lie on one body: a cohesive interface joins two bodies (inside a laminate body, give `body` and `at = \"ply_changes\"`)",
            ));
        }
        Ok(CohesiveSides::Between(sides))
    }

    /// `body` and `at = "ply_changes"`: a box body of hexes with plies, split at each element
    /// layer boundary where the plies on either side differ in angle; every layer boundary
    /// must be a ply boundary.
    fn laminate(
        &self,
        key: &dyn Fn(&str) -> String,
        c: &RawCohesive,
        name: &str,
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<CohesiveSides> {
        match c.at.as_deref() {
            Some("ply_changes") => {}
            Some(other) => {
                return Err(self.err(
                    key("at"),
                    format!("\"{other}\": the one place is \"ply_changes\" (every element layer boundary where the plies' angle changes)"),
                ))
            }
            None => {
                return Err(self.err(key("at"), "is required with `body`: at = \"ply_changes\""))
            }
        }
        let body = self.body_index(&key("body"), name, raw_bodies)?;
        let b = &bodies[body];
        let (BodyShape::Box(spec), Some(plies)) = (&b.shape, &b.plies) else {
            return Err(self.err(
                key("body"),
                format!("`{name}` is not a box with `plies`: the interfaces inside a laminate are found from its plies and its element layers"),
            ));
        };
        if spec.element == crate::mesh::box_mesh::BoxElement::Tet4 {
            return Err(self.err(
                key("body"),
                format!("`{name}` is meshed in tet4: a laminate is split between element layers of hex8 or hex8i"),
            ));
        }
        let axis = plies.axis;
        let layers = spec.axis_nodes(axis);
        let tol = 1e-6 * (layers[layers.len() - 1] - layers[0]);
        // each ply's top along the axis
        let mut tops = Vec::with_capacity(plies.layers.len());
        let mut t = plies.start;
        for p in &plies.layers {
            t += p.thickness;
            tops.push(t);
        }
        let mut planes = Vec::new();
        for &z in &layers[1..layers.len() - 1] {
            let Some(k) = tops.iter().position(|&top| (top - z).abs() <= tol) else {
                let ply = tops
                    .iter()
                    .position(|&top| top > z)
                    .unwrap_or(tops.len() - 1);
                return Err(self.err(
                    key("at"),
                    format!("the element layer boundary at {z} ({}) falls inside ply {ply} (of `{name}`'s plies, from the lowest, {} to {}): a laminate is split between plies; give the box divisions whose layers end on ply boundaries", ["x", "y", "z"][axis], tops[ply] - plies.layers[ply].thickness, tops[ply]),
                ));
            };
            if plies.layers[k].angle != plies.layers[k + 1].angle {
                planes.push(z);
            }
        }
        if planes.is_empty() {
            return Err(self.err(
                key("at"),
                format!("`{name}`'s element layers meet nowhere between plies of different angles: there is no interface to bond"),
            ));
        }
        Ok(CohesiveSides::Laminate { body, axis, planes })
    }

    /// The law's constants: each positive, and a stiffness above the snap-back limit.
    fn cohesive_law(&self, key: &dyn Fn(&str) -> String, c: &RawCohesive) -> Result<CohesiveLaw> {
        let law = CohesiveLaw {
            stiffness: self.positive(&key("stiffness"), c.stiffness)?,
            strength: [
                self.positive(&key("strength.normal"), c.strength.normal)?,
                self.positive(&key("strength.shear"), c.strength.shear)?,
            ],
            toughness: [
                self.positive(&key("toughness.normal"), c.toughness.normal)?,
                self.positive(&key("toughness.shear"), c.toughness.shear)?,
            ],
            bk: self.positive(&key("toughness.bk"), c.toughness.bk)?,
            friction: self.friction(&key("friction"), c.friction)?,
        };
        let limit = law.snap_back_stiffness();
        if law.stiffness <= limit {
            return Err(self.err(
                key("stiffness"),
                format!(
                    "{:e} is at most {limit:.4e}, the largest of strength^2 / (2 toughness) over the modes: the traction would fall before it rose (snap-back); Turon's choice is 50 E_3 / t (the laminate's through-thickness modulus over its ply thickness: 1e5 to 1e6 N/mm^3 for carbon/epoxy)",
                    law.stiffness
                ),
            ));
        }
        Ok(law)
    }
}
