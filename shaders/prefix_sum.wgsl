// Exclusive prefix sum of params.count values in one workgroup (twin: `kernels::prefix_sum`):
// starts[k] = sum of values[0..k], and starts[count] the total. Each invocation adds a
// contiguous chunk; the chunks' totals are scanned in workgroup memory.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> values: array<u32>;
@group(0) @binding(2) var<storage, read_write> starts: array<u32>;

var<workgroup> totals: array<u32, 64>;

@compute @workgroup_size(64)
fn prefix_sum(@builtin(local_invocation_index) local: u32) {
    let n = params.count;
    let chunk = (n + 63u) / 64u;
    let first = min(local * chunk, n);
    let end = min(first + chunk, n);
    var sum = 0u;
    for (var k = first; k < end; k++) {
        sum += values[k];
    }
    totals[local] = sum;
    workgroupBarrier();
    if (local == 0u) {
        var run = 0u;
        for (var i = 0u; i < 64u; i++) {
            let t = totals[i];
            totals[i] = run;
            run += t;
        }
        starts[n] = run;
    }
    workgroupBarrier();
    var run = totals[local];
    for (var k = first; k < end; k++) {
        starts[k] = run;
        run += values[k];
    }
}
