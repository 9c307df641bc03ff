//! A Gmsh-meshed elastic sphere (a quarter, by symmetry, tet4) strikes a rigid plane slowly
//! (v = 0.002 c): peak force, contact duration and maximum approach against Hertz theory,
//! within 5% each. The formulas and numbers are in `scenes/sphere_on_plane.toml` and
//! `docs/method-notes.md`.

mod common;
use common::*;

/// Hertz, E* = 1e4, R = 1, m = 4/3 pi, v = 0.2 (see the scene file).
const DELTA_M: f64 = 0.011_979_8;
const FORCE_M: f64 = 17.482_8;
const T_C: f64 = 0.176_299;
/// The sphere starts this far above the plane.
const GAP0: f64 = 0.002;

#[test]
fn sphere_on_plane_matches_hertz() {
    let (s, h) = run_scene_text("sphere_on_plane", &scene_text("sphere_on_plane.toml"));
    let s = s.expect("run completes");
    let t = h.col("time");
    // the quarter model carries a quarter of the force
    let quarter = h.col("ground.normal_force");
    let f: Vec<f64> = quarter.iter().map(|f| 4.0 * f).collect();
    let peak = f.iter().copied().fold(0.0, f64::max);
    let first = f.iter().position(|&x| x > 0.0).expect("contact");
    let last = f.iter().rposition(|&x| x > 0.0).expect("contact");
    // rows report the step ending at their time: contact spans t[first - 1] .. t[last]
    let duration = t[last] - t[first - 1];
    let approach = h
        .col("centre.uz")
        .iter()
        .map(|u| -u - GAP0)
        .fold(f64::MIN, f64::max);
    let rel = |x: f64, exact: f64| (x - exact) / exact;
    eprintln!(
        "{} elements, {} steps, {:.1} s, {:.1} iterations/step: peak force {peak:.4} ({:+.2}%), duration {duration:.5} ({:+.2}%), approach {approach:.6} ({:+.2}%), rebound {:.5}",
        s.elements,
        s.steps,
        s.wall_seconds,
        s.iterations_mean,
        100.0 * rel(peak, FORCE_M),
        100.0 * rel(duration, T_C),
        100.0 * rel(approach, DELTA_M),
        h.last("ball.vz"),
    );
    assert!(rel(peak, FORCE_M).abs() <= 0.05, "peak force {peak}");
    assert!(
        rel(duration, T_C).abs() <= 0.05,
        "contact duration {duration}"
    );
    assert!(
        rel(approach, DELTA_M).abs() <= 0.05,
        "maximum approach {approach}"
    );
    // the sphere leaves at nearly its impact speed (elastic, quasi-static)
    assert!(
        (h.last("ball.vz") - 0.2).abs() <= 0.002,
        "rebound {}",
        h.last("ball.vz")
    );
    // momentum: the plane's impulse is the quarter's change of momentum (mass from the
    // initial kinetic energy), to 1e-9
    let m = 2.0 * h.col("kinetic_energy")[0] / (0.2 * 0.2);
    let dp = m * (h.last("ball.vz") + 0.2);
    let p = common::impulse(&t, &quarter);
    assert!(
        (p - dp).abs() <= 1e-9 * dp,
        "impulse {p} vs momentum change {dp}"
    );
}
