// included by kernels that bind `reference`, `displacement: array<Split3>` and
// `faces: array<Quad>`

// The mean of face f's four stored corners at the current displacement (inside a triangle,
// whose fourth slot repeats its third, too): the point the search grid sorts the face by
// (twin: `kernels::face_cells::face_centre`).
fn face_centre(f: u32) -> vec3<f32> {
    let q = faces[f].nodes;
    let c = split_sum(reference[q.x], displacement[q.x])
        + split_sum(reference[q.y], displacement[q.y])
        + split_sum(reference[q.z], displacement[q.z])
        + split_sum(reference[q.w], displacement[q.w]);
    return 0.25 * c;
}

// Face f's box at the current displacement, its corners in absolute f32 coordinates (twin:
// `kernels::face_cells::face_box`): each corner is rounded to f32 once, so the box is within
// a few f32 ulps of the exact one; the narrow phase grows it by far more before it uses it
// to pass over faces (the exact test, relative to the node, decides the rest).
fn face_box(f: u32) -> FaceBox {
    let q = faces[f].nodes;
    let p0 = split_sum(reference[q.x], displacement[q.x]);
    let p1 = split_sum(reference[q.y], displacement[q.y]);
    let p2 = split_sum(reference[q.z], displacement[q.z]);
    let p3 = split_sum(reference[q.w], displacement[q.w]);
    return FaceBox(float3(min(min(p0, p1), min(p2, p3))), float3(max(max(p0, p1), max(p2, p3))));
}
