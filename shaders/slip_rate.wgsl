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

// include: velocity

// include: face_state

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
