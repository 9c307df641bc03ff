//! Second pass of the counting sort (CPU twin of `shaders/bucket_fill.wgsl`): item i goes to
//! `starts[keys[i]] + ranks[i]`.

pub fn bucket_fill(keys: &[u32], ranks: &[u32], starts: &[u32]) -> Vec<u32> {
    let mut sorted = vec![0u32; keys.len()];
    for (i, (&k, &r)) in keys.iter().zip(ranks).enumerate() {
        sorted[(starts[k as usize] + r) as usize] = i as u32;
    }
    sorted
}
