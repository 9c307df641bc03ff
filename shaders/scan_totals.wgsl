// The first pass of `prefix_sum` over several blocks (twin: `kernels::scan_totals`): the
// total of each block of 1024 of the params.count values, one 256-wide workgroup per block
// (four neighbouring values per invocation), into totals[block].

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> values: array<u32>;
@group(0) @binding(2) var<storage, read_write> totals: array<u32>;

var<workgroup> sums: array<u32, 256>;

fn value_or_zero(k: u32) -> u32 {
    return select(0u, values[min(k, params.count - 1u)], k < params.count);
}

@compute @workgroup_size(256)
fn scan_totals(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let base = 4u * (wid.x * 256u + local);
    sums[local] = value_or_zero(base) + value_or_zero(base + 1u) + value_or_zero(base + 2u)
        + value_or_zero(base + 3u);
    workgroupBarrier();
    for (var s = 128u; s > 0u; s >>= 1u) {
        if (local < s) {
            sums[local] += sums[local + s];
        }
        workgroupBarrier();
    }
    if (local == 0u) {
        totals[wid.x] = sums[0];
    }
}
