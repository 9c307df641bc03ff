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

// The modal coefficients of eight corner values: with the corner signs (xi_k, eta_k,
// zeta_k) of `element::hex8::CORNERS`, m1..m7 are 1/8 sum_k h_m(k) c_k for the mode signs
// h = (xi, eta, zeta, xi eta, eta zeta, xi zeta, xi eta zeta). The constant mode m0 drops
// out of every gradient and is left out. (Twin: `kernels::hex8_forces::modes`.)
struct HexModes {
    m1: vec3<f32>,
    m2: vec3<f32>,
    m3: vec3<f32>,
    m4: vec3<f32>,
    m5: vec3<f32>,
    m6: vec3<f32>,
    m7: vec3<f32>,
}

// The modes of corner values c, in three stages of sums and differences (xi, eta, zeta).
fn hex_modes(c: HexCorners) -> HexModes {
    // pairs along xi: corners 0-1, 3-2, 4-5, 7-6
    let s01 = c.c1 + c.c0;
    let d01 = c.c1 - c.c0;
    let s32 = c.c2 + c.c3;
    let d32 = c.c2 - c.c3;
    let s45 = c.c5 + c.c4;
    let d45 = c.c5 - c.c4;
    let s76 = c.c6 + c.c7;
    let d76 = c.c6 - c.c7;
    // along eta, on the bottom (zeta = -1) and top faces
    let ss_b = s32 + s01;
    let sd_b = s32 - s01;
    let ss_t = s76 + s45;
    let sd_t = s76 - s45;
    let ds_b = d32 + d01;
    let dd_b = d32 - d01;
    let ds_t = d76 + d45;
    let dd_t = d76 - d45;
    // along zeta
    return HexModes(
        0.125 * (ds_t + ds_b),
        0.125 * (sd_t + sd_b),
        0.125 * (ss_t - ss_b),
        0.125 * (dd_t + dd_b),
        0.125 * (sd_t - sd_b),
        0.125 * (ds_t - ds_b),
        0.125 * (dd_t - dd_b),
    );
}

// The corner values f_k = 1/8 sum_m h_m(k) F_m of modal forces F (F_0 = 0): the stages of
// `hex_modes` in reverse.
fn hex_corners_of_modes(f: HexModes) -> HexCorners {
    let ss_t = f.m3;
    let ss_b = -f.m3;
    let sd_t = f.m2 + f.m5;
    let sd_b = f.m2 - f.m5;
    let ds_t = f.m1 + f.m6;
    let ds_b = f.m1 - f.m6;
    let dd_t = f.m4 + f.m7;
    let dd_b = f.m4 - f.m7;
    let s76 = ss_t + sd_t;
    let s45 = ss_t - sd_t;
    let s32 = ss_b + sd_b;
    let s01 = ss_b - sd_b;
    let d76 = ds_t + dd_t;
    let d45 = ds_t - dd_t;
    let d32 = ds_b + dd_b;
    let d01 = ds_b - dd_b;
    return HexCorners(
        0.125 * (s01 - d01),
        0.125 * (s01 + d01),
        0.125 * (s32 + d32),
        0.125 * (s32 - d32),
        0.125 * (s45 - d45),
        0.125 * (s45 + d45),
        0.125 * (s76 + d76),
        0.125 * (s76 - d76),
    );
}

// The derivatives of a modal field at p: column b is d/dxi_b.
fn hex_modal_gradient(a: HexModes, p: vec3<f32>) -> mat3x3<f32> {
    return mat3x3<f32>(
        a.m1 + a.m4 * p.y + a.m6 * p.z + a.m7 * (p.y * p.z),
        a.m2 + a.m4 * p.x + a.m5 * p.z + a.m7 * (p.x * p.z),
        a.m3 + a.m5 * p.y + a.m6 * p.x + a.m7 * (p.x * p.y),
    );
}

// Adds Gauss point p (weight 1) to the modal forces f of the map's modes a and the
// displacement's modes b: F_m += det J sigma J^{-T} grad phi_m(p), with det J J^{-T} the
// cofactor matrix (twin: `kernels::hex8_forces::gauss_point`).
fn hex_modal_point(f: HexModes, a: HexModes, b: HexModes, m: Material, p: vec3<f32>) -> HexModes {
    let j = hex_modal_gradient(a, p);
    let d = hex_modal_gradient(b, p);
    let c = cofactor(j);
    let det = dot(j[0], c[0]);
    // du/dx = D J^{-1}, J^{-1} = c^T / det
    let h = (d * transpose(c)) * (1.0 / det);
    let q = elastic_stress(h, m) * c;
    var out = f;
    out.m1 += q[0];
    out.m2 += q[1];
    out.m3 += q[2];
    out.m4 += q[0] * p.y + q[1] * p.x;
    out.m5 += q[1] * p.z + q[2] * p.y;
    out.m6 += q[0] * p.z + q[2] * p.x;
    out.m7 += q[0] * (p.y * p.z) + q[1] * (p.x * p.z) + q[2] * (p.x * p.y);
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
