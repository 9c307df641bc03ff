//! The elastic law of a `[[material]]` (isotropic, orthotropic or transversely isotropic)
//! and a body's material axes: `orientation` and `plies`.

use super::Checker;
use crate::error::Result;
use crate::material::orthotropic::Orthotropic;
use crate::material::{Elastic, Rotation};
use crate::scene::raw::{RawMaterial, RawOrientation, RawPlies};
use crate::scene::{BodyShape, Plies, Ply};

/// Relative mismatch allowed between the plies' total thickness and the body's.
pub(crate) const PLY_THICKNESS_TOLERANCE: f64 = 1e-6;

impl Checker<'_> {
    /// The material's law in its own axes from exactly one of `youngs_modulus` and
    /// `poissons_ratio`, `orthotropic` or `transversely_isotropic`.
    pub(super) fn elastic(
        &self,
        key: &dyn Fn(&str) -> String,
        m: &RawMaterial,
        density: f64,
    ) -> Result<Elastic> {
        // each constant finite, named by its own key (a NaN would otherwise surface as a
        // problem of a constant derived from it)
        let given: Vec<(&str, &str, f64)> = match (&m.orthotropic, &m.transversely_isotropic) {
            (Some(o), _) => [
                ("e1", o.e1),
                ("e2", o.e2),
                ("e3", o.e3),
                ("nu12", o.nu12),
                ("nu13", o.nu13),
                ("nu23", o.nu23),
                ("g12", o.g12),
                ("g13", o.g13),
                ("g23", o.g23),
            ]
            .map(|(k, v)| ("orthotropic", k, v))
            .to_vec(),
            (None, Some(t)) => [
                ("e1", t.e1),
                ("e2", t.e2),
                ("nu12", t.nu12),
                ("nu23", t.nu23),
                ("g12", t.g12),
            ]
            .map(|(k, v)| ("transversely_isotropic", k, v))
            .to_vec(),
            (None, None) => Vec::new(),
        };
        if let Some((table, k, v)) = given.iter().find(|(_, _, v)| !v.is_finite()) {
            return Err(self.err(
                key(&format!("{table}.{k}")),
                format!("must be finite, got {v}"),
            ));
        }
        let constants = match (&m.orthotropic, &m.transversely_isotropic) {
            (None, None) => return self.isotropic(key, m, density),
            (Some(o), None) => Orthotropic {
                e: [o.e1, o.e2, o.e3],
                nu: [o.nu12, o.nu13, o.nu23],
                g: [o.g12, o.g13, o.g23],
            },
            (None, Some(t)) => {
                Orthotropic::transversely_isotropic(t.e1, t.e2, t.nu12, t.nu23, t.g12)
            }
            (Some(_), Some(_)) => {
                return Err(self.err(
                    key("orthotropic"),
                    "give one of `orthotropic` and `transversely_isotropic`, not both",
                ))
            }
        };
        let table = if m.orthotropic.is_some() {
            "orthotropic"
        } else {
            "transversely_isotropic"
        };
        if m.youngs_modulus.is_some() || m.poissons_ratio.is_some() {
            return Err(self.err(
                key(table),
                "replaces youngs_modulus and poissons_ratio: give one law per material",
            ));
        }
        if let Some(why) = constants.indefinite() {
            return Err(self.err(key(table), why));
        }
        Ok(Elastic::anisotropic(constants.stiffness(), density))
    }

    fn isotropic(
        &self,
        key: &dyn Fn(&str) -> String,
        m: &RawMaterial,
        density: f64,
    ) -> Result<Elastic> {
        let missing = |k: &str| {
            self.err(
                key(k),
                "is missing: give youngs_modulus and poissons_ratio, or an `orthotropic` or `transversely_isotropic` table",
            )
        };
        let e = m.youngs_modulus.ok_or_else(|| missing("youngs_modulus"))?;
        let nu = m.poissons_ratio.ok_or_else(|| missing("poissons_ratio"))?;
        let youngs_modulus = self.positive(&key("youngs_modulus"), e)?;
        let c2 = youngs_modulus / density;
        // a static step's massless material has no wave speed to check
        if density > 0.0 && !c2.is_normal() {
            return Err(self.err(
                key("youngs_modulus"),
                format!(
                    "with density {density:e} gives a wave speed sqrt(E/rho) = {:e}, which is no usable number (check the units of both)",
                    c2.sqrt()
                ),
            ));
        }
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(self.err(
                key("poissons_ratio"),
                format!("must lie in (-1, 0.5) for a stable isotropic solid, got {nu}"),
            ));
        }
        Ok(Elastic::from_engineering(youngs_modulus, nu, density))
    }

    /// A body's material axes: `{ axes = [a1, a2] }` (axis 1, and a vector in the 1-2 plane)
    /// or `{ axis = [..], angle = degrees }` (the global axes turned); the global axes
    /// without one.
    pub(super) fn orientation(
        &self,
        key: &dyn Fn(&str) -> String,
        raw: Option<&RawOrientation>,
    ) -> Result<Rotation> {
        let Some(o) = raw else {
            return Ok(Rotation::IDENTITY);
        };
        match (o.axes, o.axis, o.angle) {
            (Some([a1, a2]), None, None) => {
                let a1 = self.finite3(&key("orientation.axes"), a1)?;
                let a2 = self.finite3(&key("orientation.axes"), a2)?;
                Rotation::from_axes(a1, a2).ok_or_else(|| {
                    self.err(
                        key("orientation.axes"),
                        format!("{a1:?} and {a2:?} are parallel (or one is zero): they span no plane of axes 1 and 2"),
                    )
                })
            }
            (None, Some(axis), Some(angle)) => {
                let axis = self.finite3(&key("orientation.axis"), axis)?;
                let axis = crate::material::rotation::unit(axis).ok_or_else(|| {
                    self.err(key("orientation.axis"), "must be a nonzero vector")
                })?;
                if !angle.is_finite() {
                    return Err(self.err(key("orientation.angle"), "must be finite (degrees)"));
                }
                Ok(Rotation::IDENTITY.turned(axis, angle.to_radians()))
            }
            _ => Err(self.err(
                key("orientation"),
                "give either `axes = [axis 1, a vector in the 1-2 plane]` or `axis` and `angle` (degrees)",
            )),
        }
    }

    /// A body's `plies`: the stacking axis `normal` ("x", "y" or "z") and the `layers`
    /// (angle in degrees about the normal, thickness), which must fill the body's extent
    /// along the normal.
    pub(super) fn plies(
        &self,
        key: &dyn Fn(&str) -> String,
        raw: Option<&RawPlies>,
        shape: &BodyShape,
    ) -> Result<Option<Plies>> {
        let Some(p) = raw else { return Ok(None) };
        let axis = ["x", "y", "z"]
            .iter()
            .position(|a| *a == p.normal)
            .ok_or_else(|| {
                self.err(
                    key("plies.normal"),
                    format!("must be \"x\", \"y\" or \"z\", got \"{}\"", p.normal),
                )
            })?;
        if p.layers.is_empty() {
            return Err(self.err(key("plies.layers"), "holds no ply"));
        }
        let mut layers = Vec::with_capacity(p.layers.len());
        for (k, l) in p.layers.iter().enumerate() {
            let thickness =
                self.positive(&key(&format!("plies.layers[{k}].thickness")), l.thickness)?;
            if !l.angle.is_finite() {
                return Err(self.err(
                    key(&format!("plies.layers[{k}].angle")),
                    "must be finite (degrees)",
                ));
            }
            layers.push(Ply {
                angle: l.angle.to_radians(),
                thickness,
            });
        }
        let (lo, hi) = extent(shape, axis);
        let total: f64 = layers.iter().map(|l| l.thickness).sum();
        if (total - (hi - lo)).abs() > PLY_THICKNESS_TOLERANCE * (hi - lo) {
            return Err(self.err(
                key("plies.layers"),
                format!(
                    "the plies are {total} thick together and the body {} along {} (from {lo} to {hi}): they must fill it",
                    hi - lo,
                    p.normal
                ),
            ));
        }
        Ok(Some(Plies {
            axis,
            start: lo,
            layers,
        }))
    }
}

/// The body's lowest and highest coordinate along `axis`.
fn extent(shape: &BodyShape, axis: usize) -> (f64, f64) {
    match shape {
        BodyShape::Box(b) => (b.min[axis], b.max[axis]),
        BodyShape::Imported { parts, .. } => parts
            .nodes
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p[axis]), hi.max(p[axis]))
            }),
    }
}
