// The ply failure indices of the step, one evaluation point per invocation (twin:
// `kernels::failure_survey`): the point's ply stress is its operator times its cell's corner
// displacements relative to the first corner (split differences: a translation gives no
// stress and takes no digits), then the Hashin indices (fibre and matrix, tension and
// compression) and the maximum-stress index (twin: `material::failure_indices`). The
// workgroup's record, FAILURE_FIELDS floats at partials[(params.aux + workgroup) *
// FAILURE_FIELDS]: the largest of each index, then its worst point's value, number and index
// (the largest index there; the lowest point on a tie; -1 for none).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> displacement: array<Split3>;
@group(0) @binding(2) var<storage, read> points: array<SurveyPoint>;
@group(0) @binding(3) var<storage, read> operators: array<f32>;
@group(0) @binding(4) var<storage, read> strengths: array<PlyStrength>;
@group(0) @binding(5) var<storage, read_write> partials: array<f32>;

struct PlyStress {
    s11: f32,
    s22: f32,
    s33: f32,
    s12: f32,
    s23: f32,
    s13: f32,
}

struct PlyIndices {
    fibre_tension: f32,
    fibre_compression: f32,
    matrix_tension: f32,
    matrix_compression: f32,
    max_stress: f32,
}

fn normal_ratio(v: f32, t: f32, c: f32) -> f32 {
    return select(-v / c, v / t, v >= 0.0);
}

fn ply_indices(s: PlyStress, k: PlyStrength) -> PlyIndices {
    let long = (s.s12 * s.s12 + s.s13 * s.s13) / (k.s12 * k.s12);
    let trans = (s.s23 * s.s23 - s.s22 * s.s33) / (k.s23 * k.s23);
    let i1 = s.s22 + s.s33;
    var out = PlyIndices(0.0, 0.0, 0.0, 0.0, 0.0);
    if (s.s11 >= 0.0) {
        out.fibre_tension = (s.s11 / k.xt) * (s.s11 / k.xt) + long;
    } else {
        out.fibre_compression = (s.s11 / k.xc) * (s.s11 / k.xc);
    }
    if (i1 >= 0.0) {
        out.matrix_tension = (i1 / k.yt) * (i1 / k.yt) + trans + long;
    } else {
        let r = k.yc / (2.0 * k.s23);
        let q = i1 / (2.0 * k.s23);
        out.matrix_compression = (r * r - 1.0) * i1 / k.yc + q * q + trans + long;
    }
    out.max_stress = max(
        max(normal_ratio(s.s11, k.xt, k.xc), normal_ratio(s.s22, k.yt, k.yc)),
        max(
            max(normal_ratio(s.s33, k.yt, k.yc), abs(s.s12) / k.s12),
            max(abs(s.s13) / k.s12, abs(s.s23) / k.s23),
        ),
    );
    return out;
}

// The stress of point i in its ply's axes.
fn point_stress(i: u32) -> PlyStress {
    let u0 = displacement[points[i].nodes[0]];
    let base = 6u * SURVEY_COLUMNS * points[i].stress_operator;
    var s = PlyStress(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (var k = 1u; k < points[i].corners; k++) {
        let du = split_difference(displacement[points[i].nodes[k]], u0);
        for (var a = 0u; a < 3u; a++) {
            let c = base + 3u * k + a;
            let d = du[a];
            s.s11 += operators[c] * d;
            s.s22 += operators[c + SURVEY_COLUMNS] * d;
            s.s33 += operators[c + 2u * SURVEY_COLUMNS] * d;
            s.s12 += operators[c + 3u * SURVEY_COLUMNS] * d;
            s.s23 += operators[c + 4u * SURVEY_COLUMNS] * d;
            s.s13 += operators[c + 5u * SURVEY_COLUMNS] * d;
        }
    }
    return s;
}

var<workgroup> maxima: array<f32, 320>;
var<workgroup> worst_value: array<f32, 64>;
var<workgroup> worst_point: array<i32, 64>;
var<workgroup> worst_index: array<i32, 64>;

@compute @workgroup_size(64)
fn failure_survey(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let i = item_index(gid, params);
    var f = PlyIndices(0.0, 0.0, 0.0, 0.0, 0.0);
    var value = -1.0;
    var point = -1;
    var index = -1;
    if (i < params.count) {
        f = ply_indices(point_stress(i), strengths[points[i].strength]);
        // the largest index, the first of equals
        value = f.fibre_tension;
        index = 0;
        if (f.fibre_compression > value) {
            value = f.fibre_compression;
            index = 1;
        }
        if (f.matrix_tension > value) {
            value = f.matrix_tension;
            index = 2;
        }
        if (f.matrix_compression > value) {
            value = f.matrix_compression;
            index = 3;
        }
        if (f.max_stress > value) {
            value = f.max_stress;
            index = 4;
        }
        point = i32(i);
    }
    maxima[local] = f.fibre_tension;
    maxima[64u + local] = f.fibre_compression;
    maxima[128u + local] = f.matrix_tension;
    maxima[192u + local] = f.matrix_compression;
    maxima[256u + local] = f.max_stress;
    worst_value[local] = value;
    worst_point[local] = point;
    worst_index[local] = index;
    workgroupBarrier();
    for (var s = 32u; s > 0u; s >>= 1u) {
        if (local < s) {
            for (var q = 0u; q < 5u; q++) {
                maxima[64u * q + local] = max(maxima[64u * q + local], maxima[64u * q + local + s]);
            }
            let o = local + s;
            let better = worst_point[o] >= 0 && (worst_point[local] < 0
                || worst_value[o] > worst_value[local]
                || (worst_value[o] == worst_value[local] && worst_point[o] < worst_point[local]));
            if (better) {
                worst_value[local] = worst_value[o];
                worst_point[local] = worst_point[o];
                worst_index[local] = worst_index[o];
            }
        }
        workgroupBarrier();
    }
    if (local == 0u) {
        let o = (params.aux + wid.x + wid.y * groups.x) * FAILURE_FIELDS;
        for (var q = 0u; q < 5u; q++) {
            partials[o + q] = maxima[64u * q];
        }
        partials[o + 5u] = worst_value[0];
        partials[o + 6u] = f32(worst_point[0]);
        partials[o + 7u] = f32(worst_index[0]);
    }
}
