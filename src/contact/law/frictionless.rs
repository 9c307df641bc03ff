//! Frictionless contact: the normal force alone; no tangential force, no sliding state.

use crate::geometry::vector::V3;

/// Device number (`LAW_FRICTIONLESS` in `shaders/shared/law_frictionless.wgsl`).
pub const CODE: u32 = 0;

/// The frictionless law (no parameters).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Frictionless;

impl Frictionless {
    pub fn bound(&self, _normal: f64) -> f64 {
        0.0
    }

    /// Every trial returns to zero; only a zero trial is inside.
    pub fn returned(&self, trial: V3, _normal: f64) -> (V3, bool) {
        ([0.0; 3], trial == [0.0; 3])
    }

    pub fn projected(&self, _t: V3, _n: V3, _normal: f64) -> V3 {
        [0.0; 3]
    }
}
