//! Elastic laws.

/// Isotropic linear elasticity in Lamé form: sigma = lambda tr(eps) I + 2 mu eps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    pub lambda: f64,
    pub mu: f64,
    pub density: f64,
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
        }
    }

    /// Dilatational (P-) wave speed $\sqrt{(\lambda + 2\mu)/\rho}$, the speed that sets the
    /// stable explicit step and the wave resolution of an implicit one.
    pub fn wave_speed(&self) -> f64 {
        ((self.lambda + 2.0 * self.mu) / self.density).sqrt()
    }
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
}
