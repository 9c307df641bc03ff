//! Contact impulses against analytic rigid planes in the explicit step, one secondary node at
//! a time (CPU twin of `shaders/plane_contact.wgsl`).
//!
//! A node's plane constraints $g_n + \Delta t\, \dot g_{n+1/2} \le 0$ couple only through the
//! node, so each node runs the projected Jacobi sweeps of the host path
//! (`integrate::explicit`) on its own constraints: the same row-sum compliance (its plane
//! count times its largest inverse mass), the same Coulomb return map, the same
//! stopping rule, the same reach (a plane enters the step if the node is within four steps
//! of its motion of it, $g \ge -4 \Delta t |v^*|$). With one plane a node is solved in one
//! sweep.

use super::explicit_correct::LumpedNode;
use crate::geometry::quad::{dot, norm};
use crate::kernels::impulse::impulse_update;

/// Results per (plane node, plane), and per (node, face) pair of `contact_report`: the fields
/// at the offsets of [`slot`].
pub const SLOT: usize = 9;

/// The fields of a result slot (`SLOT_*` in `shaders/shared/types.wgsl`).
pub mod slot {
    pub const NORMAL_IMPULSE: usize = 0;
    /// Three floats.
    pub const FRICTION_IMPULSE: usize = 1;
    /// 0 or 1.
    pub const ACTIVE: usize = 4;
    /// 0 or 1.
    pub const SLIDING: usize = 5;
    /// The linearised end-of-step gap.
    pub const GAP: usize = 6;
    /// Friction work since the start.
    pub const FRICTION_WORK: usize = 7;
    /// The node's sweeps (`max_iterations + 1` where it did not converge).
    pub const SWEEPS: usize = 8;

    /// Whether the history reduces field `f` over the nodes by its largest value (the
    /// deepest gap, the most sweeps) rather than by its sum.
    pub fn reduced_by_max(f: usize) -> bool {
        f == GAP || f == SWEEPS
    }
}
/// Planes a node can have (the bit set and the kernel's local arrays).
pub const MAX_PLANES: usize = 8;

/// An analytic rigid plane: a point, the unit normal into the bodies' side, friction.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PlaneData {
    pub point: [f64; 3],
    pub normal: [f64; 3],
    pub mu: f64,
}

/// A secondary node and the planes it is secondary to (bit p: plane p).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PlaneNode {
    pub node: u32,
    pub planes: u32,
}

/// Constants of the explicit step's contact iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepLimits {
    pub dt: f64,
    /// Largest violation (a gap rate) the iteration leaves.
    pub tolerance: f64,
    pub max_iterations: u32,
}

/// `v` holds $v^*$ on entry (the predictor's velocity) and the corrected velocity on exit;
/// `a` is $a_n$ (for the slip of $v_{n-1/2} = v^* - \Delta t\, a_n$ in the friction work);
/// `results` holds [`SLOT`] floats per (node, plane), node-major, and its friction work
/// entries carry over from the last step.
#[allow(clippy::too_many_arguments)]
pub fn plane_contact(
    limits: SweepLimits,
    reference: &[[f64; 3]],
    u: &[f64],
    a: &[f64],
    lumped: &[LumpedNode],
    planes: &[PlaneData],
    nodes: &[PlaneNode],
    v: &mut [f64],
    results: &mut [f64],
) {
    let np = planes.len().min(MAX_PLANES);
    let dt = limits.dt;
    for (i, pn) in nodes.iter().enumerate() {
        let n = pn.node as usize;
        let on = |p: usize| pn.planes & (1 << p) != 0;
        let inv = lumped[n].inv_mass;
        let mut vel = [v[3 * n], v[3 * n + 1], v[3 * n + 2]];
        let before: [f64; 3] = std::array::from_fn(|ax| vel[ax] - dt * a[3 * n + ax]);
        let x: [f64; 3] = std::array::from_fn(|ax| reference[n][ax] + u[3 * n + ax]);
        let gap: Vec<f64> = (0..np)
            .map(|p| {
                let pl = &planes[p];
                -dot(std::array::from_fn(|ax| x[ax] - pl.point[ax]), pl.normal)
            })
            .collect();
        // the planes in reach: those the node could meet within four steps of its motion
        let reach = -4.0 * dt * norm(vel);
        let on = |p: usize| on(p) && gap[p] >= reach;
        let touches = (0..np).filter(|&p| on(p)).count() as f64;
        let mut jn = [0.0f64; MAX_PLANES];
        let mut jt = [[0.0f64; 3]; MAX_PLANES];
        // the largest inverse mass bounds |n_p . M^-1 n_q| (Gershgorin), prescribed dofs too
        let inv_max = inv.iter().copied().fold(0.0, f64::max);
        let mut sweeps = 0;
        // a node with no plane in reach takes no sweep
        let mut converged = !(0..np).any(on);
        while !converged && sweeps < limits.max_iterations {
            sweeps += 1;
            let mut violation = 0.0f64;
            let mut dv = [0.0f64; 3];
            for p in (0..np).filter(|&p| on(p)) {
                let nrm = planes[p].normal;
                // a normal that meets only prescribed dofs cannot be enforced
                if (0..3).map(|ax| nrm[ax] * nrm[ax] * inv[ax]).sum::<f64>() <= 0.0 {
                    continue;
                }
                let up = impulse_update(
                    gap[p],
                    dt,
                    vel,
                    nrm,
                    touches * inv_max,
                    planes[p].mu,
                    jn[p],
                    jt[p],
                );
                violation = violation.max(up.violation);
                (jn[p], jt[p]) = (up.jn, up.jt);
                let dj = up.dj;
                for ax in 0..3 {
                    dv[ax] += dj[ax] * inv[ax];
                }
            }
            for ax in 0..3 {
                vel[ax] += dv[ax];
            }
            if violation <= limits.tolerance {
                converged = true;
                break;
            }
        }
        v[3 * n..3 * n + 3].copy_from_slice(&vel);
        let reported = if converged {
            sweeps
        } else {
            limits.max_iterations + 1
        } as f64;
        for p in 0..np {
            let o = SLOT * (i * np + p);
            let r = &mut results[o..o + SLOT];
            if pn.planes & (1 << p) == 0 {
                r.fill(0.0);
                r[slot::GAP] = f64::NEG_INFINITY;
                continue;
            }
            let nrm = planes[p].normal;
            let mu = planes[p].mu;
            let rn = dot(vel, nrm);
            r[slot::NORMAL_IMPULSE] = jn[p];
            r[slot::FRICTION_IMPULSE..slot::FRICTION_IMPULSE + 3].copy_from_slice(&jt[p]);
            r[slot::ACTIVE] = f64::from(u8::from(jn[p] > 0.0));
            let sliding = mu > 0.0 && jn[p] > 0.0 && norm(jt[p]) >= mu * jn[p] * (1.0 - 1e-6);
            r[slot::SLIDING] = f64::from(u8::from(sliding));
            r[slot::GAP] = gap[p] - dt * rn;
            if mu > 0.0 {
                let slip: [f64; 3] = std::array::from_fn(|ax| vel[ax] - rn * nrm[ax]);
                let bn = dot(before, nrm);
                let slip_before: [f64; 3] = std::array::from_fn(|ax| before[ax] - bn * nrm[ax]);
                r[slot::FRICTION_WORK] -= (0..3)
                    .map(|ax| jt[p][ax] * 0.5 * (slip_before[ax] + slip[ax]))
                    .sum::<f64>();
            }
            r[slot::SWEEPS] = reported;
        }
    }
}
