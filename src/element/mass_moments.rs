//! [`MassMoments`]: the mass, centre of mass and inertia tensor of a solid made of elements
//! (a rigid part of a deck, whose mass properties come from its mesh).
//!
//! Each element contributes $m = \int \rho\, dV$, $\mathbf{s} = \int \rho\, \mathbf{x}\, dV$
//! and $S = \int \rho\, \mathbf{x} \mathbf{x}^T dV$, exactly: the tetrahedron in closed
//! form, the trilinear hexahedron with 3x3x3 Gauss points (its integrand is at most of
//! degree 4 in each parent coordinate, which three points integrate exactly).

use super::{hex8, tet4, ElementKind};

type M3 = [[f64; 3]; 3];

/// The zeroth, first and second mass moments of a solid about the origin.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MassMoments {
    /// $m = \int \rho\, dV$.
    pub mass: f64,
    /// $\mathbf{s} = \int \rho\, \mathbf{x}\, dV$.
    pub first: [f64; 3],
    /// $S = \int \rho\, \mathbf{x} \mathbf{x}^T dV$.
    pub second: M3,
}

impl MassMoments {
    /// The moments of one element of `kind` with corners `x` and density `density`.
    pub fn of_element(kind: ElementKind, x: &[[f64; 3]], density: f64) -> MassMoments {
        match kind {
            ElementKind::Tet4 => tet(x, density),
            // the incompatible modes carry no mass: the hex8i's geometry is the hex8's
            ElementKind::Hex8 | ElementKind::Hex8i => hex(x, density),
        }
    }

    /// The moments of two solids together.
    pub fn plus(self, o: MassMoments) -> MassMoments {
        MassMoments {
            mass: self.mass + o.mass,
            first: std::array::from_fn(|a| self.first[a] + o.first[a]),
            second: std::array::from_fn(|a| {
                std::array::from_fn(|b| self.second[a][b] + o.second[a][b])
            }),
        }
    }

    /// The centre of mass $\mathbf{c} = \mathbf{s} / m$.
    pub fn centre(&self) -> [f64; 3] {
        self.first.map(|s| s / self.mass)
    }

    /// The inertia tensor about the centre of mass,
    /// $I = \mathrm{tr}(S_c)\, 1 - S_c$ with $S_c = S - m\, \mathbf{c} \mathbf{c}^T$.
    pub fn inertia(&self) -> M3 {
        let c = self.centre();
        // each pair once, so that the tensor is symmetric to the bit
        let sc = |a: usize, b: usize| {
            let (a, b) = (a.min(b), a.max(b));
            self.second[a][b] - self.mass * c[a] * c[b]
        };
        let trace = sc(0, 0) + sc(1, 1) + sc(2, 2);
        std::array::from_fn(|a| {
            std::array::from_fn(|b| if a == b { trace - sc(a, a) } else { -sc(a, b) })
        })
    }
}

/// The tetrahedron: with $V$ its volume and $\mathbf{x}_k$ its corners,
/// $\mathbf{s} = \rho V \bar{\mathbf{x}}$ and
/// $S = \rho V / 20\, (\sum_k \mathbf{x}_k \mathbf{x}_k^T + \mathbf{t}\mathbf{t}^T)$, $\mathbf{t} = \sum_k \mathbf{x}_k$.
fn tet(x: &[[f64; 3]], density: f64) -> MassMoments {
    let c: [[f64; 3]; 4] = std::array::from_fn(|k| x[k]);
    let m = density * tet4::volume(&c);
    let t: [f64; 3] = std::array::from_fn(|a| c.iter().map(|p| p[a]).sum());
    MassMoments {
        mass: m,
        first: t.map(|ta| m * ta / 4.0),
        second: std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                let own: f64 = c.iter().map(|p| p[a] * p[b]).sum();
                m / 20.0 * (own + t[a] * t[b])
            })
        }),
    }
}

/// The trilinear hexahedron, 3x3x3 Gauss points.
fn hex(x: &[[f64; 3]], density: f64) -> MassMoments {
    let c: [[f64; 3]; 8] = std::array::from_fn(|k| x[k]);
    let r = (0.6f64).sqrt();
    let points = [(-r, 5.0 / 9.0), (0.0, 8.0 / 9.0), (r, 5.0 / 9.0)];
    let mut out = MassMoments::default();
    for &(xi, wx) in &points {
        for &(eta, wy) in &points {
            for &(zeta, wz) in &points {
                let p = [xi, eta, zeta];
                let (_, det) = hex8::gradients(&c, p);
                let n = hex8::shape(p);
                let at: [f64; 3] = std::array::from_fn(|a| (0..8).map(|k| n[k] * c[k][a]).sum());
                let w = density * det * wx * wy * wz;
                out.mass += w;
                for a in 0..3 {
                    out.first[a] += w * at[a];
                    for b in 0..3 {
                        out.second[a][b] += w * at[a] * at[b];
                    }
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hexahedron over [0, a] x [0, b] x [0, c] moved by `shift`.
    fn brick([a, b, c]: [f64; 3], shift: [f64; 3]) -> Vec<[f64; 3]> {
        (hex8::CORNERS.iter())
            .map(|k| {
                let s = [a, b, c];
                std::array::from_fn(|i| 0.5 * (k[i] + 1.0) * s[i] + shift[i])
            })
            .collect()
    }

    fn close(a: &M3, b: &M3, tol: f64) -> bool {
        (0..3).all(|i| (0..3).all(|j| (a[i][j] - b[i][j]).abs() <= tol))
    }

    #[test]
    fn a_bricks_inertia_is_the_textbook_one() {
        let (s, rho) = ([2.0, 3.0, 5.0], 7.0);
        let m = MassMoments::of_element(ElementKind::Hex8, &brick(s, [1.0, -2.0, 0.5]), rho);
        let mass = rho * 30.0;
        assert!((m.mass - mass).abs() <= 1e-12 * mass);
        let c = m.centre();
        for (a, want) in c.iter().zip([2.0, -0.5, 3.0]) {
            assert!((a - want).abs() <= 1e-12, "{c:?}");
        }
        let i = |p: f64, q: f64| mass * (p * p + q * q) / 12.0;
        let want = [
            [i(3.0, 5.0), 0.0, 0.0],
            [0.0, i(2.0, 5.0), 0.0],
            [0.0, 0.0, i(2.0, 3.0)],
        ];
        assert!(
            close(&m.inertia(), &want, 1e-11 * mass),
            "{:?}",
            m.inertia()
        );
    }

    /// A tetrahedron's inertia against the moments of a regular tetrahedron of edge a about
    /// its centre: ma^2/20 about every axis.
    #[test]
    fn a_regular_tetrahedron_turns_alike_about_every_axis() {
        let a = 1.5;
        let s = a / 8f64.sqrt();
        let mut x = [[s, s, s], [s, -s, -s], [-s, s, -s], [-s, -s, s]];
        if tet4::volume(&x) < 0.0 {
            x.swap(1, 2);
        }
        let vol = tet4::volume(&x);
        let m = MassMoments::of_element(ElementKind::Tet4, &x, 2.0);
        let mass = 2.0 * vol;
        let want = mass * a * a / 20.0;
        let i = m.inertia();
        assert!(
            close(
                &i,
                &[[want, 0.0, 0.0], [0.0, want, 0.0], [0.0, 0.0, want]],
                1e-12 * want
            ),
            "{i:?} against {want}"
        );
    }

    /// A hexahedron cut into six tetrahedra (the cube's Kuhn triangulation, mapped affinely)
    /// has their moments; the map is random, so the hexahedron is a general parallelepiped.
    #[test]
    fn a_parallelepiped_has_the_moments_of_its_six_tetrahedra() {
        let f = [[1.3, 0.4, -0.2], [-0.3, 0.9, 0.5], [0.2, -0.6, 1.1]];
        let o = [0.7, -1.1, 2.3];
        let map = |p: [f64; 3]| -> [f64; 3] {
            std::array::from_fn(|a| o[a] + (0..3).map(|b| f[a][b] * p[b]).sum::<f64>())
        };
        let cube = |k: usize| hex8::CORNERS[k].map(|v| 0.5 * (v + 1.0));
        let hex: Vec<[f64; 3]> = (0..8).map(|k| map(cube(k))).collect();
        let h = MassMoments::of_element(ElementKind::Hex8, &hex, 3.0);
        // the six paths from corner 0 to corner 6 through the cube's edges
        let paths = [[1, 2], [1, 5], [3, 2], [3, 7], [4, 5], [4, 7]];
        let mut t = MassMoments::default();
        for [p, q] in paths {
            let mut x = [hex[0], hex[p], hex[q], hex[6]];
            if tet4::volume(&x) < 0.0 {
                x.swap(1, 2);
            }
            t = t.plus(MassMoments::of_element(ElementKind::Tet4, &x, 3.0));
        }
        assert!((h.mass - t.mass).abs() <= 1e-12 * t.mass);
        let i = h.inertia();
        assert!(
            (0..3).all(|a| (0..3).all(|b| i[a][b] == i[b][a])),
            "symmetric: {i:?}"
        );
        let (ch, ct) = (h.centre(), t.centre());
        assert!(
            (0..3).all(|a| (ch[a] - ct[a]).abs() <= 1e-12),
            "{ch:?} {ct:?}"
        );
        assert!(
            close(&h.inertia(), &t.inertia(), 1e-12 * t.mass),
            "{:?} {:?}",
            h.inertia(),
            t.inertia()
        );
    }

    /// A distorted hexahedron's moments against the sum over its 6x6x6 sub-cells: a rule
    /// that were not exact would give the two different errors.
    #[test]
    fn a_distorted_hexahedrons_moments_are_exact() {
        let mut x = brick([1.0, 1.0, 1.0], [0.0; 3]);
        let jit = [0.11, -0.07, 0.05, 0.13, -0.09, 0.02, -0.12, 0.08];
        for (k, p) in x.iter_mut().enumerate() {
            p[0] += jit[k];
            p[1] -= 0.5 * jit[(k + 3) % 8];
            p[2] += 0.7 * jit[(k + 5) % 8];
        }
        let whole = MassMoments::of_element(ElementKind::Hex8, &x, 1.0);
        let n = 6;
        let at = |p: [f64; 3]| -> [f64; 3] {
            let s = hex8::shape(p);
            std::array::from_fn(|a| (0..8).map(|k| s[k] * x[k][a]).sum())
        };
        let mut parts = MassMoments::default();
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let cell: Vec<[f64; 3]> = (hex8::CORNERS.iter())
                        .map(|c| {
                            let q = [i, j, k];
                            at(std::array::from_fn(|a| {
                                -1.0 + 2.0 * (q[a] as f64 + 0.5 * (c[a] + 1.0)) / n as f64
                            }))
                        })
                        .collect();
                    parts = parts.plus(MassMoments::of_element(ElementKind::Hex8, &cell, 1.0));
                }
            }
        }
        assert!((whole.mass - parts.mass).abs() <= 1e-12);
        // the map restricted to a sub-cell is trilinear again: the sub-cells are exact pieces
        let (a, b) = (whole.inertia(), parts.inertia());
        assert!(close(&a, &b, 1e-12 * a[0][0]), "{a:?} {b:?}");
    }
}
