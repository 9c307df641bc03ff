//! Sparse Cholesky of symmetric positive definite matrices on faer: symbolic analysis once,
//! numeric factorisation when the values change, otherwise solves only.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::{MatMut, Side};

use super::Csc;
use crate::error::{ImpactError, Result};

/// The tasks faer splits its factorisations and solves into. faer sizes its parallel work by
/// the task count it is given, not by the threads that run it: a fixed count makes the
/// factor the same on 1 thread or 64 (on fewer threads the tasks queue), where faer's
/// default, the pool's thread count, would make the rounding follow the machine.
pub const FAER_TASKS: usize = 8;

/// Sets faer's parallelism to [`FAER_TASKS`] tasks on the current rayon pool.
fn fixed_parallelism() {
    faer::set_global_parallelism(faer::Par::rayon(FAER_TASKS));
}

pub struct SpdSolver {
    symbolic: SymbolicLlt<usize>,
    llt: Llt<usize, f64>,
    pattern: SymbolicSparseColMat<usize>,
    /// How many numeric factorisations were made.
    pub factorizations: usize,
}

impl SpdSolver {
    /// Analyses the pattern and factorises.
    pub fn new(a: &Csc) -> Result<SpdSolver> {
        fixed_parallelism();
        let pattern =
            SymbolicSparseColMat::new_checked(a.n, a.n, a.col_ptr.clone(), None, a.row_idx.clone());
        let symbolic = SymbolicLlt::try_new(pattern.as_ref(), Side::Upper)
            .map_err(|e| ImpactError::Solver(format!("symbolic analysis failed: {e:?}")))?;
        let mat = SparseColMat::new(pattern.clone(), a.values.clone());
        let llt = Llt::try_new_with_symbolic(symbolic.clone(), mat.as_ref(), Side::Upper)
            .map_err(|e| ImpactError::Solver(format!("the effective matrix is not positive definite ({e:?}): is every body held or free to move with positive mass?")))?;
        Ok(SpdSolver {
            symbolic,
            llt,
            pattern,
            factorizations: 1,
        })
    }

    /// A factorisation of another matrix with the same pattern (the effective matrix of another
    /// step size), reusing this one's symbolic analysis.
    pub fn sibling(&self, a: &Csc) -> Result<SpdSolver> {
        if a.n != self.pattern.nrows()
            || a.col_ptr != self.pattern.col_ptr()
            || a.row_idx != self.pattern.row_idx()
        {
            return Err(ImpactError::Solver(
                "sibling factorisation: the matrix has another sparsity pattern".into(),
            ));
        }
        let mat = SparseColMat::new(self.pattern.clone(), a.values.clone());
        let llt = Llt::try_new_with_symbolic(self.symbolic.clone(), mat.as_ref(), Side::Upper)
            .map_err(|e| ImpactError::Solver(format!("factorisation failed: {e:?}")))?;
        Ok(SpdSolver {
            symbolic: self.symbolic.clone(),
            llt,
            pattern: self.pattern.clone(),
            factorizations: 1,
        })
    }

    /// Numeric refactorisation with new values on the same pattern.
    pub fn refactor(&mut self, values: &[f64]) -> Result<()> {
        let mat = SparseColMat::new(self.pattern.clone(), values.to_vec());
        self.llt = Llt::try_new_with_symbolic(self.symbolic.clone(), mat.as_ref(), Side::Upper)
            .map_err(|e| ImpactError::Solver(format!("refactorisation failed: {e:?}")))?;
        self.factorizations += 1;
        Ok(())
    }

    /// Solves A x = b in place.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let n = b.len();
        let mat = MatMut::from_column_major_slice_mut(b, n, 1);
        self.llt.solve_in_place(mat);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_small_spd_system() {
        // tridiagonal 2 -1 with a duplicate entry summed on the diagonal
        let n = 5;
        let mut t = Vec::new();
        for i in 0..n as u32 {
            t.push((i, i, 1.0));
            t.push((i, i, 1.0));
            if i + 1 < n as u32 {
                t.push((i, i + 1, -1.0));
                t.push((i + 1, i, -1.0));
            }
        }
        let a = Csc::from_triplets(n, t);
        let s = SpdSolver::new(&a).unwrap();
        let x: Vec<f64> = (0..n).map(|i| i as f64 - 1.5).collect();
        let mut b = vec![0.0; n];
        a.mul_into(&x, &mut b);
        s.solve_in_place(&mut b);
        for i in 0..n {
            assert!((b[i] - x[i]).abs() < 1e-12);
        }
    }

    /// A sibling factorisation (another step size: another diagonal shift on the same
    /// pattern) solves its own matrix, and refuses a matrix with another pattern.
    #[test]
    fn a_sibling_solves_its_own_matrix_on_the_shared_pattern() {
        let tridiagonal = |n: usize, diag: f64| {
            let mut t = Vec::new();
            for i in 0..n as u32 {
                t.push((i, i, diag));
                if i + 1 < n as u32 {
                    t.push((i, i + 1, -1.0));
                    t.push((i + 1, i, -1.0));
                }
            }
            Csc::from_triplets(n, t)
        };
        let n = 7;
        let first = SpdSolver::new(&tridiagonal(n, 2.5)).unwrap();
        let shifted = tridiagonal(n, 40.0);
        let second = first.sibling(&shifted).unwrap();
        let x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut b = vec![0.0; n];
        shifted.mul_into(&x, &mut b);
        second.solve_in_place(&mut b);
        for i in 0..n {
            assert!((b[i] - x[i]).abs() < 1e-13, "{} vs {}", b[i], x[i]);
        }
        assert!(first.sibling(&tridiagonal(n + 1, 40.0)).is_err());
    }
}
