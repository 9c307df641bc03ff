//! The two bounds of the step's search grid (CPU twin of `shaders/search_bounds.wgsl`): the
//! fastest node's speed and the largest box side of a primary face at displacement `u`, as
//! the host path measures them (`contact::search`).

use crate::contact::search::{fastest_speed, largest_face_side};

/// `[fastest speed, largest face box side]`; `u` and `v` hold 3 values per node.
pub fn search_bounds(reference: &[[f64; 3]], u: &[f64], v: &[f64], faces: &[[u32; 4]]) -> [f64; 2] {
    [fastest_speed(v), largest_face_side(reference, u, faces)]
}
