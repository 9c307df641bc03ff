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
