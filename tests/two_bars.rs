//! Duan & Ye's example 1 against 1D wave theory: contact force rho c S v0 / 2 = 0.5 for
//! 2 l / c = 0.2, then bar A at rest and bar B at v0 = 1; total impulse 0.1.

mod common;
use common::*;

use impact::scene::DeviceChoice;

fn check_two_bars(tag: &str, scene: &str, dt: f64, tol: Tolerances, device: Option<DeviceChoice>) {
    let (s, h) = run_text_on(tag, &scene_text(scene), device);
    let s = s.expect("run completes");
    check_two_bars_history(tag, &h, &s, dt, &tol);
}

#[test]
fn fine_two_bars_match_wave_theory() {
    check_two_bars("two_bars_fine", "two_bars_fine.toml", 0.0025, FINE, None);
}

/// The same on the GPU kernels (f32), with the same tolerances.
#[test]
fn fine_two_bars_match_wave_theory_on_gpu() {
    if skip_gpu("fine_two_bars_on_gpu") {
        return;
    }
    let device = Some(DeviceChoice::Gpu);
    check_two_bars(
        "two_bars_fine_gpu",
        "two_bars_fine.toml",
        0.0025,
        FINE,
        device,
    );
}

/// The paper's coarse mesh (10 elements per bar, c dt = h), with the coarse-mesh tolerances
/// except the impulse: rows within 10%, mean within 2%, |v_A| <= 0.03, v_B within 3%, loss
/// <= 5%. This build reaches 5.2%, 0.06%, 0.0265, 2.65% and 1.6% (event sub-steps on, the
/// default). The impulse is 2.65% short against a 2% tolerance: no time integrator reaches
/// that on this mesh. The same 10-element bars integrated exactly in time (the trapezoidal
/// rule at dt / 100) lose 3.0% with consistent mass and 3.6% with lumped mass, and central
/// differences at c dt = h lose 2.5%: it is the spatial discretisation's O(h) loss at first
/// contact and its smeared release (`docs/method-notes.md`, "Contact events"). The fine mesh
/// meets every tolerance, the impulse included.
const PAPER: Tolerances = Tolerances {
    mean: 0.02,
    row: 0.10,
    impulse: 0.03,
    rest_a: 0.03,
    speed_b: 0.03,
    loss: 0.05,
};

/// Taking the steps of an impact or a release again in sub-steps (`event_substeps`, on by
/// default) moves every measure of the coarse two bars towards wave theory, against the same
/// scene with plain steps (measured: worst row 5.2% against 13.4%, impulse -2.65% against
/// -3.4%, v_A 0.0265 against 0.034, energy loss 1.6% against 2.9%).
#[test]
fn event_substeps_improve_the_paper_two_bars() {
    let text = scene_text("two_bars.toml");
    let plain_text = edit(
        &text,
        "penalty = \"adaptive\"",
        "penalty = \"adaptive\"\nevent_substeps = 1",
    );
    let (s, h) = run_text("two_bars_events", &text);
    let events = s.expect("run completes");
    let (s, hp) = run_text("two_bars_plain", &plain_text);
    let plain = s.expect("run completes");
    let (m, mp) = (
        check_release_and_energy(&h, 0.01, 0.05),
        check_release_and_energy(&hp, 0.01, 0.05),
    );
    eprintln!(
        "events: {} steps refined, row {:.4}, impulse {:.5}, v_A {:.4}, loss {:.4}; plain: row {:.4}, impulse {:.5}, v_A {:.4}, loss {:.4}",
        events.event_steps,
        m.plateau_max_dev,
        m.impulse,
        h.last("A.vx"),
        m.energy_loss,
        mp.plateau_max_dev,
        mp.impulse,
        hp.last("A.vx"),
        mp.energy_loss
    );
    // impact, the step after it, and the release ramp
    assert!(
        (2..=8).contains(&events.event_steps),
        "{}",
        events.event_steps
    );
    assert_eq!(plain.event_steps, 0);
    assert!(m.plateau_max_dev < 0.5 * mp.plateau_max_dev);
    assert!((m.impulse - 0.1).abs() < 0.85 * (mp.impulse - 0.1).abs());
    assert!(h.last("A.vx").abs() < 0.85 * hp.last("A.vx").abs());
    assert!(m.energy_loss < 0.6 * mp.energy_loss);
}

#[test]
fn paper_two_bars_match_wave_theory() {
    check_two_bars("two_bars", "two_bars.toml", 0.01, PAPER, None);
}

#[test]
fn paper_two_bars_match_wave_theory_on_gpu() {
    if skip_gpu("paper_two_bars_on_gpu") {
        return;
    }
    let device = Some(DeviceChoice::Gpu);
    check_two_bars("two_bars_gpu", "two_bars.toml", 0.01, PAPER, device);
}

/// Why the coarse mesh cannot meet the 2% impulse bound: the same 10-element bars integrated
/// (nearly) exactly in time, at dt = 1e-4 and 2e-4 (c dt = h / 100 and h / 50) with plain
/// steps, converge in time to impulses 3.0% (consistent mass) and 3.6% (lumped mass) short of
/// wave theory's 0.1. That is the spatial discretisation's error, which no time integrator
/// removes; the shipped run at dt = 0.01 (-2.65%) is already better than this limit.
#[test]
fn the_paper_mesh_misses_the_impulse_even_exactly_in_time() {
    for (mass, low, high) in [("consistent", 0.028, 0.032), ("lumped", 0.034, 0.038)] {
        let impulse = |dt: f64| {
            let text = edit(
                &edit(
                    &scene_text("two_bars.toml"),
                    "time_step = 0.01",
                    &format!("time_step = {dt}"),
                ),
                "penalty = \"adaptive\"",
                &format!("penalty = \"adaptive\"\nevent_substeps = 1\nmass = \"{mass}\""),
            );
            let (s, h) = run_text(&format!("two_bars_time_exact_{mass}_{dt}"), &text);
            assert_eq!(s.expect("run completes").unconverged_steps, 0);
            measures(&h, "impact", TWO_BARS_FORCE, dt).impulse
        };
        let (fine, finer) = (impulse(2e-4), impulse(1e-4));
        let shortfall = 1.0 - finer / 0.1;
        eprintln!(
            "{mass} mass: impulse {fine:.6} at dt 2e-4, {finer:.6} at 1e-4: {:.2}% short",
            100.0 * shortfall
        );
        assert!(
            (fine - finer).abs() <= 1e-3 * 0.1,
            "not converged in time: {fine} vs {finer}"
        );
        assert!((low..=high).contains(&shortfall), "{mass}: {shortfall}");
    }
}

/// Momentum is conserved at every step (no external force): m_A v_A + m_B v_B = m_A v0.
#[test]
fn momentum_is_conserved_through_the_impact() {
    let (s, h) = run_text("two_bars_momentum", &scene_text("two_bars.toml"));
    let s = s.expect("runs");
    assert_eq!(s.status, "completed", "{:?}", s.warnings);
    let (a, b) = (h.col("A.vx"), h.col("B.vx"));
    for (va, vb) in a.iter().zip(&b) {
        // equal masses 0.1: momentum / mass = va + vb = 1
        assert!((va + vb - 1.0).abs() < 1e-9, "va + vb = {}", va + vb);
    }
}

/// Lumped mass, the other documented choice, also holds the fine-mesh tolerances.
#[test]
fn fine_two_bars_with_lumped_mass() {
    let text = edit(
        &scene_text("two_bars_fine.toml"),
        "penalty = \"adaptive\"",
        "penalty = \"adaptive\"\nmass = \"lumped\"",
    );
    let (s, h) = run_text("two_bars_fine_lumped", &text);
    s.expect("run completes");
    let m = check_release_and_energy(&h, 0.0025, 0.015);
    assert!((m.plateau_mean - TWO_BARS_FORCE).abs() <= 0.01 * TWO_BARS_FORCE);
    assert!(
        m.plateau_max_dev <= 0.03,
        "row deviation {}",
        m.plateau_max_dev
    );
    assert!(
        (m.impulse - 0.1).abs() <= 0.02 * 0.1,
        "impulse {}",
        m.impulse
    );
}

/// Tet4 bars (`tet4_two_bars`: triangular primary faces), one cell across as the hex8 bars,
/// implicit: the hex8 fine bars' tolerances (mean 1%, rows 3%, impulse 2%, A at rest and B at
/// v0 within 0.03, loss <= 1.5%). Measured: mean 0.49998, rows 2.0%, impulse -1.3%, loss
/// 0.3%.
#[test]
fn tet4_two_bars_with_a_triangular_primary_match_wave_theory() {
    let (s, h) = run_text("two_bars_tet4", &tet4_two_bars(1, 1));
    let s = s.expect("run completes");
    check_two_bars_history("tet4 implicit", &h, &s, 0.0025, &FINE);
}

/// Tet4 bars whose contact faces do not match: A has 2 x 2 cells across, B 3 x 3, so A's
/// nodes meet B's triangles inside them (the projection's interior solution and the
/// triangles' shape functions carry the force). The same tolerances. Measured: mean
/// 0.49993, rows 1.6%, impulse -1.1%.
#[test]
fn tet4_two_bars_meeting_inside_triangles_match_wave_theory() {
    let (s, h) = run_text("two_bars_tet4_2_3", &tet4_two_bars(2, 3));
    let s = s.expect("run completes");
    check_two_bars_history("tet4 2 on 3 implicit", &h, &s, 0.0025, &FINE);
}

/// The same on the GPU kernels (the f32 triangle projection, gap and slip rate).
#[test]
fn tet4_two_bars_match_wave_theory_on_gpu() {
    if skip_gpu("tet4_two_bars_on_gpu") {
        return;
    }
    let device = Some(DeviceChoice::Gpu);
    let (s, h) = run_text_on("two_bars_tet4_gpu", &tet4_two_bars(2, 3), device);
    let s = s.expect("run completes");
    check_two_bars_history("tet4 2 on 3 implicit gpu", &h, &s, 0.0025, &FINE);
}

/// A contact's `region` keeps the secondary faces with every node inside it: one that holds
/// the struck end's whole face gives the history of the contact without it, to the last bit;
/// one that holds no whole face is refused by its key.
#[test]
fn a_contact_region_keeps_the_faces_inside_it() {
    let text = scene_text("two_bars.toml");
    let with = |region: &str| {
        edit(
            &text,
            "friction = 0.0",
            &format!("friction = 0.0\nregion = {region}"),
        )
    };
    let (plain, hp) = run_text("region_plain", &text);
    let (kept, hk) = run_text(
        "region_kept",
        &with("{ min = [-0.5, -1.0, -1.0], max = [0.5, 2.0, 2.0] }"),
    );
    assert_eq!(plain.expect("plain run").status, "completed");
    assert_eq!(kept.expect("region run").status, "completed");
    assert_eq!(hp.columns, hk.columns);
    assert_eq!(hp.bits(), hk.bits());
    let none = with("{ min = [-0.5, -1.0, -1.0], max = [0.5, 0.5, 2.0] }");
    let scene = impact::scene::Scene::parse(&none, std::path::Path::new("region.toml"))
        .expect("the scene reads");
    let err = match impact::model::Model::from_scene(&scene) {
        Ok(_) => panic!("a region without a whole face is refused"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("contact[0].region") && err.contains("holds no whole face"),
        "{err}"
    );
}

/// `[[initial_velocity]]` sets the velocity of the nodes it selects over the body's own, the
/// later of two over the earlier: bar A at rest with its nodes given v0 by a region, after a
/// set of 2 v0 on them, gives the history of bar A moving at v0, to the last bit; one that
/// selects no node is refused by its key.
#[test]
fn initial_velocities_on_a_region_give_the_moving_body() {
    let text = scene_text("two_bars.toml");
    let rest = edit(&text, "velocity = [1.0, 0.0, 0.0]\n", "");
    let given = |region: &str| {
        format!(
            "{rest}\n[[initial_velocity]]\nbody = \"A\"\nface = \"x-\"\nvelocity = [2.0, 0.0, 0.0]\n\n\
             [[initial_velocity]]\nbody = \"A\"\nregion = {region}\nvelocity = [1.0, 0.0, 0.0]\n"
        )
    };
    let (plain, hp) = run_text("velocity_plain", &text);
    let whole = "{ min = [-10.0, 0.0, 0.0], max = [0.0, 1.0, 1.0] }";
    let (set, hs) = run_text("velocity_region", &given(whole));
    assert_eq!(plain.expect("plain run").status, "completed");
    assert_eq!(set.expect("region run").status, "completed");
    assert_eq!(hp.columns, hs.columns);
    assert_eq!(hp.bits(), hs.bits());
    let none = given("{ min = [5.0, 0.0, 0.0], max = [6.0, 1.0, 1.0] }");
    let scene = impact::scene::Scene::parse(&none, std::path::Path::new("velocity.toml"))
        .expect("the scene reads");
    let err = match impact::model::Model::from_scene(&scene) {
        Ok(_) => panic!("a velocity on no node is refused"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("initial_velocity[1]") && err.contains("selects no node of body `A`"),
        "{err}"
    );
}

/// A contact's `adjust` (Abaqus's `ADJUST=`): bar B 0.05 ahead of bar A's struck end, and
/// A's end nodes within the 0.1 moved onto B's face before t = 0 (strain free), so the bars
/// touch at once and the force holds wave theory's plateau from the first step, where
/// without it the first 0.05 of time passes with no contact. A negative distance is refused
/// by its key.
#[test]
fn adjust_closes_a_small_gap_before_the_start() {
    let text = scene_text("two_bars.toml");
    let apart = edit(
        &text,
        "box = { min = [0.0, 0.0, 0.0], max = [10.0, 1.0, 1.0]",
        "box = { min = [0.05, 0.0, 0.0], max = [10.05, 1.0, 1.0]",
    );
    let adjusted = edit(&apart, "friction = 0.0", "friction = 0.0\nadjust = 0.1");
    let (s, h) = run_text("adjust_closed", &adjusted);
    let s = s.expect("adjusted run");
    assert_eq!(s.status, "completed");
    assert_eq!(s.initial_contact[0].moved, 4, "the struck end's four nodes");
    let (g, hg) = run_text("adjust_apart", &apart);
    assert_eq!(g.expect("gap run").status, "completed");
    touching_from_the_start(&h, &hg, "impact.normal_force");
    // 1D wave theory: rho c S v0 / 2 = 0.5 while the waves cross the bars (0.2)
    let (t, f) = (h.col("time"), h.col("impact.normal_force"));
    let plateau: Vec<f64> = (0..t.len())
        .filter(|&i| t[i] > 0.02 && t[i] < 0.18)
        .map(|i| f[i])
        .collect();
    let mean = plateau.iter().sum::<f64>() / plateau.len() as f64;
    assert!((mean - 0.5).abs() < 0.02 * 0.5, "plateau {mean}");
    let bad = edit(&apart, "friction = 0.0", "friction = 0.0\nadjust = -0.1");
    let e = impact::scene::Scene::parse(&bad, std::path::Path::new("adjust.toml"))
        .expect_err("a negative adjust")
        .to_string();
    assert!(e.contains("contact[0].adjust"), "{e}");
}
