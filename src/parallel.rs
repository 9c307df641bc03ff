//! Work on all cores with results that do not depend on the number of threads.
//!
//! Element and node loops write disjoint outputs, each from a fixed sequence of operations,
//! so splitting them across threads changes nothing. Sums are the one place where the order
//! of operations would follow the threads: [`ordered_sum`] splits at fixed places, sums each
//! piece in order and then the pieces in order, the same on 1 thread or 64.

use rayon::prelude::*;

/// Items per piece of an ordered sum (and the least work a thread takes in the elementwise
/// loops: below it the scheduling costs more than it saves).
pub const CHUNK: usize = 4096;

/// $\sum_{i<n} f(i)$, summed in pieces of [`CHUNK`] in order, then the pieces in order.
pub(crate) fn ordered_sum(n: usize, f: impl Fn(usize) -> f64 + Sync) -> f64 {
    let pieces: Vec<f64> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|p| (p * CHUNK..((p + 1) * CHUNK).min(n)).map(&f).sum::<f64>())
        .collect();
    pieces.into_iter().sum()
}

/// $\sum_i a_i b_i$ by [`ordered_sum`].
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    ordered_sum(a.len().min(b.len()), |i| a[i] * b[i])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_ordered_sum_is_the_same_on_any_number_of_threads() {
        let n = 10 * CHUNK + 17;
        let f = |i: usize| ((i as f64) * 0.37).sin() * 10f64.powi((i % 13) as i32 - 6);
        let sums: Vec<u64> = [1, 2, 3, 8]
            .iter()
            .map(|&t| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(t)
                    .build()
                    .unwrap();
                pool.install(|| ordered_sum(n, f)).to_bits()
            })
            .collect();
        assert!(sums.iter().all(|&s| s == sums[0]), "{sums:?}");
        // and it is the sum, to rounding
        let plain: f64 = (0..n).map(f).sum();
        assert!((f64::from_bits(sums[0]) - plain).abs() <= 1e-12 * plain.abs().max(1.0));
    }
}
