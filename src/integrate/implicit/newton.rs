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
    let diagonal: Vec<f64> = (gathers.iter())
        .map(|g| coupling(g, g, flex, alpha, asm))
        .collect();
    // the active set of the Jacobi trial lambda + m / W_ii (W_ii > 0 for a node that moves)
    let active: Vec<bool> = (0..rows.len())
        .map(|r| {
            let w = diagonal[r] * area[r];
            match w > 0.0 {
                true => lambda[r] + measure[r] / w > 0.0,
                false => lambda[r] > 0.0,
            }
        })
        .collect();
    let a: Vec<usize> = (0..rows.len()).filter(|&r| active[r]).collect();
    let mut s = DMatrix::<f64>::zeros(a.len(), a.len());
    let mut rhs = DVector::<f64>::zeros(a.len());
    for (x, &r) in a.iter().enumerate() {
        s[(x, x)] = diagonal[r];
        for (y, &c) in a.iter().enumerate().skip(x + 1) {
            let v = coupling(&gathers[r], &gathers[c], flex, alpha, asm);
            s[(x, y)] = v;
            s[(y, x)] = v;
        }
        rhs[x] = measure[r] - coupling(&gathers[r], &lag, flex, alpha, asm);
        for c in 0..rows.len() {
            if !active[c] && lambda[c] != 0.0 {
                let w = coupling(&gathers[r], &gathers[c], flex, alpha, asm) * area[c];
                rhs[x] += w * lambda[c];
            }
        }
    }
    // S y = rhs with y_j = A_j delta_j (W = S A)
    let mut y = rhs.clone();
    if !dense::spd_solve_in_place(s.clone().as_mut_slice(), y.as_mut_slice()) {
        y = s.lu().solve(&rhs)?;
    }
    if y.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mut next = vec![0.0; rows.len()];
    for (x, &r) in a.iter().enumerate() {
        next[r] = (lambda[r] + y[x] / area[r]).max(0.0);
    }
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
        if map_changed {
            self.last = f64::INFINITY;
        }
        self.rises = if residual >= self.last {
            self.rises + 1
        } else {
            0
        };
        self.last = self.last.min(residual);
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
