//! [`TrailingSolve`]: solves on the contact space of a factor whose contact equations are
//! numbered last ([`super::ordering::nested_dissection_last`]).
//!
//! With $L L^T = P A P^T$ and the contact equations C in the last places, the trailing block
//! $L_{CC}$ of L is the Cholesky factor of the Schur complement $S = A_{CC} - A_{CI}
//! A_{II}^{-1} A_{IC}$, so $(A^{-1})_{CC}\, b = S^{-1} b = L_{CC}^{-T} L_{CC}^{-1} b$: the
//! response of the contact equations to loads on them alone, found from the supernodes that
//! hold the trailing columns, without touching the rest of the factor. A supernode that
//! starts before the trailing columns carries zeros in its other columns forward (their
//! loads are zero, and so are the updates they take) and its solution there is not read.

use std::ops::Range;
use std::sync::{Mutex, PoisonError};

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::{Accum, Mat, MatMut, MatRef, Par};

use super::supernodal_solve::{eliminate, upper_solve_strided};

/// A supernode of the trailing solve: its values, its first column and column count, its
/// rows below the diagonal block (a range of [`TrailingSolve::rows`]), and how many of its
/// first columns lie before the trailing ones (skipped: their loads and updates are zero);
/// columns and rows are positions counted from [`TrailingSolve::base`].
#[derive(Debug, Clone)]
struct Node {
    val: usize,
    col: usize,
    ncols: usize,
    rows: Range<usize>,
    skip: usize,
}

/// The solve on the trailing equations of a supernodal factor.
#[derive(Debug)]
pub struct TrailingSolve {
    nodes: Vec<Node>,
    rows: Vec<usize>,
    /// The first position of the first supernode holding a trailing column.
    base: usize,
    /// The first trailing position, counted from `base`.
    first: usize,
    /// The equations in the trailing places, in their order.
    equations: Vec<usize>,
    /// The solution vector from `base` on, and a supernode's work.
    scratch: Mutex<(Vec<f64>, Vec<f64>)>,
}

impl TrailingSolve {
    /// The solve on the last `count` places of a symbolic factor; `None` for a simplicial
    /// factor or no trailing place.
    pub fn new(symbolic: &SymbolicCholesky<usize>, count: usize) -> Option<TrailingSolve> {
        let SymbolicCholeskyRaw::Supernodal(s) = symbolic.raw() else {
            return None;
        };
        let n = s.nrows();
        if count == 0 || count > n {
            return None;
        }
        let start = n - count;
        let (begin, end) = (s.supernode_begin(), s.supernode_end());
        let k0 = (0..begin.len()).find(|&k| end[k] > start)?;
        let base = begin[k0];
        let mut nodes = Vec::new();
        let mut rows = Vec::new();
        let mut front = 0;
        for k in k0..begin.len() {
            let pattern = &s.row_idx()[s.col_ptr_for_row_idx()[k]..s.col_ptr_for_row_idx()[k + 1]];
            let first = rows.len();
            rows.extend(pattern.iter().map(|&r| r - base));
            let ncols = end[k] - begin[k];
            front = front.max(ncols + pattern.len());
            nodes.push(Node {
                val: s.col_ptr_for_val()[k],
                col: begin[k] - base,
                ncols,
                rows: first..rows.len(),
                skip: start.saturating_sub(begin[k]),
            });
        }
        let equations = match symbolic.perm() {
            Some(p) => p.arrays().0[start..].to_vec(),
            None => (start..n).collect(),
        };
        Some(TrailingSolve {
            nodes,
            rows,
            base,
            first: start - base,
            equations,
            scratch: Mutex::new((vec![0.0; n - base], vec![0.0; front])),
        })
    }

    /// The equations of the trailing places, in order: the entries of the vectors
    /// [`Self::solve_in_place`] takes.
    pub fn equations(&self) -> &[usize] {
        &self.equations
    }

    /// $x = (A^{-1})_{CC}\, b$ in place, `b` given on [`Self::equations`], with the factor's
    /// values `l`.
    pub fn solve_in_place(&self, l: &[f64], b: &mut [f64]) {
        debug_assert_eq!(b.len(), self.equations.len());
        let mut scratch = self.scratch.lock().unwrap_or_else(PoisonError::into_inner);
        let (y, work) = &mut *scratch;
        y.fill(0.0);
        y[self.first..].copy_from_slice(b);
        for node in &self.nodes {
            let (block, ld, cols, rows) = self.part(node, l);
            let nc = cols.len();
            let w = &mut work[..ld - node.skip];
            w[..nc].copy_from_slice(&y[cols.clone()]);
            w[nc..].fill(0.0);
            eliminate(block, ld, w, 0..nc);
            y[cols].copy_from_slice(&w[..nc]);
            for (&r, &u) in rows.iter().zip(&w[nc..]) {
                y[r] += u;
            }
        }
        for node in self.nodes.iter().rev() {
            let (block, ld, cols, rows) = self.part(node, l);
            let nc = cols.len();
            let w = &mut work[..ld - node.skip];
            w[..nc].copy_from_slice(&y[cols.clone()]);
            for (v, &r) in w[nc..].iter_mut().zip(rows) {
                *v = y[r];
            }
            upper_solve_strided(block, ld, w, nc, 1);
            y[cols].copy_from_slice(&w[..nc]);
        }
        b.copy_from_slice(&y[self.first..]);
    }

    /// [`Self::solve_in_place`] for a block of right-hand sides, `b` column-major with one
    /// column of [`Self::equations`]' length each: each supernode's triangle is solved and
    /// its rows below updated for every column at once, with faer's dense kernels on `par`
    /// (a fixed task count, so the bits do not follow the threads). A column's bits depend
    /// on the number of columns, not on the other columns' values.
    pub fn solve_block_in_place(&self, l: &[f64], b: &mut [f64], par: Par) {
        let count = self.equations.len();
        if count == 0 || b.is_empty() {
            return;
        }
        debug_assert_eq!(b.len() % count, 0);
        let k = b.len() / count;
        let mut y = MatMut::from_column_major_slice_mut(b, count, k);
        let first = self.first;
        for node in &self.nodes {
            let (l_diag, l_below, cols, rows) = self.blocks(node, l);
            let mut w = Mat::from_fn(cols.len(), k, |i, c| y[(cols.start + i - first, c)]);
            triangular_solve::solve_lower_triangular_in_place(l_diag, w.as_mut(), par);
            (y.as_mut().subrows_mut(cols.start - first, cols.len())).copy_from(&w);
            if !rows.is_empty() {
                let mut t = Mat::<f64>::zeros(rows.len(), k);
                matmul(t.as_mut(), Accum::Replace, l_below, w.as_ref(), 1.0, par);
                for (i, &r) in rows.iter().enumerate() {
                    for c in 0..k {
                        y[(r - first, c)] -= t[(i, c)];
                    }
                }
            }
        }
        for node in self.nodes.iter().rev() {
            let (l_diag, l_below, cols, rows) = self.blocks(node, l);
            let mut w = Mat::from_fn(cols.len(), k, |i, c| y[(cols.start + i - first, c)]);
            if !rows.is_empty() {
                let x = Mat::from_fn(rows.len(), k, |i, c| y[(rows[i] - first, c)]);
                let lt = l_below.transpose();
                matmul(w.as_mut(), Accum::Add, lt, x.as_ref(), -1.0, par);
            }
            triangular_solve::solve_upper_triangular_in_place(l_diag.transpose(), w.as_mut(), par);
            (y.as_mut().subrows_mut(cols.start - first, cols.len())).copy_from(&w);
        }
    }

    /// A supernode's trailing part as dense blocks: its diagonal triangle and its rows below
    /// (columns of the part), its trailing columns and its rows below (positions from `base`).
    #[allow(clippy::type_complexity)]
    fn blocks<'l>(
        &self,
        node: &Node,
        l: &'l [f64],
    ) -> (MatRef<'l, f64>, MatRef<'l, f64>, Range<usize>, &[usize]) {
        let (block, ld, cols, rows) = self.part(node, l);
        let nc = cols.len();
        let part = MatRef::from_column_major_slice_with_stride(block, nc + rows.len(), nc, ld);
        (
            part.subrows(0, nc),
            part.subrows(nc, rows.len()),
            cols,
            rows,
        )
    }

    /// The first position the solve reads of the factor (the supernodes from there on).
    pub fn base(&self) -> usize {
        self.base
    }

    /// The factor values the solve reads (twice: forward and backward).
    pub fn values(&self) -> usize {
        (self.nodes.iter())
            .map(|n| (n.ncols - n.skip) * (n.ncols - n.skip + n.rows.len()))
            .sum()
    }

    /// The part of a supernode's block the solve reads: its values from its first trailing
    /// column's diagonal entry, its columns' length, its trailing columns (positions from
    /// `base`) and its rows below.
    fn part<'l>(&self, node: &Node, l: &'l [f64]) -> (&'l [f64], usize, Range<usize>, &[usize]) {
        let ld = node.ncols + node.rows.len();
        let start = node.val + node.skip * ld + node.skip;
        let cols = node.col + node.skip..node.col + node.ncols;
        (
            &l[start..node.val + node.ncols * ld],
            ld,
            cols,
            &self.rows[node.rows.clone()],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_matrices::{grid_matrix, Lcg};
    use super::super::SpdSolver;

    /// A 27-point grid matrix of m^3 nodes, its top layer marked, and its factor with that
    /// layer numbered last.
    fn top_layer_last(m: usize) -> (super::super::Csc, Vec<bool>, SpdSolver) {
        let a = grid_matrix(m, 3);
        let last: Vec<bool> = (0..a.n).map(|i| i / (m * m) == m - 1).collect();
        let solver = SpdSolver::with_last(&a, &last).unwrap();
        (a, last, solver)
    }

    fn max_abs(v: impl IntoIterator<Item = f64>) -> f64 {
        v.into_iter().fold(0.0, |m, x| m.max(x.abs()))
    }

    /// On a 27-point grid matrix with its top layer numbered last, the trailing solve of a
    /// load on that layer gives the full solve's response there, and the contact-space
    /// operator it builds column by column is symmetric.
    #[test]
    fn the_trailing_solve_is_the_full_solve_on_the_contact_space() {
        let (a, last, solver) = top_layer_last(14);
        let trailing = solver.contact_space().expect("a supernodal factor");
        let plain = SpdSolver::new(&a, super::super::Ordering::NestedDissection).unwrap();
        let (with, without) = (
            solver.stats().factor_nonzeros,
            plain.stats().factor_nonzeros,
        );
        eprintln!("factor values: {with} with the top layer last, {without} without");
        assert!(
            with < 2 * without,
            "the constraint costs little fill: {with} against {without}"
        );
        let marked: Vec<usize> = (0..a.n).filter(|&i| last[i]).collect();
        assert_eq!(trailing.equations(), &marked[..]);
        assert!(
            trailing.base() > a.n / 2,
            "the solve reads the factor's end only"
        );
        let mut rng = Lcg(9);
        let b: Vec<f64> = marked.iter().map(|_| rng.next() - 0.5).collect();
        let mut full = vec![0.0; a.n];
        for (&i, &v) in marked.iter().zip(&b) {
            full[i] = v;
        }
        solver.solve_in_place(&mut full);
        let mut x = b.clone();
        solver.contact_solve_in_place(&mut x);
        let want: Vec<f64> = marked.iter().map(|&i| full[i]).collect();
        let diff = max_abs(x.iter().zip(&want).map(|(p, q)| p - q));
        assert!(diff <= 1e-13 * max_abs(want.iter().copied()), "{diff}");
        // W = (A^-1)_CC column by column: symmetric to rounding
        let k = marked.len().min(40);
        let w: Vec<Vec<f64>> = (0..k)
            .map(|j| {
                let mut e = vec![0.0; marked.len()];
                e[j] = 1.0;
                solver.contact_solve_in_place(&mut e);
                e
            })
            .collect();
        let scale = max_abs(w.iter().flatten().copied());
        let asymmetry = (0..k)
            .flat_map(|i| (0..k).map(move |j| (i, j)))
            .map(|(i, j)| (w[i][j] - w[j][i]).abs())
            .fold(0.0, f64::max);
        assert!(asymmetry <= 1e-13 * scale, "{asymmetry}");
    }

    /// A block of right-hand sides solves each column as the single solve does, to
    /// rounding; a column's bits do not depend on the other columns' values.
    #[test]
    fn the_block_solve_is_the_single_solves_and_each_column_its_own() {
        let (_, _, solver) = top_layer_last(12);
        let count = solver
            .contact_space()
            .expect("a supernodal factor")
            .equations()
            .len();
        let k = 7;
        let mut rng = Lcg(5);
        let b: Vec<f64> = (0..count * k).map(|_| rng.next() - 0.5).collect();
        let mut x = b.clone();
        assert!(solver.contact_solve_block_in_place(&mut x));
        let (mut worst, mut scale) = (0.0f64, 0.0f64);
        for c in 0..k {
            let mut single = b[c * count..(c + 1) * count].to_vec();
            solver.contact_solve_in_place(&mut single);
            for (p, q) in x[c * count..].iter().zip(&single) {
                worst = worst.max((p - q).abs());
                scale = scale.max(q.abs());
            }
        }
        assert!(worst <= 1e-12 * scale, "{worst:.2e} of {scale:.2e}");
        // column 2 alone among zeros: the same bits
        let mut alone = vec![0.0; count * k];
        alone[2 * count..3 * count].copy_from_slice(&b[2 * count..3 * count]);
        solver.contact_solve_block_in_place(&mut alone);
        let same = (alone[2 * count..3 * count]
            .iter()
            .zip(&x[2 * count..3 * count]))
        .all(|(p, q)| p.to_bits() == q.to_bits());
        assert!(same, "a column's bits follow its neighbours");
        assert_eq!(solver.stats().contact_solves, 2 * k + k);
    }
}
