//! Elastic laws: isotropic in Lamé form, or a general (orthotropic, rotated) stiffness in
//! Voigt form.

pub mod cohesive;
pub mod damage;
pub mod failure;
pub mod layup;
pub mod orthotropic;
pub mod rotation;

pub use cohesive::{CohesiveLaw, SlidingStep};
pub use damage::PlyDamage;
pub use failure::{failure_indices, Strength};
pub use layup::{Layup, LayupPly};
pub use orthotropic::Orthotropic;
pub use rotation::Rotation;

/// A stiffness in Voigt order (xx, yy, zz, yz, xz, xy) acting on engineering strains
/// ($\gamma_{yz} = 2\varepsilon_{yz}$ ...): $\sigma_I = C_{IJ} \varepsilon_J$. Its entries are the
/// tensor's, $C_{IJ} = C_{ijkl}$ with $I = (ij)$, $J = (kl)$.
pub(crate) type Voigt = [[f64; 6]; 6];

/// The (i, j) index pair of each Voigt row.
pub const VOIGT_PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

/// The Voigt row of the index pair (i, j).
pub(crate) fn voigt_index(i: usize, j: usize) -> usize {
    match (i.min(j), i.max(j)) {
        (a, b) if a == b => a,
        (1, 2) => 3,
        (0, 2) => 4,
        _ => 5,
    }
}

/// Linear elasticity: isotropic, sigma = lambda tr(eps) I + 2 mu eps, or with a full stiffness
/// `c` in the global axes (then `lambda` and `mu` are unused).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    pub lambda: f64,
    pub mu: f64,
    pub density: f64,
    /// The stiffness in the global axes of an anisotropic material (None: isotropic).
    pub c: Option<Voigt>,
}

impl Elastic {
    /// From Young's modulus E and Poisson's ratio nu:
    /// $\lambda = E\nu/((1+\nu)(1-2\nu))$, $\mu = E/(2(1+\nu))$.
    pub fn from_engineering(youngs_modulus: f64, poissons_ratio: f64, density: f64) -> Elastic {
        let (e, nu) = (youngs_modulus, poissons_ratio);
        Elastic {
            lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            mu: e / (2.0 * (1.0 + nu)),
            density,
            c: None,
        }
    }

    /// A material of stiffness `c` in the global axes.
    pub fn anisotropic(c: Voigt, density: f64) -> Elastic {
        Elastic {
            lambda: 0.0,
            mu: 0.0,
            density,
            c: Some(c),
        }
    }

    /// The stiffness in Voigt form (built from lambda and mu when isotropic).
    pub fn voigt(&self) -> Voigt {
        if let Some(c) = self.c {
            return c;
        }
        let (l, m) = (self.lambda, self.mu);
        let mut c = [[0.0; 6]; 6];
        for i in 0..3 {
            for (j, cij) in c[i].iter_mut().take(3).enumerate() {
                *cij = l + if i == j { 2.0 * m } else { 0.0 };
            }
            c[i + 3][i + 3] = m;
        }
        c
    }

    /// The material with its axes turned by `r` (an isotropic one is unchanged).
    pub fn rotated(&self, r: &Rotation) -> Elastic {
        match self.c {
            None => *self,
            Some(c) => Elastic::anisotropic(r.rotate_voigt(&c), self.density),
        }
    }

    /// The stress of the displacement gradient h (h[a][b] = du_a/dx_b).
    pub fn stress(&self, h: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        match &self.c {
            None => {
                let tr = h[0][0] + h[1][1] + h[2][2];
                std::array::from_fn(|a| {
                    std::array::from_fn(|b| {
                        self.mu * (h[a][b] + h[b][a]) + if a == b { self.lambda * tr } else { 0.0 }
                    })
                })
            }
            Some(c) => voigt_stress(c, h),
        }
    }

    /// The largest speed of a plane wave in any direction, $\sqrt{\max_n
    /// \lambda_{max}(\Gamma(n)) / \rho}$ with the acoustic tensor $\Gamma_{ik} = C_{ijkl} n_j n_l$
    /// (the dilatational speed $\sqrt{(\lambda + 2\mu)/\rho}$ when isotropic).
    pub fn wave_speed(&self) -> f64 {
        match &self.c {
            None => ((self.lambda + 2.0 * self.mu) / self.density).sqrt(),
            Some(c) => (rotation::largest_acoustic_eigenvalue(c) / self.density).sqrt(),
        }
    }
}

/// $\sigma = C \varepsilon$ of the displacement gradient h, as a symmetric tensor.
pub(crate) fn voigt_stress(c: &Voigt, h: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let e = VOIGT_PAIRS.map(|(i, j)| if i == j { h[i][i] } else { h[i][j] + h[j][i] });
    let s: [f64; 6] = std::array::from_fn(|i| (0..6).map(|j| c[i][j] * e[j]).sum());
    [[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]]
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn lame_constants_of_a_uniaxial_bar() {
        let m = Elastic::from_engineering(100.0, 0.0, 0.01);
        assert_eq!(m.lambda, 0.0);
        assert_eq!(m.mu, 50.0);
        assert!((m.wave_speed() - 100.0).abs() < 1e-12);
    }

    #[test]
    fn the_voigt_form_of_an_isotropic_material_gives_its_stress_and_wave_speed() {
        let iso = Elastic::from_engineering(70.0, 0.3, 2.0);
        let full = Elastic::anisotropic(iso.voigt(), 2.0);
        let h = [
            [0.01, 0.002, -0.003],
            [0.004, -0.002, 0.001],
            [0.0, 0.005, 0.006],
        ];
        let (a, b) = (iso.stress(&h), full.stress(&h));
        for i in 0..3 {
            for j in 0..3 {
                assert!((a[i][j] - b[i][j]).abs() < 1e-14, "{a:?} {b:?}");
            }
        }
        assert!((iso.wave_speed() - full.wave_speed()).abs() < 1e-9 * iso.wave_speed());
    }
}
