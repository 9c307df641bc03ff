// Element geometry shared by the element kernels (twins: `element::hex8`, `element::tet4`).

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
    // the rows of J^{-1} are (j1 x j2, j2 x j0, j0 x j1) / det, so the matrix with these as
    // columns is J^{-T}, and grad N = J^{-T} dN/dxi
    let inv_t = mat3x3<f32>(cross(j1, j2), cross(j2, j0), cross(j0, j1)) * (1.0 / out.det);
    for (var k = 0u; k < 8u; k++) {
        out.grads[k] = inv_t * dn[k];
    }
    return out;
}

// Shape function gradients and volume of a tet4.
struct TetGradients {
    grads: array<vec3<f32>, 4>,
    volume: f32,
}

// The gradients of a tet4 with edges a, b, c from corner 0: J = [a b c] (columns), the rows
// of J^{-1} are (b x c, c x a, a x b) / det.
fn tet_gradients(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> TetGradients {
    let bc = cross(b, c);
    let det = dot(a, bc);
    let g1 = bc / det;
    let g2 = cross(c, a) / det;
    let g3 = cross(a, b) / det;
    var out: TetGradients;
    out.grads = array<vec3<f32>, 4>(-(g1 + g2 + g3), g1, g2, g3);
    out.volume = det / 6.0;
    return out;
}
