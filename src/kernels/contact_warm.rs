//! The warm start's velocity change of the device contact iteration (CPU twin of
//! `shaders/contact_warm.wgsl`, after `body_gather` on the rigid bodies): where the
//! iteration sweeps, [`super::contact_apply`] of the impulse changes that
//! [`super::contact_compliance`] set to the pairs' warm start impulses, the rigid body ranges'
//! gathered by [`super::body_gather`] first.

use super::contact_constraints::Constraint;
use super::contact_finish::SweepInputs;
use super::sweep_control::SweepState;
use super::{body_gather, contact_apply};

/// `w`: what the sweeps read (of which the contact nodes and their links, the pairs' sort
/// by face and the lumped masses).
pub fn contact_warm(
    w: &SweepInputs,
    state: &SweepState,
    constraints: &[Constraint],
    dj: &mut [f64],
    v: &mut [f64],
) {
    if !state.sweeping() {
        return;
    }
    body_gather(w.links, constraints, dj);
    contact_apply(
        w.nodes,
        w.links,
        constraints,
        w.starts,
        w.sorted,
        dj,
        w.lumped,
        v,
    );
}
