// Element geometry shared by the element kernels (twins: `element::hex8`, `element::tet4`),
// written without arrays (corners as named struct fields, loops unrolled) so that every
// value stays in registers on GPU hardware (`tests/shader_rules.rs`).

// The cofactor matrix det(J) J^{-T} of J (columns j0 j1 j2): its columns are
// j1 x j2, j2 x j0, j0 x j1.
fn cofactor(j: mat3x3<f32>) -> mat3x3<f32> {
    return mat3x3<f32>(cross(j[1], j[2]), cross(j[2], j[0]), cross(j[0], j[1]));
}

// Linear elastic stress of the displacement gradient h (h[b] holds du/dx_b).
fn elastic_stress(h: mat3x3<f32>, m: Material) -> mat3x3<f32> {
    if (m.anisotropic != 0u) {
        return voigt_stress(h, m);
    }
    let tr = h[0].x + h[1].y + h[2].z;
    var s = (h + transpose(h)) * m.mu;
    s[0].x += m.lambda * tr;
    s[1].y += m.lambda * tr;
    s[2].z += m.lambda * tr;
    return s;
}

// sigma = C eps with the engineering strains of h in Voigt order (xx, yy, zz, yz, xz, xy)
// (twin: `material::voigt_stress`).
fn voigt_stress(h: mat3x3<f32>, m: Material) -> mat3x3<f32> {
    let e0 = h[0].x;
    let e1 = h[1].y;
    let e2 = h[2].z;
    let e3 = h[2].y + h[1].z;
    let e4 = h[2].x + h[0].z;
    let e5 = h[1].x + h[0].y;
    let s0 = m.c11 * e0 + m.c12 * e1 + m.c13 * e2 + m.c14 * e3 + m.c15 * e4 + m.c16 * e5;
    let s1 = m.c12 * e0 + m.c22 * e1 + m.c23 * e2 + m.c24 * e3 + m.c25 * e4 + m.c26 * e5;
    let s2 = m.c13 * e0 + m.c23 * e1 + m.c33 * e2 + m.c34 * e3 + m.c35 * e4 + m.c36 * e5;
    let s3 = m.c14 * e0 + m.c24 * e1 + m.c34 * e2 + m.c44 * e3 + m.c45 * e4 + m.c46 * e5;
    let s4 = m.c15 * e0 + m.c25 * e1 + m.c35 * e2 + m.c45 * e3 + m.c55 * e4 + m.c56 * e5;
    let s5 = m.c16 * e0 + m.c26 * e1 + m.c36 * e2 + m.c46 * e3 + m.c56 * e4 + m.c66 * e5;
    return mat3x3<f32>(vec3<f32>(s0, s5, s4), vec3<f32>(s5, s1, s3), vec3<f32>(s4, s3, s2));
}

// Eight corner vectors of a hex8 (positions, displacements or forces).
struct HexCorners {
    c0: vec3<f32>,
    c1: vec3<f32>,
    c2: vec3<f32>,
    c3: vec3<f32>,
    c4: vec3<f32>,
    c5: vec3<f32>,
    c6: vec3<f32>,
    c7: vec3<f32>,
}

// dN_k/dxi at p for the corner at c of the parent cube.
fn hex_dn(c: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    let s = vec3<f32>(1.0) + c * p;
    return 0.125 * vec3<f32>(c.x * s.y * s.z, s.x * c.y * s.z, s.x * s.y * c.z);
}

// Adds Gauss point p (weight 1) to the corner forces f: f_k += det J sigma grad N_k.
fn hex_gauss_corners(f: HexCorners, x: HexCorners, u: HexCorners, m: Material, p: vec3<f32>) -> HexCorners {
    let d0 = hex_dn(vec3<f32>(-1.0, -1.0, -1.0), p);
    let d1 = hex_dn(vec3<f32>(1.0, -1.0, -1.0), p);
    let d2 = hex_dn(vec3<f32>(1.0, 1.0, -1.0), p);
    let d3 = hex_dn(vec3<f32>(-1.0, 1.0, -1.0), p);
    let d4 = hex_dn(vec3<f32>(-1.0, -1.0, 1.0), p);
    let d5 = hex_dn(vec3<f32>(1.0, -1.0, 1.0), p);
    let d6 = hex_dn(vec3<f32>(1.0, 1.0, 1.0), p);
    let d7 = hex_dn(vec3<f32>(-1.0, 1.0, 1.0), p);
    // J (columns d/dxi_b) = sum_k x_k dN_k/dxi_b
    let j = mat3x3<f32>(x.c0 * d0.x, x.c0 * d0.y, x.c0 * d0.z)
        + mat3x3<f32>(x.c1 * d1.x, x.c1 * d1.y, x.c1 * d1.z)
        + mat3x3<f32>(x.c2 * d2.x, x.c2 * d2.y, x.c2 * d2.z)
        + mat3x3<f32>(x.c3 * d3.x, x.c3 * d3.y, x.c3 * d3.z)
        + mat3x3<f32>(x.c4 * d4.x, x.c4 * d4.y, x.c4 * d4.z)
        + mat3x3<f32>(x.c5 * d5.x, x.c5 * d5.y, x.c5 * d5.z)
        + mat3x3<f32>(x.c6 * d6.x, x.c6 * d6.y, x.c6 * d6.z)
        + mat3x3<f32>(x.c7 * d7.x, x.c7 * d7.y, x.c7 * d7.z);
    let det = determinant(j);
    let inv_t = cofactor(j) * (1.0 / det);
    let g0 = inv_t * d0;
    let g1 = inv_t * d1;
    let g2 = inv_t * d2;
    let g3 = inv_t * d3;
    let g4 = inv_t * d4;
    let g5 = inv_t * d5;
    let g6 = inv_t * d6;
    let g7 = inv_t * d7;
    // h[b] = sum_k u_k g_k,b
    let h = mat3x3<f32>(u.c0 * g0.x, u.c0 * g0.y, u.c0 * g0.z)
        + mat3x3<f32>(u.c1 * g1.x, u.c1 * g1.y, u.c1 * g1.z)
        + mat3x3<f32>(u.c2 * g2.x, u.c2 * g2.y, u.c2 * g2.z)
        + mat3x3<f32>(u.c3 * g3.x, u.c3 * g3.y, u.c3 * g3.z)
        + mat3x3<f32>(u.c4 * g4.x, u.c4 * g4.y, u.c4 * g4.z)
        + mat3x3<f32>(u.c5 * g5.x, u.c5 * g5.y, u.c5 * g5.z)
        + mat3x3<f32>(u.c6 * g6.x, u.c6 * g6.y, u.c6 * g6.z)
        + mat3x3<f32>(u.c7 * g7.x, u.c7 * g7.y, u.c7 * g7.z);
    let s = elastic_stress(h, m);
    var out = f;
    out.c0 += (s * g0) * det;
    out.c1 += (s * g1) * det;
    out.c2 += (s * g2) * det;
    out.c3 += (s * g3) * det;
    out.c4 += (s * g4) * det;
    out.c5 += (s * g5) * det;
    out.c6 += (s * g6) * det;
    out.c7 += (s * g7) * det;
    return out;
}

// Shape function gradients and volume of a tet4.
struct TetGradients {
    g0: vec3<f32>,
    g1: vec3<f32>,
    g2: vec3<f32>,
    g3: vec3<f32>,
    volume: f32,
}

// The gradients of a tet4 with edges a, b, c from corner 0: J = [a b c] (columns), the rows
// of J^{-1} are (b x c, c x a, a x b) / det.
fn tet_gradients(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> TetGradients {
    let bc = cross(b, c);
    let det = dot(a, bc);
    var out: TetGradients;
    out.g1 = bc / det;
    out.g2 = cross(c, a) / det;
    out.g3 = cross(a, b) / det;
    out.g0 = -(out.g1 + out.g2 + out.g3);
    out.volume = det / 6.0;
    return out;
}
