//! CPU twin of `shaders/hex8i_forces.wgsl`: internal corner forces of hex8i elements (the
//! hex8 with incompatible modes, [`crate::element::hex8i`]), $f = K_c d$ with each element's
//! condensed stiffness and $d$ its corner displacements less its translation and rotation
//! ([`hex8i::forces`]), from the values kept from the start ([`super::KeptData`]).

use rayon::prelude::*;

use super::hex8_forces::ELEMENTS_PER_TASK;
use super::ElementData;
use crate::element::{hex8i, ElementKind};

/// Corner forces of every hex8i: `corner_forces[8 e + k]` is corner k of hex8i e
/// (overwrites it; the caller passes the block's part of the corner array, see
/// [`crate::element::CornerLayout`]); `kept` holds [`hex8i::KEPT`] values per element.
pub fn hex8i_forces(
    data: &ElementData,
    kept: &[f64],
    u: &[[f64; 3]],
    corner_forces: &mut [[f64; 3]],
) {
    hex8i_forces_but(data, kept, u, corner_forces, &[]);
}

/// [`hex8i_forces`] but for the elements `skip` marks (their corners left as they were;
/// an empty `skip` marks none).
pub(crate) fn hex8i_forces_but(
    data: &ElementData,
    kept: &[f64],
    u: &[[f64; 3]],
    corner_forces: &mut [[f64; 3]],
    skip: &[bool],
) {
    let block = data.elements.block(ElementKind::Hex8i);
    corner_forces[..block.nodes.len()]
        .par_chunks_mut(8)
        .with_min_len(ELEMENTS_PER_TASK)
        .zip(
            block
                .corners::<8>()
                .par_iter()
                .zip(kept.par_chunks(hex8i::KEPT)),
        )
        .enumerate()
        .for_each(|(e, (out, (hex, k)))| {
            if skip.get(e) == Some(&true) {
                return;
            }
            let x = hex.map(|n| data.reference[n as usize]);
            out.copy_from_slice(&hex8i::forces(k, &x, &hex.map(|n| u[n as usize])));
        });
}
