//! The gather and the corrector of the explicit step in one pass (CPU twin of
//! `shaders/gather_correct.wgsl`): each node's internal force summed from its element
//! corners ([`node_gather`]), then [`explicit_correct`] over one body's nodes.

use super::explicit_correct::{explicit_correct, LumpedNode, FIELDS};
use super::node_gather::{node_gather, Incidence};

/// [`explicit_correct`] over nodes `first..first + count` with the forces gathered from
/// `corner_forces` by `incidence`; returns the workgroups' history sums.
#[allow(clippy::too_many_arguments)]
pub fn gather_correct(
    dt: f64,
    (first, count): (usize, usize),
    u: &[f64],
    (incidence, corner_forces): (&Incidence, &[[f64; 3]]),
    lumped: &[LumpedNode],
    v: &mut [f64],
    a: &mut [f64],
) -> Vec<[f64; FIELDS]> {
    let mut forces = vec![[0.0; 3]; incidence.nodes()];
    node_gather(incidence, corner_forces, &mut forces);
    let flat: Vec<f64> = forces.into_iter().flatten().collect();
    explicit_correct(dt, first, count, u, &flat, lumped, v, a)
}
