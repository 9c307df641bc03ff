// First pass of the counting sort of items by key: each item's rank among the items of its
// bucket, and the bucket sizes (twin: `kernels::bucket_count`). The counts start at zero; the
// ranks within a bucket come in the order the atomics run (the sort is not stable, and the
// search does not need it to be).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> keys: array<u32>;
@group(0) @binding(2) var<storage, read_write> counts: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read_write> ranks: array<u32>;

@compute @workgroup_size(64)
fn bucket_count(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i >= params.count) {
        return;
    }
    ranks[i] = atomicAdd(&counts[keys[i]], 1u);
}
