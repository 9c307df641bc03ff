//! The sweeps of the device contact iteration in one workgroup (CPU twin of
//! `shaders/contact_solve.wgsl`): [`contact_sweep`], [`contact_apply`] and [`sweep_control`]
//! repeated until the iteration stops (its first decision, before any sweep, already taken).

use super::contact_apply::contact_apply;
use super::contact_constraints::{Constraint, ContactPair};
use super::contact_sweep::contact_sweep;
use super::contact_touches::ContactNode;
use super::explicit_correct::LumpedNode;
use super::sweep_control::{sweep_control, SweepState};

/// The nodes and links of the iteration and its face buckets (see [`ContactNode`]).
pub struct SolveLinks<'a> {
    pub nodes: &'a [ContactNode],
    pub links: &'a [u32],
    pub starts: &'a [u32],
    pub sorted: &'a [u32],
    pub lumped: &'a [LumpedNode],
}

/// Sweeps until `state` stops sweeping: updates the impulses, `dj` and the velocities `v`.
#[allow(clippy::too_many_arguments)]
pub fn contact_solve(
    dt: f64,
    tolerance: f64,
    max_iterations: u32,
    constraints: &mut [Constraint],
    pairs: &[ContactPair],
    l: &SolveLinks,
    dj: &mut [f64],
    v: &mut [f64],
    state: &mut SweepState,
) {
    while state.sweeping() {
        state.violation = contact_sweep(dt, constraints, pairs, v, dj);
        contact_apply(
            l.nodes,
            l.links,
            constraints,
            l.starts,
            l.sorted,
            dj,
            l.lumped,
            v,
        );
        sweep_control(state, tolerance, max_iterations);
    }
}
