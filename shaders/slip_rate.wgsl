// Covariant slip rates (v1 - v2(xi)) . tau_a(xi) of each contact point in the convected basis
// of its primary face, zero where the query has no face (twin: `kernels::slip_rate`).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> reference: array<Split3>;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> velocity: array<f32>;
@group(0) @binding(4) var<storage, read> queries: array<ContactQuery>;
@group(0) @binding(5) var<storage, read> faces: array<Quad>;
@group(0) @binding(6) var<storage, read> points: array<ContactPoint>;
@group(0) @binding(7) var<storage, read_write> slip: array<vec2<f32>>;

fn load_v(n: u32) -> vec3<f32> {
    return vec3<f32>(velocity[3u * n], velocity[3u * n + 1u], velocity[3u * n + 2u]);
}

// The corners of face f at u relative to a point (split reference rs, displacement us).
fn corners_from(f: vec4<u32>, rs: Split3, us: Split3) -> FaceCorners {
    return FaceCorners(
        split_difference(reference[f.x], rs) + split_difference(displacement[f.x], us),
        split_difference(reference[f.y], rs) + split_difference(displacement[f.y], us),
        split_difference(reference[f.z], rs) + split_difference(displacement[f.z], us),
        split_difference(reference[f.w], rs) + split_difference(displacement[f.w], us),
    );
}

// The velocity of face f at xi.
fn face_velocity(f: vec4<u32>, xi: vec2<f32>) -> vec3<f32> {
    return face_interpolate(face_shape(f, xi), load_v(f.x), load_v(f.y), load_v(f.z), load_v(f.w));
}

@compute @workgroup_size(64)
fn slip_rate(@builtin(global_invocation_id) gid: vec3<u32>) {
    let q = item_index(gid, params);
    if (q >= params.count) {
        return;
    }
    let cp = points[q];
    if (cp.face == NO_FACE) {
        slip[q] = vec2<f32>(0.0);
        return;
    }
    let s = queries[q].secondary;
    let rs = reference[s];
    let us = displacement[s];
    let face = faces[cp.face].nodes;
    let xi = vec2<f32>(cp.xi.x, cp.xi.y);
    let g = face_geometry(face, corners_from(face, rs, us), xi);
    let rel = load_v(s) - face_velocity(face, xi);
    slip[q] = vec2<f32>(dot(rel, g.t1), dot(rel, g.t2));
}
