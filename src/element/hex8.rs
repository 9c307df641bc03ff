//! The trilinear hexahedron (hex8) with 2x2x2 Gauss quadrature.
//!
//! Corner k sits at $(\xi, \eta, \zeta) = $ `CORNERS[k]` in the parent cube $[-1, 1]^3$,
//! with shape function $N_k = \tfrac18 (1 + \xi_k \xi)(1 + \eta_k \eta)(1 + \zeta_k \zeta)$.

use crate::material::Elastic;

pub(crate) const CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// The six faces in the corner order above (bottom face counter-clockwise seen from +z,
/// then the top face), each ordered so that its normal points out of a positive element.
pub(crate) const FACES: [[usize; 4]; 6] = [
    [0, 3, 2, 1],
    [4, 5, 6, 7],
    [0, 1, 5, 4],
    [1, 2, 6, 5],
    [2, 3, 7, 6],
    [3, 0, 4, 7],
];

/// The 2x2x2 Gauss points (all weights are 1).
pub(crate) fn gauss_points() -> [[f64; 3]; 8] {
    let g = 1.0 / 3f64.sqrt();
    CORNERS.map(|c| c.map(|x| x * g))
}

/// Shape functions at a parent point.
pub fn shape(p: [f64; 3]) -> [f64; 8] {
    CORNERS.map(|c| 0.125 * (1.0 + c[0] * p[0]) * (1.0 + c[1] * p[1]) * (1.0 + c[2] * p[2]))
}

/// Parent derivatives dN_k/dxi_a at a parent point.
pub(crate) fn shape_derivatives(p: [f64; 3]) -> [[f64; 3]; 8] {
    CORNERS.map(|c| {
        let f = [1.0 + c[0] * p[0], 1.0 + c[1] * p[1], 1.0 + c[2] * p[2]];
        [
            0.125 * c[0] * f[1] * f[2],
            0.125 * f[0] * c[1] * f[2],
            0.125 * f[0] * f[1] * c[2],
        ]
    })
}

/// The Jacobian $J_{ab} = \sum_k x_{k,a}\, \partial N_k/\partial\xi_b$ at a parent point, with
/// the parent derivatives there.
pub(crate) fn jacobian(x: &[[f64; 3]; 8], p: [f64; 3]) -> ([[f64; 3]; 3], [[f64; 3]; 8]) {
    let dn = shape_derivatives(p);
    let mut j = [[0.0; 3]; 3];
    for k in 0..8 {
        for a in 0..3 {
            for b in 0..3 {
                j[a][b] += x[k][a] * dn[k][b];
            }
        }
    }
    (j, dn)
}

/// Physical gradients dN_k/dx and the Jacobian determinant at a parent point:
/// $\nabla N_k = J^{-T} \nabla_\xi N_k$ with $J$ of [`jacobian`].
pub(crate) fn gradients(x: &[[f64; 3]; 8], p: [f64; 3]) -> ([[f64; 3]; 8], f64) {
    let (j, dn) = jacobian(x, p);
    let det = j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
    // inverse of J (cofactors / det); grad N = J^{-T} dN/dxi
    let inv = [
        [
            (j[1][1] * j[2][2] - j[1][2] * j[2][1]) / det,
            (j[0][2] * j[2][1] - j[0][1] * j[2][2]) / det,
            (j[0][1] * j[1][2] - j[0][2] * j[1][1]) / det,
        ],
        [
            (j[1][2] * j[2][0] - j[1][0] * j[2][2]) / det,
            (j[0][0] * j[2][2] - j[0][2] * j[2][0]) / det,
            (j[0][2] * j[1][0] - j[0][0] * j[1][2]) / det,
        ],
        [
            (j[1][0] * j[2][1] - j[1][1] * j[2][0]) / det,
            (j[0][1] * j[2][0] - j[0][0] * j[2][1]) / det,
            (j[0][0] * j[1][1] - j[0][1] * j[1][0]) / det,
        ],
    ];
    let grads = dn.map(|d| {
        // (J^{-T} d)_a = sum_b inv[b][a] d_b
        [
            inv[0][0] * d[0] + inv[1][0] * d[1] + inv[2][0] * d[2],
            inv[0][1] * d[0] + inv[1][1] * d[1] + inv[2][1] * d[2],
            inv[0][2] * d[0] + inv[1][2] * d[1] + inv[2][2] * d[2],
        ]
    });
    (grads, det)
}

/// Element stiffness, 24x24 row-major in (node, component) order:
/// $K_{ij} = \sum_g w_g \det J\, k(\nabla N_i, \nabla N_j)$ with the block
/// [`super::stiffness_block`].
pub fn stiffness(x: &[[f64; 3]; 8], m: &Elastic) -> [[f64; 24]; 24] {
    let mut k = [[0.0; 24]; 24];
    for p in gauss_points() {
        let (g, det) = gradients(x, p);
        for i in 0..8 {
            for j in 0..8 {
                let v = super::stiffness_block(&g[i], &g[j], m);
                for a in 0..3 {
                    for b in 0..3 {
                        k[3 * i + a][3 * j + b] += v[a][b] * det;
                    }
                }
            }
        }
    }
    k
}

/// Consistent mass (scalar, per node pair): $M_{ij} = \sum_g w_g \det J\, \rho N_i N_j$.
pub(crate) fn consistent_mass(x: &[[f64; 3]; 8], density: f64) -> [[f64; 8]; 8] {
    let mut mm = [[0.0; 8]; 8];
    for p in gauss_points() {
        let n = shape(p);
        let (_, det) = gradients(x, p);
        for i in 0..8 {
            for j in 0..8 {
                mm[i][j] += density * n[i] * n[j] * det;
            }
        }
    }
    mm
}

/// Lumped mass: the row sums of the consistent mass (exact total mass, positive for
/// any element whose Jacobian stays positive).
pub(crate) fn lumped_mass(x: &[[f64; 3]; 8], density: f64) -> [f64; 8] {
    consistent_mass(x, density).map(|row| row.iter().sum())
}

/// Element volume.
pub(crate) fn volume(x: &[[f64; 3]; 8]) -> f64 {
    gauss_points().iter().map(|&p| gradients(x, p).1).sum()
}

#[cfg(test)]
mod tests {
    use super::super::checks;
    use super::*;

    fn distorted() -> [[f64; 3]; 8] {
        let mut x = CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0)));
        let jit = [0.11, -0.07, 0.05, 0.13, -0.09, 0.02, -0.12, 0.08];
        for (k, p) in x.iter_mut().enumerate() {
            p[0] += jit[k];
            p[1] += 0.5 * jit[(k + 3) % 8];
            p[2] -= 0.7 * jit[(k + 5) % 8];
        }
        x
    }

    #[test]
    fn partition_of_unity_and_zero_gradient_sum() {
        let x = distorted();
        for p in gauss_points() {
            let s: f64 = shape(p).iter().sum();
            assert!((s - 1.0).abs() < 1e-14);
            let (g, det) = gradients(&x, p);
            assert!(det > 0.0);
            for a in 0..3 {
                let s: f64 = g.iter().map(|gi| gi[a]).sum();
                assert!(s.abs() < 1e-12);
            }
        }
    }

    #[test]
    fn stiffness_is_symmetric_and_has_six_rigid_modes() {
        let x = distorted();
        let k = stiffness(&x, &Elastic::from_engineering(200.0, 0.3, 1.0));
        checks::assert_symmetric_with_rigid_modes(&k, &x, 1e-10, 1e-10);
    }

    /// A turned orthotropic material: a symmetric stiffness with the rigid modes, and the
    /// exact energy V eps:C:eps / 2 of a uniform strain.
    #[test]
    fn anisotropic_stiffness_has_rigid_modes_and_the_exact_energy() {
        let x = distorted();
        let m = checks::turned_ply();
        let k = stiffness(&x, &m);
        checks::assert_symmetric_with_rigid_modes(&k, &x, 1e-10, 1e-9);
        let u: Vec<f64> = checks::uniform_strain(&x).concat();
        let energy: f64 = (0..24)
            .map(|i| u[i] * (0..24).map(|j| k[i][j] * u[j]).sum::<f64>())
            .sum::<f64>()
            / 2.0;
        let want = checks::strain_energy(volume(&x), &m);
        assert!((energy - want).abs() < 1e-12 * want, "{energy} {want}");
    }

    #[test]
    fn patch_test_uniform_strain_gives_the_exact_energy() {
        let x = distorted();
        let m = Elastic::from_engineering(70.0, 0.25, 1.0);
        let u: Vec<f64> = checks::uniform_strain(&x).concat();
        let k = stiffness(&x, &m);
        let energy: f64 = (0..24)
            .map(|i| u[i] * (0..24).map(|j| k[i][j] * u[j]).sum::<f64>())
            .sum::<f64>()
            / 2.0;
        let want = checks::uniform_strain_energy(volume(&x), &m);
        assert!((energy - want).abs() < 1e-12 * want.abs().max(1e-30) * 1e3);
    }

    #[test]
    fn mass_sums_to_rho_v() {
        let x = distorted();
        let total: f64 = lumped_mass(&x, 2.5).iter().sum();
        assert!((total - 2.5 * volume(&x)).abs() < 1e-12);
    }
}
