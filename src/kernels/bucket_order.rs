//! Puts the items of each of the first `buckets` buckets of a counting sort in increasing
//! order (CPU twin of `shaders/bucket_order.wgsl`), so that sums over a bucket run in the
//! same order every time.

pub fn bucket_order(buckets: usize, starts: &[u32], sorted: &mut [u32]) {
    for b in 0..buckets {
        sorted[starts[b] as usize..starts[b + 1] as usize].sort_unstable();
    }
}
