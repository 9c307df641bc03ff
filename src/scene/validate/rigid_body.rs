//! `[[rigid_body]]`: the mass, the motion and the analytic shape of each rigid body.

use super::Checker;
use crate::error::Result;
use crate::geometry::rigid_shape::RigidShape;
use crate::material::rotation::unit;
use crate::scene::raw::{RawRigidBody, RawRigidShape};
use crate::scene::{RigidBodySpec, RigidMotion};

impl Checker<'_> {
    /// Every `[[rigid_body]]`, checked.
    pub(super) fn rigid_bodies(&self, raw: &[RawRigidBody]) -> Result<Vec<RigidBodySpec>> {
        (raw.iter().enumerate())
            .map(|(i, b)| {
                let key = |k: &str| format!("rigid_body[{i}].{k} (rigid body `{}`)", b.name);
                self.rigid_body(&key, b)
            })
            .collect()
    }

    /// The inertia tensor: finite, symmetric (to 1e-9 of its largest entry) and positive
    /// definite.
    fn inertia(&self, key: &str, i: [[f64; 3]; 3]) -> Result<[[f64; 3]; 3]> {
        for row in i {
            self.finite3(key, row)?;
        }
        let scale = i.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        let symmetric = (0..3).all(|a| (0..3).all(|b| (i[a][b] - i[b][a]).abs() <= 1e-9 * scale));
        if !symmetric {
            return Err(self.err(
                key,
                "must be symmetric (an inertia tensor about `position`)",
            ));
        }
        let m = nalgebra::Matrix3::from_fn(|a, b| i[a][b]);
        if scale <= 0.0 || m.cholesky().is_none() {
            return Err(self.err(
                key,
                "must be positive definite (each principal moment > 0): its eigenvalues are the body's principal moments of inertia",
            ));
        }
        let mut p: Vec<f64> = m.symmetric_eigenvalues().iter().copied().collect();
        p.sort_by(f64::total_cmp);
        if p[0] < 1e-12 * p[2] {
            return Err(self.err(
                key,
                format!("has principal moments {:.3e} and {:.3e}, more than 1e12 apart: the body's spin cannot be integrated in f64", p[0], p[2]),
            ));
        }
        // the spin integration inverts the tensor: its determinant must be a normal number
        let det = m.determinant();
        if !(det.is_normal()
            && m.try_inverse()
                .is_some_and(|v| v.iter().all(|x| x.is_finite())))
        {
            return Err(self.err(
                key,
                format!("is too small to invert in f64 (determinant {det:.3e}): give it in the scene's units, where it is about mass x size^2"),
            ));
        }
        // every body's principal moments satisfy I_3 <= I_1 + I_2
        if p[2] > (p[0] + p[1]) * (1.0 + 1e-9) {
            return Err(self.err(
                key,
                format!("has principal moments {:.6e}, {:.6e} and {:.6e}: the largest exceeds the sum of the other two, which no body's do", p[0], p[1], p[2]),
            ));
        }
        Ok(i)
    }

    fn rigid_body(&self, key: &dyn Fn(&str) -> String, b: &RawRigidBody) -> Result<RigidBodySpec> {
        let motion = self.choice(
            &key("motion"),
            b.motion.as_deref(),
            RigidMotion::Free,
            RigidMotion::CHOICES,
        )?;
        let mass = match (b.mass, motion) {
            (Some(m), _) => self.positive(&key("mass"), m)?,
            (None, RigidMotion::Free) => {
                return Err(self.err(
                    key("mass"),
                    "is required for a free body (motion = \"free\", the default): it moves under its contact forces and gravity",
                ))
            }
            (None, _) => 0.0,
        };
        let inertia = match (b.inertia, motion) {
            (None, _) => None,
            (Some(i), RigidMotion::Free) => Some(self.inertia(&key("inertia"), i)?),
            (Some(_), _) => {
                return Err(self.err(
                    key("inertia"),
                    "is for a free body (motion = \"free\"): a fixed or prescribed body moves as it is told whatever the forces",
                ))
            }
        };
        let angular_velocity = self.finite3(
            &key("angular_velocity"),
            b.angular_velocity.unwrap_or([0.0; 3]),
        )?;
        if angular_velocity != [0.0; 3] {
            let why = match motion {
                RigidMotion::Fixed => Some("a fixed body does not move: give motion = \"prescribed\" to spin it at this rate"),
                RigidMotion::Free if inertia.is_none() => Some("a free body without `inertia` only translates (as a guided tup does): give its `inertia` to let it rotate"),
                _ => None,
            };
            if let Some(why) = why {
                return Err(self.err(key("angular_velocity"), why));
            }
        }
        let velocity = self.finite3(&key("velocity"), b.velocity.unwrap_or([0.0; 3]))?;
        if motion == RigidMotion::Fixed && velocity != [0.0; 3] {
            return Err(self.err(
                key("velocity"),
                "a fixed body does not move: give motion = \"prescribed\" to move it at this velocity",
            ));
        }
        Ok(RigidBodySpec {
            name: b.name.clone(),
            mass,
            position: self.finite3(&key("position"), b.position)?,
            velocity,
            inertia,
            angular_velocity,
            shape: self.rigid_shape(key, &b.shape)?,
            motion,
        })
    }

    /// Exactly one of the shapes, with positive sizes and unit directions.
    fn rigid_shape(&self, key: &dyn Fn(&str) -> String, s: &RawRigidShape) -> Result<RigidShape> {
        let given = [
            ("sphere", s.sphere.is_some()),
            ("cylinder", s.cylinder.is_some()),
            ("plane", s.plane.is_some()),
            ("plate", s.plate.is_some()),
            (
                "mesh",
                s.mesh.is_some() || s.surface.is_some() || s.origin.is_some(),
            ),
        ];
        let named: Vec<&str> = given.iter().filter(|g| g.1).map(|g| g.0).collect();
        if named.len() != 1 {
            return Err(self.err(
                key("shape"),
                format!(
                    "give exactly one of `sphere`, `cylinder`, `plane`, `plate` or `mesh` (found {})",
                    if named.is_empty() {
                        "none".into()
                    } else {
                        named.join(", ")
                    }
                ),
            ));
        }
        let direction = |k: &str, v: [f64; 3]| -> Result<[f64; 3]> {
            let v = self.finite3(&key(k), v)?;
            unit(v).ok_or_else(|| self.err(key(k), "must not be the zero vector"))
        };
        if let Some(sp) = &s.sphere {
            return Ok(RigidShape::Sphere {
                radius: self.positive(&key("shape.sphere.radius"), sp.radius)?,
            });
        }
        if let Some(c) = &s.cylinder {
            let round = match c.ends.as_deref() {
                None | Some("flat") => false,
                Some("round") => true,
                Some(other) => {
                    return Err(self.err(
                        key("shape.cylinder.ends"),
                        format!("`{other}` is not one of `flat` (the default) or `round`"),
                    ))
                }
            };
            return Ok(RigidShape::Cylinder {
                radius: self.positive(&key("shape.cylinder.radius"), c.radius)?,
                axis: direction("shape.cylinder.axis", c.axis)?,
                length: self.non_negative_length(&key("shape.cylinder.length"), c.length)?,
                round,
            });
        }
        if let Some(p) = &s.plane {
            return Ok(RigidShape::Plane {
                normal: direction("shape.plane.normal", p.normal)?,
            });
        }
        if let Some(p) = &s.plate {
            let normal = direction("shape.plate.normal", p.normal)?;
            let side = |a: usize| self.positive(&key("shape.plate.size"), p.size[a]);
            let size = [side(0)?, side(1)?];
            let opening = p.opening.unwrap_or([0.0; 2]);
            for (a, &o) in opening.iter().enumerate() {
                if !(o.is_finite() && o >= 0.0 && o < size[a]) {
                    return Err(self.err(
                        key("shape.plate.opening"),
                        format!(
                            "{opening:?}: each side of the window must be at least 0 and smaller than the plate's side {} (size = {size:?})",
                            size[a]
                        ),
                    ));
                }
            }
            return Ok(RigidShape::Plate {
                normal,
                axes: RigidShape::plate_axes(normal),
                size,
                opening,
            });
        }
        self.meshed_shape(key, s)
    }

    /// `{ mesh = "file", surface = "name", origin = [..] }`: the file's named surface, its
    /// point `origin` (default the file's origin) placed at the body's `position`, quads
    /// split into two triangles.
    fn meshed_shape(&self, key: &dyn Fn(&str) -> String, s: &RawRigidShape) -> Result<RigidShape> {
        let (Some(file), Some(surface)) = (&s.mesh, &s.surface) else {
            return Err(self.err(
                key("shape.surface"),
                "a meshed shape gives both `mesh` (the file) and `surface` (the name of its surface)",
            ));
        };
        let path = (self.path.parent())
            .map(|d| d.join(file))
            .unwrap_or_else(|| std::path::PathBuf::from(file));
        if let Err(source) = std::fs::metadata(&path) {
            return Err(crate::error::ImpactError::MeshFile {
                scene: self.path.to_path_buf(),
                key: key("shape.mesh"),
                path,
                source,
            });
        }
        let (parts, notices) = crate::mesh::import(&path, 1.0, [0.0; 3], None)?;
        self.notices.borrow_mut().extend(notices);
        let names: Vec<&str> = parts.surfaces.iter().map(|s| s.name.as_str()).collect();
        let Some(found) = super::find_name(&names, surface) else {
            let hint = super::closest(surface, names.iter().copied())
                .map(|c| format!(" (did you mean `{c}`?)"))
                .unwrap_or_default();
            return Err(self.err(
                key("shape.surface"),
                format!(
                    "{} has no surface named `{surface}`; its surfaces are {names:?}{hint}",
                    path.display()
                ),
            ));
        };
        let origin = self.finite3(&key("shape.origin"), s.origin.unwrap_or([0.0; 3]))?;
        let at = |n: u32| {
            let x = parts.nodes[n as usize];
            std::array::from_fn(|a| x[a] - origin[a])
        };
        let triangles = (parts.surfaces[found].faces.iter())
            .flat_map(|f| match *f {
                crate::geometry::face::Face::Quad([a, b, c, d]) => {
                    vec![[at(a), at(b), at(c)], [at(a), at(c), at(d)]]
                }
                crate::geometry::face::Face::Triangle([a, b, c]) => vec![[at(a), at(b), at(c)]],
            })
            .collect();
        match crate::geometry::rigid_mesh::RigidMesh::new(triangles) {
            Some(m) => Ok(RigidShape::Mesh(std::sync::Arc::new(m))),
            None => Err(self.err(
                key("shape.surface"),
                format!(
                    "surface `{surface}` of {} has no face of positive area",
                    path.display()
                ),
            )),
        }
    }

    fn non_negative_length(&self, key: &str, v: f64) -> Result<f64> {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(key, format!("{v} must be a finite length of 0 or more")))
        }
    }
}
