//! A bar strikes an analytic rigid wall at v0 = 1: force rho c S v0 = 1.0 for 2 l / c = 0.2,
//! then rebound at -1. The bar has 40 elements (dt = 0.0025, c dt = h).

mod common;
use common::*;

#[test]
fn bar_on_rigid_wall_rebounds_at_minus_one() {
    let text = scene_text("bar_on_wall.toml")
        .replace("divisions = [10, 1, 1]", "divisions = [40, 1, 1]")
        .replace("time_step = 0.01", "time_step = 0.0025");
    let (s, h) = run_text("bar_on_wall_fine", &text);
    let s = s.expect("run completes");
    let dt = 0.0025;
    let m = measures(&h, "wall", 1.0, dt);
    eprintln!(
        "wall: plateau mean {:.5} max dev {:.4} release {} rebound {:.5} loss {:.4} iterations/step {:.2}",
        m.plateau_mean, m.plateau_max_dev, m.last_contact, h.last("bar.vx"), m.energy_loss, s.iterations_mean
    );
    assert!(
        (m.plateau_mean - 1.0).abs() <= 0.02,
        "mean force {}",
        m.plateau_mean
    );
    assert!(
        m.plateau_max_dev <= 0.05,
        "row deviation {}",
        m.plateau_max_dev
    );
    assert!(
        (m.last_contact - 0.2).abs() <= 2.0 * dt + 1e-9,
        "release {}",
        m.last_contact
    );
    assert!(
        (h.last("bar.vx") + 1.0).abs() <= 0.03,
        "rebound {}",
        h.last("bar.vx")
    );
    assert!(
        m.max_energy_rise <= 1e-6,
        "energy rise {}",
        m.max_energy_rise
    );
    // the wall takes twice the bar's momentum
    assert!((m.impulse - 0.2 * (-h.last("bar.vx") + 1.0) / 2.0).abs() < 1e-9);
    assert!(h.col("wall.max_penetration").iter().all(|p| *p <= dt * 1.0));
}
