// Each element's stable explicit step, 2 / sqrt(max_i sum_j |K_ij| / m_i): Gershgorin's bound
// on the largest eigenvalue of M_e^-1 K_e with the row-sum lumped mass (twin:
// `kernels::stable_step`, the same bound as `integrate::stable_step::element_stable_step`).
// One invocation per element of one block, its connectivity column by column as the force
// kernels read it (corner k of element e at `k params.count + e`): hex8s where params.aux is
// 0 (2x2x2 Gauss, as the force kernel), tet4s where it is 1; element e's step goes to
// `params.aux2 + e`. The smallest over the mesh bounds the step of central difference
// (Irons' element eigenvalue inequality).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> reference: array<Split3>;
@group(0) @binding(2) var<storage, read> block_nodes: array<u32>;
@group(0) @binding(3) var<storage, read> block_material: array<u32>;
@group(0) @binding(4) var<storage, read> materials: array<Material>;
@group(0) @binding(5) var<storage, read_write> steps: array<f32>;

// Corner k of element e of the block.
fn corner(e: u32, k: u32) -> u32 {
    return block_nodes[k * params.count + e];
}

// This kernel runs once, at setup, and keeps the plain per-corner arrays of the textbook
// form (the per-step kernels use the array-free forms of `shared/element.wgsl`).

// The hex8's corners in its parent cube; the 2x2x2 Gauss points are these times 1/sqrt(3).
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

// Shape function gradients and det J at one Gauss point.
struct HexGauss {
    grads: array<vec3<f32>, 8>,
    det: f32,
}

// The gradients and det J at Gauss point g of a hex8 with corners x (relative to any origin).
fn hex_gauss(x: array<vec3<f32>, 8>, g: u32) -> HexGauss {
    let p = HEX_CORNERS[g] * 0.57735026918962576;
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
    var out: HexGauss;
    out.det = determinant(mat3x3<f32>(j0, j1, j2));
    let inv_t = cofactor(mat3x3<f32>(j0, j1, j2)) * (1.0 / out.det);
    for (var k = 0u; k < 8u; k++) {
        out.grads[k] = inv_t * dn[k];
    }
    return out;
}

// Entry (i, j) of the 3x3 stiffness block of nodes a, b for one integration point with weight
// w: w (lambda ga_i gb_j + mu ga_j gb_i + mu delta_ij ga . gb), or w ga_k C_ikjl gb_l.
fn block(ga: vec3<f32>, gb: vec3<f32>, m: Material, w: f32) -> mat3x3<f32> {
    if (m.anisotropic != 0u) {
        // column j: the force on a of a unit displacement along j at b, sigma(e_j gb^T) ga
        let ex = vec3<f32>(1.0, 0.0, 0.0);
        let ey = vec3<f32>(0.0, 1.0, 0.0);
        let ez = vec3<f32>(0.0, 0.0, 1.0);
        let kx = voigt_stress(mat3x3<f32>(ex * gb.x, ex * gb.y, ex * gb.z), m) * ga;
        let ky = voigt_stress(mat3x3<f32>(ey * gb.x, ey * gb.y, ey * gb.z), m) * ga;
        let kz = voigt_stress(mat3x3<f32>(ez * gb.x, ez * gb.y, ez * gb.z), m) * ga;
        return mat3x3<f32>(kx, ky, kz) * w;
    }
    // columns j: column j holds the entries (., j)
    let d = m.mu * dot(ga, gb);
    var k = mat3x3<f32>(
        m.lambda * ga * gb.x + m.mu * gb * ga.x,
        m.lambda * ga * gb.y + m.mu * gb * ga.y,
        m.lambda * ga * gb.z + m.mu * gb * ga.z,
    );
    k[0].x += d;
    k[1].y += d;
    k[2].z += d;
    return k * w;
}

// The largest absolute row sum of rows 3a..3a+3 given the node's eight blocks, over its mass.
fn row_bound(k: array<mat3x3<f32>, 8>, mass: f32) -> f32 {
    var r = vec3<f32>(0.0);
    for (var b = 0u; b < 8u; b++) {
        r += abs(k[b][0]) + abs(k[b][1]) + abs(k[b][2]);
    }
    return max(r.x, max(r.y, r.z)) / mass;
}

fn hex_step(e: u32) -> f32 {
    let m = materials[block_material[e]];
    let r0 = reference[corner(e, 0u)];
    var x: array<vec3<f32>, 8>;
    for (var k = 0u; k < 8u; k++) {
        x[k] = split_difference(reference[corner(e, k)], r0);
    }
    // gradients and weights (det J) at the eight Gauss points
    var grads: array<vec3<f32>, 64>;
    var dets: array<f32, 8>;
    for (var g = 0u; g < 8u; g++) {
        let hg = hex_gauss(x, g);
        dets[g] = hg.det;
        for (var k = 0u; k < 8u; k++) {
            grads[8u * g + k] = hg.grads[k];
        }
    }
    var w2 = 0.0;
    for (var a = 0u; a < 8u; a++) {
        var k: array<mat3x3<f32>, 8>;
        var mass = 0.0;
        for (var b = 0u; b < 8u; b++) {
            k[b] = mat3x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
        }
        let ca = HEX_CORNERS[a];
        for (var g = 0u; g < 8u; g++) {
            let p = HEX_CORNERS[g] * 0.57735026918962576;
            let s = vec3<f32>(1.0) + ca * p;
            // row-sum lumping: m_a = rho sum_g N_a det J
            mass += m.density * 0.125 * s.x * s.y * s.z * dets[g];
            let ga = grads[8u * g + a];
            for (var b = 0u; b < 8u; b++) {
                k[b] += block(ga, grads[8u * g + b], m, dets[g]);
            }
        }
        w2 = max(w2, row_bound(k, mass));
    }
    return 2.0 / sqrt(w2);
}

fn tet_step(t: u32) -> f32 {
    let m = materials[block_material[t]];
    let r0 = reference[corner(t, 0u)];
    let a = split_difference(reference[corner(t, 1u)], r0);
    let b = split_difference(reference[corner(t, 2u)], r0);
    let c = split_difference(reference[corner(t, 3u)], r0);
    let tg = tet_gradients(a, b, c);
    let grads = array<vec3<f32>, 4>(tg.g0, tg.g1, tg.g2, tg.g3);
    let vol = tg.volume;
    let mass = m.density * vol / 4.0;
    var w2 = 0.0;
    for (var i = 0u; i < 4u; i++) {
        var k: array<mat3x3<f32>, 8>;
        for (var j = 0u; j < 8u; j++) {
            k[j] = mat3x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
        }
        for (var j = 0u; j < 4u; j++) {
            k[j] = block(grads[i], grads[j], m, vol);
        }
        w2 = max(w2, row_bound(k, mass));
    }
    return 2.0 / sqrt(w2);
}

@compute @workgroup_size(64)
fn stable_step(@builtin(global_invocation_id) gid: vec3<u32>) {
    let e = item_index(gid, params);
    if (e >= params.count) {
        return;
    }
    if (params.aux == 0u) {
        steps[params.aux2 + e] = hex_step(e);
    } else {
        steps[params.aux2 + e] = tet_step(e);
    }
}
