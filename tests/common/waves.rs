//! Wave-theory checks of contact histories: force plateau, duration, release and energy.

use impact::output::Summary;

use super::history::History;

/// Wave-theory measures of a history's contact force.
pub struct ForceMeasures {
    pub plateau_mean: f64,
    pub plateau_max_dev: f64,
    pub last_contact: f64,
    pub impulse: f64,
    pub max_energy_rise: f64,
    pub energy_loss: f64,
}

pub fn measures(h: &History, contact: &str, exact: f64, dt: f64) -> ForceMeasures {
    let t = h.col("time");
    let f = h.col(&format!("{contact}.normal_force"));
    let e = h.col("total_energy");
    let plateau: Vec<f64> = t
        .iter()
        .zip(&f)
        .filter(|(t, _)| **t >= 0.02 - 1e-9 && **t <= 0.18 + 1e-9)
        .map(|(_, f)| *f)
        .collect();
    let mean = plateau.iter().sum::<f64>() / plateau.len() as f64;
    ForceMeasures {
        plateau_mean: mean,
        plateau_max_dev: plateau
            .iter()
            .map(|p| (p - exact).abs() / exact)
            .fold(0.0, f64::max),
        last_contact: t
            .iter()
            .zip(&f)
            .filter(|(_, f)| **f > 0.0)
            .map(|(t, _)| *t)
            .fold(0.0, f64::max),
        impulse: f.iter().sum::<f64>() * dt,
        max_energy_rise: e.windows(2).map(|w| w[1] - w[0]).fold(f64::MIN, f64::max) / e[0],
        energy_loss: (e[0] - e[e.len() - 1]) / e[0],
    }
}

/// The two bars' exact contact force, rho c S v0 / 2.
pub const TWO_BARS_FORCE: f64 = 0.5;

/// Release at 0.2 +- 2 dt, no step raising the energy by more than 1e-6 of E0, and a loss
/// in [0, loss_max].
pub fn check_release_and_energy(h: &History, dt: f64, loss_max: f64) -> ForceMeasures {
    let m = measures(h, "impact", TWO_BARS_FORCE, dt);
    assert!(
        (m.last_contact - 0.2).abs() <= 2.0 * dt + 1e-9,
        "release at {} (exact 0.2 +- 2 dt)",
        m.last_contact
    );
    assert!(
        m.max_energy_rise <= 1e-6,
        "total energy rose by {:.3e} of its initial value in one step",
        m.max_energy_rise
    );
    assert!(
        m.energy_loss >= 0.0 && m.energy_loss <= loss_max,
        "energy loss {}",
        m.energy_loss
    );
    m
}

/// Tolerances of one two-bar check (relative unless named otherwise).
pub struct Tolerances {
    pub mean: f64,
    pub row: f64,
    pub impulse: f64,
    /// Largest |v_A| after release.
    pub rest_a: f64,
    /// Largest |v_B - 1| after release.
    pub speed_b: f64,
    pub loss: f64,
}

/// The two bars' history against wave theory with the given tolerances (and every step's
/// contact iteration converged).
pub fn check_two_bars_history(
    tag: &str,
    h: &History,
    s: &Summary,
    dt: f64,
    tol: &Tolerances,
) -> ForceMeasures {
    let m = check_release_and_energy(h, dt, tol.loss);
    eprintln!(
        "{tag}: plateau mean {:.5} max dev {:.4} release {} impulse {:.5} loss {:.4} iterations/step {:.2} (max {})",
        m.plateau_mean, m.plateau_max_dev, m.last_contact, m.impulse, m.energy_loss, s.iterations_mean, s.iterations_max
    );
    assert!((m.plateau_mean - TWO_BARS_FORCE).abs() <= tol.mean * TWO_BARS_FORCE);
    assert!(
        m.plateau_max_dev <= tol.row,
        "row deviation {}",
        m.plateau_max_dev
    );
    assert!(
        (m.impulse - 0.1).abs() <= tol.impulse * 0.1,
        "impulse {}",
        m.impulse
    );
    assert!(
        h.last("A.vx").abs() <= tol.rest_a,
        "A keeps {}",
        h.last("A.vx")
    );
    assert!(
        (h.last("B.vx") - 1.0).abs() <= tol.speed_b,
        "B moves at {}",
        h.last("B.vx")
    );
    assert_eq!(s.unconverged_steps, 0);
    m
}

/// The core issue's fine-mesh tolerances.
pub const FINE: Tolerances = Tolerances {
    mean: 0.01,
    row: 0.03,
    impulse: 0.02,
    rest_a: 0.03,
    speed_b: 0.03,
    loss: 0.015,
};

/// The two bars 0.05 apart: with `adjust` closing the gap (`adjusted`) their contact force
/// `column` is above 0.3 (of wave theory's 0.5) on every step before t = 0.04, and without it
/// (`apart`) zero there, the gap still open.
pub fn touching_from_the_start(adjusted: &History, apart: &History, column: &str) {
    let (t, f, fg) = (
        adjusted.col("time"),
        adjusted.col(column),
        apart.col(column),
    );
    let early: Vec<usize> = (0..t.len())
        .filter(|&i| t[i] > 0.0 && t[i] < 0.04)
        .collect();
    assert!(!early.is_empty());
    for &i in &early {
        assert_eq!(fg[i], 0.0, "apart at t = {}", t[i]);
        assert!(f[i] > 0.3, "touching at t = {}: {}", t[i], f[i]);
    }
}
