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
        (raw.iter().enumerate())
            .map(|(i, c)| {
                let key = |k: &str| format!("cohesive[{i}].{k} (cohesive `{}`)", c.name);
                self.one_cohesive(&key, c, raw_bodies, bodies)
            })
            .collect()
    }

    fn one_cohesive(
        &self,
        key: &dyn Fn(&str) -> String,
        c: &RawCohesive,
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<CohesiveSpec> {
        if c.body.is_some() || c.at.is_some() {
            return Err(ImpactError::Unsupported {
                path: self.path.to_path_buf(),
                key: key(if c.at.is_some() { "at" } else { "body" }),
                message: "interfaces inside a laminate (`body` with `at = \"ply_changes\"`) are not available yet: mesh the plies as bodies and bond them with `between`".into(),
            });
        }
        let Some(between) = &c.between else {
            return Err(self.err(
                key("between"),
                "is required: the two sides, e.g. [{ body = \"top\", face = \"z-\" }, { body = \"bottom\", face = \"z+\" }]",
            ));
        };
        let [a, b] = between.as_slice() else {
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
                "both sides lie on one body: a cohesive interface joins two bodies",
            ));
        }
        let region = match &c.region {
            Some(r) => Some((
                self.finite3(&key("region.min"), r.min)?,
                self.finite3(&key("region.max"), r.max)?,
            )),
            None => None,
        };
        if let Some(mu) = c.friction.filter(|&mu| mu != 0.0) {
            return Err(ImpactError::Unsupported {
                path: self.path.to_path_buf(),
                key: key("friction"),
                message: format!("{mu}: friction between separated faces is not available yet (they meet without it: give 0 or leave it out)"),
            });
        }
        Ok(CohesiveSpec {
            name: c.name.clone(),
            sides,
            region,
            law: self.cohesive_law(key, c)?,
        })
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
