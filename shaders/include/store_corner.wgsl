// included by the element force kernels, which bind `corner_forces: array<f32>`
// (read_write) and take params.aux (C, the corner slots of all blocks) and params.aux2 (B,
// the block's first slot)

// Stores force f of the block's corner slot `slot` (k E + e for corner k of element e):
// component a at corner_forces[a C + B + slot].
fn store_corner(slot: u32, f: vec3<f32>) {
    let c = params.aux;
    let s = params.aux2 + slot;
    corner_forces[s] = f.x;
    corner_forces[c + s] = f.y;
    corner_forces[2u * c + s] = f.z;
}
