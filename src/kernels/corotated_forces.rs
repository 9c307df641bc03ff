//! The element forces of `run.kinematics = "corotational"`, on the CPU in f64 (there is no
//! device form yet: such a run's kernels are the CPU's): each element's frame
//! ([`crate::element::corotation`]), its own forces in that frame, turned back.

use rayon::prelude::*;

use super::hex8_forces::{self, ELEMENTS_PER_TASK};
use super::{ElementData, KeptData};
use crate::element::corotation::{self, Mat3};
use crate::element::{hex8i, tet4, CornerLayout, ElementKind};
use crate::parallel::ordered_sum;

/// Each element's frame at the last force evaluation, per block (by kind index), element
/// after element.
#[derive(Debug, Clone, Default)]
pub struct Frames {
    pub blocks: Vec<Vec<Mat3>>,
}

impl Frames {
    pub fn new(data: &ElementData) -> Self {
        let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        Frames {
            blocks: (data.elements.blocks.iter())
                .map(|b| vec![identity; b.len()])
                .collect(),
        }
    }

    /// The frames of a kind's block.
    pub fn of_kind(&self, kind: ElementKind) -> &[Mat3] {
        self.blocks.get(kind.index()).map_or(&[], Vec::as_slice)
    }
}

/// Corner forces of every element at displacement `u`, in `layout`, each in its frame (found
/// anew for every element, written to `frames`); the elements `skip` marks keep their
/// corners (the damage pass gives theirs, in the same frames).
pub(crate) fn corotated_forces(
    data: &ElementData,
    (layout, kept): (&CornerLayout, &KeptData),
    u: &[[f64; 3]],
    corner_forces: &mut [[f64; 3]],
    (skip, frames): (&[Vec<bool>], &mut Frames),
) {
    for block in &data.elements.blocks {
        let start = layout.offset(block.kind);
        let out = &mut corner_forces[start..start + block.nodes.len()];
        let skip = skip.get(block.kind.index()).map_or(&[][..], Vec::as_slice);
        let frames = &mut frames.blocks[block.kind.index()];
        let material = |e: usize| &data.materials[block.material[e] as usize];
        match block.kind {
            ElementKind::Hex8 => block_forces::<8>(
                data,
                block,
                u,
                (out, skip, frames),
                (
                    |_, x| corotation::centre_gradients(x),
                    |e, x, d| hex8_forces::element_forces(x, d, material(e)),
                ),
            ),
            ElementKind::Tet4 => block_forces::<4>(
                data,
                block,
                u,
                (out, skip, frames),
                (
                    |_, x| corotation::centre_gradients(x),
                    |e, x, d| tet4::forces(x, d, material(e)),
                ),
            ),
            ElementKind::Hex8i => {
                let kept = kept.of_kind(ElementKind::Hex8i);
                let of = |e: usize| &kept[e * hex8i::KEPT..(e + 1) * hex8i::KEPT];
                // the centre gradients the element keeps (the same bits as found anew)
                let gradients = |e: usize, _: &[[f64; 3]; 8]| {
                    let g = &of(e)[hex8i::PACKED..];
                    std::array::from_fn(|k| [g[3 * k], g[3 * k + 1], g[3 * k + 2]])
                };
                block_forces::<8>(
                    data,
                    block,
                    u,
                    (out, skip, frames),
                    (gradients, |e, x, d| hex8i::forces(of(e), x, d)),
                )
            }
        }
    }
}

/// One block's frames and, where `skip` does not mark the element, its turned forces from
/// `local` (element number, reference corners, local displacements); `gradients` gives an
/// element's centre gradients (element number, reference corners).
fn block_forces<const N: usize>(
    data: &ElementData,
    block: &crate::element::ElementBlock,
    u: &[[f64; 3]],
    (out, skip, frames): (&mut [[f64; 3]], &[bool], &mut [Mat3]),
    (gradients, local): (
        impl Fn(usize, &[[f64; 3]; N]) -> [[f64; 3]; N] + Sync,
        impl Fn(usize, &[[f64; 3]; N], &[[f64; 3]; N]) -> [[f64; 3]; N] + Sync,
    ),
) {
    out[..block.nodes.len()]
        .par_chunks_mut(N)
        .with_min_len(ELEMENTS_PER_TASK)
        .zip(block.corners::<N>().par_iter().zip(frames.par_iter_mut()))
        .enumerate()
        .for_each(|(e, (out, (corners, frame)))| {
            let x = corners.map(|n| data.reference[n as usize]);
            let ue = corners.map(|n| u[n as usize]);
            let g = gradients(e, &x);
            let r = corotation::rotation(&g, &ue);
            *frame = r;
            if skip.get(e) == Some(&true) {
                return;
            }
            let d = corotation::local(&r, &x, &ue);
            out.copy_from_slice(&corotation::turned_forces(&r, &g, &d, &local(e, &x, &d)));
        });
}

/// The sum over the elements of [`corotation::turn_energy`] at their corner forces (in
/// `layout`) and frames: what $\tfrac12 u^n \cdot f_{int}$ holds beyond the elements'
/// strain energy. Summed in element order, whatever the threads.
pub(crate) fn turn_energy(
    data: &ElementData,
    layout: &CornerLayout,
    corner_forces: &[[f64; 3]],
    frames: &Frames,
) -> f64 {
    let mut total = 0.0;
    for block in &data.elements.blocks {
        let start = layout.offset(block.kind);
        let frames = frames.of_kind(block.kind);
        let n = block.kind.corners();
        total += ordered_sum(block.len(), |e| {
            let f = &corner_forces[start + n * e..start + n * (e + 1)];
            let x = |k: usize| data.reference[block.nodes[n * e + k] as usize];
            match n {
                8 => corotation::turn_energy::<8>(&frames[e], &std::array::from_fn(x), f),
                _ => corotation::turn_energy::<4>(&frames[e], &std::array::from_fn(x), f),
            }
        });
    }
    total
}
