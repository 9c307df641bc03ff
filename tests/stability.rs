//! Stability where methods fail (the study's atlas in miniature):
//! - the classical gap constraint with the trapezoidal rule chatters on the two bars and
//!   gains energy, worse on the finer mesh; the paper's gap-rate constraint does not;
//! - a fixed penalty that is too large runs out of iterations and diverges, where the
//!   adaptive law started from the same value converges.

mod common;
use common::*;

struct Chatter {
    openings: usize,
    energy_growth: f64,
    iterations_mean: f64,
}

fn chatter(scene: &str, constraint: &str) -> Chatter {
    let text = edit(
        &scene_text(scene),
        "constraint = \"gap_rate\"",
        &format!("constraint = \"{constraint}\""),
    );
    let (s, h) = run_text(&format!("chatter_{scene}_{constraint}"), &text);
    let s = s.expect("run completes");
    let t = h.col("time");
    let active = h.col("impact.active");
    let openings = (1..t.len())
        .filter(|&i| t[i] >= 0.02 && t[i] <= 0.18 && active[i] == 0.0 && active[i - 1] > 0.0)
        .count();
    let e = h.col("total_energy");
    let c = Chatter {
        openings,
        energy_growth: e.iter().fold(0.0f64, |a, b| a.max(*b)) / e[0],
        iterations_mean: s.iterations_mean,
    };
    eprintln!(
        "{scene} {constraint}: {} openings on the plateau, max energy / initial {:.3}, {:.2} iterations per step",
        c.openings, c.energy_growth, c.iterations_mean
    );
    c
}

#[test]
fn classical_gap_chatters_and_gap_rate_does_not() {
    let coarse_gap = chatter("two_bars.toml", "gap");
    let fine_gap = chatter("two_bars_fine.toml", "gap");
    let coarse_rate = chatter("two_bars.toml", "gap_rate");
    let fine_rate = chatter("two_bars_fine.toml", "gap_rate");
    assert!(
        coarse_gap.openings >= 2,
        "gap: contact should open and close"
    );
    assert!(coarse_gap.energy_growth > 1.1, "gap: energy should grow");
    assert!(
        fine_gap.openings > coarse_gap.openings,
        "finer mesh should chatter more"
    );
    assert!(fine_gap.energy_growth > coarse_gap.energy_growth);
    for r in [coarse_rate, fine_rate] {
        assert_eq!(
            r.openings, 0,
            "gap rate must hold the contact on the plateau"
        );
        assert!(r.energy_growth <= 1.0 + 1e-6);
    }
}

#[test]
fn too_large_fixed_penalty_fails_where_adaptive_converges() {
    let with = |law| penalty_scene(law, "1.0e3");
    let (fixed, _) = run_text("penalty_fixed_1e3", &with("fixed"));
    let err = fixed.expect_err("a fixed penalty of 1e3 (eps s ~ 1e4) must not converge");
    let msg = err.to_string();
    eprintln!("fixed eps = 1e3: {msg}");
    assert!(msg.contains("diverged"), "{msg}");
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out_path("penalty_fixed_1e3").join("summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(summary["status"], "diverged");
    assert!(
        summary["iterations_max"].as_u64().unwrap() >= 100,
        "ran out of iterations"
    );

    let (adaptive, h) = run_text("penalty_adaptive_1e3", &with("adaptive"));
    let s = adaptive.expect("the adaptive law converges from the same start");
    eprintln!(
        "adaptive from eps = 1e3: {:.2} iterations per step (max {}), final eps {:.4e}, {} decreases, {} increases",
        s.iterations_mean,
        s.iterations_max,
        s.interfaces[0].penalty_normal_final.expect("an implicit run has a penalty"),
        s.interfaces[0].penalty_decreases,
        s.interfaces[0].penalty_increases
    );
    assert_eq!(s.unconverged_steps, 0);
    assert!(s.interfaces[0].penalty_decreases >= 1);
    let m = measures(&h, "impact", 0.5, 0.01);
    assert!(
        (m.plateau_mean - 0.5).abs() <= 0.01,
        "force {}",
        m.plateau_mean
    );
}

#[test]
fn too_small_fixed_penalty_is_slow_where_adaptive_is_not() {
    let with = |law| penalty_scene(law, "1.0e-3");
    let (fixed, _) = run_text("penalty_fixed_1e-3", &with("fixed"));
    let fixed = fixed.expect("runs");
    let (adaptive, _) = run_text("penalty_adaptive_1e-3", &with("adaptive"));
    let adaptive = adaptive.expect("runs");
    eprintln!(
        "eps = 1e-3: fixed {:.2} iterations per step ({} unconverged), adaptive {:.2} ({} unconverged)",
        fixed.iterations_mean, fixed.unconverged_steps, adaptive.iterations_mean, adaptive.unconverged_steps
    );
    assert!(
        fixed.unconverged_steps > 0,
        "eps s ~ 1e-3 cannot converge in 100 iterations"
    );
    assert_eq!(adaptive.unconverged_steps, 0);
    assert!(adaptive.iterations_mean * 5.0 < fixed.iterations_mean);
}

/// The paper's two bars with the given penalty law started from `eps`, and the plain
/// iteration (Anderson acceleration would hide what the penalty law does).
fn penalty_scene(law: &str, eps: &str) -> String {
    edit(
        &scene_text("two_bars.toml"),
        "penalty = \"adaptive\"",
        &format!("penalty = \"{law}\"\npenalty_normal = {eps}\nacceleration = \"none\""),
    )
}
