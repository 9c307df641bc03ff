//! Anderson acceleration of the multiplier iteration.
//!
//! The augmented Lagrange update is a fixed-point map $x \mapsto G(x)$ on the multipliers
//! (normal pressures and tangential tractions): one linear solve and one projected update per
//! evaluation. Its contraction is $|1 - \epsilon s|$ in each mode of the contact compliance,
//! so when the compliances of a contact patch spread (a stiff body on many contact nodes: the
//! rigid modes are compliant, the deformation modes are not) no single eps makes every mode
//! fast, and the plain iteration creeps at a ratio near 1.
//!
//! Anderson's method (type II, Walker & Ni 2011) keeps the last few pairs
//! $(x_j, G(x_j))$ and takes $x_{k+1} = G(x_k) - \Delta G\,\gamma$, with $\gamma$ the least
//! squares fit $\min_\gamma |f_k - \Delta F\,\gamma|_w$ of the residuals $f = G(x) - x$ in the
//! area-weighted norm of the convergence test. On a linear map it is a Krylov method (GMRES
//! in exact arithmetic), so the creeping modes are removed together. The caller projects the
//! result back onto the admissible set (pressures >= 0, tractions inside the cone).
//!
//! Safeguards: the history is cleared whenever the map changes (the penalty was adapted, the
//! candidate set grew) and whenever the residual grows, which then falls back to the plain
//! step $x_{k+1} = G(x_k)$.

use std::collections::VecDeque;

use nalgebra::{DMatrix, DVector};

/// Pairs kept in the history.
pub(crate) const DEPTH: usize = 5;

#[derive(Debug, Clone, Default)]
pub struct Anderson {
    /// (G(x_j), f_j) of the last iterates, oldest first, already weighted.
    history: VecDeque<(Vec<f64>, Vec<f64>)>,
    last_residual: f64,
}

impl Anderson {
    /// Forgets the history (the fixed-point map has changed).
    pub fn reset(&mut self) {
        self.history.clear();
        self.last_residual = f64::INFINITY;
    }

    /// Next iterate from x and G(x) (weights w, each > 0) into `out`; returns whether it was
    /// accelerated (false: `out` = G(x)).
    pub fn step(&mut self, x: &[f64], g: &[f64], w: &[f64], out: &mut [f64]) -> bool {
        let n = x.len();
        let gw: Vec<f64> = (0..n).map(|i| g[i] * w[i]).collect();
        let fw: Vec<f64> = (0..n).map(|i| (g[i] - x[i]) * w[i]).collect();
        let norm = fw.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm > self.last_residual && !self.history.is_empty() {
            self.history.clear();
        }
        self.last_residual = norm;
        self.history.push_back((gw, fw));
        if self.history.len() > DEPTH + 1 {
            self.history.pop_front();
        }
        out.copy_from_slice(g);
        let m = self.history.len() - 1;
        if m == 0 {
            return false;
        }
        // differences of successive residuals and maps
        let (gk, fk) = self.history.back().expect("non-empty");
        let mut df = DMatrix::<f64>::zeros(n, m);
        let mut dg = DMatrix::<f64>::zeros(n, m);
        for j in 0..m {
            let (g0, f0) = &self.history[j];
            let (g1, f1) = &self.history[j + 1];
            for i in 0..n {
                df[(i, j)] = f1[i] - f0[i];
                dg[(i, j)] = g1[i] - g0[i];
            }
        }
        let fk = DVector::from_column_slice(fk);
        // least squares by the normal equations, lightly regularised
        let mut a = df.transpose() * &df;
        let trace = (0..m).map(|j| a[(j, j)]).sum::<f64>();
        if !(trace > 0.0 && trace.is_finite()) {
            return false;
        }
        for j in 0..m {
            a[(j, j)] += 1e-12 * trace;
        }
        let b = df.transpose() * &fk;
        let Some(gamma) = a.cholesky().map(|c| c.solve(&b)) else {
            return false;
        };
        if !gamma.iter().all(|v| v.is_finite()) {
            return false;
        }
        let step = &dg * gamma;
        for i in 0..n {
            out[i] = (gk[i] - step[i]) / w[i];
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear contraction with spread rates: x -> x + (b - A x) with eigenvalues of A in
    /// (0.001, 1]; plain iteration needs thousands of steps, Anderson a handful.
    #[test]
    fn anderson_solves_an_ill_conditioned_linear_fixed_point() {
        let rates = [1.0, 0.3, 0.05, 0.01, 0.001];
        let b = [1.0, -2.0, 0.5, 3.0, -1.0];
        let exact: Vec<f64> = (0..5).map(|i| b[i] / rates[i]).collect();
        let w = [1.0; 5];
        let g = |x: &[f64]| -> Vec<f64> { (0..5).map(|i| x[i] + b[i] - rates[i] * x[i]).collect() };
        let mut aa = Anderson::default();
        aa.reset();
        let mut x = vec![0.0; 5];
        let mut iters = 0;
        while iters < 50 {
            let gx = g(&x);
            let res: f64 = (0..5).map(|i| (gx[i] - x[i]).powi(2)).sum::<f64>().sqrt();
            if res < 1e-10 {
                break;
            }
            let mut out = vec![0.0; 5];
            aa.step(&x, &gx, &w, &mut out);
            x = out;
            iters += 1;
        }
        for i in 0..5 {
            assert!(
                (x[i] - exact[i]).abs() < 1e-6 * exact[i].abs(),
                "{x:?} vs {exact:?}"
            );
        }
        assert!(iters <= 12, "{iters} iterations");
    }
}
