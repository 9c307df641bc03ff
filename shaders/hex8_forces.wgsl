// Corner forces of linear elastic hex8 elements, f_e = sum_g det J B^T sigma over the 2x2x2
// Gauss points (twin: `kernels::hex8_forces`). One invocation per element; node_gather sums the
// corners to the nodes in a fixed order.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> reference: array<Split3>;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> hexes: array<Hex8>;
@group(0) @binding(4) var<storage, read> materials: array<Material>;
// 24 per element: corner k, component a at 24 e + 3 k + a
@group(0) @binding(5) var<storage, read_write> corner_forces: array<f32>;

@compute @workgroup_size(64)
fn hex8_forces(@builtin(global_invocation_id) gid: vec3<u32>) {
    let e = item_index(gid, params);
    if (e >= params.count) {
        return;
    }
    let hex = hexes[e];
    let m = materials[hex.material];
    // corner positions and displacements relative to corner 0 (the gradient of a constant is
    // zero), so f32 keeps the element's own scale
    let r0 = reference[hex.nodes[0]];
    let u0 = displacement[hex.nodes[0]];
    var x: array<vec3<f32>, 8>;
    var u: array<vec3<f32>, 8>;
    for (var k = 0u; k < 8u; k++) {
        let n = hex.nodes[k];
        x[k] = split_difference(reference[n], r0);
        u[k] = split_difference(displacement[n], u0);
    }
    var f: array<vec3<f32>, 8>;
    for (var k = 0u; k < 8u; k++) {
        f[k] = vec3<f32>(0.0);
    }
    for (var g = 0u; g < 8u; g++) {
        let hg = hex_gauss(x, g);
        let det = hg.det;
        var h = mat3x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
        let grads = hg.grads;
        for (var k = 0u; k < 8u; k++) {
            let gk = grads[k];
            // H[a][b] = sum_k u_k,a g_k,b; column b of h holds H[.][b]
            h[0] += u[k] * gk.x;
            h[1] += u[k] * gk.y;
            h[2] += u[k] * gk.z;
        }
        let tr = h[0].x + h[1].y + h[2].z;
        var s = (h + transpose(h)) * m.mu;
        s[0].x += m.lambda * tr;
        s[1].y += m.lambda * tr;
        s[2].z += m.lambda * tr;
        for (var k = 0u; k < 8u; k++) {
            // (sigma g_k) * det; sigma is symmetric
            f[k] += (s * grads[k]) * det;
        }
    }
    for (var k = 0u; k < 8u; k++) {
        let o = 24u * e + 3u * k;
        corner_forces[o] = f[k].x;
        corner_forces[o + 1u] = f[k].y;
        corner_forces[o + 2u] = f[k].z;
    }
}
