//! Coulomb friction: a pressed node carries a tangential force up to $\mu$ times its normal
//! force; inside the cone it sticks, on it it slides against its slip (method.md section 3).

use crate::geometry::vector::{dot, norm, V3};

/// Device number (`LAW_COULOMB` in `shaders/shared/law_coulomb.wgsl`).
pub const CODE: u32 = 1;

/// Coulomb's law with coefficient `mu` > 0.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Coulomb {
    pub mu: f64,
}

impl Coulomb {
    /// The cone's radius $\mu N$.
    pub fn bound(&self, normal: f64) -> f64 {
        self.mu * normal
    }

    /// The trial scaled back onto the cone when it lies outside (twin:
    /// `coulomb_returned`).
    pub fn returned(&self, trial: V3, normal: f64) -> (V3, bool) {
        let radius = self.bound(normal);
        let size = norm(trial);
        if size > radius {
            (trial.map(|x| x * radius / size), false)
        } else {
            (trial, true)
        }
    }

    /// The return map of the implicit iteration: `t` without its component along the unit
    /// normal `n`, scaled back onto the cone when it lies outside.
    pub fn projected(&self, t: V3, n: V3, normal: f64) -> V3 {
        let r = self.bound(normal);
        if r <= 0.0 {
            return [0.0; 3];
        }
        let tn = dot(t, n);
        let t = [t[0] - tn * n[0], t[1] - tn * n[1], t[2] - tn * n[2]];
        let l = norm(t);
        let scale = if l > r { r / l } else { 1.0 };
        t.map(|x| x * scale)
    }

    /// A pressed node whose force reaches the cone within `tolerance` slides (twin:
    /// `coulomb_sliding`).
    pub fn is_sliding(&self, t: V3, normal: f64, tolerance: f64) -> bool {
        self.mu > 0.0 && normal > 0.0 && norm(t) >= self.mu * normal * (1.0 - tolerance)
    }
}
