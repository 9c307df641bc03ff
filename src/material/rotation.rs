//! Material axes: the rotation from a material's own axes to the global ones, and its
//! stiffness turned with it.

use super::{voigt_index, Voigt, VOIGT_PAIRS};

/// Material axes 1, 2, 3 as orthonormal rows in global coordinates (right-handed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rotation {
    pub axes: [[f64; 3]; 3],
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a` scaled to length 1; `None` only when it is zero or not finite. A vector whose squared
/// length would overflow or underflow (`[-1e200, 0, 0]`, `[1e-170, 0, 0]`) is scaled by its
/// largest component first.
pub fn unit(a: [f64; 3]) -> Option<[f64; 3]> {
    if !a.iter().all(|x| x.is_finite()) {
        return None;
    }
    let n = dot(a, a).sqrt();
    if n.is_finite() && n > 1e-150 {
        return Some(a.map(|x| x / n));
    }
    let largest = a.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if largest == 0.0 {
        return None;
    }
    let s = a.map(|x| x / largest);
    let n = dot(s, s).sqrt();
    Some(s.map(|x| x / n))
}

impl Rotation {
    /// The global axes.
    pub const IDENTITY: Rotation = Rotation {
        axes: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };

    /// Axis 1 along `a1`, axis 2 the part of `a2` normal to it, axis 3 = 1 x 2. `None` when
    /// either is zero or they are parallel (within 1e-9 of the angle).
    pub fn from_axes(a1: [f64; 3], a2: [f64; 3]) -> Option<Rotation> {
        let e1 = unit(a1)?;
        let a2 = unit(a2)?;
        let e3 = cross(e1, a2);
        if dot(e3, e3).sqrt() < 1e-9 {
            return None;
        }
        let e3 = unit(e3)?;
        Some(Rotation {
            axes: [e1, cross(e3, e1), e3],
        })
    }

    /// These axes turned by `angle` (radians, right-handed) about the global `axis` (a unit
    /// vector).
    pub fn turned(&self, axis: [f64; 3], angle: f64) -> Rotation {
        let (s, c) = angle.sin_cos();
        // Rodrigues: v c + (k x v) s + k (k . v)(1 - c)
        let turn = |v: [f64; 3]| {
            let kv = cross(axis, v);
            let kd = dot(axis, v) * (1.0 - c);
            std::array::from_fn(|i| v[i] * c + kv[i] * s + axis[i] * kd)
        };
        Rotation {
            axes: self.axes.map(turn),
        }
    }

    /// A tensor given in the global axes, in the material ones: $T_m = Q T_g Q^T$.
    pub fn to_material(&self, t: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let q = &self.axes;
        std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                (0..3)
                    .map(|i| (0..3).map(|j| q[a][i] * t[i][j] * q[b][j]).sum::<f64>())
                    .sum()
            })
        })
    }

    /// The strain of the displacement gradient `h` (global axes) in the material axes, in
    /// Voigt order with engineering shears: $\varepsilon_m = Q\, \mathrm{sym}(h)\, Q^T$.
    pub fn strain_to_material(&self, h: &[[f64; 3]; 3]) -> [f64; 6] {
        let sym: [[f64; 3]; 3] =
            std::array::from_fn(|a| std::array::from_fn(|b| 0.5 * (h[a][b] + h[b][a])));
        let e = self.to_material(&sym);
        [
            e[0][0],
            e[1][1],
            e[2][2],
            2.0 * e[1][2],
            2.0 * e[0][2],
            2.0 * e[0][1],
        ]
    }

    /// A stress given in the material axes (Voigt order) in the global ones, as a tensor:
    /// $\sigma_g = Q^T \sigma_m Q$.
    pub fn stress_to_global(&self, s: &[f64; 6]) -> [[f64; 3]; 3] {
        let t = [[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]];
        let q = &self.axes;
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                (0..3)
                    .map(|a| (0..3).map(|b| q[a][i] * t[a][b] * q[b][j]).sum::<f64>())
                    .sum()
            })
        })
    }

    /// The stiffness `c` of the material axes in the global axes:
    /// $C^g_{pqrs} = Q_{ap} Q_{bq} Q_{cr} Q_{ds} C_{abcd}$.
    pub fn rotate_voigt(&self, c: &Voigt) -> Voigt {
        let q = &self.axes;
        let mut t = to_tensor(c);
        // one index at a time: 4 x 81 x 3 products
        for slot in 0..4 {
            let mut next = [[[[0.0; 3]; 3]; 3]; 3];
            for (i, n) in next.iter_mut().enumerate() {
                for (j, n) in n.iter_mut().enumerate() {
                    for (k, n) in n.iter_mut().enumerate() {
                        for (l, n) in n.iter_mut().enumerate() {
                            let mut idx = [i, j, k, l];
                            *n = (0..3)
                                .map(|a| {
                                    let p = idx[slot];
                                    idx[slot] = a;
                                    let v = q[a][p] * t[idx[0]][idx[1]][idx[2]][idx[3]];
                                    idx[slot] = p;
                                    v
                                })
                                .sum();
                        }
                    }
                }
            }
            t = next;
        }
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let ((a, b), (c, d)) = (VOIGT_PAIRS[i], VOIGT_PAIRS[j]);
                t[a][b][c][d]
            })
        })
    }
}

fn to_tensor(c: &Voigt) -> [[[[f64; 3]; 3]; 3]; 3] {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            std::array::from_fn(|k| {
                std::array::from_fn(|l| c[voigt_index(i, j)][voigt_index(k, l)])
            })
        })
    })
}

/// $\max_n \lambda_{max}(\Gamma(n))$ over unit directions n, $\Gamma_{ik} = C_{ijkl} n_j n_l$: the
/// largest squared plane-wave speed times the density. A Fibonacci sphere of 4,000
/// directions, then a pattern search from the best of them.
pub(crate) fn largest_acoustic_eigenvalue(c: &Voigt) -> f64 {
    let t = to_tensor(c);
    let gamma_max = |n: [f64; 3]| {
        let n = unit(n).unwrap_or([1.0, 0.0, 0.0]);
        let g = nalgebra::Matrix3::from_fn(|i, k| {
            let mut s = 0.0;
            for j in 0..3 {
                for l in 0..3 {
                    s += t[i][j][k][l] * n[j] * n[l];
                }
            }
            s
        });
        nalgebra::SymmetricEigen::new(g).eigenvalues.max()
    };
    let count = 4000;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let (mut best, mut value) = ([1.0, 0.0, 0.0], f64::NEG_INFINITY);
    for k in 0..count {
        let z = 1.0 - 2.0 * (k as f64 + 0.5) / count as f64;
        let r = (1.0 - z * z).sqrt();
        let (s, c) = (golden * k as f64).sin_cos();
        let n = [r * c, r * s, z];
        let v = gamma_max(n);
        if v > value {
            (best, value) = (n, v);
        }
    }
    let mut step = 0.05;
    while step > 1e-7 {
        let mut moved = false;
        for a in 0..3 {
            for sign in [-1.0, 1.0] {
                let mut n = best;
                n[a] += sign * step;
                let v = gamma_max(n);
                if v > value {
                    (best, value, moved) = (unit(n).unwrap_or(best), v, true);
                }
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    value
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parallel_or_zero_axes_give_no_rotation() {
        assert!(Rotation::from_axes([1.0, 0.0, 0.0], [2.0, 0.0, 0.0]).is_none());
        assert!(Rotation::from_axes([0.0; 3], [0.0, 1.0, 0.0]).is_none());
        let r = Rotation::from_axes([1.0, 1.0, 0.0], [0.0, 1.0, 0.0]).unwrap();
        let s = 0.5f64.sqrt();
        for (a, b) in r
            .axes
            .iter()
            .flatten()
            .zip([s, s, 0.0, -s, s, 0.0, 0.0, 0.0, 1.0])
        {
            assert!((a - b).abs() < 1e-15);
        }
    }

    /// Turning a stiffness and turning a strain the other way give the same energy; a quarter
    /// turn about z swaps C11 and C22.
    #[test]
    fn a_rotated_stiffness_keeps_the_energy_of_the_rotated_strain() {
        let mut c = [[0.0; 6]; 6];
        let d = [140.0, 10.0, 11.0, 3.5, 5.0, 5.5];
        for i in 0..6 {
            c[i][i] = d[i];
        }
        (c[0][1], c[0][2], c[1][2]) = (3.0, 3.2, 4.4);
        (c[1][0], c[2][0], c[2][1]) = (3.0, 3.2, 4.4);
        let r = Rotation::IDENTITY
            .turned([0.0, 0.0, 1.0], 0.3)
            .turned([1.0, 0.0, 0.0], -0.7);
        let cg = r.rotate_voigt(&c);
        let eps_g = [
            [0.01, 0.002, -0.003],
            [0.002, -0.004, 0.005],
            [-0.003, 0.005, 0.006],
        ];
        let eps_m = r.to_material(&eps_g);
        let energy = |c: &Voigt, e: &[[f64; 3]; 3]| {
            let s = super::super::voigt_stress(c, e);
            (0..3)
                .map(|i| (0..3).map(|j| s[i][j] * e[i][j]).sum::<f64>())
                .sum::<f64>()
        };
        let (a, b) = (energy(&cg, &eps_g), energy(&c, &eps_m));
        assert!((a - b).abs() < 1e-13 * a.abs(), "{a} {b}");
        let q = Rotation::IDENTITY.turned([0.0, 0.0, 1.0], std::f64::consts::FRAC_PI_2);
        let cq = q.rotate_voigt(&c);
        assert!((cq[0][0] - c[1][1]).abs() < 1e-12 && (cq[1][1] - c[0][0]).abs() < 1e-12);
    }

    #[test]
    fn the_largest_wave_of_an_isotropic_stiffness_is_the_p_wave() {
        let m = super::super::Elastic::from_engineering(200.0, 0.3, 1.0);
        let v = largest_acoustic_eigenvalue(&m.voigt());
        assert!((v - (m.lambda + 2.0 * m.mu)).abs() < 1e-10 * v);
    }
}
