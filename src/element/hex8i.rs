//! The hex8 with incompatible modes (hex8i; Wilson, Taylor, Beresford and Wilson 1976;
//! Abaqus's C3D8I): the trilinear brick enriched by the three bubble modes
//! $P_m = 1 - \xi_m^2$ per displacement component, whose nine amplitudes are condensed out
//! inside the element, so that it stays an 8-node element everywhere else.
//!
//! The bubbles supply the quadratic displacement of bending that locks the plain hex8 (its
//! spurious shear strain): a cantilever one element thick bends to within a few per cent of
//! beam theory where the hex8 reaches 0.08 of it. The modes' spatial gradients are taken with
//! the Jacobian at the centre, $\nabla P_m = \frac{\det J_0}{\det J} J_0^{-T} \nabla_\xi
//! P_m$ (Taylor's modification), so that $\int \nabla P_m\, dV = 0$ on any shape: a distorted
//! element passes the constant-strain patch test. Stiffness, with the corners' gradients
//! $\nabla N_k$ and the modes' as three more "nodes":
//! $K = \sum_g \det J_g\, k(\nabla_i, \nabla_j)$ (11 x 11 blocks, [`super::stiffness_block`]),
//! then $K_c = K_{uu} - K_{u\alpha} K_{\alpha\alpha}^{-1} K_{\alpha u}$, 24 x 24. The modes
//! carry no mass: the mass is the hex8's.
//!
//! The element is linear, so its corner forces are $f = K_c u$; the force kernel keeps $K_c$
//! per element with the corners' gradients at the centre ([`kept`]). It multiplies the
//! corner displacements relative to corner 0 less the element's rigid rotation at its centre
//! ([`forces`]): $K_c$ annihilates both, and without them the products of a thin element's
//! large membrane entries with a rotating element's displacements would cancel to its small
//! bending forces in f32.

use super::hex8;
use super::section::Section;

/// Entries of a symmetric 24 x 24 matrix packed by its upper triangle, row by row.
pub(crate) const PACKED: usize = 24 * 25 / 2;

/// The packed index of entry (r, c) of a symmetric 24 x 24 matrix.
pub(crate) fn packed_index(r: usize, c: usize) -> usize {
    let (r, c) = if r <= c { (r, c) } else { (c, r) };
    // rows of 24, 23, ... entries: row r starts at 24 r - r (r - 1) / 2, entry c at c - r
    r * (47 - r) / 2 + c
}

/// The inverse and the determinant of the Jacobian at the centre ([`hex8::jacobian`]).
pub(crate) fn centre_jacobian(x: &[[f64; 3]; 8]) -> ([[f64; 3]; 3], f64) {
    let (j, _) = hex8::jacobian(x, [0.0; 3]);
    let m = nalgebra::Matrix3::from_fn(|a, b| j[a][b]);
    let det = m.determinant();
    let inv = m.try_inverse().unwrap_or_else(nalgebra::Matrix3::zeros);
    (
        std::array::from_fn(|a| std::array::from_fn(|b| inv[(a, b)])),
        det,
    )
}

/// The 33 x 33 stiffness of the corners and the modes, in (node, component) order with the
/// modes as nodes 8, 9, 10.
fn enriched_stiffness(x: &[[f64; 3]; 8], section: Section) -> nalgebra::DMatrix<f64> {
    let (inv0, det0) = centre_jacobian(x);
    let mut k = nalgebra::DMatrix::zeros(33, 33);
    for (p, w, m) in section.hex_points() {
        let (g, det) = hex8::gradients(x, p);
        let (m, det_w) = (&m, det * w);
        // grad P_m = det J0 / det J * J0^-T (-2 xi_m e_m): row m of J0^-1, scaled
        let modes: [[f64; 3]; 3] =
            std::array::from_fn(|mm| inv0[mm].map(|v| -2.0 * p[mm] * v * det0 / det));
        let grad = |i: usize| if i < 8 { g[i] } else { modes[i - 8] };
        for i in 0..11 {
            for j in 0..11 {
                let v = super::stiffness_block(&grad(i), &grad(j), m);
                for a in 0..3 {
                    for b in 0..3 {
                        k[(3 * i + a, 3 * j + b)] += v[a][b] * det_w;
                    }
                }
            }
        }
    }
    k
}

/// The condensed element stiffness, 24 x 24 in (node, component) order.
pub fn stiffness<'a>(x: &[[f64; 3]; 8], section: impl Into<Section<'a>>) -> [[f64; 24]; 24] {
    let k = enriched_stiffness(x, section.into());
    let kuu = k.view((0, 0), (24, 24));
    let kua = k.view((0, 24), (24, 9));
    let kaa = k.view((24, 24), (9, 9)).into_owned();
    // K_aa is positive definite for an element of positive Jacobian; a singular one (a
    // degenerate element, refused by the element checks) condenses nothing
    let solved = match kaa.cholesky() {
        Some(c) => c.solve(&kua.transpose()),
        None => nalgebra::DMatrix::zeros(9, 24),
    };
    let kc = kuu - kua * solved;
    // symmetric to rounding; keep it exactly symmetric
    std::array::from_fn(|r| std::array::from_fn(|c| 0.5 * (kc[(r, c)] + kc[(c, r)])))
}

/// [`stiffness`] packed by its upper triangle ([`PACKED`] entries, [`packed_index`]).
pub(crate) fn condensed_packed(x: &[[f64; 3]; 8], section: Section) -> [f64; PACKED] {
    let k = stiffness(x, section);
    let mut out = [0.0; PACKED];
    for r in 0..24 {
        for c in r..24 {
            out[packed_index(r, c)] = k[r][c];
        }
    }
    out
}

/// Values the force kernel keeps per element: the packed condensed stiffness, then the
/// corners' gradients at the centre.
pub(crate) const KEPT: usize = PACKED + 24;

/// What the force kernel keeps of an element ([`KEPT`] values).
pub fn kept<'a>(x: &[[f64; 3]; 8], section: impl Into<Section<'a>>) -> [f64; KEPT] {
    let mut out = [0.0; KEPT];
    out[..PACKED].copy_from_slice(&condensed_packed(x, section.into()));
    let (g, _) = hex8::gradients(x, [0.0; 3]);
    for (k, gk) in g.iter().enumerate() {
        out[PACKED + 3 * k..PACKED + 3 * k + 3].copy_from_slice(gk);
    }
    out
}

/// The corner displacements relative to corner 0, less the element's rotation at its
/// centre: $d_k = u_k - u_0 - W (x_k - x_0)$ with $W$ the skew part of
/// $\sum_k (u_k - u_0) \otimes \nabla N_k(0)$.
pub(crate) fn straining(kept: &[f64], x: &[[f64; 3]; 8], u: &[[f64; 3]; 8]) -> [[f64; 3]; 8] {
    let d: [[f64; 3]; 8] = u.map(|p| std::array::from_fn(|a| p[a] - u[0][a]));
    let g = |k: usize, b: usize| kept[PACKED + 3 * k + b];
    let h: [[f64; 3]; 3] =
        std::array::from_fn(|a| std::array::from_fn(|b| (0..8).map(|k| d[k][a] * g(k, b)).sum()));
    let w: [[f64; 3]; 3] =
        std::array::from_fn(|a| std::array::from_fn(|b| 0.5 * (h[a][b] - h[b][a])));
    std::array::from_fn(|k| {
        let r: [f64; 3] = std::array::from_fn(|b| x[k][b] - x[0][b]);
        std::array::from_fn(|a| d[k][a] - (0..3).map(|b| w[a][b] * r[b]).sum::<f64>())
    })
}

/// The elastic condensation of the modes, $A_0 = -K_{\alpha\alpha}^{-1} K_{\alpha u}$: the
/// modes' amplitudes $\alpha = A_0 u$ of the corner displacements (9 x 24 row-major, mode
/// m's component c in row 3 m + c; zero for a degenerate element).
pub fn condensation(x: &[[f64; 3]; 8], section: Section) -> Vec<f64> {
    let k = enriched_stiffness(x, section);
    let kau = k.view((24, 0), (9, 24)).into_owned();
    let a = match k.view((24, 24), (9, 9)).into_owned().cholesky() {
        Some(c) => -c.solve(&kau),
        None => nalgebra::DMatrix::zeros(9, 24),
    };
    (0..9)
        .flat_map(|r| (0..24).map(move |j| (r, j)))
        .map(|(r, j)| a[(r, j)])
        .collect()
}

/// The displacement gradient at each natural point of `points` as a linear operator on the
/// 24 corner displacements (row 3 a + b: du_a/dx_b), with the modes' amplitudes that the
/// condensation gives them, $\alpha = -K_{\alpha\alpha}^{-1} K_{\alpha u} u$ (the stresses of
/// plies off the centre, where the modes' gradients do not vanish).
pub fn gradient_operators(
    x: &[[f64; 3]; 8],
    section: Section,
    points: &[[f64; 3]],
) -> Vec<[[f64; 24]; 9]> {
    let k = enriched_stiffness(x, section);
    let kau = k.view((24, 0), (9, 24)).into_owned();
    // alpha = A u
    let a = match k.view((24, 24), (9, 9)).into_owned().cholesky() {
        Some(c) => -c.solve(&kau),
        None => nalgebra::DMatrix::zeros(9, 24),
    };
    let (inv0, det0) = centre_jacobian(x);
    (points.iter())
        .map(|&p| {
            let (g, det) = hex8::gradients(x, p);
            let modes: [[f64; 3]; 3] =
                std::array::from_fn(|m| inv0[m].map(|v| -2.0 * p[m] * v * det0 / det));
            std::array::from_fn(|r| {
                let (ca, cb) = (r / 3, r % 3);
                std::array::from_fn(|j| {
                    let (n, comp) = (j / 3, j % 3);
                    let corner = if comp == ca { g[n][cb] } else { 0.0 };
                    corner
                        + (0..3)
                            .map(|m| a[(3 * m + ca, j)] * modes[m][cb])
                            .sum::<f64>()
                })
            })
        })
        .collect()
}

/// The displacement gradients at the natural points `points` of corner displacements `u`
/// ([`gradient_operators`] applied to them).
pub fn gradients_at(
    x: &[[f64; 3]; 8],
    section: Section,
    u: &[[f64; 3]; 8],
    points: &[[f64; 3]],
) -> Vec<[[f64; 3]; 3]> {
    let uv: Vec<f64> = u.iter().flatten().copied().collect();
    (gradient_operators(x, section, points).iter())
        .map(|op| {
            std::array::from_fn(|a| {
                std::array::from_fn(|b| (0..24).map(|j| op[3 * a + b][j] * uv[j]).sum())
            })
        })
        .collect()
}

/// Corner forces $f = K_c d$ of the kept values, the reference corners and the corner
/// displacements, with $d$ the element's [`straining`] displacements.
pub fn forces(kept: &[f64], x: &[[f64; 3]; 8], u: &[[f64; 3]; 8]) -> [[f64; 3]; 8] {
    let d = straining(kept, x, u);
    let d: [f64; 24] = std::array::from_fn(|r| d[r / 3][r % 3]);
    // the packed upper triangle row by row: each entry serves its row and, off the
    // diagonal, its column
    let mut f = [0.0; 24];
    let mut k = kept[..PACKED].iter();
    for r in 0..24 {
        let mut row = 0.0;
        for (c, kc) in (r..24).zip(&mut k) {
            row += kc * d[c];
            if c != r {
                f[c] += kc * d[r];
            }
        }
        f[r] += row;
    }
    std::array::from_fn(|n| [f[3 * n], f[3 * n + 1], f[3 * n + 2]])
}

#[cfg(test)]
mod tests {
    use super::super::checks;
    use super::*;
    use crate::material::Elastic;

    fn distorted() -> [[f64; 3]; 8] {
        let mut x = hex8::CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0)));
        x[6] = [1.2, 1.1, 0.9];
        x[1] = [1.1, -0.1, 0.05];
        x[4] = [-0.1, 0.05, 1.1];
        x
    }

    #[test]
    fn packing_covers_the_upper_triangle_once() {
        let mut seen = [false; PACKED];
        for r in 0..24 {
            for c in r..24 {
                let i = packed_index(r, c);
                assert!(!seen[i], "({r}, {c})");
                seen[i] = true;
                assert_eq!(packed_index(c, r), i);
            }
        }
        assert!(seen.iter().all(|&s| s));
    }

    /// Symmetric, six rigid-body modes free of force, positive on the other 18.
    #[test]
    fn condensed_stiffness_is_a_sound_element_matrix() {
        let m = Elastic::from_engineering(200.0, 0.3, 7.8);
        let x = distorted();
        let k = stiffness(&x, &m);
        checks::assert_symmetric_with_rigid_modes(&k, &x, 1e-12, 1e-9);
        let e = nalgebra::DMatrix::from_fn(24, 24, |r, c| k[r][c]).symmetric_eigenvalues();
        let top = e.max();
        assert_eq!(e.iter().filter(|&&v| v > 1e-9 * top).count(), 18, "{e}");
        assert!(e.iter().all(|&v| v > -1e-9 * top), "{e}");
    }

    /// A cantilever one element across (width `w` along y, height `t` along z) and `n`
    /// elements along x (length `len`, clamped at x = 0), its node columns at x = i len / n
    /// moved by `shift(i, k)` at height level k (0 bottom, 1 top): the tip displacement,
    /// averaged over the tip's four nodes, along `axis` under a unit tip load along it.
    struct Cantilever {
        n: usize,
        len: f64,
        w: f64,
        t: f64,
        m: Elastic,
        shift: Shift,
    }

    /// A node column's shift along x: `shift(i, k)` for column i at height level k.
    type Shift = fn(usize, usize) -> f64;

    impl Cantilever {
        fn tip(&self, element: Stiffness, axis: usize) -> f64 {
            let n = self.n;
            let h = self.len / n as f64;
            let node = |i: usize, j: usize, k: usize| 4 * i + 2 * k + j;
            let mut x = vec![[0.0; 3]; 4 * (n + 1)];
            for i in 0..=n {
                for k in 0..2 {
                    for j in 0..2 {
                        let xi = i as f64 * h + (self.shift)(i, k);
                        x[node(i, j, k)] = [xi, j as f64 * self.w, k as f64 * self.t];
                    }
                }
            }
            let ndof = 3 * x.len();
            let mut kg = nalgebra::DMatrix::zeros(ndof, ndof);
            for i in 0..n {
                let corners = [
                    node(i, 0, 0),
                    node(i + 1, 0, 0),
                    node(i + 1, 1, 0),
                    node(i, 1, 0),
                    node(i, 0, 1),
                    node(i + 1, 0, 1),
                    node(i + 1, 1, 1),
                    node(i, 1, 1),
                ];
                let ke = element(&corners.map(|c| x[c]), &self.m);
                for (a, &ca) in corners.iter().enumerate() {
                    for (b, &cb) in corners.iter().enumerate() {
                        for r in 0..3 {
                            for c in 0..3 {
                                kg[(3 * ca + r, 3 * cb + c)] += ke[3 * a + r][3 * b + c];
                            }
                        }
                    }
                }
            }
            // the root's 12 dofs fixed; the tip load on the tip's four nodes
            let free = ndof - 12;
            let kf = kg.view((12, 12), (free, free)).into_owned();
            let mut f = nalgebra::DVector::zeros(free);
            let tip_nodes = [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(j, k)| node(n, j, k));
            for &t in &tip_nodes {
                f[3 * t + axis - 12] = 0.25;
            }
            let u = kf.cholesky().expect("positive definite").solve(&f);
            tip_nodes.iter().map(|&t| u[3 * t + axis - 12]).sum::<f64>() / 4.0
        }
    }

    /// An element stiffness function (hex8's or hex8i's).
    type Stiffness = fn(&[[f64; 3]; 8], &Elastic) -> [[f64; 24]; 24];

    /// The hex8i's stiffness of one law, as a [`Stiffness`].
    fn solid(x: &[[f64; 3]; 8], m: &Elastic) -> [[f64; 24]; 24] {
        stiffness(x, m)
    }

    /// The tip deflection of a cantilever one element thick (`t`, width 1, length 6) and `n`
    /// elements long under a tip shear (nu = 0, clamped root), against Timoshenko's
    /// P L^3 / (3 E I) + P L / (kappa G A).
    fn cantilever(n: usize, t: f64, element: Stiffness) -> f64 {
        let (len, e_mod) = (6.0, 1000.0);
        let beam = Cantilever {
            n,
            len,
            w: 1.0,
            t,
            m: Elastic::from_engineering(e_mod, 0.0, 1.0),
            shift: |_, _| 0.0,
        };
        let tip = beam.tip(element, 2);
        let i_mom = t.powi(3) / 12.0;
        let shear = len / (5.0 / 6.0 * 0.5 * e_mod * t);
        tip / (len.powi(3) / (3.0 * e_mod * i_mom) + shear)
    }

    /// MacNeal and Harder's straight cantilever (1985): length 6, height 0.2, width 0.1,
    /// E = 1e7, nu = 0.3, six elements, a unit tip shear in the plane of the height
    /// (reference tip deflection 0.1081) and out of it (0.4321), on three meshes: regular,
    /// trapezoidal (the element boundaries inclined at 45 degrees, alternately) and
    /// parallelogram (all inclined at 45 degrees; the end faces square on both). The regular
    /// mesh is within 3% of the reference with hex8i; the distorted meshes are reported
    /// (docs/validation.md) and are no worse than the plain hex8's.
    #[test]
    fn macneal_harder_straight_cantilever() {
        let meshes: [(&str, Shift); 3] = [
            ("regular", |_, _| 0.0),
            ("trapezoidal", |i, k| {
                let inner = if i == 0 || i == 6 { 0.0 } else { 1.0 };
                let side = if i % 2 == 0 { 1.0 } else { -1.0 };
                inner * side * if k == 0 { -0.1 } else { 0.1 }
            }),
            ("parallelogram", |i, k| {
                let inner = if i == 0 || i == 6 { 0.0 } else { 1.0 };
                inner * if k == 0 { -0.1 } else { 0.1 }
            }),
        ];
        for (name, shift) in meshes {
            let beam = Cantilever {
                n: 6,
                len: 6.0,
                w: 0.1,
                t: 0.2,
                m: Elastic::from_engineering(1.0e7, 0.3, 1.0),
                shift,
            };
            let ratio = |element: Stiffness| {
                [(2, 0.1081), (1, 0.4321)]
                    .map(|(axis, reference)| beam.tip(element, axis) / reference)
            };
            let (hex8i, hex8) = (ratio(solid), ratio(hex8::stiffness));
            eprintln!(
                "{name}: tip / reference, in-plane and out-of-plane shear: hex8i {:.3} {:.3}, hex8 {:.3} {:.3}",
                hex8i[0], hex8i[1], hex8[0], hex8[1]
            );
            if name == "regular" {
                // within 3%: with nu = 0.3 the root clamped in all three directions holds
                // the Poisson contraction there (with nu = 0 the same mesh is within 1%,
                // a_thin_cantilever_bends_without_locking)
                for r in hex8i {
                    assert!((r - 1.0).abs() < 0.03, "{name}: hex8i {r}");
                }
            }
            for (a, b) in hex8i.iter().zip(hex8) {
                assert!(*a >= b, "{name}: hex8i {a} below hex8 {b}");
            }
        }
    }

    /// Bending without locking: one element thick and six long, within 1% of beam theory
    /// from a stocky beam (elements 1 x 1 x 1) to a thin one (elements 1 long, 0.1 thick),
    /// where the plain hex8 gives a fraction of it.
    #[test]
    fn a_thin_cantilever_bends_without_locking() {
        for t in [1.0, 0.1] {
            let hex8i = cantilever(6, t, solid);
            let hex8 = cantilever(6, t, hex8::stiffness);
            eprintln!(
                "thickness {t}: tip deflection / Timoshenko: hex8i {hex8i:.4}, hex8 {hex8:.4}"
            );
            assert!((hex8i - 1.0).abs() < 0.01, "hex8i {hex8i}");
            assert!(hex8 < 0.7, "hex8 {hex8}");
        }
    }

    /// A linear displacement field gives the corner forces of its constant stress on any
    /// shape (the patch test, element by element: the modes stay at rest).
    #[test]
    fn a_constant_strain_is_reproduced_on_a_distorted_element() {
        let m = Elastic::from_engineering(200.0, 0.3, 7.8);
        let x = distorted();
        let h = [
            [1e-3, 2e-4, -3e-4],
            [5e-4, -2e-3, 1e-4],
            [0.0, 3e-4, 1.5e-3],
        ];
        let u = x.map(|p| std::array::from_fn(|a| (0..3).map(|b| h[a][b] * p[b]).sum()));
        let k = kept(&x, &m);
        let f = forces(&k, &x, &u);
        let plain = hex8::stiffness(&x, &m);
        for r in 0..24 {
            let want: f64 = (0..24).map(|c| plain[r][c] * u[c / 3][c % 3]).sum();
            let got = f[r / 3][r % 3];
            assert!(
                (got - want).abs() < 1e-10 * want.abs().max(1e-3),
                "{r}: {got} {want}"
            );
        }
    }

    /// A bilayer beam element (two isotropic plies with nu = 0, E 1 and 5, thicknesses 0.3
    /// and 0.7 of the height) bent to a constant curvature about any axis height: the
    /// field is the element's (a bubble carries the deflection), so its condensed energy
    /// is the exact 1/2 kappa^2 L b sum E_k int (z - z_n)^2 dz, ply by ply; and a layup of
    /// one law is the solid element.
    #[test]
    fn a_layered_element_bends_a_bilayer_exactly() {
        use crate::material::{Layup, LayupPly};
        let (len, b, t) = (3.0, 0.5, 0.4);
        let x = hex8::CORNERS.map(|c| {
            [
                0.5 * len * (1.0 + c[0]),
                0.5 * b * (1.0 + c[1]),
                0.5 * t * (1.0 + c[2]),
            ]
        });
        let ply = |lo: f64, hi: f64, e: f64| LayupPly {
            lo,
            hi,
            elastic: Elastic::from_engineering(e, 0.0, 1.0),
            material: 0,
        };
        // the ply boundary at 0.3 t: natural coordinate -1 + 2 * 0.3
        let split = -1.0 + 2.0 * 0.3;
        let layup = Layup {
            axis: 2,
            plies: vec![ply(-1.0, split, 1.0), ply(split, 1.0, 5.0)],
        };
        let k = stiffness(&x, Section::Layered(&layup));
        let (kappa, z_n) = (0.01, 0.13);
        let u: Vec<f64> = x
            .iter()
            .flat_map(|p| [-kappa * p[0] * (p[2] - z_n), 0.0, 0.5 * kappa * p[0] * p[0]])
            .collect();
        let energy: f64 = 0.5
            * (0..24)
                .map(|r| (0..24).map(|c| u[r] * k[r][c] * u[c]).sum::<f64>())
                .sum::<f64>();
        let moment = |e: f64, z0: f64, z1: f64| e * ((z1 - z_n).powi(3) - (z0 - z_n).powi(3)) / 3.0;
        let exact =
            0.5 * kappa * kappa * len * b * (moment(1.0, 0.0, 0.3 * t) + moment(5.0, 0.3 * t, t));
        assert!(
            (energy - exact).abs() <= 1e-10 * exact,
            "energy {energy}, exact {exact}"
        );
        // one law in every ply is the solid element (on a parallelepiped, where both rules
        // integrate the polynomial integrand exactly)
        let m = Elastic::from_engineering(2.0, 0.3, 1.0);
        let sheared = x.map(|p| [p[0] + 0.4 * p[2], p[1] + 0.2 * p[0], p[2] + 0.1 * p[1]]);
        let same = Layup {
            axis: 2,
            plies: [(-1.0, -0.2), (-0.2, 0.5), (0.5, 1.0)]
                .map(|(lo, hi)| LayupPly {
                    lo,
                    hi,
                    elastic: m,
                    material: 0,
                })
                .to_vec(),
        };
        let (a, b) = (
            stiffness(&sheared, Section::Layered(&same)),
            stiffness(&sheared, &m),
        );
        for r in 0..24 {
            for c in 0..24 {
                assert!(
                    (a[r][c] - b[r][c]).abs() <= 1e-12 * b[r][r].abs(),
                    "{r} {c}"
                );
            }
        }
    }
}
