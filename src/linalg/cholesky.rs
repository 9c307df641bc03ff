//! Sparse Cholesky of symmetric positive definite matrices on faer: a fill-reducing ordering
//! and symbolic analysis once, numeric factorisation when the values change, otherwise
//! solves only. Each factor keeps its own counts and times for the run's summary.

use std::cell::Cell;
use std::sync::Arc;
use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};

use super::contact_space::TrailingSolve;
use super::ordering::{nested_dissection, nested_dissection_last, Ordering, Permutation};
use super::supernodal_solve::SupernodalSolve;
use super::Csc;
use crate::error::{ImpactError, Result};

/// The tasks faer splits its factorisations and solves into. faer sizes its parallel work by
/// the task count it is given, not by the threads that run it: a fixed count makes the
/// factor the same on 1 thread or 64 (on fewer threads the tasks queue), where faer's
/// default, the pool's thread count, would make the rounding follow the machine.
pub const FAER_TASKS: usize = 8;

/// The largest share of the plain factor's values that a solve on the contact space may
/// read ([`SpdSolver::for_contact`]).
pub const MAX_TRAILING_SHARE: f64 = 0.25;
/// The most the contact equations numbered last may grow the factor
/// ([`SpdSolver::for_contact`]).
pub const MAX_FILL_GROWTH: f64 = 2.0;

/// The pattern of `a` as faer takes it.
fn pattern_of(a: &Csc) -> SymbolicSparseColMat<usize> {
    SymbolicSparseColMat::new_checked(a.n, a.n, a.col_ptr.clone(), None, a.row_idx.clone())
}

fn par() -> Par {
    Par::rayon(FAER_TASKS)
}

/// A Cholesky factor of the implicit path: its ordering, size, and what its factorisations
/// and solves cost (the summary's `linear_solver` and `mass_factor`).
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct FactorStats {
    /// The fill-reducing ordering: "nested_dissection" or "amd".
    pub ordering: Ordering,
    pub equations: usize,
    /// Nonzeros of the matrix (full storage).
    pub matrix_nonzeros: usize,
    /// Values the factor stores (supernodal blocks counted whole).
    pub factor_nonzeros: usize,
    /// The ordering and the symbolic analysis.
    pub analysis_seconds: f64,
    pub factorizations: usize,
    pub factorization_seconds: f64,
    /// Triangular solve pairs of the whole model (one per multiplier iteration and step, or
    /// two per step where the iteration solves on the contact space).
    pub solves: usize,
    pub solve_seconds: f64,
    /// The equations numbered last for the contact space (0: none), and the solves on
    /// them alone.
    pub contact_equations: usize,
    pub contact_solves: usize,
    pub contact_solve_seconds: f64,
}

impl FactorStats {
    /// The stats of a factor of `a` analysed in `seconds` with `ordering`, before any
    /// factorisation or solve.
    fn analysed(
        a: &Csc,
        ordering: Ordering,
        symbolic: &SymbolicCholesky<usize>,
        seconds: f64,
    ) -> FactorStats {
        FactorStats {
            ordering,
            equations: a.n,
            matrix_nonzeros: a.nnz(),
            factor_nonzeros: symbolic.len_val(),
            analysis_seconds: seconds,
            ..FactorStats::default()
        }
    }
}

pub struct SpdSolver {
    symbolic: Arc<SymbolicCholesky<usize>>,
    pattern: SymbolicSparseColMat<usize>,
    factor: Vec<f64>,
    /// The tree-parallel solve of a supernodal factor (`None`: faer's solve).
    tree_solve: Option<SupernodalSolve>,
    /// The solve on the equations numbered last ([`SpdSolver::with_last`]).
    contact: Option<TrailingSolve>,
    stats: FactorStats,
    solves: Cell<(usize, f64)>,
    contact_solves: Cell<(usize, f64)>,
}

/// The fill-reducing ordering and symbolic analysis of `a`'s pattern.
pub(super) fn analyse(
    a: &Csc,
    pattern: &SymbolicSparseColMat<usize>,
    ordering: Ordering,
) -> Result<Arc<SymbolicCholesky<usize>>> {
    let failed = |e| ImpactError::Solver(format!("symbolic analysis failed: {e:?}"));
    let symbolic = match ordering {
        Ordering::Amd => factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Upper,
            SymmetricOrdering::Amd,
            Default::default(),
        ),
        Ordering::NestedDissection => return analyse_permuted(pattern, &nested_dissection(a)?),
    };
    symbolic.map(Arc::new).map_err(failed)
}

/// The symbolic analysis of a pattern in the order of `p`.
fn analyse_permuted(
    pattern: &SymbolicSparseColMat<usize>,
    p: &Permutation,
) -> Result<Arc<SymbolicCholesky<usize>>> {
    let perm = PermRef::new_checked(&p.forward, &p.inverse, pattern.nrows());
    factorize_symbolic_cholesky(
        pattern.as_ref(),
        Side::Upper,
        SymmetricOrdering::Custom(perm),
        Default::default(),
    )
    .map(Arc::new)
    .map_err(|e| ImpactError::Solver(format!("symbolic analysis failed: {e:?}")))
}

/// The bytes a numeric factorisation on `symbolic` holds at its peak: its values and faer's
/// workspace.
fn factor_bytes(symbolic: &SymbolicCholesky<usize>) -> u64 {
    let scratch = symbolic.factorize_numeric_llt_scratch::<f64>(par(), Default::default());
    (symbolic.len_val() as u64)
        .saturating_mul(8)
        .saturating_add(scratch.size_bytes() as u64)
}

/// The numeric factor of `a` on a symbolic analysis of its pattern.
pub(super) fn factorise(
    symbolic: &SymbolicCholesky<usize>,
    a: SparseColMatRef<'_, usize, f64>,
) -> Result<Vec<f64>> {
    let scratch = symbolic.factorize_numeric_llt_scratch::<f64>(par(), Default::default());
    let values = symbolic.len_val();
    let needed = factor_bytes(symbolic);
    let too_large = |limit: u64, limit_source: String| {
        ImpactError::TooLarge {
        // the run names the scene
        path: Default::default(),
        what: format!(
            "the sparse Cholesky factor's {values} values and its workspace, known from the symbolic analysis"
        ),
        estimate: needed,
        limit,
        limit_source,
    }
    };
    if let Some((limit, source)) = crate::limits::host_limit(0).filter(|(l, _)| needed > *l) {
        return Err(too_large(limit, source));
    }
    // an allocation refused (under `ulimit -v`) is the same error, not an abort
    let mut factor = Vec::new();
    factor
        .try_reserve_exact(values)
        .map_err(|_| too_large(needed, "the allocator refused it".into()))?;
    factor.resize(values, 0.0);
    let mut mem = MemBuffer::try_new(scratch)
        .map_err(|_| too_large(needed, "the allocator refused the workspace".into()))?;
    symbolic
        .factorize_numeric_llt(
            &mut factor,
            a,
            Side::Upper,
            Default::default(),
            par(),
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map_err(|e| ImpactError::Solver(format!("the effective matrix is not positive definite ({e:?}): is every body held or free to move with positive mass?")))?;
    Ok(factor)
}

/// A factor's ordering and symbolic analysis, before any value is computed: what its
/// numeric factorisation will hold is known exactly ([`Self::bytes`]), so a caller can check
/// every factor of a model against the memory before allocating one.
pub struct SpdAnalysis {
    symbolic: Arc<SymbolicCholesky<usize>>,
    pattern: SymbolicSparseColMat<usize>,
    stats: FactorStats,
    contact: Option<TrailingSolve>,
}

impl SpdAnalysis {
    /// Orders and analyses the pattern of `a`.
    pub fn new(a: &Csc, ordering: Ordering) -> Result<SpdAnalysis> {
        let start = Instant::now();
        let pattern = pattern_of(a);
        let symbolic = analyse(a, &pattern, ordering)?;
        let analysis_seconds = start.elapsed().as_secs_f64();
        let stats = FactorStats::analysed(a, ordering, &symbolic, analysis_seconds);
        Ok(SpdAnalysis {
            symbolic,
            pattern,
            stats,
            contact: None,
        })
    }

    /// [`Self::new`] with the equations `last` marks numbered after all the others (nested
    /// dissection of the rest), so that [`SpdSolver::contact_solve_in_place`] solves on
    /// them alone (where the factor is supernodal).
    pub fn with_last(a: &Csc, last: &[bool]) -> Result<SpdAnalysis> {
        let start = Instant::now();
        let pattern = pattern_of(a);
        let symbolic = analyse_permuted(&pattern, &nested_dissection_last(a, last)?)?;
        let count = last.iter().filter(|&&m| m).count();
        let contact = TrailingSolve::new(&symbolic, count);
        Ok(Self::with_contact(a, (symbolic, pattern, start), contact))
    }

    /// The analysis for a multiplier iteration on the contact equations `last`: with them
    /// numbered last ([`Self::with_last`]) where its contact-space solve reads at most
    /// [`MAX_TRAILING_SHARE`] of the values of the factor `ordering` gives and its fill at
    /// most [`MAX_FILL_GROWTH`] times that factor's, else that factor without a contact
    /// space (too many contact equations for the model: their block is dense).
    pub fn for_contact(a: &Csc, last: &[bool], ordering: Ordering) -> Result<SpdAnalysis> {
        let start = Instant::now();
        let pattern = pattern_of(a);
        let plain = analyse(a, &pattern, ordering)?;
        let symbolic = analyse_permuted(&pattern, &nested_dissection_last(a, last)?)?;
        let count = last.iter().filter(|&&m| m).count();
        let contact = TrailingSolve::new(&symbolic, count);
        let (values, plain_values) = (symbolic.len_val() as f64, plain.len_val() as f64);
        let worth = contact.as_ref().is_some_and(|t| {
            (t.values() as f64) <= MAX_TRAILING_SHARE * plain_values
                && values <= MAX_FILL_GROWTH * plain_values
        });
        match worth {
            true => Ok(Self::with_contact(a, (symbolic, pattern, start), contact)),
            false => {
                let seconds = start.elapsed().as_secs_f64();
                let stats = FactorStats::analysed(a, ordering, &plain, seconds);
                Ok(SpdAnalysis {
                    symbolic: plain,
                    pattern,
                    stats,
                    contact: None,
                })
            }
        }
    }

    /// The analysis with the contact equations last, and its contact-space solve (if any).
    fn with_contact(
        a: &Csc,
        (symbolic, pattern, start): (
            Arc<SymbolicCholesky<usize>>,
            SymbolicSparseColMat<usize>,
            Instant,
        ),
        contact: Option<TrailingSolve>,
    ) -> SpdAnalysis {
        let seconds = start.elapsed().as_secs_f64();
        let stats = FactorStats {
            contact_equations: contact.as_ref().map_or(0, |t| t.equations().len()),
            ..FactorStats::analysed(a, Ordering::NestedDissection, &symbolic, seconds)
        };
        SpdAnalysis {
            symbolic,
            pattern,
            stats,
            contact,
        }
    }

    /// The values the factor will store.
    pub fn values(&self) -> usize {
        self.symbolic.len_val()
    }

    /// The equations numbered last for the contact space (0: none).
    pub fn contact_equations(&self) -> usize {
        self.stats.contact_equations
    }

    /// The bytes a numeric factorisation holds at its peak: the factor's values and faer's
    /// workspace.
    pub fn bytes(&self) -> u64 {
        factor_bytes(&self.symbolic)
    }

    /// The numeric factor of `a`, whose pattern this analysis was made from.
    pub fn factorise(self, a: &Csc) -> Result<SpdSolver> {
        let mut s = SpdSolver {
            factor: Vec::new(),
            tree_solve: SupernodalSolve::new(&self.symbolic),
            contact: self.contact,
            symbolic: self.symbolic,
            pattern: self.pattern,
            stats: self.stats,
            solves: Cell::new((0, 0.0)),
            contact_solves: Cell::new((0, 0.0)),
        };
        s.refactor(&a.values)?;
        Ok(s)
    }
}

impl SpdSolver {
    /// Orders, analyses the pattern and factorises.
    pub fn new(a: &Csc, ordering: Ordering) -> Result<SpdSolver> {
        SpdAnalysis::new(a, ordering)?.factorise(a)
    }

    /// [`SpdAnalysis::with_last`], factorised.
    pub fn with_last(a: &Csc, last: &[bool]) -> Result<SpdSolver> {
        SpdAnalysis::with_last(a, last)?.factorise(a)
    }

    /// [`SpdAnalysis::for_contact`], factorised.
    pub fn for_contact(a: &Csc, last: &[bool], ordering: Ordering) -> Result<SpdSolver> {
        SpdAnalysis::for_contact(a, last, ordering)?.factorise(a)
    }

    /// The solve on the equations numbered last, where [`Self::with_last`] made one (a
    /// supernodal factor).
    pub fn contact_space(&self) -> Option<&TrailingSolve> {
        self.contact.as_ref()
    }

    /// $x = (A^{-1})_{CC}\, b$ in place on the equations numbered last, `b` in the order of
    /// [`TrailingSolve::equations`]; false (and `b` untouched) without a contact space.
    pub fn contact_solve_in_place(&self, b: &mut [f64]) -> bool {
        let Some(t) = &self.contact else {
            return false;
        };
        let start = Instant::now();
        t.solve_in_place(&self.factor, b);
        let (count, seconds) = self.contact_solves.get();
        (self.contact_solves).set((count + 1, seconds + start.elapsed().as_secs_f64()));
        true
    }

    /// $X = (A^{-1})_{CC}\, B$ in place for a block of right-hand sides on the equations
    /// numbered last: `b` column-major, one column of [`TrailingSolve::equations`]' length
    /// per right-hand side ([`TrailingSolve::solve_block_in_place`]; each column counts as a
    /// contact solve); false (and `b` untouched) without a contact space.
    pub fn contact_solve_block_in_place(&self, b: &mut [f64]) -> bool {
        let Some(t) = &self.contact else {
            return false;
        };
        let start = Instant::now();
        t.solve_block_in_place(&self.factor, b, par());
        let columns = b.len() / t.equations().len().max(1);
        let (count, seconds) = self.contact_solves.get();
        (self.contact_solves).set((count + columns, seconds + start.elapsed().as_secs_f64()));
        true
    }

    /// A factorisation of another matrix with the same pattern (the effective matrix of another
    /// step size), reusing this one's ordering and symbolic analysis, and its contact space
    /// where it has one.
    pub fn sibling(&self, a: &Csc) -> Result<SpdSolver> {
        if a.n != self.pattern.nrows()
            || a.col_ptr != self.pattern.col_ptr()
            || a.row_idx != self.pattern.row_idx()
        {
            return Err(ImpactError::Solver(
                "sibling factorisation: the matrix has another sparsity pattern".into(),
            ));
        }
        let stats = FactorStats {
            analysis_seconds: 0.0,
            factorizations: 0,
            factorization_seconds: 0.0,
            solves: 0,
            solve_seconds: 0.0,
            ..self.stats.clone()
        };
        let contact = (self.contact.as_ref())
            .and_then(|t| TrailingSolve::new(&self.symbolic, t.equations().len()));
        let analysis = SpdAnalysis {
            symbolic: self.symbolic.clone(),
            pattern: self.pattern.clone(),
            stats,
            contact,
        };
        analysis.factorise(a)
    }

    /// Numeric refactorisation with new values on the same pattern.
    pub fn refactor(&mut self, values: &[f64]) -> Result<()> {
        let start = Instant::now();
        let mat = SparseColMat::new(self.pattern.clone(), values.to_vec());
        self.factor = factorise(&self.symbolic, mat.as_ref())?;
        self.stats.factorizations += 1;
        self.stats.factorization_seconds += start.elapsed().as_secs_f64();
        Ok(())
    }

    /// Solves A x = b in place.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let start = Instant::now();
        match &self.tree_solve {
            Some(tree) => tree.solve_in_place(&self.factor, b),
            None => self.faer_solve_in_place(b, 1),
        }
        let (count, seconds) = self.solves.get();
        self.solves
            .set((count + 1, seconds + start.elapsed().as_secs_f64()));
    }

    /// Solves A X = B in place for a block of right-hand sides, `b` column-major (one
    /// column of the equations' length each), with faer's supernodal solve on a fixed task
    /// count: a column's bits depend on the number of columns, not on the others' values.
    /// Each column counts as a solve.
    pub fn solve_block_in_place(&self, b: &mut [f64]) {
        let n = self.pattern.nrows();
        if n == 0 || b.is_empty() {
            return;
        }
        let start = Instant::now();
        let k = b.len() / n;
        self.faer_solve_in_place(b, k);
        let (count, seconds) = self.solves.get();
        self.solves
            .set((count + k, seconds + start.elapsed().as_secs_f64()));
    }

    /// Solves A X = B in place with faer's own solve, `b` column-major with `k` columns.
    fn faer_solve_in_place(&self, b: &mut [f64], k: usize) {
        let n = b.len() / k;
        let rhs = MatMut::from_column_major_slice_mut(b, n, k);
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(k, par()));
        LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            rhs,
            par(),
            MemStack::new(&mut mem),
        );
    }

    /// Numeric factorisations made so far.
    pub fn factorizations(&self) -> usize {
        self.stats.factorizations
    }

    /// The ordering, sizes, counts and times of this factor.
    pub fn stats(&self) -> FactorStats {
        let (solves, solve_seconds) = self.solves.get();
        let (contact_solves, contact_solve_seconds) = self.contact_solves.get();
        FactorStats {
            solves,
            solve_seconds,
            contact_solves,
            contact_solve_seconds,
            ..self.stats.clone()
        }
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
        let s = SpdSolver::new(&a, Ordering::Amd).unwrap();
        let x: Vec<f64> = (0..n).map(|i| i as f64 - 1.5).collect();
        let mut b = vec![0.0; n];
        a.mul_into(&x, &mut b);
        s.solve_in_place(&mut b);
        for i in 0..n {
            assert!((b[i] - x[i]).abs() < 1e-12);
        }
    }

    /// The analysis knows the factor's size before it exists: the values a factorisation
    /// on it stores are the values it announced, and its bytes count them and the workspace.
    #[test]
    fn an_analysis_announces_the_size_of_its_factor() {
        let (nx, ny) = (30, 20);
        let id = |i: usize, j: usize| (i * ny + j) as u32;
        let mut t = Vec::new();
        for i in 0..nx {
            for j in 0..ny {
                t.push((id(i, j), id(i, j), 4.5));
                for (di, dj) in [(1, 0), (0, 1)] {
                    if i + di < nx && j + dj < ny {
                        t.push((id(i, j), id(i + di, j + dj), -1.0));
                        t.push((id(i + di, j + dj), id(i, j), -1.0));
                    }
                }
            }
        }
        let a = Csc::from_triplets(nx * ny, t);
        for ordering in [Ordering::Amd, Ordering::NestedDissection] {
            let analysis = SpdAnalysis::new(&a, ordering).unwrap();
            let (values, bytes) = (analysis.values(), analysis.bytes());
            assert!(
                bytes >= 8 * values as u64,
                "{bytes} bytes for {values} values"
            );
            let solver = analysis.factorise(&a).unwrap();
            assert_eq!(solver.factor.len(), values);
            assert_eq!(solver.stats().factor_nonzeros, values);
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
        let first = SpdSolver::new(&tridiagonal(n, 2.5), Ordering::NestedDissection).unwrap();
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
