//! CPU twin of `shaders/corner_select.wgsl`: the corner forces of chosen corners, in the
//! order chosen. A rank of a decomposed run reads back only the corners of the nodes it
//! shares with its neighbours (`domain::forces`).

/// `out[i]` is `corner_forces[chosen[i]]` (overwrites `out`, which holds `chosen.len()`).
pub fn corner_select(corner_forces: &[[f64; 3]], chosen: &[u32], out: &mut [[f64; 3]]) {
    for (o, &c) in out.iter_mut().zip(chosen) {
        *o = corner_forces[c as usize];
    }
}
