// One history row of the explicit step, one workgroup per value (twin:
// `kernels::history_reduce`). Column c reduces the entries first + k * stride, k < count, of
// its source by its op:
//   0: sum of the correctors' workgroup partials,
//   1: sum of the contact results (per plane node and plane, or per contact pair),
//   2: largest contact result, and 0 (penetration, sweeps),
//   3: displacement component `first` (3 n + axis; a probe),
//   4: velocity component `first` (a probe),
//   5: the corner forces at the indices corner_lists[first + k] (a support's reaction).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> columns: array<ReduceColumn>;
@group(0) @binding(2) var<storage, read> partials: array<f32>;
@group(0) @binding(3) var<storage, read> results: array<f32>;
@group(0) @binding(4) var<storage, read> displacement: array<Split3>;
@group(0) @binding(5) var<storage, read> velocity: array<f32>;
@group(0) @binding(6) var<storage, read> corner_forces: array<f32>;
@group(0) @binding(7) var<storage, read> corner_lists: array<u32>;
// the submission's rows; this launch writes its row at rows[params.aux..]
@group(0) @binding(8) var<storage, read_write> rows: array<f32>;

// invocations per column; each keeps four running values (independent loads in flight)
const LANES: u32 = 256u;
var<workgroup> scratch: array<f32, 256>;

fn combine(a: f32, b: f32, is_max: bool) -> f32 {
    return select(a + b, max(a, b), is_max);
}

fn entry(col: ReduceColumn, at: u32) -> f32 {
    switch col.op {
        case OP_PARTIALS: {
            return partials[at];
        }
        case OP_SUM, OP_MAX: {
            return results[at];
        }
        case OP_DISPLACEMENT: {
            return split_value(displacement[at / 3u])[at % 3u];
        }
        case OP_CORNERS: {
            return corner_forces[corner_lists[at]];
        }
        default: {
            return velocity[at];
        }
    }
}

@compute @workgroup_size(256)
fn history_reduce(
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let c = wid.x + wid.y * groups.x;
    let valid = c < params.count;
    let col = columns[min(c, params.count - 1u)];
    let is_max = col.op == OP_MAX;
    var acc = vec4<f32>(0.0);
    if (valid) {
        // entries local, local + LANES, ...: four at a time, then the rest
        var k = local;
        for (; k + 3u * LANES < col.count; k += 4u * LANES) {
            let at = col.first + k * col.stride;
            let step = LANES * col.stride;
            let x = vec4<f32>(
                entry(col, at),
                entry(col, at + step),
                entry(col, at + 2u * step),
                entry(col, at + 3u * step),
            );
            acc = select(acc + x, max(acc, x), is_max);
        }
        for (; k < col.count; k += LANES) {
            acc.x = combine(acc.x, entry(col, col.first + k * col.stride), is_max);
        }
    }
    scratch[local] = combine(combine(acc.x, acc.y, is_max), combine(acc.z, acc.w, is_max), is_max);
    workgroupBarrier();
    for (var s = LANES / 2u; s > 0u; s >>= 1u) {
        if (local < s) {
            scratch[local] = combine(scratch[local], scratch[local + s], is_max);
        }
        workgroupBarrier();
    }
    if (valid && local == 0u) {
        rows[params.aux + c] = scratch[0];
    }
}
