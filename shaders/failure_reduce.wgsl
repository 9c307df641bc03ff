// The failure survey's workgroup records merged into one, in one workgroup (twin:
// `kernels::failure_reduce`): params.count records from partials[params.aux *
// FAILURE_FIELDS], the merged record written at rows[params.aux2..] (its place in the
// submission's history row). The largest of each index, and the worst point of the largest
// value, the lowest point on a tie: the merges' order does not change the result.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> partials: array<f32>;
@group(0) @binding(2) var<storage, read_write> rows: array<f32>;

const REDUCE_SIZE: u32 = 256u;

var<workgroup> maxima: array<f32, 1280>;
var<workgroup> worst_value: array<f32, 256>;
var<workgroup> worst_point: array<f32, 256>;
var<workgroup> worst_index: array<f32, 256>;

// Whether (value, point) b is worse than a: the larger value, then the lower point; a
// point of -1 is none.
fn worse(a_value: f32, a_point: f32, b_value: f32, b_point: f32) -> bool {
    return b_point >= 0.0 && (a_point < 0.0 || b_value > a_value
        || (b_value == a_value && b_point < a_point));
}

@compute @workgroup_size(256)
fn failure_reduce(@builtin(local_invocation_index) local: u32) {
    var m0 = 0.0;
    var m1 = 0.0;
    var m2 = 0.0;
    var m3 = 0.0;
    var m4 = 0.0;
    var value = -1.0;
    var point = -1.0;
    var index = -1.0;
    for (var g = local; g < params.count; g += REDUCE_SIZE) {
        let o = (params.aux + g) * FAILURE_FIELDS;
        m0 = max(m0, partials[o]);
        m1 = max(m1, partials[o + 1u]);
        m2 = max(m2, partials[o + 2u]);
        m3 = max(m3, partials[o + 3u]);
        m4 = max(m4, partials[o + 4u]);
        if (worse(value, point, partials[o + 5u], partials[o + 6u])) {
            value = partials[o + 5u];
            point = partials[o + 6u];
            index = partials[o + 7u];
        }
    }
    maxima[local] = m0;
    maxima[REDUCE_SIZE + local] = m1;
    maxima[2u * REDUCE_SIZE + local] = m2;
    maxima[3u * REDUCE_SIZE + local] = m3;
    maxima[4u * REDUCE_SIZE + local] = m4;
    worst_value[local] = value;
    worst_point[local] = point;
    worst_index[local] = index;
    workgroupBarrier();
    for (var s = REDUCE_SIZE / 2u; s > 0u; s >>= 1u) {
        if (local < s) {
            for (var q = 0u; q < 5u; q++) {
                let at = REDUCE_SIZE * q + local;
                maxima[at] = max(maxima[at], maxima[at + s]);
            }
            let o = local + s;
            if (worse(worst_value[local], worst_point[local], worst_value[o], worst_point[o])) {
                worst_value[local] = worst_value[o];
                worst_point[local] = worst_point[o];
                worst_index[local] = worst_index[o];
            }
        }
        workgroupBarrier();
    }
    if (local == 0u) {
        for (var q = 0u; q < 5u; q++) {
            rows[params.aux2 + q] = maxima[REDUCE_SIZE * q];
        }
        rows[params.aux2 + 5u] = worst_value[0];
        rows[params.aux2 + 6u] = worst_point[0];
        rows[params.aux2 + 7u] = worst_index[0];
    }
}
