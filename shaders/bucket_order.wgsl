// Puts the items of each bucket of a counting sort in increasing order (twin:
// `kernels::bucket_order`), one bucket per invocation, by insertion sort (the buckets of the
// contact iteration hold the few pairs on one face). `bucket_count` ranks the items of a
// bucket in the order its atomics ran, which changes from run to run; the contact
// iteration's gathers add f32 values in bucket order, so without this their sums, and the
// run, would not be the same bits every time. params.count buckets (the sentinel bucket of
// the pairs on no face is left as it is: nothing reads it).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> starts: array<u32>;
@group(0) @binding(2) var<storage, read_write> sorted: array<u32>;

@compute @workgroup_size(64)
fn bucket_order(@builtin(global_invocation_id) gid: vec3<u32>) {
    let b = item_index(gid, params);
    if (b >= params.count) {
        return;
    }
    let first = starts[b];
    let end = starts[b + 1u];
    for (var i = first + 1u; i < end; i++) {
        let x = sorted[i];
        var j = i;
        while (j > first && sorted[j - 1u] > x) {
            sorted[j] = sorted[j - 1u];
            j--;
        }
        sorted[j] = x;
    }
}
