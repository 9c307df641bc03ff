//! CPU twin of `shaders/tet4_forces.wgsl`: internal corner forces of linear elastic tet4
//! elements, $f_k = V \sigma \nabla N_k$ with the element's constant strain (see
//! [`crate::element::tet4::forces`]).

use rayon::prelude::*;

use super::hex8_forces::ELEMENTS_PER_TASK;
use super::ElementData;
use crate::element::{tet4, ElementKind};

/// Corner forces of every tet: `corner_forces[4 t + k]` is corner k of tet t (overwrites it;
/// the caller passes the tet4 block's part of the corner array, see
/// [`crate::element::CornerLayout`]). [`super::node_gather`] sums them to the nodes.
/// Elements run on all threads, each writing its own corners.
pub fn tet4_forces(data: &ElementData, u: &[[f64; 3]], corner_forces: &mut [[f64; 3]]) {
    tet4_forces_but(data, u, corner_forces, &[]);
}

/// [`tet4_forces`] but for the elements `skip` marks (their corners left as they were; an
/// empty `skip` marks none).
pub(crate) fn tet4_forces_but(
    data: &ElementData,
    u: &[[f64; 3]],
    corner_forces: &mut [[f64; 3]],
    skip: &[bool],
) {
    let block = data.elements.block(ElementKind::Tet4);
    corner_forces[..block.nodes.len()]
        .par_chunks_mut(4)
        .with_min_len(ELEMENTS_PER_TASK)
        .zip(block.corners::<4>().par_iter().zip(&block.material))
        .enumerate()
        .for_each(|(e, (out, (tet, &mat)))| {
            if skip.get(e) == Some(&true) {
                return;
            }
            let m = data.materials[mat as usize];
            let x = tet.map(|n| data.reference[n as usize]);
            let ue = tet.map(|n| u[n as usize]);
            out.copy_from_slice(&tet4::forces(&x, &ue, &m));
        });
}
