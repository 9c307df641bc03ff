//! One projected Jacobi sweep of the device contact iteration (CPU twin of
//! `shaders/contact_sweep.wgsl`), the host path's sweep (`integrate::explicit`): from the
//! relative velocity at the sweep's start, $J_N \leftarrow \max(J_N + r / \tilde C, 0)$ with
//! the residual $r = g_n / \Delta t - \dot{\bar g}$, and with friction the tangential impulse
//! that stops the slip, returned onto the cone $|J_T| \le \mu J_N$.

use super::contact_constraints::{relative, Constraint, ContactPair};
use crate::contact::quad::{dot, norm};

/// Updates the impulses, writes each pair's impulse change into `dj` (3 per pair, zero for
/// a pair out of reach or not enforceable) and returns the sweep's largest violation.
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
            let rel = relative(c, pair.node, v);
            let rn = dot(rel, c.normal);
            let r = c.gap / dt - rn;
            let new_n = (c.jn + r / c.compliance).max(0.0);
            violation = violation.max(if new_n > 0.0 { r.abs() } else { r.max(0.0) });
            d = c.normal.map(|x| (new_n - c.jn) * x);
            c.jn = new_n;
            if pair.mu > 0.0 {
                let slip: [f64; 3] = std::array::from_fn(|a| rel[a] - rn * c.normal[a]);
                let trial: [f64; 3] = std::array::from_fn(|a| c.jt[a] - slip[a] / c.compliance);
                let radius = pair.mu * new_n;
                let size = norm(trial);
                let next = if size > radius {
                    trial.map(|x| x * radius / size)
                } else {
                    if new_n > 0.0 {
                        violation = violation.max(norm(slip));
                    }
                    trial
                };
                for a in 0..3 {
                    d[a] += next[a] - c.jt[a];
                }
                c.jt = next;
            }
        }
        dj[3 * p..3 * p + 3].copy_from_slice(&d);
    }
    violation
}
