//! The bounds of the step's search grid (CPU twin of `shaders/search_bounds.wgsl`): the
//! fastest node's speed and the largest box side of a primary face at displacement `u`, as
//! the host path measures them (`search`), and the largest move of a face's centre from
//! where the faces were last sorted.

use super::face_cells::face_centre;

/// `[fastest speed, largest face box side, largest drift]`; `u` and `v` hold 3 values per
/// node; `centres` the faces' centres at their last sort (the drift is a centre's largest
/// coordinate change).
pub fn search_bounds(
    reference: &[[f64; 3]],
    u: &[f64],
    v: &[f64],
    faces: &[[u32; 4]],
    centres: &[[f64; 3]],
) -> [f64; 3] {
    let position = |n: u32| -> [f64; 3] {
        std::array::from_fn(|a| reference[n as usize][a] + u[3 * n as usize + a])
    };
    let drift = (faces.iter().zip(centres))
        .map(|(f, c)| {
            let now = face_centre(f, position);
            (0..3).map(|a| (now[a] - c[a]).abs()).fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    [
        fastest_speed(v),
        largest_face_side(reference, u, faces),
        drift,
    ]
}

/// The fastest node's speed (`v`: 3 per node).
pub(crate) fn fastest_speed(v: &[f64]) -> f64 {
    v.chunks_exact(3)
        .map(|c| (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt())
        .fold(0.0, f64::max)
}

/// The largest side of a face's box at displacement `u` (3 per node).
pub(crate) fn largest_face_side(reference: &[[f64; 3]], u: &[f64], faces: &[[u32; 4]]) -> f64 {
    let mut extent = 0.0f64;
    for f in faces {
        for a in 0..3 {
            let x = f.map(|n| reference[n as usize][a] + u[3 * n as usize + a]);
            let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            extent = extent.max(hi - lo);
        }
    }
    extent
}
