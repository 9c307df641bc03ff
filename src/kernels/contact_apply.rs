//! The velocity change of one sweep of the device contact iteration (CPU twin of
//! `shaders/contact_apply.wgsl`): each contact node gathers the impulse changes of the pairs
//! it is the secondary node of, minus $N_k$ times those of the pairs on each primary face
//! whose corner k it is, and minus the gathered impulse change of each rigid body range it
//! carries ([`super::body_gather`], after the pairs' own in `dj`), times its inverse mass. (The kernel's first invocation also applies
//! the iteration's stopping rule after the sweep, whose twin is
//! [`super::sweep_control`].)

use super::contact_constraints::Constraint;
use super::contact_touches::ContactNode;
use super::explicit_correct::LumpedNode;

#[allow(clippy::too_many_arguments)]
pub fn contact_apply(
    nodes: &[ContactNode],
    links: &[u32],
    constraints: &[Constraint],
    starts: &[u32],
    sorted: &[u32],
    dj: &[f64],
    lumped: &[LumpedNode],
    v: &mut [f64],
) {
    for cn in nodes {
        let dv = node_change(cn, links, constraints, (starts, sorted), dj, lumped);
        let n = cn.node as usize;
        for a in 0..3 {
            v[3 * n + a] += dv[a];
        }
    }
}

/// Contact node `cn`'s velocity change from the impulse changes `dj` (3 per pair, then per
/// rigid body range), the pairs bucketed by face in (`starts`, `sorted`).
pub fn node_change(
    cn: &ContactNode,
    links: &[u32],
    constraints: &[Constraint],
    (starts, sorted): (&[u32], &[u32]),
    dj: &[f64],
    lumped: &[LumpedNode],
) -> [f64; 3] {
    let mut delta = [0.0f64; 3];
    for &p in &links[cn.pair_first as usize..cn.pair_end as usize] {
        for a in 0..3 {
            delta[a] += dj[3 * p as usize + a];
        }
    }
    for &l in &links[cn.face_first as usize..cn.face_end as usize] {
        let (f, k) = ((l / 4) as usize, (l % 4) as usize);
        for &q in &sorted[starts[f] as usize..starts[f + 1] as usize] {
            let w = constraints[q as usize].weights[k];
            for a in 0..3 {
                delta[a] -= w * dj[3 * q as usize + a];
            }
        }
    }
    for &r in &links[cn.body_first as usize..cn.body_end as usize] {
        let o = 3 * (constraints.len() + r as usize);
        for a in 0..3 {
            delta[a] -= dj[o + a];
        }
    }
    let n = cn.node as usize;
    [0, 1, 2].map(|a| delta[a] * lumped[n].inv_mass[a])
}
