// Exclusive prefix sum of params.count values in one workgroup (twin: `kernels::prefix_sum`):
// starts[k] = sum of values[0..k], and starts[count] the total. The values are taken in
// tiles of 1024, four consecutive values per invocation (neighbouring invocations read
// neighbouring words); each tile's four-value totals are scanned in workgroup memory and
// the tile's total carried into the next.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> values: array<u32>;
@group(0) @binding(2) var<storage, read_write> starts: array<u32>;

const SCAN_SIZE: u32 = 256u;

var<workgroup> sums: array<u32, SCAN_SIZE>;

fn value_or_zero(k: u32) -> u32 {
    return select(0u, values[min(k, params.count - 1u)], k < params.count);
}

@compute @workgroup_size(256)
fn prefix_sum(@builtin(local_invocation_index) local: u32) {
    let n = params.count;
    let tiles = (n + 4u * SCAN_SIZE - 1u) / (4u * SCAN_SIZE);
    var carry = 0u;
    for (var t = 0u; t < tiles; t++) {
        let base = 4u * (t * SCAN_SIZE + local);
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
        var run = carry + sums[local] - total;
        carry += sums[SCAN_SIZE - 1u];
        // every invocation has read the tile's sums before the next tile writes them
        workgroupBarrier();
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
    }
    if (local == 0u) {
        starts[n] = carry;
    }
}
