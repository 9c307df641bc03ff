//! The two bounds of the step's search grid (CPU twin of `shaders/search_bounds.wgsl`): the
//! fastest node's speed and the largest box side of a primary face at displacement `u`.

use crate::contact::quad::norm;

/// `[fastest speed, largest face box side]`; `u` and `v` hold 3 values per node.
pub fn search_bounds(reference: &[[f64; 3]], u: &[f64], v: &[f64], faces: &[[u32; 4]]) -> [f64; 2] {
    let speed = v
        .chunks_exact(3)
        .map(|c| norm([c[0], c[1], c[2]]))
        .fold(0.0, f64::max);
    let mut side = 0.0f64;
    for f in faces {
        for a in 0..3 {
            let x = f.map(|n| reference[n as usize][a] + u[3 * n as usize + a]);
            let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            side = side.max(hi - lo);
        }
    }
    [speed, side]
}
