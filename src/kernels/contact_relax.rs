//! One sweep of the staged device contact iteration in one dispatch (CPU twin of
//! `shaders/contact_relax.wgsl`), for an iteration with no rigid body ranges: recorded sweep
//! d carries the contact nodes' velocities past sweep d - 1 (its [`node_change`]s) and runs
//! sweep d at them ([`contact_sweep`]); the settle after R recorded sweeps leaves the
//! velocities and the phase where [`super::contact_apply`] and [`sweep_control`] would have.
//!
//! [`sweep_control`]: super::sweep_control

use super::contact_apply::node_change;
use super::contact_constraints::Constraint;
use super::contact_finish::SweepInputs;
use super::contact_sweep::contact_sweep;
use super::sweep_control::{phase_after, SweepState, SWEEPING};

/// What the recorded sweeps carry from one to the next.
#[derive(Debug, Clone)]
pub struct Relaxation {
    /// The iteration's state: `sweeps` counts the sweeps that ran; the phase is the start's
    /// until the settle.
    pub state: SweepState,
    /// Sweep k's largest violation at k % 3.
    pub ring: [f64; 3],
    /// The impulse changes of sweep k in half k % 2 (3 per pair a half).
    pub dj: Vec<f64>,
    /// The contact nodes' velocities before sweep k in slot k % 2 (3 per contact node a
    /// slot); before sweep 1, the warm start's in slot 1.
    pub carried: Vec<f64>,
}

/// Which launch of `contact_relax`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Relax {
    /// Recorded sweep d (from 1).
    Sweep(u32),
    /// The settle after R recorded sweeps.
    Settle(u32),
}

/// Runs one launch on `r`, the constraints' impulses and the model's velocity `v` (written
/// at the contact nodes by the settle alone).
pub fn contact_relax(
    launch: Relax,
    s: &SweepInputs,
    r: &mut Relaxation,
    constraints: &mut [Constraint],
    v: &mut [f64],
) {
    match launch {
        Relax::Sweep(d) => sweep(d, s, r, constraints, v),
        Relax::Settle(recorded) => settle(recorded + 1, s, r, constraints, v),
    }
}

/// Contact node i's velocity in `carried` slot `slot` (of `nc` contact nodes).
fn carried_at(r: &Relaxation, nc: usize, slot: usize, i: usize) -> [f64; 3] {
    let o = 3 * (slot * nc + i);
    [r.carried[o], r.carried[o + 1], r.carried[o + 2]]
}

/// Contact node i's velocity before sweep d.
fn before_sweep(d: u32, i: usize, s: &SweepInputs, r: &Relaxation, c: &[Constraint]) -> [f64; 3] {
    let nc = s.nodes.len();
    if d == 1 {
        return carried_at(r, nc, 1, i);
    }
    let half = (d as usize - 1) % 2;
    let np = c.len();
    let dj = &r.dj[3 * np * half..3 * np * (half + 1)];
    let dv = node_change(&s.nodes[i], s.links, c, (s.starts, s.sorted), dj, s.lumped);
    let v = carried_at(r, nc, half, i);
    [0, 1, 2].map(|a| v[a] + dv[a])
}

fn phase(s: &SweepInputs, r: &Relaxation, sweeps: u32) -> u32 {
    phase_after(
        sweeps,
        r.ring[sweeps as usize % 3],
        s.tolerance,
        s.max_iterations,
    )
}

fn sweep(d: u32, s: &SweepInputs, r: &mut Relaxation, c: &mut [Constraint], v: &[f64]) {
    let last = r.state.sweeps;
    let carries = d >= 2 && last >= d - 1;
    let sweeping = match d {
        1 => r.state.phase == SWEEPING,
        _ => carries && phase(s, r, d - 1) == SWEEPING,
    };
    let nc = s.nodes.len();
    let before: Vec<[f64; 3]> = (0..nc).map(|i| before_sweep(d, i, s, r, c)).collect();
    if carries {
        let slot = d as usize % 2;
        for (i, b) in before.iter().enumerate() {
            let o = 3 * (slot * nc + i);
            r.carried[o..o + 3].copy_from_slice(b);
        }
    }
    if !sweeping {
        return;
    }
    r.ring[(d as usize + 1) % 3] = 0.0;
    r.state.sweeps = d;
    // the sweep reads the contact nodes' velocities alone
    let mut at = v.to_vec();
    for (cn, b) in s.nodes.iter().zip(&before) {
        let n = cn.node as usize;
        at[3 * n..3 * n + 3].copy_from_slice(b);
    }
    let np = c.len();
    let half = d as usize % 2;
    let dj = &mut r.dj[3 * np * half..3 * np * (half + 1)];
    let violation = contact_sweep(s.dt, c, s.pairs, &at, dj);
    let k = d as usize % 3;
    r.ring[k] = r.ring[k].max(violation);
}

fn settle(d: u32, s: &SweepInputs, r: &mut Relaxation, c: &[Constraint], v: &mut [f64]) {
    let last = r.state.sweeps;
    if last == 0 {
        return;
    }
    let nc = s.nodes.len();
    for (i, cn) in s.nodes.iter().enumerate() {
        let b = match last == d - 1 {
            true => before_sweep(d, i, s, r, c),
            false => carried_at(r, nc, (last as usize + 1) % 2, i),
        };
        let n = cn.node as usize;
        v[3 * n..3 * n + 3].copy_from_slice(&b);
    }
    r.state.phase = phase(s, r, last);
}
