// The step's energy dissipated by damage, one workgroup (twin: `kernels::damage_reduce`):
// the sums of every damageable element's dissipation and of its fibre share
// (records[1 + DAMAGE_RECORD i + 3] and + 4, an f32's bits) into rows[params.aux] and
// rows[params.aux + 1]; then the step counter records[0] goes up by one.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> records: array<u32>;
@group(0) @binding(2) var<storage, read_write> rows: array<f32>;

const DAMAGE_LANES: u32 = 256u;
var<workgroup> sums: array<vec2<f32>, 256>;

@compute @workgroup_size(256)
fn damage_reduce(@builtin(local_invocation_index) local: u32) {
    var acc = vec2<f32>(0.0);
    for (var i = local; i < params.count; i += DAMAGE_LANES) {
        let at = 1u + DAMAGE_RECORD * i + 3u;
        acc += vec2<f32>(bitcast<f32>(records[at]), bitcast<f32>(records[at + 1u]));
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
        rows[params.aux] = sums[0].x;
        rows[params.aux + 1u] = sums[0].y;
        records[0] += 1u;
    }
}
