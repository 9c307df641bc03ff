// Each cohesive interface's history values of the step, one workgroup of 256 per interface
// (twin: `kernels::cohesive_reduce`): its separated area (pairs at damage 1), its damaged
// area (damage above 0), and the sums of its pairs' dissipation and stored-energy offset,
// into rows[params.aux + COHESIVE_COLUMNS w ..] for interface w (the workgroup's x).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> ranges: array<vec2<u32>>;
@group(0) @binding(2) var<storage, read> pairs: array<CohesivePair>;
@group(0) @binding(3) var<storage, read> state: array<PairState>;
@group(0) @binding(4) var<storage, read> outputs: array<PairOutput>;
@group(0) @binding(5) var<storage, read_write> rows: array<f32>;

const COHESIVE_LANES: u32 = 256u;
var<workgroup> sums: array<vec4<f32>, 256>;

@compute @workgroup_size(256)
fn cohesive_reduce(
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
) {
    let r = ranges[wid.x];
    var acc = vec4<f32>(0.0);
    for (var p = r.x + local; p < r.y; p += COHESIVE_LANES) {
        let a = pairs[p].area;
        let d = state[p].damage;
        let o = outputs[p];
        acc += vec4<f32>(select(0.0, a, d >= 1.0), select(0.0, a, d > 0.0), o.dissipated, o.offset);
    }
    sums[local] = acc;
    workgroupBarrier();
    for (var s = COHESIVE_LANES / 2u; s > 0u; s >>= 1u) {
        if (local < s) {
            sums[local] += sums[local + s];
        }
        workgroupBarrier();
    }
    if (local == 0u) {
        let at = params.aux + COHESIVE_COLUMNS * wid.x;
        rows[at] = sums[0].x;
        rows[at + 1u] = sums[0].y;
        rows[at + 2u] = sums[0].z;
        rows[at + 3u] = sums[0].w;
    }
}
