//! The `[[equation]]`s on the free equations of a static step or an implicit dynamic one:
//! each dependent dof's free equation is replaced by the independent ones it follows
//! ($u = T q$), so the matrix solved is $T^T A T$ with a unit diagonal on the dependent
//! equations, the residual $T^T r$, and the dependent dofs are set from the others after
//! each solve.

use crate::linalg::Csc;
use crate::model::equations::Equation;

pub(crate) struct Constraints {
    equations: Vec<Equation>,
    /// The dependent equations, each with the free equations it follows and their factors.
    on_equations: Vec<(u32, Vec<(u32, f64)>)>,
    /// For each free equation, its place in `on_equations` (`u32::MAX` for an independent).
    slot: Vec<u32>,
}

impl Constraints {
    /// The equations on the free equations `equation` numbers (dofs a fix holds leave the
    /// matrix: their terms only move the dependent dof).
    pub fn new(equations: &[Equation], equation: &[u32], free: usize) -> Self {
        let mut slot = vec![u32::MAX; free];
        let mut on_equations = Vec::with_capacity(equations.len());
        for e in equations {
            let d = equation[e.dependent as usize];
            let terms = (e.terms.iter())
                .filter(|t| equation[t.0 as usize] != u32::MAX)
                .map(|&(dof, c)| (equation[dof as usize], c))
                .collect();
            slot[d as usize] = on_equations.len() as u32;
            on_equations.push((d, terms));
        }
        Constraints {
            equations: equations.to_vec(),
            on_equations,
            slot,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.equations.is_empty()
    }

    /// Sets every dependent dof of `u` (all dofs) from the dofs it follows.
    pub fn apply(&self, u: &mut [f64]) {
        for e in &self.equations {
            u[e.dependent as usize] = e.terms.iter().map(|&(d, c)| c * u[d as usize]).sum();
        }
    }

    /// The equations and factors free equation `r` stands for.
    fn expand(&self, r: u32) -> Vec<(u32, f64)> {
        match self.slot[r as usize] {
            u32::MAX => vec![(r, 1.0)],
            k => self.on_equations[k as usize].1.clone(),
        }
    }

    /// $T^T A T$ of the triplets, with a unit diagonal on the dependent equations.
    pub fn condense(&self, t: Vec<(u32, u32, f64)>) -> Vec<(u32, u32, f64)> {
        if self.is_empty() {
            return t;
        }
        let mut out = Vec::with_capacity(t.len());
        for (r, c, v) in t {
            match (self.slot[r as usize], self.slot[c as usize]) {
                (u32::MAX, u32::MAX) => out.push((r, c, v)),
                _ => {
                    for (r2, a) in self.expand(r) {
                        for (c2, b) in self.expand(c) {
                            out.push((r2, c2, a * b * v));
                        }
                    }
                }
            }
        }
        out.extend(self.on_equations.iter().map(|(d, _)| (*d, *d, 1.0)));
        out
    }

    /// $T^T A T$ of a matrix on the free equations.
    pub fn condense_matrix(&self, a: &Csc) -> Csc {
        let mut t = Vec::with_capacity(a.nnz());
        for j in 0..a.n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                t.push((a.row_idx[p] as u32, j as u32, a.values[p]));
            }
        }
        Csc::from_triplets(a.n, self.condense(t))
    }

    /// $T^T r$ on the free equations: each dependent equation's residual moved to the
    /// equations it follows.
    pub fn condense_residual(&self, r: &mut [f64]) {
        for (d, terms) in &self.on_equations {
            let rd = std::mem::take(&mut r[*d as usize]);
            for &(j, c) in terms {
                r[j as usize] += c * rd;
            }
        }
    }
}
