// included by kernels that bind `velocity: array<f32>` (3 per node)

// The velocity of node n.
fn load_v(n: u32) -> vec3<f32> {
    return vec3<f32>(velocity[3u * n], velocity[3u * n + 1u], velocity[3u * n + 2u]);
}

// The velocity of secondary node `node` relative to its primary point: the velocity of
// `face` (its corners, or NO_FACE first for a rigid plane, which does not move) at the
// contact point's shape-function `weights`.
fn relative_velocity(node: u32, face: vec4<u32>, weights: vec4<f32>) -> vec3<f32> {
    var rel = load_v(node);
    if (face.x != NO_FACE) {
        rel -= face_interpolate(
            weights,
            load_v(face.x),
            load_v(face.y),
            load_v(face.z),
            load_v(face.w),
        );
    }
    return rel;
}
