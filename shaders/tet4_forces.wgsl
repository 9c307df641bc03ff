// Corner forces of linear elastic tet4 elements, f_k = V sigma grad N_k with the element's
// constant strain (twin: `kernels::tet4_forces`). One invocation per element. The corner
// forces follow the hex8 corners in the same array: corner k of tet t, component a, at
// params.aux + 12 t + 3 k + a, so node_gather sums hexes and tets alike.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> reference: array<Split3>;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> tets: array<Tet4>;
@group(0) @binding(4) var<storage, read> materials: array<Material>;
@group(0) @binding(5) var<storage, read_write> corner_forces: array<f32>;

@compute @workgroup_size(64)
fn tet4_forces(@builtin(global_invocation_id) gid: vec3<u32>) {
    let t = item_index(gid, params);
    if (t >= params.count) {
        return;
    }
    let tet = tets[t];
    let m = materials[tet.material];
    // edges from corner 0 and displacements relative to corner 0, so f32 keeps the
    // element's own scale
    let r0 = reference[tet.nodes[0]];
    let u0 = displacement[tet.nodes[0]];
    let a = split_difference(reference[tet.nodes[1]], r0);
    let b = split_difference(reference[tet.nodes[2]], r0);
    let c = split_difference(reference[tet.nodes[3]], r0);
    let u1 = split_difference(displacement[tet.nodes[1]], u0);
    let u2 = split_difference(displacement[tet.nodes[2]], u0);
    let u3 = split_difference(displacement[tet.nodes[3]], u0);
    let tg = tet_gradients(a, b, c);
    let g1 = tg.grads[1];
    let g2 = tg.grads[2];
    let g3 = tg.grads[3];
    // H[a][b] = sum_k u_k,a g_k,b (column b of h holds H[.][b]); corner 0 moves by zero
    let h = mat3x3<f32>(
        u1 * g1.x + u2 * g2.x + u3 * g3.x,
        u1 * g1.y + u2 * g2.y + u3 * g3.y,
        u1 * g1.z + u2 * g2.z + u3 * g3.z,
    );
    let tr = h[0].x + h[1].y + h[2].z;
    var s = (h + transpose(h)) * m.mu;
    s[0].x += m.lambda * tr;
    s[1].y += m.lambda * tr;
    s[2].z += m.lambda * tr;
    for (var k = 0u; k < 4u; k++) {
        let f = (s * tg.grads[k]) * tg.volume;
        let o = params.aux + 12u * t + 3u * k;
        corner_forces[o] = f.x;
        corner_forces[o + 1u] = f.y;
        corner_forces[o + 2u] = f.z;
    }
}
