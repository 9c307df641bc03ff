//! One projected Jacobi update of an explicit contact constraint, and the energy its
//! impulses take ([`impulse_energy`]), shared by the host path (`integrate::explicit`) and
//! the CPU twins of the device's contact kernels (`kernels::plane_contact`,
//! `kernels::contact_sweep`, `kernels::contact_report`); `shaders/shared/contact.wgsl` is the
//! update's WGSL copy.
//!
//! The constraint is the step's gap rate in forward-increment form,
//! $g_n + \Delta t\, \dot g \le 0$ with $\dot g = -v_{rel} \cdot n$: the normal impulse moves
//! by the residual $r = g_n / \Delta t - v_{rel} \cdot n$ over the split compliance and is
//! kept $\ge 0$. Under a frictional law the tangential impulse that stops the slip is
//! returned onto the law's set ([`ContactLaw::returned`]: Coulomb's cone $|J_T| \le \mu J_N$).

use crate::contact::law::ContactLaw;
use crate::geometry::vector::{dot, norm};

/// The energy a constraint's impulses `jn`, `jt` took over the step, as (impact loss,
/// friction work): the normal and the tangential impulse each against the mean of the
/// relative velocity's part along it before the impulses (`before`, at $v_{n-1/2}$) and after
/// them (`after`, at $v_{n+1/2}$), their shares of the change of the time-centred energy
/// (`docs/method-notes.md`).
pub(crate) fn impulse_energy(
    (jn, jt): (f64, [f64; 3]),
    normal: [f64; 3],
    (before, after): ([f64; 3], [f64; 3]),
) -> (f64, f64) {
    let (bn, rn) = (dot(before, normal), dot(after, normal));
    let slip_before: [f64; 3] = std::array::from_fn(|a| before[a] - bn * normal[a]);
    let slip: [f64; 3] = std::array::from_fn(|a| after[a] - rn * normal[a]);
    let friction = (0..3)
        .map(|a| jt[a] * 0.5 * (slip_before[a] + slip[a]))
        .sum::<f64>();
    (jn * 0.5 * (bn + rn), friction)
}

/// The relative velocity of secondary node `node` against its primary point in the velocity
/// field `v` (3 per node): the face's nodes weighted by their shape functions, or nothing (a
/// rigid plane).
pub(crate) fn relative_velocity(
    v: &[f64],
    node: u32,
    face: Option<(&[u32; 4], &[f64; 4])>,
) -> [f64; 3] {
    let n = node as usize;
    let mut rel = [v[3 * n], v[3 * n + 1], v[3 * n + 2]];
    if let Some((nodes, weights)) = face {
        for k in 0..4 {
            let m = nodes[k] as usize;
            for a in 0..3 {
                rel[a] -= weights[k] * v[3 * m + a];
            }
        }
    }
    rel
}

/// The constraint's new impulses, their change and its violation (a gap rate: the residual
/// where pressed or opening too fast, and the slip where sticking).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ImpulseUpdate {
    pub jn: f64,
    pub jt: [f64; 3],
    pub dj: [f64; 3],
    pub violation: f64,
}

/// `rel` is the relative velocity of the secondary node against its primary point at the
/// sweep's start; `jn`, `jt` the impulses so far.
#[allow(clippy::too_many_arguments)]
pub(crate) fn impulse_update(
    gap: f64,
    dt: f64,
    rel: [f64; 3],
    normal: [f64; 3],
    compliance: f64,
    law: &ContactLaw,
    jn: f64,
    jt: [f64; 3],
) -> ImpulseUpdate {
    let rn = dot(rel, normal);
    let r = gap / dt - rn;
    let new_n = (jn + r / compliance).max(0.0);
    let mut violation = if new_n > 0.0 { r.abs() } else { r.max(0.0) };
    let mut dj = normal.map(|x| (new_n - jn) * x);
    let mut next = jt;
    if law.is_frictional() {
        let slip: [f64; 3] = std::array::from_fn(|a| rel[a] - rn * normal[a]);
        let trial: [f64; 3] = std::array::from_fn(|a| jt[a] - slip[a] / compliance);
        let sticks;
        (next, sticks) = law.returned(trial, new_n);
        if sticks && new_n > 0.0 {
            violation = violation.max(norm(slip));
        }
        for a in 0..3 {
            dj[a] += next[a] - jt[a];
        }
    }
    ImpulseUpdate {
        jn: new_n,
        jt: next,
        dj,
        violation,
    }
}
