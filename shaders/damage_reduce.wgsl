// The step's energy dissipated by damage, one workgroup (twin: `kernels::damage_reduce`):
// the sum of every damageable element's dissipation (records[1 + DAMAGE_RECORD i + 3], an
// f32's bits) into rows[params.aux]; then the step counter records[0] goes up by one.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> records: array<u32>;
@group(0) @binding(2) var<storage, read_write> rows: array<f32>;

const DAMAGE_LANES: u32 = 256u;
var<workgroup> sums: array<f32, 256>;

@compute @workgroup_size(256)
fn damage_reduce(@builtin(local_invocation_index) local: u32) {
    var acc = 0.0;
    for (var i = local; i < params.count; i += DAMAGE_LANES) {
        acc += bitcast<f32>(records[1u + DAMAGE_RECORD * i + 3u]);
    }
    sums[local] = acc;
    workgroupBarrier();
    for (var s = DAMAGE_LANES / 2u; s > 0u; s >>= 1u) {
        if (local < s) {
            sums[local] += sums[local + s];
        }
        workgroupBarrier();
    }
    if (local == 0u) {
        rows[params.aux] = sums[0];
        records[0] += 1u;
    }
}
