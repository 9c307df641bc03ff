//! The contact results of the step (CPU twin of `shaders/contact_report.wgsl`), in the plane
//! kernel's layout ([`super::plane_contact::SLOT`] per pair): normal impulse, friction
//! impulse (3), active, sliding, linearised end-of-step gap ($-\infty$ out of reach), friction
//! work since the start, the iteration's sweeps, the impulse on the secondary node (3), the
//! work of a driven rigid body's driver since the start and the energy the normal impulse
//! took since the start (the impact loss). (Where the step's predictor ran
//! in the search's bounds, the kernel also drifts the contact nodes: that is
//! [`super::explicit_drift`], whose bits `tests/gpu_contact.rs` holds the device's to.)

use super::contact_constraints::{relative, Constraint, ContactPair, RigidSurface};
use super::contact_gap::NO_FACE;
use super::plane_contact::{slot, SLOT};
use crate::geometry::vector::dot;
use crate::kernels::impulse::impulse_energy;

/// `sweeps`: the count to report ([`super::sweep_control::SweepState::reported`]); the
/// friction work, driver work and impact loss entries of `results` carry over from the last
/// step.
pub fn contact_report(
    dt: f64,
    sweeps: u32,
    (constraints, pairs): (&[Constraint], &[ContactPair]),
    rigid: &[RigidSurface],
    v: &[f64],
    results: &mut [f64],
) {
    for (p, (c, pair)) in constraints.iter().zip(pairs).enumerate() {
        let r = &mut results[SLOT * p..SLOT * (p + 1)];
        r[slot::SWEEPS] = sweeps as f64;
        if !c.in_reach {
            r[..6].fill(0.0);
            r[slot::IMPULSE..slot::IMPULSE + 3].fill(0.0);
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
        let (impact, friction) = impulse_energy((c.jn, c.jt), c.normal, (c.before, rel));
        r[slot::IMPACT_LOSS] -= impact;
        if pair.law.is_frictional() {
            r[slot::FRICTION_WORK] -= friction;
        }
        let j: [f64; 3] = std::array::from_fn(|a| c.jn * c.normal[a] + c.jt[a]);
        r[slot::IMPULSE..slot::IMPULSE + 3].copy_from_slice(&j);
        if let Some(s) = (pair.body != NO_FACE).then(|| &rigid[pair.body as usize]) {
            if s.driven {
                let b = 3 * s.node as usize;
                r[slot::DRIVER_WORK] += dot(j, [v[b], v[b + 1], v[b + 2]]);
            }
        }
    }
}
