//! One projected Jacobi sweep of the device contact iteration (CPU twin of
//! `shaders/contact_sweep.wgsl`), the host path's sweep (`integrate::explicit`): each pair's
//! [`impulse_update`] from the relative velocity at the sweep's start.

use super::contact_constraints::{relative, Constraint, ContactPair};
use crate::kernels::impulse::impulse_update;

/// Updates the impulses, writes each pair's impulse change into `dj` (3 per pair, zero for
/// a pair out of reach or not enforceable; the rigid body ranges' after them are
/// [`super::body_gather`]'s) and returns the sweep's largest violation.
pub fn contact_sweep(
    dt: f64,
    constraints: &mut [Constraint],
    pairs: &[ContactPair],
    v: &[f64],
    dj: &mut [f64],
) -> f64 {
    let mut violation = 0.0f64;
    for (p, (c, pair)) in constraints.iter_mut().zip(pairs).enumerate() {
        let mut d = [0.0f64; 3];
        if c.in_reach && c.compliance > 0.0 {
            let up = impulse_update(
                c.gap,
                dt,
                relative(c, pair.node, v),
                c.normal,
                c.compliance,
                &pair.law,
                c.jn,
                c.jt,
            );
            violation = violation.max(up.violation);
            (c.jn, c.jt, d) = (up.jn, up.jt, up.dj);
        }
        dj[3 * p..3 * p + 3].copy_from_slice(&d);
    }
    violation
}
