//! The corotated frame of an element (`run.kinematics = "corotational"`): large rotations
//! with small strains.
//!
//! Each element computes its forces in a frame that turns with it: $R$, the rotation of the
//! polar decomposition $F = R U$ of the deformation gradient at its centre, takes the current
//! corners back to the reference orientation, the element's own (linear) forces act on what
//! is left, $d_k = R^T (x_k - x_0) - (X_k - X_0)$ with $x = X + u$, and $R$ turns them back
//! with the frame's own turn ([`turned_forces`]: the forces are the gradient of the energy
//! $\tfrac12 d \cdot f^{loc}$). A rigid rotation of any size then strains nothing, and a plate
//! that deflects by about its thickness stretches as it bends (its membrane stiffening),
//! which the linear strain of the displacement misses.

use nalgebra::Matrix3;

use super::{hex8, tet4};

/// A 3 x 3 matrix as rows.
pub type Mat3 = [[f64; 3]; 3];

/// The shape functions' gradients at the element's centre (a hex8's at its natural centre,
/// a tet4's constant ones); `N` is the corner count, 8 or 4.
pub fn centre_gradients<const N: usize>(x: &[[f64; 3]; N]) -> [[f64; 3]; N] {
    match N {
        8 => {
            let x8: &[[f64; 3]; 8] = x[..].try_into().expect("eight corners");
            let g = hex8::gradients(x8, [0.0; 3]).0;
            std::array::from_fn(|k| g[k])
        }
        4 => {
            let x4: &[[f64; 3]; 4] = x[..].try_into().expect("four corners");
            let g = tet4::gradients(x4).0;
            std::array::from_fn(|k| g[k])
        }
        _ => unreachable!("hexes and tets only"),
    }
}

/// The rotation of the element whose centre gradients are `g` at corner displacements `u`:
/// the orthogonal factor of $F = I + \sum_k (u_k - u_0) \otimes \nabla N_k$.
pub fn rotation<const N: usize>(g: &[[f64; 3]; N], u: &[[f64; 3]; N]) -> Mat3 {
    let mut f = Matrix3::identity();
    for k in 1..N {
        for a in 0..3 {
            for b in 0..3 {
                f[(a, b)] += (u[k][a] - u[0][a]) * g[k][b];
            }
        }
    }
    let r = polar_rotation(f);
    std::array::from_fn(|a| std::array::from_fn(|b| r[(a, b)]))
}

/// The orthogonal factor R of $F = R U$ (U symmetric positive definite): Newton's iteration
/// $X \leftarrow \tfrac12 (X + X^{-T})$, which converges quadratically from a deformation
/// gradient near a rotation; an inverted or degenerate F, or one the iteration does not
/// settle, takes the singular value decomposition, the proper rotation nearest it.
fn polar_rotation(f: Matrix3<f64>) -> Matrix3<f64> {
    if f.determinant() > 0.0 {
        let mut x = f;
        for _ in 0..12 {
            let Some(inv) = x.try_inverse() else { break };
            let next = 0.5 * (x + inv.transpose());
            let change = (next - x).norm();
            x = next;
            if change <= 1e-15 * 3f64.sqrt() {
                return x;
            }
        }
    }
    let svd = f.svd(true, true);
    let (mut u, v_t): (Matrix3<f64>, Matrix3<f64>) = (
        svd.u.unwrap_or_else(Matrix3::identity),
        svd.v_t.unwrap_or_else(Matrix3::identity),
    );
    if (u * v_t).determinant() < 0.0 {
        // the smallest singular value's direction turned over: a proper rotation
        let smallest = (0..3)
            .min_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]))
            .unwrap_or(2);
        u.column_mut(smallest).neg_mut();
    }
    u * v_t
}

/// The corner displacements in the frame `r`: $d_k = R^T (x_k - x_0) - (X_k - X_0)$, with
/// $x = X + u$ (relative to corner 0: the element's translation drops out).
pub fn local<const N: usize>(r: &Mat3, x: &[[f64; 3]; N], u: &[[f64; 3]; N]) -> [[f64; 3]; N] {
    std::array::from_fn(|k| {
        let p: [f64; 3] = std::array::from_fn(|a| (x[k][a] - x[0][a]) + (u[k][a] - u[0][a]));
        std::array::from_fn(|a| (0..3).map(|b| r[b][a] * p[b]).sum::<f64>() - (x[k][a] - x[0][a]))
    })
}

/// The corner forces of an element in the frame `r` whose local displacements `d` (centre
/// gradients `g`) give its own forces `f_loc`: the gradient of its energy
/// $\tfrac12 d \cdot f^{loc}$ as the frame turns with the corners,
/// $f_k = R\,(f^{loc}_k - \mu \times \nabla N_k)$. The second term is the frame's own
/// turn: with $U = I + \sum_k d_k \otimes \nabla N_k$ (the stretch, $R^T F$), a variation of
/// the corners turns the frame by $\omega = 2 (\mathrm{tr}\,U\, I - U)^{-1}
/// \mathrm{axial}(\mathrm{skew}(R^T \delta F))$, which changes the energy by
/// $-\omega \cdot m$ with $m = \sum_k d_k \times f^{loc}_k$, the moment the local forces
/// leave about the turned corners; so $\mu = (\mathrm{tr}\,U\, I - U)^{-1} m$. Without it
/// the forces are not the energy's gradient by a relative amount of the order of the strain
/// (a swinging strip's energy rose by 6e-4 at its turn).
pub fn turned_forces<const N: usize>(
    r: &Mat3,
    g: &[[f64; 3]; N],
    d: &[[f64; 3]; N],
    f_loc: &[[f64; 3]; N],
) -> [[f64; 3]; N] {
    let cross = |a: &[f64; 3], b: &[f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let mut m = [0.0; 3];
    let mut stretch: Matrix3<f64> = Matrix3::identity();
    for k in 1..N {
        let c = cross(&d[k], &f_loc[k]);
        for a in 0..3 {
            m[a] += c[a];
            for b in 0..3 {
                stretch[(a, b)] += d[k][a] * g[k][b];
            }
        }
    }
    let a: Matrix3<f64> = Matrix3::identity() * stretch.trace() - stretch;
    let mu = a
        .try_inverse()
        .map(|inv| inv * nalgebra::Vector3::from(m))
        .map_or([0.0; 3], |v| [v[0], v[1], v[2]]);
    let local: [[f64; 3]; N] = std::array::from_fn(|k| {
        let t = cross(&mu, &g[k]);
        std::array::from_fn(|c| f_loc[k][c] - t[c])
    });
    turn(r, &local)
}

/// Vectors turned by `r` (local to global).
pub fn turn<const N: usize>(r: &Mat3, f: &[[f64; 3]; N]) -> [[f64; 3]; N] {
    f.map(|v| std::array::from_fn(|a| (0..3).map(|b| r[a][b] * v[b]).sum()))
}

/// Vectors turned back by `r` (global to local, $R^T v$).
pub fn turn_back<const N: usize>(r: &Mat3, f: &[[f64; 3]]) -> [[f64; 3]; N] {
    std::array::from_fn(|k| std::array::from_fn(|a| (0..3).map(|b| r[b][a] * f[k][b]).sum()))
}

/// What the strain energy loses to an element's turn: with corner forces `f` (global, in
/// equilibrium, $\sum_k f_k = 0$) in the frame `r`, the element's time-centred energy
/// $\tfrac12 \sum_k d^{n}_k \cdot f^{loc}_k$ (its displacements of the step before, taken
/// into the same frame) is $\tfrac12 \sum_k u^n_k \cdot f_k$ less
/// $\tfrac12 \sum_k ((R - I)(X_k - X_0)) \cdot f_k$, which this returns. Summed over the
/// elements, the strain energy is $\tfrac12 u^n \cdot f_{int}$ less that sum.
pub fn turn_energy<const N: usize>(r: &Mat3, x: &[[f64; 3]; N], f: &[[f64; 3]]) -> f64 {
    let mut e = 0.0;
    for k in 1..N {
        let dx: [f64; 3] = std::array::from_fn(|a| x[k][a] - x[0][a]);
        for a in 0..3 {
            let turned: f64 = (0..3).map(|b| r[a][b] * dx[b]).sum::<f64>() - dx[a];
            e += turned * f[k][a];
        }
    }
    0.5 * e
}

#[cfg(test)]
mod tests {
    use super::*;

    fn turn_about(axis: [f64; 3], angle: f64) -> Mat3 {
        let n = nalgebra::Vector3::from(axis).normalize();
        let r = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_unchecked(n), angle);
        std::array::from_fn(|a| std::array::from_fn(|b| r[(a, b)]))
    }

    fn distorted() -> [[f64; 3]; 8] {
        let mut x = hex8::CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0)));
        x[6] = [1.2, 1.1, 0.9];
        x[1] = [1.1, -0.1, 0.05];
        x
    }

    /// A stretch turned by R: the frame found is R, and the local displacements are the
    /// stretch's.
    #[test]
    fn a_turned_stretch_gives_its_rotation_and_its_stretch() {
        let x = distorted();
        let r = turn_about([0.3, -1.0, 0.7], 2.1);
        let stretch = [
            [1.002, 0.0005, 0.0],
            [0.0005, 0.999, 0.0],
            [0.0, 0.0, 1.001],
        ];
        let u: [[f64; 3]; 8] = std::array::from_fn(|k| {
            let s: [f64; 3] =
                std::array::from_fn(|a| (0..3).map(|b| stretch[a][b] * x[k][b]).sum());
            std::array::from_fn(|a| (0..3).map(|b| r[a][b] * s[b]).sum::<f64>() - x[k][a])
        });
        let found = rotation(&centre_gradients(&x), &u);
        for a in 0..3 {
            for b in 0..3 {
                assert!((found[a][b] - r[a][b]).abs() < 1e-13, "{found:?}");
            }
        }
        let d = local(&found, &x, &u);
        for k in 0..8 {
            for a in 0..3 {
                let want: f64 = (0..3)
                    .map(|b| (stretch[a][b] - f64::from(u8::from(a == b))) * (x[k][b] - x[0][b]))
                    .sum();
                assert!((d[k][a] - want).abs() < 1e-13, "corner {k}: {:?}", d[k]);
            }
        }
    }

    /// An inverted element still gets a proper rotation.
    #[test]
    fn an_inverted_element_gets_a_proper_rotation() {
        let x = distorted();
        let u: [[f64; 3]; 8] = std::array::from_fn(|k| [0.0, 0.0, -2.0 * x[k][2]]);
        let r = rotation(&centre_gradients(&x), &u);
        let m = Matrix3::from_fn(|a, b| r[a][b]);
        assert!((m.determinant() - 1.0).abs() < 1e-12);
        assert!((m.transpose() * m - Matrix3::identity()).norm() < 1e-12);
    }

    /// The energy lost to the turn: for displacements $u = R(X + d) - X$ and any equilibrated
    /// forces, $\tfrac12 u \cdot f$ less it is $\tfrac12 (R d) \cdot f$.
    #[test]
    fn the_turn_energy_leaves_the_local_energy() {
        let x = distorted();
        let r = turn_about([1.0, 2.0, -0.5], 0.8);
        let d: [[f64; 3]; 8] =
            std::array::from_fn(|k| [0.01 * k as f64, -0.003, 0.002 * (k % 3) as f64]);
        let u: [[f64; 3]; 8] = std::array::from_fn(|k| {
            let p: [f64; 3] = std::array::from_fn(|a| x[k][a] + d[k][a]);
            std::array::from_fn(|a| (0..3).map(|b| r[a][b] * p[b]).sum::<f64>() - x[k][a])
        });
        let mut f: [[f64; 3]; 8] = std::array::from_fn(|k| [1.0 + k as f64, -2.0 * k as f64, 0.5]);
        let sum: [f64; 3] = std::array::from_fn(|a| f.iter().map(|v| v[a]).sum());
        f[0] = std::array::from_fn(|a| f[0][a] - sum[a]);
        let whole: f64 = (0..8)
            .map(|k| (0..3).map(|a| u[k][a] * f[k][a]).sum::<f64>())
            .sum();
        let rd = turn(&r, &d);
        let want: f64 = (0..8)
            .map(|k| (0..3).map(|a| rd[k][a] * f[k][a]).sum::<f64>())
            .sum();
        let got = 0.5 * whole - turn_energy(&r, &x, &f);
        assert!((got - 0.5 * want).abs() < 1e-12, "{got} {}", 0.5 * want);
    }
}
