// included by kernels that bind `velocity: array<f32>` (3 per node)

// The velocity of node n.
fn load_v(n: u32) -> vec3<f32> {
    return vec3<f32>(velocity[3u * n], velocity[3u * n + 1u], velocity[3u * n + 2u]);
}
