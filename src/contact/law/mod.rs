//! Contact laws as kinds: what tangential force a pressed secondary node may carry, given its
//! normal force. Each law is one file: its parameters, the bound of the tangential force, the
//! return of a trial force onto the admissible set and the test of sliding. The implicit
//! multiplier iteration ([`super::friction`]), the explicit impulse sweeps
//! ([`crate::kernels::impulse`] and the reports) and the WGSL kernels (`shaders/shared/law_*.wgsl`
//! through `contact_law.wgsl`, each the twin of its file here) all go through [`ContactLaw`].
//!
//! On the device a law is two words of a pair or a plane: its [`ContactLaw::code`] and its
//! [`ContactLaw::coefficient`].

pub mod coulomb;
pub mod frictionless;

pub use coulomb::Coulomb;
pub use frictionless::Frictionless;

use crate::geometry::vector::V3;

/// The law of one interface.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum ContactLaw {
    Frictionless(Frictionless),
    Coulomb(Coulomb),
}

impl Default for ContactLaw {
    fn default() -> Self {
        ContactLaw::Frictionless(Frictionless)
    }
}

impl ContactLaw {
    /// The law of a scene's `friction` coefficient: Coulomb where it is positive, else
    /// frictionless.
    pub fn of_friction(mu: f64) -> Self {
        if mu > 0.0 {
            ContactLaw::Coulomb(Coulomb { mu })
        } else {
            ContactLaw::Frictionless(Frictionless)
        }
    }

    /// Whether the law carries a tangential force (and so dissipates work, and keeps a
    /// tangential state in the iterations).
    pub fn is_frictional(&self) -> bool {
        match self {
            ContactLaw::Frictionless(_) => false,
            ContactLaw::Coulomb(_) => true,
        }
    }

    /// The largest magnitude of the tangential force under the normal force `normal` (the
    /// radius of the admissible set).
    pub fn bound(&self, normal: f64) -> f64 {
        match self {
            ContactLaw::Frictionless(l) => l.bound(normal),
            ContactLaw::Coulomb(l) => l.bound(normal),
        }
    }

    /// A tangential trial force returned onto the admissible set of the normal force
    /// `normal`, and whether the trial was inside it (the node sticks).
    pub fn returned(&self, trial: V3, normal: f64) -> (V3, bool) {
        match self {
            ContactLaw::Frictionless(l) => l.returned(trial, normal),
            ContactLaw::Coulomb(l) => l.returned(trial, normal),
        }
    }

    /// The trial `t` without its component along the unit normal `n`, returned onto the
    /// admissible set of the normal force `normal` (zero where that set is a point).
    pub fn projected(&self, t: V3, n: V3, normal: f64) -> V3 {
        match self {
            ContactLaw::Frictionless(l) => l.projected(t, n, normal),
            ContactLaw::Coulomb(l) => l.projected(t, n, normal),
        }
    }

    /// Whether a node pressed by `normal` with the tangential force `t` slides: its force
    /// lies on the bound, within the relative distance `tolerance`.
    pub fn is_sliding(&self, t: V3, normal: f64, tolerance: f64) -> bool {
        match self {
            ContactLaw::Frictionless(_) => false,
            ContactLaw::Coulomb(l) => l.is_sliding(t, normal, tolerance),
        }
    }

    /// The law's number on the device (`shaders/shared/contact_law.wgsl`).
    pub fn code(&self) -> u32 {
        match self {
            ContactLaw::Frictionless(_) => frictionless::CODE,
            ContactLaw::Coulomb(_) => coulomb::CODE,
        }
    }

    /// The law's coefficient on the device (the Coulomb coefficient; 0 without one).
    pub fn coefficient(&self) -> f64 {
        match self {
            ContactLaw::Frictionless(_) => 0.0,
            ContactLaw::Coulomb(l) => l.mu,
        }
    }
}

/// `frictionless`, or `friction 0.3` for Coulomb's law (the report's words).
impl std::fmt::Display for ContactLaw {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ContactLaw::Frictionless(_) => write!(f, "frictionless"),
            ContactLaw::Coulomb(l) => write!(f, "friction {}", l.mu),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::vector::norm;

    const LAWS: [ContactLaw; 2] = [
        ContactLaw::Frictionless(Frictionless),
        ContactLaw::Coulomb(Coulomb { mu: 0.3 }),
    ];

    #[test]
    fn a_returned_force_lies_within_the_bound_and_an_inside_trial_is_kept() {
        for law in LAWS {
            for trial in [[0.01, -0.02, 0.0], [3.0, 4.0, 0.0], [0.0; 3]] {
                let (t, sticks) = law.returned(trial, 10.0);
                assert!(
                    norm(t) <= law.bound(10.0) * (1.0 + 1e-15),
                    "{law:?} {trial:?}"
                );
                if norm(trial) <= law.bound(10.0) {
                    assert!(sticks && t == trial, "{law:?} {trial:?}");
                }
            }
        }
    }

    #[test]
    fn a_projection_removes_the_normal_part_first() {
        let n = [0.0, 0.0, 1.0];
        for law in LAWS {
            let t = law.projected([0.1, 0.0, 7.0], n, 10.0);
            assert_eq!(t[2], 0.0);
            assert!(norm(t) <= law.bound(10.0) + 1e-15);
        }
        let c = ContactLaw::of_friction(0.3);
        assert_eq!(c.projected([0.1, 0.0, 7.0], n, 10.0), [0.1, 0.0, 0.0]);
        let t = c.projected([30.0, 40.0, 7.0], n, 10.0);
        let want = [1.8, 2.4, 0.0];
        assert!((0..3).all(|a| (t[a] - want[a]).abs() < 1e-15), "{t:?}");
    }

    #[test]
    fn the_scene_coefficient_chooses_the_kind() {
        assert_eq!(ContactLaw::of_friction(0.0), ContactLaw::default());
        assert!(!ContactLaw::of_friction(0.0).is_frictional());
        assert_eq!(ContactLaw::of_friction(0.4).coefficient(), 0.4);
        assert_ne!(
            ContactLaw::of_friction(0.4).code(),
            ContactLaw::default().code()
        );
    }
}
