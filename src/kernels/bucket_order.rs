//! Puts the items of each of the first `buckets` buckets of a counting sort in increasing
//! order (CPU twin of `shaders/bucket_order.wgsl`), so that sums over a bucket run in the
//! same order every time, and clears every bucket's size (the sentinel's too) for the next
//! count. (The kernel also clears the contact iteration's state words: the twins start each
//! step from a fresh [`super::SweepState`].)

pub fn bucket_order(buckets: usize, starts: &[u32], sorted: &mut [u32], counts: &mut [u32]) {
    for b in 0..buckets {
        sorted[starts[b] as usize..starts[b + 1] as usize].sort_unstable();
    }
    counts[..=buckets].fill(0);
}
