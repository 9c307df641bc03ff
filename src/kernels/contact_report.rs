//! The contact results of the step (CPU twin of `shaders/contact_report.wgsl`), in the plane
//! kernel's layout ([`super::plane_contact::SLOT`] per pair): normal impulse, friction
//! impulse (3), active, sliding, linearised end-of-step gap ($-\infty$ out of reach), friction
//! work since the start, and the iteration's sweeps.

use super::contact_constraints::{relative, Constraint, ContactPair};
use super::plane_contact::{slot, SLOT};
use crate::geometry::vector::dot;

/// `sweeps`: the count to report ([`super::sweep_control::SweepState::reported`]); the
/// friction work entries of `results` carry over from the last step.
pub fn contact_report(
    dt: f64,
    sweeps: u32,
    constraints: &[Constraint],
    pairs: &[ContactPair],
    v: &[f64],
    results: &mut [f64],
) {
    for (p, (c, pair)) in constraints.iter().zip(pairs).enumerate() {
        let r = &mut results[SLOT * p..SLOT * (p + 1)];
        r[slot::SWEEPS] = sweeps as f64;
        if !c.in_reach {
            r[..6].fill(0.0);
            r[slot::GAP] = f64::NEG_INFINITY;
            continue;
        }
        let rel = relative(c, pair.node, v);
        let rn = dot(rel, c.normal);
        r[slot::NORMAL_IMPULSE] = c.jn;
        r[slot::FRICTION_IMPULSE..slot::FRICTION_IMPULSE + 3].copy_from_slice(&c.jt);
        r[slot::ACTIVE] = if c.jn > 0.0 { 1.0 } else { 0.0 };
        let sliding = pair.law.is_sliding(c.jt, c.jn, 1e-6);
        r[slot::SLIDING] = if sliding { 1.0 } else { 0.0 };
        r[slot::GAP] = c.gap - dt * rn;
        if pair.law.is_frictional() {
            let slip: [f64; 3] = std::array::from_fn(|a| rel[a] - rn * c.normal[a]);
            r[slot::FRICTION_WORK] -= (0..3)
                .map(|a| c.jt[a] * 0.5 * (c.slip[a] + slip[a]))
                .sum::<f64>();
        }
    }
}
