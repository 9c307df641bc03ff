// Corner forces of linear elastic tet4 elements, f_k = V sigma grad N_k with the element's
// constant strain (twin: `kernels::tet4_forces`). One invocation per element. Layouts as in
// `hex8_forces.wgsl`: node k of tet t at block_nodes[k T + t] (T = params.count); component a
// of corner k at corner_forces[a C + B + k T + t] (C = params.aux, the corner slots of all
// blocks; B = params.aux2, the block's first slot), so node_gather sums every block alike.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> reference: array<Split3>;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> block_nodes: array<u32>;
@group(0) @binding(4) var<storage, read> block_material: array<u32>;
@group(0) @binding(5) var<storage, read> materials: array<Material>;
@group(0) @binding(6) var<storage, read_write> corner_forces: array<f32>;

// include: store_corner

@compute @workgroup_size(64)
fn tet4_forces(@builtin(global_invocation_id) gid: vec3<u32>) {
    let t = item_index(gid, params);
    let nt = params.count;
    if (t >= nt) {
        return;
    }
    let n0 = block_nodes[t];
    let n1 = block_nodes[nt + t];
    let n2 = block_nodes[2u * nt + t];
    let n3 = block_nodes[3u * nt + t];
    let m = materials[block_material[t]];
    // edges from corner 0 and displacements relative to corner 0, so f32 keeps the
    // element's own scale
    let r0 = reference[n0];
    let d0 = displacement[n0];
    let tg = tet_gradients(
        split_difference(reference[n1], r0),
        split_difference(reference[n2], r0),
        split_difference(reference[n3], r0),
    );
    let u1 = split_difference(displacement[n1], d0);
    let u2 = split_difference(displacement[n2], d0);
    let u3 = split_difference(displacement[n3], d0);
    // h[b] = du/dx_b = sum_k u_k g_k,b; corner 0 moves by zero
    let h = mat3x3<f32>(
        u1 * tg.g1.x + u2 * tg.g2.x + u3 * tg.g3.x,
        u1 * tg.g1.y + u2 * tg.g2.y + u3 * tg.g3.y,
        u1 * tg.g1.z + u2 * tg.g2.z + u3 * tg.g3.z,
    );
    let sv = elastic_stress(h, m) * tg.volume;
    store_corner(t, sv * tg.g0);
    store_corner(nt + t, sv * tg.g1);
    store_corner(2u * nt + t, sv * tg.g2);
    store_corner(3u * nt + t, sv * tg.g3);
}
