//! The split compliance of each in-reach constraint (CPU twin of
//! `shaders/contact_compliance.wgsl`): the host path's row-sum (Gershgorin) bound,
//! $\sum_{node} |w_{node}|\, t_{node} \max_a M^{-1}_{node,a}$ (t from
//! [`super::contact_touches`]), or zero where the normal meets only prescribed dofs (its
//! warm start's impulses are then zeroed). Each pair's impulse change `dj` becomes its warm
//! start's impulse, which [`super::contact_warm`] applies. (The kernel's first invocation
//! also starts the iteration: [`super::sweep_control`].)

use super::contact_constraints::{Constraint, ContactPair};
use super::contact_gap::NO_FACE;
use super::explicit_correct::LumpedNode;

pub fn contact_compliance(
    constraints: &mut [Constraint],
    pairs: &[ContactPair],
    touches: &[f64],
    lumped: &[LumpedNode],
    dj: &mut [f64],
) {
    let along = |n: u32, nrm: [f64; 3]| -> f64 {
        let inv = lumped[n as usize].inv_mass;
        (0..3).map(|a| nrm[a] * nrm[a] * inv[a]).sum()
    };
    let inv_max = |n: u32| lumped[n as usize].inv_mass.into_iter().fold(0.0, f64::max);
    for (p, (c, pair)) in constraints.iter_mut().zip(pairs).enumerate() {
        dj[3 * p..3 * p + 3].fill(0.0);
        if !c.in_reach {
            continue;
        }
        let s = pair.node;
        let mut a = along(s, c.normal);
        let mut bound = touches[s as usize] * inv_max(s);
        if c.face[0] != NO_FACE {
            for k in 0..4 {
                let m = c.face[k];
                let w = c.weights[k].abs();
                a += w * along(m, c.normal);
                bound += w * touches[m as usize] * inv_max(m);
            }
        }
        if a > 0.0 {
            c.compliance = bound;
            for ax in 0..3 {
                dj[3 * p + ax] = c.jn * c.normal[ax] + c.jt[ax];
            }
        } else {
            (c.compliance, c.jn, c.jt) = (0.0, 0.0, [0.0; 3]);
        }
    }
}
