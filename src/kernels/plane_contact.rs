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
use crate::contact::law::ContactLaw;
use crate::geometry::vector::{dot, norm};
use crate::kernels::impulse::{impulse_energy, impulse_update};

/// Results per (plane node, plane), and per (node, face) pair of `contact_report`: the fields
/// at the offsets of [`slot`].
pub const SLOT: usize = 14;

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
    /// The impulse on the secondary node, $J_N n + J_T$: three floats.
    pub const IMPULSE: usize = 9;
    /// The work of a driven rigid body's driver since the start (zero against a plane).
    pub const DRIVER_WORK: usize = 12;
    /// The energy the normal impulses took since the start.
    pub const IMPACT_LOSS: usize = 13;

    /// Whether the history reduces field `f` over the nodes by its largest value (the
    /// deepest gap, the most sweeps) rather than by its sum.
    pub fn reduced_by_max(f: usize) -> bool {
        f == GAP || f == SWEEPS
    }
}
/// Planes a node can have (the bit set and the kernel's local arrays).
pub(crate) const MAX_PLANES: usize = 8;

/// An analytic rigid plane: a point, the unit normal into the bodies' side, its contact law.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PlaneData {
    pub point: [f64; 3],
    pub normal: [f64; 3],
    pub law: ContactLaw,
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
///
/// One node at a time, in the kernel's steps: its planes' gaps and the planes in reach
/// (`planes_in_reach`), its sweeps (`sweeps`, each a `sweep`), its new velocity, and its
/// results per plane (`report`).
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
    let planes = &planes[..planes.len().min(MAX_PLANES)];
    let np = planes.len();
    let dt = limits.dt;
    for (i, pn) in nodes.iter().enumerate() {
        let n = pn.node as usize;
        let vel = [v[3 * n], v[3 * n + 1], v[3 * n + 2]];
        // v_{n-1/2} = v* - dt a_n: the velocity before the step, for the friction work and
        // the impact loss
        let before: [f64; 3] = std::array::from_fn(|ax| vel[ax] - dt * a[3 * n + ax]);
        let x: [f64; 3] = std::array::from_fn(|ax| reference[n][ax] + u[3 * n + ax]);
        let (gap, mask) = planes_in_reach(planes, pn.planes, x, -4.0 * dt * norm(vel));
        let node = sweeps(limits, planes, &gap, mask, lumped[n].inv_mass, vel);
        v[3 * n..3 * n + 3].copy_from_slice(&node.vel);
        let r = &mut results[SLOT * i * np..SLOT * (i + 1) * np];
        report(dt, planes, pn.planes, &gap, before, &node, r);
    }
}

/// A node's state through its sweeps: its velocity and its impulses on each plane.
struct NodeSweeps {
    vel: [f64; 3],
    jn: [f64; MAX_PLANES],
    jt: [[f64; 3]; MAX_PLANES],
    /// The sweeps taken, or `max_iterations + 1` where the node did not converge.
    reported: f64,
}

/// The gap to each plane at `x`, and the planes in reach as a bit set: the node's planes
/// (`own`) that it could meet within four steps of its motion (`gap >= reach`, with
/// `reach` = $-4 \Delta t |v^*|$).
fn planes_in_reach(planes: &[PlaneData], own: u32, x: [f64; 3], reach: f64) -> (Vec<f64>, u32) {
    let gap: Vec<f64> = planes
        .iter()
        .map(|pl| -dot(std::array::from_fn(|ax| x[ax] - pl.point[ax]), pl.normal))
        .collect();
    let mask = (0..planes.len())
        .filter(|&p| own & (1 << p) != 0 && gap[p] >= reach)
        .fold(0u32, |m, p| m | 1 << p);
    (gap, mask)
}

/// The projected Jacobi sweeps of one node on its planes in reach (`mask`), from the
/// velocity $v^*$, until no gap rate is violated by more than the tolerance or
/// `max_iterations` sweeps are taken.
fn sweeps(
    limits: SweepLimits,
    planes: &[PlaneData],
    gap: &[f64],
    mask: u32,
    inv: [f64; 3],
    vel: [f64; 3],
) -> NodeSweeps {
    // the largest inverse mass bounds |n_p . M^-1 n_q| (Gershgorin), prescribed dofs too
    let inv_max = inv.iter().copied().fold(0.0, f64::max);
    let compliance = mask.count_ones() as f64 * inv_max;
    let mut node = NodeSweeps {
        vel,
        jn: [0.0; MAX_PLANES],
        jt: [[0.0; 3]; MAX_PLANES],
        reported: 0.0,
    };
    let mut sweeps = 0;
    // a node with no plane in reach takes no sweep
    let mut converged = mask == 0;
    while !converged && sweeps < limits.max_iterations {
        sweeps += 1;
        let violation = sweep(limits.dt, planes, gap, mask, inv, compliance, &mut node);
        converged = violation <= limits.tolerance;
    }
    node.reported = if converged {
        sweeps
    } else {
        limits.max_iterations + 1
    } as f64;
    node
}

/// One sweep: every plane in reach's impulse update from the sweep's starting velocity, then
/// their velocity changes applied together; returns the largest violation.
fn sweep(
    dt: f64,
    planes: &[PlaneData],
    gap: &[f64],
    mask: u32,
    inv: [f64; 3],
    compliance: f64,
    node: &mut NodeSweeps,
) -> f64 {
    let mut violation = 0.0f64;
    let mut dv = [0.0f64; 3];
    let in_reach = |&(p, _): &(usize, &PlaneData)| mask & (1 << p) != 0;
    for (p, plane) in planes.iter().enumerate().filter(in_reach) {
        let nrm = plane.normal;
        // a normal that meets only prescribed dofs cannot be enforced
        if (0..3).map(|ax| nrm[ax] * nrm[ax] * inv[ax]).sum::<f64>() <= 0.0 {
            continue;
        }
        let up = impulse_update(
            gap[p], dt, node.vel, nrm, compliance, &plane.law, node.jn[p], node.jt[p],
        );
        violation = violation.max(up.violation);
        (node.jn[p], node.jt[p]) = (up.jn, up.jt);
        for ax in 0..3 {
            dv[ax] += up.dj[ax] * inv[ax];
        }
    }
    for ax in 0..3 {
        node.vel[ax] += dv[ax];
    }
    violation
}

/// Writes the node's results, [`SLOT`] floats per plane, into `r`: zeros and no gap for the
/// planes it is not secondary to (`own`); the impulses, whether it is active and sliding,
/// the linearised end-of-step gap, the friction work and impact loss added and the sweeps
/// for the others.
fn report(
    dt: f64,
    planes: &[PlaneData],
    own: u32,
    gap: &[f64],
    before: [f64; 3],
    node: &NodeSweeps,
    r: &mut [f64],
) {
    let vel = node.vel;
    for (p, (plane, r)) in planes.iter().zip(r.chunks_exact_mut(SLOT)).enumerate() {
        if own & (1 << p) == 0 {
            r.fill(0.0);
            r[slot::GAP] = f64::NEG_INFINITY;
            continue;
        }
        let (nrm, law, jn, jt) = (plane.normal, plane.law, node.jn[p], node.jt[p]);
        let rn = dot(vel, nrm);
        r[slot::NORMAL_IMPULSE] = jn;
        r[slot::FRICTION_IMPULSE..slot::FRICTION_IMPULSE + 3].copy_from_slice(&jt);
        r[slot::ACTIVE] = f64::from(u8::from(jn > 0.0));
        let sliding = law.is_sliding(jt, jn, 1e-6);
        r[slot::SLIDING] = f64::from(u8::from(sliding));
        r[slot::GAP] = gap[p] - dt * rn;
        let (impact, friction) = impulse_energy((jn, jt), nrm, (before, vel));
        r[slot::IMPACT_LOSS] -= impact;
        if law.is_frictional() {
            r[slot::FRICTION_WORK] -= friction;
        }
        r[slot::SWEEPS] = node.reported;
        let j: [f64; 3] = std::array::from_fn(|ax| jn * nrm[ax] + jt[ax]);
        r[slot::IMPULSE..slot::IMPULSE + 3].copy_from_slice(&j);
    }
}
