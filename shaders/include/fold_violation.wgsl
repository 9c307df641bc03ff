// included by 64-lane kernels that bind `state: array<atomic<u32>, 8>` (read_write) and
// declare `var<workgroup> worst: array<f32, 64>`

// Folds the lanes' violations into state word `word`: the workgroup's maximum by a tree,
// then one atomicMax of its bits (non-negative floats order as their bits). Every lane of
// the workgroup calls it (its barriers).
fn fold_violation(local: u32, violation: f32, word: u32) {
    worst[local] = violation;
    workgroupBarrier();
    for (var s = 32u; s > 0u; s >>= 1u) {
        if (local < s) {
            worst[local] = max(worst[local], worst[local + s]);
        }
        workgroupBarrier();
    }
    if (local == 0u && worst[0] > 0.0) {
        atomicMax(&state[word], bitcast<u32>(worst[0]));
    }
}
