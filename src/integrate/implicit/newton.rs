//! The semi-smooth Newton step of the contact iteration (`implicit.acceleration = "newton"`).
//!
//! With the geometry of the current iterate held (normals, closest faces and points), the
//! measure of every candidate is affine in the pressures: $m(\lambda + \Delta) = m(\lambda) -
//! W \Delta$ with $W_{ij} = A_j\, g_i^T (\alpha_K K_{eff}^{-1} + \alpha_M M^{-1})\, g_j$, where
//! $g_i$ gathers node i's relative velocity along its normal (+n on the secondary node,
//! $-N_k n$ on its primary face's nodes, -n on a rigid body's node) and $A_j$ is node j's
//! area; $\alpha_K = \gamma w_f/(\beta \Delta t)$ and $\alpha_M = \Delta t (1 - \gamma/(2\beta))$
//! for the gap rate (0 for the classical gap, whose measure is scaled alike). The augmented
//! Lagrange update $\lambda \leftarrow \langle \lambda + \epsilon m \rangle$ has the same
//! solution as its fixed point. The active set of the Jacobi trial, $\mathcal A = \{i :
//! \lambda_i + m_i / W_{ii} > 0\}$ (the primal-dual active set method of Hintermüller, Ito &
//! Kunisch 2002, weighted by W's diagonal, so that the penalty's scale does not decide
//! membership), gives the Newton step
//!
//! $\lambda_{\mathcal A} \leftarrow \lambda_{\mathcal A} + W_{\mathcal A\mathcal A}^{-1}
//! (m_{\mathcal A} + W_{\mathcal A \mathcal I} \lambda_{\mathcal I} - B d)$, $\lambda_{\mathcal
//! I} \leftarrow 0$, then clipped at zero, where $B d$ is the measures' response to the
//! forces the last solve did not see (`lag` of [`newton_update`]).
//!
//! $K_{eff}^{-1}$ on the nodes comes from the run's [`super::flexibility::Flexibility`]; the
//! consistent mass's inverse is taken as the lumped one (W only steers the step: each
//! iteration's measures still come from the full solve, so the iteration converges to the
//! same multipliers, and the step is exact in the common trapezoidal rule, where
//! $\alpha_M = 0$).

use nalgebra::{DMatrix, DVector};

use crate::geometry::face;
use crate::kernels::contact_gap::NO_FACE;
use crate::linalg::{dense, Assembled};
use crate::model::{Model, Primary};

use super::flexibility::Flexibility;
use super::interface::InterfaceState;

/// The most nodes a candidate's gather touches: its own and a quadrilateral face's four.
const TERMS: usize = 5;

/// One candidate: its interface and node, and its gather $g_i$ as (node, coefficient) pairs.
pub(super) struct Row {
    interface: usize,
    node: usize,
    terms: [(u32, [f64; 3]); TERMS],
    len: usize,
}

impl Row {
    fn push(&mut self, node: u32, c: [f64; 3]) {
        self.terms[self.len] = (node, c);
        self.len += 1;
    }

    fn terms(&self) -> &[(u32, [f64; 3])] {
        &self.terms[..self.len]
    }
}

/// Every candidate's gather, in interface and node order.
pub(super) fn rows(model: &Model, interfaces: &[InterfaceState], faces: &[[u32; 4]]) -> Vec<Row> {
    let mut rows = Vec::new();
    for (k, (itf, st)) in model.interfaces.iter().zip(interfaces).enumerate() {
        for (i, &n) in itf.nodes.iter().enumerate() {
            let p = st.points[i];
            if !st.candidate[i] || p.face == NO_FACE {
                continue;
            }
            let nrm = p.normal;
            let mut row = Row {
                interface: k,
                node: i,
                terms: [(0, [0.0; 3]); TERMS],
                len: 0,
            };
            row.push(n, nrm);
            match &itf.primary {
                Primary::Surface { .. } => {
                    let f = faces[p.face as usize];
                    let w = face::shape(&f, p.xi);
                    for (&m, &wk) in f.iter().zip(&w) {
                        if wk != 0.0 {
                            row.push(m, nrm.map(|x| -wk * x));
                        }
                    }
                }
                Primary::Rigid { node, .. } => row.push(*node, nrm.map(|x| -x)),
                Primary::Plane { .. } => {}
            }
            rows.push(row);
        }
    }
    rows
}

/// The nodes the candidates' gathers touch (the flexibility must hold them).
pub(super) fn touched_nodes(rows: &[Row]) -> Vec<u32> {
    rows.iter()
        .flat_map(|r| r.terms().iter().map(|t| t.0))
        .collect()
}

/// The nodes the candidates are likely to touch next: each secondary node that has a face
/// but is not a candidate, nearest the surface first, and its face's nodes (a rigid body's
/// node), for a flexibility's block solves to fill their free columns with.
pub(super) fn nodes_ahead(
    model: &Model,
    interfaces: &[InterfaceState],
    faces: &[[u32; 4]],
) -> Vec<u32> {
    // (gap, interface, node): the largest gap (the least separated) first
    let mut near: Vec<(f64, usize, usize)> = Vec::new();
    for (k, st) in interfaces.iter().enumerate() {
        for (i, p) in st.points.iter().enumerate() {
            if p.face != NO_FACE && !st.candidate[i] && p.gap.is_finite() {
                near.push((p.gap, k, i));
            }
        }
    }
    near.sort_by(|a, b| b.0.total_cmp(&a.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    let mut nodes = Vec::new();
    for (_, k, i) in near {
        let itf = &model.interfaces[k];
        nodes.push(itf.nodes[i]);
        match &itf.primary {
            Primary::Surface { .. } => {
                let face = faces[interfaces[k].points[i].face as usize];
                nodes.extend(face);
            }
            Primary::Rigid { node, .. } => nodes.push(*node),
            Primary::Plane { .. } => {}
        }
    }
    nodes
}

/// (node, coefficient) terms with each node's place in the flexibility; `None` where it
/// lacks one.
fn placed(terms: &[(u32, [f64; 3])], flex: &Flexibility) -> Option<Vec<(u32, usize, [f64; 3])>> {
    (terms.iter())
        .map(|&(n, c)| flex.slot(n).map(|p| (n, p, c)))
        .collect()
}

/// $g_r^T (\alpha_K H + \alpha_M M^{-1}) g_s$ of two placed gathers.
fn coupling(
    r: &[(u32, usize, [f64; 3])],
    s: &[(u32, usize, [f64; 3])],
    flex: &Flexibility,
    (alpha_k, alpha_m): (f64, f64),
    asm: &Assembled,
) -> f64 {
    let mut sum = 0.0;
    for &(p, sp, cp) in r {
        for &(q, sq, cq) in s {
            for (a, ca) in cp.iter().enumerate() {
                for (b, cb) in cq.iter().enumerate() {
                    sum += alpha_k * ca * flex.entry((sp, a), (sq, b)) * cb;
                }
            }
            if p == q && alpha_m != 0.0 {
                for a in 0..3 {
                    if asm.equation[3 * p as usize + a] != u32::MAX {
                        sum += alpha_m * cp[a] * cq[a] / asm.nodal_mass[p as usize];
                    }
                }
            }
        }
    }
    sum
}

/// The Newton step of the candidates' pressures (module docs), from the measures the last
/// update left. Returns its relative size (area-weighted, as the update's change); `None`
/// (nothing changed) where its matrix is singular. With `keep_below = Some(tol)`, a step
/// of relative size at most tol is not taken (the iteration has converged). `lag` is the change of
/// the nodal contact forces that the last solve did not see: the current pressures on the
/// current geometry less the forces it solved with (the forces take each iteration's
/// normals and points from the one before), whose response the step includes.
pub(super) fn newton_update(
    model: &Model,
    (interfaces, rows): (&mut [InterfaceState], &[Row]),
    lag: &[(u32, [f64; 3])],
    flex: &Flexibility,
    (alpha, asm): ((f64, f64), &Assembled),
    keep_below: Option<f64>,
) -> Option<f64> {
    let lag = placed(lag, flex)?;
    let gathers = (rows.iter())
        .map(|r| placed(r.terms(), flex))
        .collect::<Option<Vec<_>>>()?;
    let lambda: Vec<f64> = (rows.iter())
        .map(|r| interfaces[r.interface].lambda[r.node])
        .collect();
    let measure: Vec<f64> = (rows.iter())
        .map(|r| interfaces[r.interface].measure[r.node])
        .collect();
    let area: Vec<f64> = (rows.iter())
        .map(|r| model.interfaces[r.interface].area[r.node].max(f64::MIN_POSITIVE))
        .collect();
    // S = W A^-1 on every candidate (symmetric), and the measures less the lag's response
    let n = rows.len();
    let mut s = DMatrix::<f64>::zeros(n, n);
    for r in 0..n {
        for c in r..n {
            let v = coupling(&gathers[r], &gathers[c], flex, alpha, asm);
            s[(r, c)] = v;
            s[(c, r)] = v;
        }
    }
    let m0: Vec<f64> = (0..n)
        .map(|r| measure[r] - coupling(&gathers[r], &lag, flex, alpha, asm))
        .collect();
    let next = linear_model_pressures(&s, (&lambda, &m0, &area))?;
    let (mut change, mut scale) = (0.0, 0.0);
    for r in 0..rows.len() {
        change += (area[r] * (next[r] - lambda[r])).powi(2);
        scale += (area[r] * next[r].max(lambda[r])).powi(2);
    }
    let relative = match change > 0.0 {
        true => (change / scale).sqrt(),
        false => 0.0,
    };
    if keep_below.is_some_and(|tol| relative <= tol) {
        return Some(relative);
    }
    for (row, &x) in rows.iter().zip(&next) {
        interfaces[row.interface].lambda[row.node] = x;
    }
    Some(relative)
}

/// The most active sets the Newton step tries on the linear model before it takes the last.
const ACTIVE_SET_ROUNDS: usize = 8;

/// The pressures of the linear model $m(\lambda') = m_0 - S A (\lambda' - \lambda)$ (W = S
/// A) with $\lambda' \ge 0$, $m(\lambda') \le 0$ and $\lambda' m(\lambda') = 0$: the
/// primal-dual active set iteration on it, from the Jacobi trial's set, until the set
/// repeats (at most [`ACTIVE_SET_ROUNDS`] sets, the last then taken), clipped at zero.
/// `None` where S is singular on a set.
fn linear_model_pressures(
    s: &DMatrix<f64>,
    (lambda, m0, area): (&[f64], &[f64], &[f64]),
) -> Option<Vec<f64>> {
    let n = lambda.len();
    // the Jacobi trial lambda + m / W_ii > 0 (W_ii > 0 for a node that moves)
    let trial = |lambda: &[f64], m: &[f64]| -> Vec<bool> {
        (0..n)
            .map(|r| {
                let w = s[(r, r)] * area[r];
                match w > 0.0 {
                    true => lambda[r] + m[r] / w > 0.0,
                    false => lambda[r] > 0.0,
                }
            })
            .collect()
    };
    let mut active = trial(lambda, m0);
    let mut next = lambda.to_vec();
    for _ in 0..ACTIVE_SET_ROUNDS {
        next = active_set_solve(s, (lambda, m0, area), &active)?;
        let again = trial(&next, &model_measures(s, (lambda, m0, area), &next));
        if again == active {
            break;
        }
        active = again;
    }
    for x in &mut next {
        *x = x.max(0.0);
    }
    Some(next)
}

/// The linear model's measures at the pressures `next`: $m_0 - S A (\lambda' - \lambda)$.
fn model_measures(
    s: &DMatrix<f64>,
    (lambda, m0, area): (&[f64], &[f64], &[f64]),
    next: &[f64],
) -> Vec<f64> {
    (0..lambda.len())
        .map(|r| {
            let moved: f64 = (0..lambda.len())
                .map(|c| s[(r, c)] * area[c] * (next[c] - lambda[c]))
                .sum();
            m0[r] - moved
        })
        .collect()
}

/// The pressures that zero the linear model's measures on the `active` candidates, with the
/// others' zero: $S_{AA} y = m_{0,A} + S_{AI} A_I \lambda_I$, $y = A_A (\lambda'_A -
/// \lambda_A)$ (W = S A); `None` where S is singular.
fn active_set_solve(
    s: &DMatrix<f64>,
    (lambda, m0, area): (&[f64], &[f64], &[f64]),
    active: &[bool],
) -> Option<Vec<f64>> {
    let a: Vec<usize> = (0..lambda.len()).filter(|&r| active[r]).collect();
    let s_aa = DMatrix::from_fn(a.len(), a.len(), |x, y| s[(a[x], a[y])]);
    let rhs = DVector::from_fn(a.len(), |x, _| {
        let r = a[x];
        let inactive: f64 = (0..lambda.len())
            .filter(|&c| !active[c] && lambda[c] != 0.0)
            .map(|c| s[(r, c)] * area[c] * lambda[c])
            .sum();
        m0[r] + inactive
    });
    let mut y = rhs.clone();
    if !dense::spd_solve_in_place(s_aa.clone().as_mut_slice(), y.as_mut_slice()) {
        y = s_aa.lu().solve(&rhs)?;
    }
    if y.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mut next = vec![0.0; lambda.len()];
    for (x, &r) in a.iter().enumerate() {
        next[r] = lambda[r] + y[x] / area[r];
    }
    Some(next)
}

/// When a step's iteration takes Newton steps: at most [`NewtonGuard::MAX_STEPS`] of them,
/// and only while they bring the update's residual to a new low within
/// [`NewtonGuard::MAX_RISES`] steps (the low is forgotten when the candidates or a penalty
/// change). After that the step goes on with Anderson's acceleration, started afresh: this
/// catches an active set that cycles, and geometry that moves too far for W.
pub(super) struct NewtonGuard {
    /// Whether the step began with Newton steps, and whether it still takes them.
    began: bool,
    on: bool,
    steps: usize,
    /// Steps since the lowest residual, and that residual.
    rises: usize,
    last: f64,
    /// Set once, when the guard turns Newton off (Anderson then starts afresh).
    left: bool,
}

impl NewtonGuard {
    const MAX_STEPS: usize = 30;
    const MAX_RISES: usize = 3;

    pub(super) fn new(on: bool) -> Self {
        NewtonGuard {
            began: on,
            on,
            steps: 0,
            rises: 0,
            last: f64::INFINITY,
            left: false,
        }
    }

    /// Whether the next update may be a Newton step, given the update's residual now.
    pub(super) fn allows(&mut self, residual: f64, map_changed: bool) -> bool {
        if !self.on {
            return false;
        }
        // a changed map (a candidate admitted, a penalty adapted) makes a new problem: its
        // low starts with the next residual, this one being the old problem's
        (self.rises, self.last) = match map_changed {
            true => (0, f64::INFINITY),
            false if residual >= self.last => (self.rises + 1, self.last),
            false => (0, residual),
        };
        self.steps += 1;
        if self.steps > Self::MAX_STEPS || self.rises >= Self::MAX_RISES {
            self.on = false;
            self.left = true;
            return false;
        }
        true
    }

    /// Leaves Newton for the rest of the step (its step could not be taken).
    pub(super) fn give_up(&mut self) {
        if self.on {
            self.on = false;
            self.left = true;
        }
    }

    /// Whether the step began with Newton steps and left them.
    pub(super) fn was_left(&self) -> bool {
        self.began && !self.on
    }

    /// Whether Newton was just left (once).
    pub(super) fn left(&mut self) -> bool {
        std::mem::take(&mut self.left)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::test_matrices::Lcg;

    /// A compliance like the contact's: nodes on a line, each pressure moving its
    /// neighbours less with distance (the exponential kernel, SPD, scaled by random node
    /// weights on both sides).
    fn compliance(n: usize, rng: &mut Lcg) -> DMatrix<f64> {
        let x: Vec<f64> = (0..n).map(|i| i as f64 + 0.3 * rng.next()).collect();
        let d: Vec<f64> = (0..n).map(|_| 0.5 + rng.next()).collect();
        DMatrix::from_fn(n, n, |r, c| {
            d[r] * d[c] * (-(x[r] - x[c]).abs() / 1.5).exp()
        })
    }

    /// On a linear model the Newton step's pressures solve the complementarity problem:
    /// nonnegative pressures, no node approaching (m <= 0), and m = 0 wherever a node is
    /// pressed; from the Jacobi trial's set the active set iteration finds the set that the
    /// enumeration of every set finds.
    #[test]
    fn the_newton_step_solves_the_linear_models_complementarity_problem() {
        let mut rng = Lcg(11);
        // cases whose solution's set is not the Jacobi trial's
        let mut changed = 0;
        for case in 0..200 {
            let n = 2 + case % 7;
            let s = compliance(n, &mut rng);
            let area: Vec<f64> = (0..n).map(|_| 0.5 + rng.next()).collect();
            let lambda: Vec<f64> = (0..n).map(|_| (rng.next() - 0.4).max(0.0)).collect();
            let m0: Vec<f64> = (0..n).map(|_| 2.0 * rng.next() - 1.0).collect();
            let next = linear_model_pressures(&s, (&lambda, &m0, &area)).expect("SPD");
            let trial = (0..n)
                .any(|r| (lambda[r] + m0[r] / (s[(r, r)] * area[r]) > 0.0) != (next[r] > 0.0));
            changed += usize::from(trial);
            let m = model_measures(&s, (&lambda, &m0, &area), &next);
            let scale = m0.iter().fold(1.0f64, |a, x| a.max(x.abs()));
            for r in 0..n {
                assert!(next[r] >= 0.0);
                assert!(
                    m[r] <= 1e-12 * scale,
                    "case {case}: node {r} approaches, {m:?}"
                );
                if next[r] > 0.0 {
                    assert!(m[r].abs() <= 1e-12 * scale, "case {case}: node {r}");
                }
            }
            // the unique solution (S A is a P-matrix): the one set whose solve satisfies all
            let mut found = 0;
            for bits in 0..(1u32 << n) {
                let set: Vec<bool> = (0..n).map(|r| bits >> r & 1 == 1).collect();
                let Some(p) = active_set_solve(&s, (&lambda, &m0, &area), &set) else {
                    continue;
                };
                let mp = model_measures(&s, (&lambda, &m0, &area), &p);
                if (0..n).all(|r| p[r] >= -1e-12 && mp[r] <= 1e-12 * scale) {
                    found += 1;
                    for r in 0..n {
                        assert!((p[r].max(0.0) - next[r]).abs() <= 1e-9 * (1.0 + p[r].abs()));
                    }
                }
            }
            assert!(found >= 1, "case {case}: some set solves it");
        }
        assert!(
            changed >= 20,
            "{changed} cases needed more than the trial's set"
        );
    }

    /// The guard allows Newton steps while the residual reaches new lows within three, the
    /// low restarting after a changed map: the residual of the iteration that admitted a
    /// candidate belongs to the old candidates, so the new low starts after it.
    #[test]
    fn the_guard_restarts_its_low_after_a_changed_map() {
        let mut g = NewtonGuard::new(true);
        // converging, a candidate admitted at 4e-8, then the new problem's first residuals
        for (r, changed) in [
            (9.9, false),
            (0.23, false),
            (4.9e-5, false),
            (4.3e-8, true),
            (0.93, false),
            (0.10, false),
            (4.2e-5, false),
        ] {
            assert!(g.allows(r, changed), "{r}");
        }
        // three without a new low: left for Anderson's update
        assert!(g.allows(1e-4, false) && g.allows(2e-4, false));
        assert!(!g.allows(3e-4, false));
        assert!(g.was_left());
    }
}
