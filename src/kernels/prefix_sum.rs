//! Exclusive prefix sum (CPU twin of `shaders/prefix_sum.wgsl`, run after its first pass,
//! [`super::scan_totals`]): `starts[k]` is the sum of `values[..k]`, and the last entry (one
//! more than there are values) the total.

pub fn prefix_sum(values: &[u32]) -> Vec<u32> {
    let mut starts = Vec::with_capacity(values.len() + 1);
    let mut run = 0u32;
    for &v in values {
        starts.push(run);
        run += v;
    }
    starts.push(run);
    starts
}
