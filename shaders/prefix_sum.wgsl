// Exclusive prefix sum of params.count values (twin: `kernels::prefix_sum`): starts[k] = sum
// of values[0..k], and starts[count] the total. One 256-wide workgroup per block of 1024
// values, four neighbouring values per invocation: the block's offset is the sum of the
// totals of the blocks before it (`scan_totals`, the first pass; none for the first block),
// the block's four-value sums are scanned in workgroup memory, and the last block writes
// the total.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> values: array<u32>;
@group(0) @binding(2) var<storage, read> totals: array<u32>;
@group(0) @binding(3) var<storage, read_write> starts: array<u32>;

const SCAN_SIZE: u32 = 256u;

var<workgroup> sums: array<u32, SCAN_SIZE>;

fn value_or_zero(k: u32) -> u32 {
    return select(0u, values[min(k, params.count - 1u)], k < params.count);
}

// The sum of the totals of the blocks before `block`, in every invocation.
fn block_offset(block: u32, local: u32) -> u32 {
    var part = 0u;
    for (var c = local; c < block; c += SCAN_SIZE) {
        part += totals[c];
    }
    sums[local] = part;
    workgroupBarrier();
    for (var s = SCAN_SIZE / 2u; s > 0u; s >>= 1u) {
        if (local < s) {
            sums[local] += sums[local + s];
        }
        workgroupBarrier();
    }
    let offset = sums[0];
    // every invocation has read it before the scan writes the sums again
    workgroupBarrier();
    return offset;
}

@compute @workgroup_size(256)
fn prefix_sum(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let n = params.count;
    let block = wid.x;
    let offset = block_offset(block, local);
    let base = 4u * (block * SCAN_SIZE + local);
    let v0 = value_or_zero(base);
    let v1 = value_or_zero(base + 1u);
    let v2 = value_or_zero(base + 2u);
    let v3 = value_or_zero(base + 3u);
    let total = v0 + v1 + v2 + v3;
    sums[local] = total;
    workgroupBarrier();
    for (var o = 1u; o < SCAN_SIZE; o <<= 1u) {
        var add = 0u;
        if (local >= o) {
            add = sums[local - o];
        }
        workgroupBarrier();
        sums[local] += add;
        workgroupBarrier();
    }
    var run = offset + sums[local] - total;
    if (base < n) {
        starts[base] = run;
    }
    run += v0;
    if (base + 1u < n) {
        starts[base + 1u] = run;
    }
    run += v1;
    if (base + 2u < n) {
        starts[base + 2u] = run;
    }
    run += v2;
    if (base + 3u < n) {
        starts[base + 3u] = run;
    }
    if (block + 1u == groups.x && local == 0u) {
        starts[n] = offset + sums[SCAN_SIZE - 1u];
    }
}
