// Closest-point projection of secondary nodes onto their candidate primary quads: xi, outward
// normal, gap g = -(x1 - y) . n (> 0 penetration) and gap rate -(v1 - v2(xi)) . n
// (twin: `kernels::contact_gap`). Positions are taken relative to the secondary node, so f32
// keeps the precision of the local geometry.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> reference: array<Split3>;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> velocity: array<f32>;
@group(0) @binding(4) var<storage, read> queries: array<ContactQuery>;
@group(0) @binding(5) var<storage, read> candidates: array<u32>;
@group(0) @binding(6) var<storage, read> faces: array<Quad>;
@group(0) @binding(7) var<storage, read_write> points: array<ContactPoint>;

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
fn contact_gap(@builtin(global_invocation_id) gid: vec3<u32>) {
    let q = item_index(gid, params);
    if (q >= params.count) {
        return;
    }
    let query = queries[q];
    let s = query.secondary;
    let rs = reference[s];
    let us = displacement[s];
    let vs = load_v(s);
    var best = open_point();
    var best_d = bitcast<f32>(0x7f800000u); // +inf
    for (var c = query.first; c < query.end; c++) {
        let fi = candidates[c];
        let face = faces[fi].nodes;
        // the secondary node is the origin
        let hit = face_hit(face, corners_from(face, rs, us));
        if (hit.distance < best_d) {
            best_d = hit.distance;
            best = hit_point(fi, hit, vs - face_velocity(face, hit.xi));
        }
    }
    points[q] = best;
}
