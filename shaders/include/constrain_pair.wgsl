// included by kernels that bind `step: Step`, `grid: SearchGrid`, `reference`,
// `displacement`, `velocity`, `acceleration`, `pairs`, `points`, `faces`, `constraints`
// (read_write), `keys` (read_write), `rigid` and `results` (the last step's report), and
// include `velocity.wgsl`

// The constraint of one pair (twin: `kernels::contact_constraints`); see
// `contact_constraints.wgsl`.

fn load_a(n: u32) -> vec3<f32> {
    return vec3<f32>(acceleration[3u * n], acceleration[3u * n + 1u], acceleration[3u * n + 2u]);
}

// The impulses pair p's sweeps start from (the warm start), against a face or a rigid body
// in reach: its last step's, as the report left them, the tangential one without its part
// along the new normal `nrm` and returned onto the law's set.
fn warm_impulses(p: u32, nrm: vec3<f32>) -> vec4<f32> {
    let o = SLOT * p;
    let jn = max(results[o + SLOT_NORMAL_IMPULSE], 0.0);
    let t = vec3<f32>(
        results[o + SLOT_FRICTION_IMPULSE],
        results[o + SLOT_FRICTION_IMPULSE + 1u],
        results[o + SLOT_FRICTION_IMPULSE + 2u],
    );
    return vec4<f32>(law_projected(pairs[p].law, pairs[p].mu, t, nrm, jn), jn);
}

// Pair p's constraint and bucket key (`other`: the key of a pair on no face).
fn constrain_pair(p: u32, other: u32) {
    let pair = pairs[p];
    let n = pair.node;
    var face = vec4<u32>(NO_FACE);
    var w = vec4<f32>(0.0);
    var nrm = vec3<f32>(0.0);
    var gap = 0.0;
    var reach = false;
    var key = other;
    let vn = load_v(n);
    // v_{n-1/2} of the relative motion: v* - dt a_n
    var rel_before = vn - step.dt * load_a(n);
    if (pair.query != NO_FACE) {
        let pt = points[pair.query];
        if (pt.face != NO_FACE) {
            nrm = vec3_of(pt.normal);
            gap = pt.gap;
            reach = gap >= -max(grid.margin, 1e-30);
            if (reach) {
                face = faces[pt.face].nodes;
                w = face_shape(face, vec2<f32>(pt.xi.x, pt.xi.y));
                key = pt.face;
                rel_before -= face_interpolate(
                    w,
                    load_v(face.x) - step.dt * load_a(face.x),
                    load_v(face.y) - step.dt * load_a(face.y),
                    load_v(face.z) - step.dt * load_a(face.z),
                    load_v(face.w) - step.dt * load_a(face.w),
                );
            }
        }
    } else if (pair.body != NO_FACE) {
        let b = rigid[pair.body].node;
        let r = split_difference(reference[n], reference[b])
            + (split_value(displacement[n]) - split_value(displacement[b]));
        let sd = rigid_distance(rigid[pair.body], r);
        nrm = sd.n;
        gap = -sd.d;
        reach = gap >= -4.0 * step.dt * length(vn - load_v(b));
        if (reach) {
            face = vec4<u32>(b);
            w = vec4<f32>(1.0, 0.0, 0.0, 0.0);
            rel_before -= load_v(b) - step.dt * load_a(b);
        }
    } else {
        nrm = vec3_of(pair.normal);
        let x = split_difference(reference[n], pair.point) + split_value(displacement[n]);
        gap = -dot(x, nrm);
        reach = gap >= -4.0 * step.dt * length(vn);
    }
    var warm = vec4<f32>(0.0);
    if (reach && face.x != NO_FACE) {
        warm = warm_impulses(p, nrm);
    }
    constraints[p] = Constraint(
        array<u32, 4>(face.x, face.y, face.z, face.w),
        array<f32, 4>(w.x, w.y, w.z, w.w),
        float3(nrm),
        gap,
        0.0,
        warm.w,
        float3(warm.xyz),
        float3(rel_before),
        select(0u, 1u, reach),
    );
    keys[p] = key;
}
