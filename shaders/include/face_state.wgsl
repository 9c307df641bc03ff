// included by kernels that bind `reference` and `displacement` (array<Split3>) and include
// `velocity.wgsl`

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
