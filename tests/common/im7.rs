//! IM7/8552 (NASA CompDam) for the cohesive beams: the moduli, the `[[material]]` of the
//! scenes' text, and Williams' crack-length correction of beam theory.

/// E1, E2 (= E3) and G13 (= G12), MPa.
pub const E1: f64 = 171_420.0;
pub const E2: f64 = 9_080.0;
pub const G13: f64 = 5_290.0;

/// The material `im7`, orthotropic with these moduli (nu12 = nu13 0.32, nu23 0.52, G23
/// 2,987 MPa).
pub const MATERIAL: &str = r#"[[material]]
name = "im7"
density = 1.57e-9
orthotropic = { e1 = 171420.0, e2 = 9080.0, e3 = 9080.0, nu12 = 0.32, nu13 = 0.32, nu23 = 0.52, g12 = 5290.0, g13 = 5290.0, g23 = 2987.0 }
"#;

/// Williams' (1989) chi, whose chi h corrects an arm's crack length for its shear and its
/// root's rotation: $\sqrt{E_1 / (11 G_{13})} (3 - 2 (\Gamma / (1 + \Gamma))^2)$, $\Gamma =
/// 1.18 \sqrt{E_1 E_2} / G_{13}$ (2.381 here).
pub fn williams_chi() -> f64 {
    let gamma = 1.18 * (E1 * E2).sqrt() / G13;
    (E1 / (11.0 * G13)).sqrt() * (3.0 - 2.0 * (gamma / (1.0 + gamma)).powi(2))
}
