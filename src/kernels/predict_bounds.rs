//! The predictor with the bounds of the search grid in one pass (CPU twin of
//! `shaders/predict_bounds.wgsl`): [`explicit_predict`] over every node, then
//! [`search_bounds`] at $v^*$.

use super::explicit_predict::explicit_predict;
use super::search_bounds::search_bounds;

/// Predicts `v` ($v_n$ in, $v^*$ out) and returns the bounds `[fastest speed, largest face
/// box side, largest drift]` (see [`search_bounds`]).
pub fn predict_bounds(
    dt: f64,
    (reference, u, a): (&[[f64; 3]], &[f64], &[f64]),
    v: &mut [f64],
    faces: &[[u32; 4]],
    centres: &[[f64; 3]],
) -> [f64; 3] {
    explicit_predict(dt, a, v);
    search_bounds(reference, u, v, faces, centres)
}
