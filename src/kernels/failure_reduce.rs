//! The failure survey's workgroup records merged into one (CPU twin of
//! `shaders/failure_reduce.wgsl`): the largest of each index, and the worst point of the
//! largest value, the lowest point on a tie (so the order of the merges does not matter).

/// Values of a record: the five indices' maxima, then the worst point's value, its number
/// and the index that was largest there (`-1` for none).
pub const FAILURE_FIELDS: usize = 8;

/// A record with nothing in it.
pub(crate) fn empty() -> [f64; FAILURE_FIELDS] {
    let mut r = [0.0; FAILURE_FIELDS];
    r[5..].fill(-1.0);
    r
}

/// Merges record `b` into `a`: the larger of each maximum, and the worst point of the larger
/// value (the lower point on a tie).
pub fn merge(a: &mut [f64; FAILURE_FIELDS], b: &[f64]) {
    for k in 0..5 {
        a[k] = a[k].max(b[k]);
    }
    let better = b[6] >= 0.0 && (a[6] < 0.0 || b[5] > a[5] || (b[5] == a[5] && b[6] < a[6]));
    if better {
        a[5..].copy_from_slice(&b[5..FAILURE_FIELDS]);
    }
}

/// The workgroups' records merged into one.
pub fn failure_reduce(partials: &[f64]) -> [f64; FAILURE_FIELDS] {
    let mut rec = empty();
    for g in partials.chunks_exact(FAILURE_FIELDS) {
        merge(&mut rec, g);
    }
    rec
}
