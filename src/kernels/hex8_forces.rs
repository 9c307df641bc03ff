//! CPU twin of `shaders/hex8_forces.wgsl`: internal nodal forces of linear elastic hex8
//! elements, $f_e = \sum_g w_g \det J\, B^T \sigma$, with
//! the material's stress $\sigma(\varepsilon)$ ([`Elastic::stress`]) and
//! $\varepsilon = \mathrm{sym}(\sum_k u_k \otimes \nabla N_k)$ at each of the 2x2x2 Gauss points.

use rayon::prelude::*;

use super::ElementData;
use crate::element::{hex8, ElementKind};
use crate::material::Elastic;

/// Corner forces of one element from its reference corners and corner displacements.
///
/// Written in the hex8's modal form, which gives the same forces as the Gauss-point sum over
/// $B^T \sigma$ with a third of the work: with the corner signs $(\xi_k, \eta_k, \zeta_k)$
/// of [`hex8::CORNERS`] and the modes $h_m = (1, \xi_k, \eta_k, \zeta_k, \xi_k\eta_k,
/// \eta_k\zeta_k, \xi_k\zeta_k, \xi_k\eta_k\zeta_k)$, the map is
/// $x(\xi) = \sum_m a_m \phi_m(\xi)$ with $a_m = \tfrac18 \sum_k h_m(k)\, x_k$, so the
/// Jacobian at a Gauss point takes 4 terms per column instead of 8, and likewise the
/// displacement gradient. The corner forces $f_k = \sum_g \det J_g\, \sigma_g J_g^{-T}
/// \nabla_\xi N_k(g)$ collect, per mode, $F_m$, and $f_k = \tfrac18 \sum_m h_m(k) F_m$.
pub(crate) fn element_forces(x: &[[f64; 3]; 8], u: &[[f64; 3]; 8], m: &Elastic) -> [[f64; 3]; 8] {
    // the map's modes from corners relative to the first: the Jacobian depends on
    // differences only, and these keep their digits where absolute coordinates are large
    let a = modes(&x.map(|p| [p[0] - x[0][0], p[1] - x[0][1], p[2] - x[0][2]]));
    let b = modes(u);
    let mut f_modes = [[0.0; 3]; 8];
    let g = 1.0 / 3f64.sqrt();
    for p in [-g, g] {
        for q in [-g, g] {
            for r in [-g, g] {
                // point (xi, eta, zeta) = (r, q, p): the order of hex8::gauss_points
                gauss_point(&a, &b, [r, q, p], m, &mut f_modes);
            }
        }
    }
    let mut f = [[0.0; 3]; 8];
    for (k, fk) in f.iter_mut().enumerate() {
        let h = mode_signs(k);
        for c in 0..3 {
            let mut sum = 0.0;
            for m in 1..8 {
                sum += h[m] * f_modes[m][c];
            }
            fk[c] = 0.125 * sum;
        }
    }
    f
}

/// The mode signs $h_m(k)$ of corner k.
fn mode_signs(k: usize) -> [f64; 8] {
    let [s, t, v] = hex8::CORNERS[k];
    [1.0, s, t, v, s * t, t * v, s * v, s * t * v]
}

/// The modal coefficients $a_m = \tfrac18 \sum_k h_m(k)\, x_k$ of corner values.
fn modes(x: &[[f64; 3]; 8]) -> [[f64; 3]; 8] {
    let mut a = [[0.0; 3]; 8];
    for (k, xk) in x.iter().enumerate() {
        let h = mode_signs(k);
        for m in 0..8 {
            for c in 0..3 {
                a[m][c] += h[m] * xk[c];
            }
        }
    }
    a.map(|v| v.map(|c| 0.125 * c))
}

/// The derivatives of a modal field at xi: column b is d/dxi_b, row a the component.
fn modal_gradient(a: &[[f64; 3]; 8], [s, t, v]: [f64; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|c| {
        [
            a[1][c] + a[4][c] * t + a[6][c] * v + a[7][c] * t * v,
            a[2][c] + a[4][c] * s + a[5][c] * v + a[7][c] * s * v,
            a[3][c] + a[5][c] * t + a[6][c] * s + a[7][c] * s * t,
        ]
    })
}

/// Adds one Gauss point's $\det J\, \sigma J^{-T}$ to the modal forces.
fn gauss_point(
    a: &[[f64; 3]; 8],
    b: &[[f64; 3]; 8],
    xi: [f64; 3],
    m: &Elastic,
    f_modes: &mut [[f64; 3]; 8],
) {
    let j = modal_gradient(a, xi);
    let d = modal_gradient(b, xi);
    let cof = [
        [
            j[1][1] * j[2][2] - j[1][2] * j[2][1],
            j[1][2] * j[2][0] - j[1][0] * j[2][2],
            j[1][0] * j[2][1] - j[1][1] * j[2][0],
        ],
        [
            j[0][2] * j[2][1] - j[0][1] * j[2][2],
            j[0][0] * j[2][2] - j[0][2] * j[2][0],
            j[0][1] * j[2][0] - j[0][0] * j[2][1],
        ],
        [
            j[0][1] * j[1][2] - j[0][2] * j[1][1],
            j[0][2] * j[1][0] - j[0][0] * j[1][2],
            j[0][0] * j[1][1] - j[0][1] * j[1][0],
        ],
    ];
    let det = j[0][0] * cof[0][0] + j[0][1] * cof[0][1] + j[0][2] * cof[0][2];
    // J^{-1} = cof^T / det: H = D J^{-1}, H_ac = sum_b D_ab cof_cb / det
    let h: [[f64; 3]; 3] = std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            (d[r][0] * cof[c][0] + d[r][1] * cof[c][1] + d[r][2] * cof[c][2]) / det
        })
    });
    let sigma = m.stress(&h);
    // det J sigma J^{-T} = sigma cof: Q_ab = sum_c sigma_ac cof_cb
    let qm: [[f64; 3]; 3] = std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            sigma[r][0] * cof[0][c] + sigma[r][1] * cof[1][c] + sigma[r][2] * cof[2][c]
        })
    });
    let [s, t, v] = xi;
    for r in 0..3 {
        let (q0, q1, q2) = (qm[r][0], qm[r][1], qm[r][2]);
        f_modes[1][r] += q0;
        f_modes[2][r] += q1;
        f_modes[3][r] += q2;
        f_modes[4][r] += q0 * t + q1 * s;
        f_modes[5][r] += q1 * v + q2 * t;
        f_modes[6][r] += q0 * v + q2 * s;
        f_modes[7][r] += q0 * t * v + q1 * s * v + q2 * s * t;
    }
}

/// Corner forces of every hex8: `corner_forces[8 e + k]` is corner k of hex8 e (overwrites
/// it; the caller passes the hex8 block's part of the corner array, see
/// [`crate::element::CornerLayout`]). [`super::node_gather`] sums them to the nodes.
/// Elements run on all threads; each writes its own corners, so the result does not depend
/// on the thread count.
pub fn hex8_forces(data: &ElementData, u: &[[f64; 3]], corner_forces: &mut [[f64; 3]]) {
    hex8_forces_but(data, u, corner_forces, &[]);
}

/// [`hex8_forces`] but for the elements `skip` marks (their corners left as they were; an
/// empty `skip` marks none).
pub(crate) fn hex8_forces_but(
    data: &ElementData,
    u: &[[f64; 3]],
    corner_forces: &mut [[f64; 3]],
    skip: &[bool],
) {
    let block = data.elements.block(ElementKind::Hex8);
    corner_forces[..block.nodes.len()]
        .par_chunks_mut(8)
        .with_min_len(ELEMENTS_PER_TASK)
        .zip(block.corners::<8>().par_iter().zip(&block.material))
        .enumerate()
        .for_each(|(e, (out, (hex, &mat)))| {
            if skip.get(e) == Some(&true) {
                return;
            }
            let m = data.materials[mat as usize];
            let x = hex.map(|n| data.reference[n as usize]);
            let ue = hex.map(|n| u[n as usize]);
            out.copy_from_slice(&element_forces(&x, &ue, &m));
        });
}

/// The fewest elements a thread takes at a time.
pub(crate) const ELEMENTS_PER_TASK: usize = 256;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Elastic;

    /// The modal forces against the Gauss-point stiffness, for an isotropic material and an
    /// orthotropic one turned off its axes (every stiffness entry nonzero).
    #[test]
    fn element_forces_equal_stiffness_times_displacement() {
        for m in [
            Elastic::from_engineering(10.0, 0.3, 1.0),
            crate::element::checks::turned_ply(),
        ] {
            forces_equal_stiffness_times_displacement(&m);
        }
    }

    fn forces_equal_stiffness_times_displacement(m: &Elastic) {
        let mut x = hex8::CORNERS;
        x[6] = [1.2, 0.9, 1.1];
        x[1][2] = -0.8;
        let u: [[f64; 3]; 8] = std::array::from_fn(|k| {
            [
                0.01 * k as f64,
                -0.02 * (k % 3) as f64,
                0.005 * (k * k) as f64,
            ]
        });
        let f = element_forces(&x, &u, m);
        let k = hex8::stiffness(&x, m);
        let scale = k.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
        for i in 0..24 {
            let want: f64 = (0..24).map(|j| k[i][j] * u[j / 3][j % 3]).sum();
            assert!((f[i / 3][i % 3] - want).abs() < 1e-13 * scale * (1.0 + want.abs()));
        }
    }
}
