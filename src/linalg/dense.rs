//! Dense symmetric positive definite solves on faer's blocked Cholesky, on one thread: the
//! contact iteration's small dense systems (the Newton step's W on its active set), whose
//! bits must not depend on the threads.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::{Conj, MatMut, Par};

/// Solves A x = b in place: `a` holds A column-major (n x n, its lower triangle read) and is
/// overwritten by its Cholesky factor, `b` (n values) by x. False, with `b` untouched,
/// where A is not positive definite.
pub fn spd_solve_in_place(a: &mut [f64], b: &mut [f64]) -> bool {
    let n = b.len();
    debug_assert_eq!(a.len(), n * n);
    let mut l = MatMut::from_column_major_slice_mut(a, n, n);
    let par = Par::Seq;
    let factor_req = llt::factor::cholesky_in_place_scratch::<f64>(n, par, Default::default());
    let solve_req = llt::solve::solve_in_place_scratch::<f64>(n, 1, par);
    let mut mem = MemBuffer::new(factor_req.or(solve_req));
    let stack = MemStack::new(&mut mem);
    let factored = llt::factor::cholesky_in_place(
        l.as_mut(),
        Default::default(),
        par,
        stack,
        Default::default(),
    );
    if factored.is_err() {
        return false;
    }
    let x = MatMut::from_column_major_slice_mut(b, n, 1);
    llt::solve::solve_in_place_with_conj(l.as_ref(), Conj::No, x, par, stack);
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::test_matrices::Lcg;

    /// On a random SPD matrix the solve meets A x = b to rounding; an indefinite matrix is
    /// refused and leaves b as it was.
    #[test]
    fn the_dense_solve_meets_the_system_and_refuses_an_indefinite_one() {
        let n = 150;
        let mut rng = Lcg(3);
        let g: Vec<f64> = (0..n * n).map(|_| rng.next() - 0.5).collect();
        // A = G G^T + n I
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let s: f64 = (0..n).map(|k| g[i + k * n] * g[j + k * n]).sum();
                a[i + j * n] = s + if i == j { n as f64 } else { 0.0 };
            }
        }
        let b: Vec<f64> = (0..n).map(|_| rng.next() - 0.5).collect();
        let mut x = b.clone();
        assert!(spd_solve_in_place(&mut a.clone(), &mut x));
        let worst = (0..n)
            .map(|i| ((0..n).map(|j| a[i + j * n] * x[j]).sum::<f64>() - b[i]).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12 * n as f64, "{worst:.2e}");
        a[0] = -1.0;
        let mut y = b.clone();
        assert!(!spd_solve_in_place(&mut a, &mut y));
        assert_eq!(y, b);
    }
}
