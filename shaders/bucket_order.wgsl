// Puts the items of each bucket of a counting sort in increasing order (twin:
// `kernels::bucket_order`), one bucket per invocation, by insertion sort (the buckets of the
// contact iteration hold the few pairs on one face). `bucket_count` ranks the items of a
// bucket in the order its atomics ran, which changes from run to run; the contact
// iteration's gathers add f32 values in bucket order, so without this their sums, and the
// run, would not be the same bits every time. params.count buckets (the sentinel bucket of
// the pairs on no face is left as it is: nothing reads it).
//
// It also clears what the next stages and the next step start from, saving a dispatch each:
// every bucket's size (the scan has read them; the sentinel's by the first invocation), so
// that the next step's `bucket_count` counts from zero, and the iteration's state words
// (the last step's report has read them), which `contact_touches` counts the pairs in reach
// into next, and the search bounds bounds[0..3] (the step's search has read them), which
// the next step's `search_bounds` or `predict_bounds` folds into.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> starts: array<u32>;
@group(0) @binding(2) var<storage, read_write> sorted: array<u32>;
@group(0) @binding(3) var<storage, read_write> counts: array<u32>;
@group(0) @binding(4) var<storage, read_write> state: array<u32, 8>;
@group(0) @binding(5) var<storage, read_write> bounds: array<u32, 6>;

// include: order_bucket

@compute @workgroup_size(64)
fn bucket_order(@builtin(global_invocation_id) gid: vec3<u32>) {
    let b = item_index(gid, params);
    if (b == 0u) {
        counts[params.count] = 0u;
        for (var w = 0u; w < 8u; w++) {
            state[w] = 0u;
        }
        for (var k = 0u; k < 3u; k++) {
            bounds[k] = 0u;
        }
    }
    if (b >= params.count) {
        return;
    }
    counts[b] = 0u;
    order_bucket(b);
}
