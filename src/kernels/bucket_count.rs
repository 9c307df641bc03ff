//! First pass of the counting sort by key (CPU twin of `shaders/bucket_count.wgsl`): bucket
//! sizes and each item's rank in its bucket. The twin ranks in item order; the device ranks in
//! the order its atomics run, so only the sizes and the set of ranks of a bucket compare.

pub fn bucket_count(keys: &[u32], buckets: usize) -> (Vec<u32>, Vec<u32>) {
    let mut counts = vec![0u32; buckets];
    let ranks = keys
        .iter()
        .map(|&k| {
            let r = counts[k as usize];
            counts[k as usize] += 1;
            r
        })
        .collect();
    (counts, ranks)
}
