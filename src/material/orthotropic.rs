//! Orthotropic linear elasticity from engineering constants, in the material's own axes
//! 1, 2, 3: Young's moduli $E_i$, Poisson's ratios $\nu_{ij}$ (strain $-\nu_{ij}\sigma/E_i$
//! along j under a stress along i) and shear moduli $G_{ij}$.

use super::Voigt;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orthotropic {
    /// E1, E2, E3.
    pub e: [f64; 3],
    /// nu12, nu13, nu23.
    pub nu: [f64; 3],
    /// G12, G13, G23.
    pub g: [f64; 3],
}

/// The constants' names, as the scene spells them.
pub(crate) const E_NAMES: [&str; 3] = ["e1", "e2", "e3"];
pub(crate) const NU_NAMES: [&str; 3] = ["nu12", "nu13", "nu23"];
pub(crate) const G_NAMES: [&str; 3] = ["g12", "g13", "g23"];

impl Orthotropic {
    /// Isotropic in the 2-3 plane about the fibre axis 1: E3 = E2, nu13 = nu12, G13 = G12
    /// and G23 = E2 / (2 (1 + nu23)).
    pub fn transversely_isotropic(e1: f64, e2: f64, nu12: f64, nu23: f64, g12: f64) -> Self {
        Orthotropic {
            e: [e1, e2, e2],
            nu: [nu12, nu12, nu23],
            g: [g12, g12, e2 / (2.0 * (1.0 + nu23))],
        }
    }

    /// The compliance in Voigt order (11, 22, 33, 23, 13, 12), engineering shear strains.
    pub fn compliance(&self) -> Voigt {
        let [e1, e2, e3] = self.e;
        let [n12, n13, n23] = self.nu;
        let [g12, g13, g23] = self.g;
        let mut s = [[0.0; 6]; 6];
        s[0][0] = 1.0 / e1;
        s[1][1] = 1.0 / e2;
        s[2][2] = 1.0 / e3;
        (s[0][1], s[1][0]) = (-n12 / e1, -n12 / e1);
        (s[0][2], s[2][0]) = (-n13 / e1, -n13 / e1);
        (s[1][2], s[2][1]) = (-n23 / e2, -n23 / e2);
        s[3][3] = 1.0 / g23;
        s[4][4] = 1.0 / g13;
        s[5][5] = 1.0 / g12;
        s
    }

    /// Why the constants give no positive definite stiffness, naming the constants, or
    /// `None` when they do: moduli must be positive, each $\nu_{ij}^2 < E_i / E_j$, and the
    /// normal compliance's determinant positive.
    pub fn indefinite(&self) -> Option<String> {
        let bad = |names: &[&str], what: &str| Some(format!("{} {what}", names.join(", ")));
        for (k, &e) in self.e.iter().enumerate() {
            if !(e.is_finite() && e > 0.0) {
                return bad(
                    &[E_NAMES[k]],
                    &format!("must be a positive modulus, got {e}"),
                );
            }
        }
        for (k, &g) in self.g.iter().enumerate() {
            if !(g.is_finite() && g > 0.0) {
                return bad(
                    &[G_NAMES[k]],
                    &format!("must be a positive modulus, got {g}"),
                );
            }
        }
        let [e1, e2, e3] = self.e;
        for (k, (ei, ej)) in [(e1, e2), (e1, e3), (e2, e3)].into_iter().enumerate() {
            let nu = self.nu[k];
            if !(nu.is_finite() && nu * nu < ei / ej) {
                let limit = (ei / ej).sqrt();
                return bad(
                    &[NU_NAMES[k]],
                    &format!("= {nu} must lie within ±{limit:.6} (the square root of the moduli's ratio) for a positive definite stiffness"),
                );
            }
        }
        let s = self.compliance();
        if det3(&s) <= 0.0 {
            return bad(
                &NU_NAMES,
                "together give a normal compliance with no positive determinant (1 - nu12 nu21 - nu13 nu31 - nu23 nu32 - 2 nu21 nu32 nu13 must be > 0)",
            );
        }
        None
    }

    /// The stiffness, the compliance's inverse (call [`Self::indefinite`] first).
    pub fn stiffness(&self) -> Voigt {
        let s = self.compliance();
        let d = det3(&s);
        let m = |i: usize, j: usize| s[i][j];
        // the normal block's inverse by cofactors
        let cof = |i: usize, j: usize| {
            let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
            let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
            m(r0, c0) * m(r1, c1) - m(r0, c1) * m(r1, c0)
        };
        let mut c = [[0.0; 6]; 6];
        for i in 0..3 {
            for (j, cij) in c[i].iter_mut().take(3).enumerate() {
                *cij = cof(j, i) / d;
            }
            c[i + 3][i + 3] = 1.0 / s[i + 3][i + 3];
        }
        c
    }
}

/// The determinant of the normal (upper left 3 x 3) block.
fn det3(s: &Voigt) -> f64 {
    s[0][0] * (s[1][1] * s[2][2] - s[1][2] * s[2][1])
        - s[0][1] * (s[1][0] * s[2][2] - s[1][2] * s[2][0])
        + s[0][2] * (s[1][0] * s[2][1] - s[1][1] * s[2][0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Elastic;

    #[test]
    fn isotropic_constants_give_the_isotropic_stiffness() {
        let (e, nu) = (200.0, 0.3);
        let g = e / (2.0 * (1.0 + nu));
        let o = Orthotropic {
            e: [e; 3],
            nu: [nu; 3],
            g: [g; 3],
        };
        assert_eq!(o.indefinite(), None);
        let (c, want) = (o.stiffness(), Elastic::from_engineering(e, nu, 1.0).voigt());
        for i in 0..6 {
            for j in 0..6 {
                assert!((c[i][j] - want[i][j]).abs() < 1e-12 * e, "{i} {j}");
            }
        }
    }

    #[test]
    fn the_stiffness_inverts_the_compliance() {
        let o = Orthotropic::transversely_isotropic(140.0, 10.0, 0.3, 0.45, 5.0);
        let (c, s) = (o.stiffness(), o.compliance());
        for (i, ci) in c.iter().enumerate() {
            for j in 0..6 {
                let p: f64 = ci.iter().zip(&s).map(|(cik, sk)| cik * sk[j]).sum();
                assert!((p - (i == j) as u8 as f64).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn indefinite_constants_are_named() {
        let mut o = Orthotropic::transversely_isotropic(140.0, 10.0, 0.3, 0.45, 5.0);
        o.nu[0] = 4.0; // nu12^2 must stay below E1 / E2 = 14
        assert!(o.indefinite().unwrap().starts_with("nu12"));
        o.nu[0] = 0.3;
        o.g[2] = -1.0;
        assert!(o.indefinite().unwrap().starts_with("g23"));
        // each pair admissible, the three together not
        let o = Orthotropic {
            e: [1.0; 3],
            nu: [0.9, 0.9, 0.9],
            g: [1.0; 3],
        };
        assert!(o.indefinite().unwrap().starts_with("nu12, nu13, nu23"));
    }
}
