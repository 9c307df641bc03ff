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

const HEX_CORNERS: array<vec3<f32>, 8> = array<vec3<f32>, 8>(
    vec3<f32>(-1.0, -1.0, -1.0),
    vec3<f32>(1.0, -1.0, -1.0),
    vec3<f32>(1.0, 1.0, -1.0),
    vec3<f32>(-1.0, 1.0, -1.0),
    vec3<f32>(-1.0, -1.0, 1.0),
    vec3<f32>(1.0, -1.0, 1.0),
    vec3<f32>(1.0, 1.0, 1.0),
    vec3<f32>(-1.0, 1.0, 1.0),
);

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
    let gp = 0.57735026918962576;
    for (var g = 0u; g < 8u; g++) {
        let p = HEX_CORNERS[g] * gp;
        // parent derivatives and the Jacobian J[a][b] = sum_k x_k,a dN_k/dxi_b (columns: b)
        var dn: array<vec3<f32>, 8>;
        var j0 = vec3<f32>(0.0); // column d/dxi
        var j1 = vec3<f32>(0.0);
        var j2 = vec3<f32>(0.0);
        for (var k = 0u; k < 8u; k++) {
            let c = HEX_CORNERS[k];
            let s = vec3<f32>(1.0) + c * p;
            dn[k] = 0.125 * vec3<f32>(c.x * s.y * s.z, s.x * c.y * s.z, s.x * s.y * c.z);
            j0 += x[k] * dn[k].x;
            j1 += x[k] * dn[k].y;
            j2 += x[k] * dn[k].z;
        }
        let jm = mat3x3<f32>(j0, j1, j2); // columns: jm[b][a] = J[a][b]
        let det = determinant(jm);
        // the rows of J^{-1} are (j1 x j2, j2 x j0, j0 x j1) / det, so the matrix with these
        // as columns is J^{-T}, and grad N = J^{-T} dN/dxi
        let inv_t = mat3x3<f32>(cross(j1, j2), cross(j2, j0), cross(j0, j1)) * (1.0 / det);
        var h = mat3x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
        var grads: array<vec3<f32>, 8>;
        for (var k = 0u; k < 8u; k++) {
            let gk = inv_t * dn[k];
            grads[k] = gk;
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
