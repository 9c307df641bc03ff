//! The linear tetrahedron (tet4, constant strain).
//!
//! Corners 0..3 with shape functions $N_0 = 1 - \xi - \eta - \zeta$, $N_1 = \xi$,
//! $N_2 = \eta$, $N_3 = \zeta$; the corner order has positive volume,
//! $(x_1 - x_0) \times (x_2 - x_0) \cdot (x_3 - x_0) > 0$ (mesh readers reorder elements that
//! come the other way round). The gradients are constant, so one point integrates the
//! stiffness exactly.

use crate::material::Elastic;

/// Physical gradients dN_k/dx (constant over the element) and the volume.
///
/// With $J = [x_1 - x_0, x_2 - x_0, x_3 - x_0]$ (columns), $\nabla N_k = J^{-T} \nabla_\xi N_k$,
/// and the rows of $J^{-1}$ are the cross products of the columns over $\det J$.
pub(crate) fn gradients(x: &[[f64; 3]; 4]) -> ([[f64; 3]; 4], f64) {
    let d = |k: usize| [x[k][0] - x[0][0], x[k][1] - x[0][1], x[k][2] - x[0][2]];
    let (a, b, c) = (d(1), d(2), d(3));
    let cross = |p: [f64; 3], q: [f64; 3]| {
        [
            p[1] * q[2] - p[2] * q[1],
            p[2] * q[0] - p[0] * q[2],
            p[0] * q[1] - p[1] * q[0],
        ]
    };
    let (bc, ca, ab) = (cross(b, c), cross(c, a), cross(a, b));
    let det = a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2];
    let g1 = bc.map(|v| v / det);
    let g2 = ca.map(|v| v / det);
    let g3 = ab.map(|v| v / det);
    let g0 = [0, 1, 2].map(|i| -(g1[i] + g2[i] + g3[i]));
    ([g0, g1, g2, g3], det / 6.0)
}

/// Element volume (signed: negative for an inverted corner order).
pub(crate) fn volume(x: &[[f64; 3]; 4]) -> f64 {
    gradients(x).1
}

/// Element stiffness, 12x12 row-major in (node, component) order:
/// $K_{ij} = V\, k(\nabla N_i, \nabla N_j)$ with the block [`super::stiffness_block`].
pub fn stiffness(x: &[[f64; 3]; 4], m: &Elastic) -> [[f64; 12]; 12] {
    let (g, vol) = gradients(x);
    let mut k = [[0.0; 12]; 12];
    for i in 0..4 {
        for j in 0..4 {
            let v = super::stiffness_block(&g[i], &g[j], m);
            for a in 0..3 {
                for b in 0..3 {
                    k[3 * i + a][3 * j + b] = v[a][b] * vol;
                }
            }
        }
    }
    k
}

/// Consistent mass (scalar, per node pair): $M_{ij} = \rho V (1 + \delta_{ij}) / 20$.
pub(crate) fn consistent_mass(x: &[[f64; 3]; 4], density: f64) -> [[f64; 4]; 4] {
    let m = density * volume(x) / 20.0;
    std::array::from_fn(|i| std::array::from_fn(|j| if i == j { 2.0 * m } else { m }))
}

/// Lumped mass: a quarter of the element's mass on each corner (the row sums of the
/// consistent mass).
pub(crate) fn lumped_mass(x: &[[f64; 3]; 4], density: f64) -> [f64; 4] {
    [density * volume(x) / 4.0; 4]
}

/// Corner forces $f_k = V \sigma \nabla N_k$ for the corner displacements `u`, with
/// the material's stress $\sigma(\varepsilon)$ (CPU twin of
/// `shaders/tet4_forces.wgsl`, through [`crate::kernels::tet4_forces`]).
pub fn forces(x: &[[f64; 3]; 4], u: &[[f64; 3]; 4], m: &Elastic) -> [[f64; 3]; 4] {
    let (g, vol) = gradients(x);
    let s = super::stress(&g, u, m);
    g.map(|gk| [0, 1, 2].map(|a| (s[a][0] * gk[0] + s[a][1] * gk[1] + s[a][2] * gk[2]) * vol))
}

/// The (constant) Cauchy stress of the element.
pub fn stress(x: &[[f64; 3]; 4], u: &[[f64; 3]; 4], m: &Elastic) -> [[f64; 3]; 3] {
    let (g, _) = gradients(x);
    super::stress(&g, u, m)
}

/// The four faces, ordered so that $(x_1 - x_0) \times (x_2 - x_0)$ of each points out of a
/// positively oriented element.
pub(crate) const FACES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];

#[cfg(test)]
mod tests {
    use super::super::checks;
    use super::*;

    fn distorted() -> [[f64; 3]; 4] {
        [
            [0.1, -0.05, 0.02],
            [1.2, 0.1, -0.1],
            [0.2, 0.9, 0.15],
            [-0.1, 0.2, 1.1],
        ]
    }

    #[test]
    fn stiffness_is_symmetric_and_has_six_rigid_modes() {
        let x = distorted();
        let k = stiffness(&x, &Elastic::from_engineering(200.0, 0.3, 1.0));
        checks::assert_symmetric_with_rigid_modes(&k, &x, 1e-12, 1e-11);
    }

    #[test]
    fn uniform_strain_gives_the_exact_energy_and_forces_equal_k_u() {
        let x = distorted();
        let m = Elastic::from_engineering(70.0, 0.25, 1.0);
        let e = checks::STRAIN;
        let ue: [[f64; 3]; 4] = checks::uniform_strain(&x).try_into().unwrap();
        let k = stiffness(&x, &m);
        let f = forces(&x, &ue, &m);
        let mut energy = 0.0;
        for i in 0..12 {
            let ku: f64 = (0..12).map(|j| k[i][j] * ue[j / 3][j % 3]).sum();
            assert!((f[i / 3][i % 3] - ku).abs() < 1e-13 * (1.0 + ku.abs()));
            energy += 0.5 * ue[i / 3][i % 3] * ku;
        }
        let want = checks::uniform_strain_energy(volume(&x), &m);
        assert!((energy - want).abs() < 1e-12 * want);
        let tr = e[0][0] + e[1][1] + e[2][2];
        // the stress is the exact one of the strain
        let s = stress(&x, &ue, &m);
        assert!((s[0][1] - 2.0 * m.mu * e[0][1]).abs() < 1e-14);
        assert!((s[2][2] - (m.lambda * tr + 2.0 * m.mu * e[2][2])).abs() < 1e-14);
    }

    #[test]
    fn faces_point_outwards_and_masses_sum_to_rho_v() {
        let x = distorted();
        let centre: [f64; 3] = std::array::from_fn(|a| x.iter().map(|p| p[a]).sum::<f64>() / 4.0);
        for f in FACES {
            let (p, q, r) = (x[f[0]], x[f[1]], x[f[2]]);
            let u = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            let v = [r[0] - p[0], r[1] - p[1], r[2] - p[2]];
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let out: f64 = (0..3).map(|a| n[a] * (p[a] - centre[a])).sum();
            assert!(out > 0.0, "face {f:?} points inwards");
        }
        let v = volume(&x);
        assert!(v > 0.0);
        let lumped: f64 = lumped_mass(&x, 2.5).iter().sum();
        let consistent: f64 = consistent_mass(&x, 2.5).iter().flatten().sum();
        assert!((lumped - 2.5 * v).abs() < 1e-14 && (consistent - 2.5 * v).abs() < 1e-14);
    }
}
