// Closest-point projection of secondary nodes onto their candidate primary faces: xi, outward
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

// include: velocity

// include: face_state

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
