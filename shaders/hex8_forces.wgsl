// Corner forces of linear elastic hex8 elements, f_e = sum_g det J B^T sigma over the 2x2x2
// Gauss points (twin: `kernels::hex8_forces`), in the element's modal form (a third of the
// Gauss-point sum's arithmetic; `shared/element.wgsl`).
// One invocation per element; node_gather sums the corners to the nodes in a fixed order.
//
// Layouts (neighbouring invocations touch neighbouring words, `element::CornerLayout`): node
// k of element e at block_nodes[k E + e] (E = params.count); the corner forces
// component-major, component a of corner k of element e at corner_forces[a C + B + k E + e]
// (C = params.aux, the corner slots of all blocks; B = params.aux2, the block's first slot).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> reference: array<Split3>;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> block_nodes: array<u32>;
@group(0) @binding(4) var<storage, read> block_material: array<u32>;
@group(0) @binding(5) var<storage, read> materials: array<Material>;
@group(0) @binding(6) var<storage, read_write> corner_forces: array<f32>;

const GAUSS: f32 = 0.57735026918962576;

// include: store_corner

@compute @workgroup_size(64)
fn hex8_forces(@builtin(global_invocation_id) gid: vec3<u32>) {
    let e = item_index(gid, params);
    let ne = params.count;
    if (e >= ne) {
        return;
    }
    let n0 = block_nodes[e];
    let n1 = block_nodes[ne + e];
    let n2 = block_nodes[2u * ne + e];
    let n3 = block_nodes[3u * ne + e];
    let n4 = block_nodes[4u * ne + e];
    let n5 = block_nodes[5u * ne + e];
    let n6 = block_nodes[6u * ne + e];
    let n7 = block_nodes[7u * ne + e];
    // corner positions and displacements relative to corner 0 (the gradient of a constant is
    // zero), so f32 keeps the element's own scale
    let r0 = reference[n0];
    let d0 = displacement[n0];
    let zero = vec3<f32>(0.0);
    let x = HexCorners(
        zero,
        split_difference(reference[n1], r0),
        split_difference(reference[n2], r0),
        split_difference(reference[n3], r0),
        split_difference(reference[n4], r0),
        split_difference(reference[n5], r0),
        split_difference(reference[n6], r0),
        split_difference(reference[n7], r0),
    );
    let u = HexCorners(
        zero,
        split_difference(displacement[n1], d0),
        split_difference(displacement[n2], d0),
        split_difference(displacement[n3], d0),
        split_difference(displacement[n4], d0),
        split_difference(displacement[n5], d0),
        split_difference(displacement[n6], d0),
        split_difference(displacement[n7], d0),
    );
    let m = materials[block_material[e]];
    let a = hex_modes(x);
    let b = hex_modes(u);
    // the twin's order of the Gauss points (xi fastest)
    let q = GAUSS;
    let zero_modes = HexModes(zero, zero, zero, zero, zero, zero, zero);
    var fm = hex_modal_point(zero_modes, a, b, m, vec3<f32>(-q, -q, -q));
    fm = hex_modal_point(fm, a, b, m, vec3<f32>(q, -q, -q));
    fm = hex_modal_point(fm, a, b, m, vec3<f32>(-q, q, -q));
    fm = hex_modal_point(fm, a, b, m, vec3<f32>(q, q, -q));
    fm = hex_modal_point(fm, a, b, m, vec3<f32>(-q, -q, q));
    fm = hex_modal_point(fm, a, b, m, vec3<f32>(q, -q, q));
    fm = hex_modal_point(fm, a, b, m, vec3<f32>(-q, q, q));
    fm = hex_modal_point(fm, a, b, m, vec3<f32>(q, q, q));
    let f = hex_corners_of_modes(fm);
    store_corner(e, f.c0);
    store_corner(ne + e, f.c1);
    store_corner(2u * ne + e, f.c2);
    store_corner(3u * ne + e, f.c3);
    store_corner(4u * ne + e, f.c4);
    store_corner(5u * ne + e, f.c5);
    store_corner(6u * ne + e, f.c6);
    store_corner(7u * ne + e, f.c7);
}
