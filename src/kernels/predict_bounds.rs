//! The predictor with the bounds of the search grid in one pass (CPU twin of
//! `shaders/predict_bounds.wgsl`): [`explicit_predict`] over every node, then
//! [`search_bounds`] at $v^*$, and the drift of every node that is not `late` (the contact
//! iteration drifts those after its sweeps).

use super::explicit_predict::explicit_predict;
use super::search_bounds::search_bounds;

/// Predicts `v` ($v_n$ in, $v^*$ out), returns the bounds `[fastest speed, largest face box
/// side, largest drift]` at $u_n$ (see [`search_bounds`]) and drifts `u` ($u_n$ in,
/// $u_n + \Delta t\, v^*$ out) at every node `n` where `late[n]` is false (every face corner
/// is late, so the bounds do not depend on the order).
pub fn predict_bounds(
    dt: f64,
    (reference, a): (&[[f64; 3]], &[f64]),
    (u, v): (&mut [f64], &mut [f64]),
    (faces, centres): (&[[u32; 4]], &[[f64; 3]]),
    late: &[bool],
) -> [f64; 3] {
    explicit_predict(dt, a, v);
    let bounds = search_bounds(reference, u, v, faces, centres);
    for (n, _) in late.iter().enumerate().filter(|(_, &l)| !l) {
        for k in 3 * n..3 * n + 3 {
            u[k] += dt * v[k];
        }
    }
    bounds
}
