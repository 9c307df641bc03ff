//! The end of the device contact iteration (CPU twin of `shaders/contact_finish.wgsl`):
//! while the iteration sweeps on after the sweeps recorded, the remaining sweeps, each a
//! [`contact_sweep`], the stopping rule ([`sweep_control`]), the rigid bodies' gathers
//! ([`body_gather`]) and a [`contact_apply`], as the recorded sweeps run them.

use super::body_gather::body_gather;
use super::contact_apply::contact_apply;
use super::contact_constraints::{Constraint, ContactPair};
use super::contact_sweep::contact_sweep;
use super::contact_touches::ContactNode;
use super::explicit_correct::LumpedNode;
use super::sweep_control::{sweep_control, SweepState};

/// What one sweep reads besides the constraints, the velocity and the impulse changes.
pub struct SweepInputs<'a> {
    pub dt: f64,
    pub tolerance: f64,
    pub max_iterations: u32,
    pub pairs: &'a [ContactPair],
    pub nodes: &'a [ContactNode],
    pub links: &'a [u32],
    pub starts: &'a [u32],
    pub sorted: &'a [u32],
    pub lumped: &'a [LumpedNode],
}

/// Sweeps until the iteration has stopped (converged or at the sweep limit). `dj` holds the
/// pairs' impulse changes, then the rigid body ranges'.
pub fn contact_finish(
    s: &SweepInputs,
    state: &mut SweepState,
    constraints: &mut [Constraint],
    dj: &mut [f64],
    v: &mut [f64],
) {
    while state.sweeping() {
        let violation = contact_sweep(s.dt, constraints, s.pairs, v, dj);
        state.violation = state.violation.max(violation);
        sweep_control(state, s.tolerance, s.max_iterations);
        body_gather(s.links, constraints, dj);
        contact_apply(
            s.nodes,
            s.links,
            constraints,
            s.starts,
            s.sorted,
            dj,
            s.lumped,
            v,
        );
    }
}
