//! The first `count` words of a buffer set to one value (CPU twin of
//! `shaders/fill_words.wgsl`): the device zeroes its counters and accumulators with it
//! inside a compute pass.

pub fn fill_words(words: &mut [u32], count: usize, value: u32) {
    let count = count.min(words.len());
    words[..count].fill(value);
}
