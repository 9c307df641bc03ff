//! The implicit contact iteration's semi-smooth Newton step (`acceleration = "newton"`): the
//! same histories as Anderson's iteration to the iteration's tolerance, in fewer
//! iterations; a resumed run equals the unbroken one bit for bit; friction keeps Anderson's.

mod common;

use common::history::{history_difference, same_columns, History};
use common::scenes::{edit, history_text, out_path, run_resumable, run_text, scene_text};

/// The scene with `acceleration = "newton"` (the default) in its `[implicit]` table.
fn newton(text: &str) -> String {
    edit(text, "[implicit]", "[implicit]\nacceleration = \"newton\"")
}

/// The scene with `acceleration = "anderson"`.
fn anderson(text: &str) -> String {
    edit(
        text,
        "[implicit]",
        "[implicit]\nacceleration = \"anderson\"",
    )
}

/// The steel ball on the [0/90]s plate over its first 20 steps (17 of them in contact).
fn ball_on_laminate() -> String {
    edit(
        &scene_text("sphere_on_laminate.toml"),
        "end_time = 1.4e-4",
        "end_time = 2.0e-5",
    )
}

#[test]
fn newton_follows_anderson_on_the_ball_on_the_laminate_in_fewer_iterations() {
    let text = ball_on_laminate();
    let (anderson, ha) = run_text("newton_ball_anderson", &anderson(&text));
    let (newton, hn) = run_text("newton_ball_newton", &newton(&text));
    let (anderson, newton) = (anderson.expect("anderson"), newton.expect("newton"));
    for s in [&anderson, &newton] {
        assert_eq!(s.status, "completed");
        assert_eq!(s.unconverged_steps, 0);
    }
    let force = history_difference(&ha, &hn, &same_columns(&["impact.normal_force"]));
    let motion = history_difference(
        &ha,
        &hn,
        &same_columns(&["centre.uz", "centre.vz", "below.uz", "total_energy"]),
    );
    eprintln!(
        "ball on the laminate, 20 steps: {:.2} iterations a step with Anderson, {:.2} with Newton; force {force:.2e}, motion {motion:.2e}",
        anderson.iterations_mean, newton.iterations_mean
    );
    // both stop at a relative change of 1e-6 a step; Anderson's answer is the farther from
    // the converged one (2e-6 of the force at 12 us, docs/method-notes.md)
    assert!(force <= 3e-5, "normal force differs by {force:.2e}");
    assert!(motion <= 5e-6, "motion differs by {motion:.2e}");
    assert!(
        newton.iterations_mean * 3.0 < anderson.iterations_mean,
        "{} against {}",
        newton.iterations_mean,
        anderson.iterations_mean
    );
}

/// A block dropped on a rigid floor (a plane: the secondary nodes alone carry the gather),
/// the whole bottom face in contact; the classical gap constraint too (measure scaled by
/// gamma / (beta dt), no mass term), whose impact gains energy (the paper's point, warned of)
/// with either iteration.
#[test]
fn newton_follows_anderson_on_a_block_dropped_on_a_floor() {
    for constraint in ["gap_rate", "gap"] {
        let implicit = format!("constraint = \"{constraint}\"");
        let text = common::bench_scenes::implicit_block_drop([6, 6, 6], 40, &implicit);
        let (anderson, ha) = run_text(
            &format!("newton_block_anderson_{constraint}"),
            &anderson(&text),
        );
        let (newton, hn) = run_text(&format!("newton_block_newton_{constraint}"), &newton(&text));
        let (anderson, newton) = (anderson.expect("anderson"), newton.expect("newton"));
        let status = match constraint {
            "gap_rate" => "completed",
            _ => "completed_with_warnings",
        };
        for s in [&anderson, &newton] {
            assert_eq!(s.status, status, "{constraint}: {:?}", s.warnings);
            assert!(s.warnings.iter().all(|w| w.kind == "energy_rise"));
            assert_eq!(s.unconverged_steps, 0);
        }
        let d = history_difference(
            &ha,
            &hn,
            &same_columns(&["drop.normal_force", "block.vz", "total_energy"]),
        );
        eprintln!(
            "{constraint}: {:.2} iterations a step with Anderson, {:.2} with Newton; difference {d:.2e}",
            anderson.iterations_mean, newton.iterations_mean
        );
        assert!(d <= 1e-4, "{constraint}: histories differ by {d:.2e}");
        assert!(newton.iterations_mean < anderson.iterations_mean);
    }
}

/// Runs `text` in `tag`'s folder (fresh unless `resume`).
fn run_in(tag: &str, text: &str, resume: bool) -> impact::Result<impact::output::Summary> {
    run_resumable(tag, "newton_resumed", text, (resume, None))
}

/// The flexibility's nodes travel in the checkpoint in the order they joined, so the resumed
/// run rebuilds the same matrix and takes the same Newton steps.
#[test]
fn a_newton_run_resumed_from_its_checkpoint_equals_the_unbroken_run() {
    let text = edit(
        &newton(&ball_on_laminate()),
        "end_time = 2.0e-5",
        "end_time = 1.2e-5",
    );
    let text = edit(&text, "[output]", "[output]\ncheckpoint_every = 4");
    let (full, part) = ("newton_resume_full", "newton_resume_part");
    let s = run_in(full, &text, false).expect("unbroken");
    run_in(
        part,
        &edit(&text, "end_time = 1.2e-5", "end_time = 8.0e-6"),
        false,
    )
    .expect("first half");
    let r = run_in(part, &text, true).expect("resumed");
    assert_eq!(r.status, "completed");
    assert_eq!(history_text(full), history_text(part), "histories");
    assert_eq!(r.energy_final.to_bits(), s.energy_final.to_bits());
    let h = History::read(&out_path(part).join("history.csv"));
    assert!(h.col("impact.normal_force").iter().any(|&f| f > 0.0));
}

/// On the contact space the flexibility's columns are solved in blocks; the resumed run
/// rebuilds them in other blocks and takes the same steps.
#[test]
fn a_newton_run_on_the_contact_space_resumed_equals_the_unbroken_run() {
    let text = |steps| {
        let t = common::bench_scenes::implicit_block_drop([10; 3], steps, "");
        format!("{t}\n[output]\ncheckpoint_every = 4\n")
    };
    let (full, part) = ("newton_space_resume_full", "newton_space_resume_part");
    let s = run_in(full, &text(12), false).expect("unbroken");
    let space = s.linear_solver.as_ref().expect("implicit");
    assert!(space.contact_equations > 0 && space.contact_solves > 0);
    assert!(s.newton.as_ref().is_some_and(|n| n.steps > 0));
    run_in(part, &text(8), false).expect("first part");
    let r = run_in(part, &text(12), true).expect("resumed");
    assert_eq!(r.status, "completed");
    assert_eq!(history_text(full), history_text(part), "histories");
    assert_eq!(r.energy_final.to_bits(), s.energy_final.to_bits());
}

/// With friction on an interface the iteration keeps Anderson's acceleration: the same bits.
#[test]
fn with_friction_newton_leaves_the_iteration_to_anderson() {
    let text = edit(
        &common::bench_scenes::implicit_block_drop([4, 4, 4], 20, ""),
        "primary = { rigid_body = \"floor\" }",
        "primary = { rigid_body = \"floor\" }\nfriction = 0.3",
    );
    let text = edit(
        &text,
        "velocity = [0.0, 0.0, -1.0]",
        "velocity = [0.5, 0.0, -1.0]",
    );
    let (a, ha) = run_text("newton_friction_anderson", &anderson(&text));
    let (n, hn) = run_text("newton_friction_newton", &newton(&text));
    let (a, n) = (a.expect("anderson"), n.expect("newton"));
    assert_eq!(n.status, "completed");
    assert!(ha.col("drop.tangential_force").iter().any(|&f| f > 0.0));
    assert_eq!(
        (a.iterations_total, a.energy_final.to_bits()),
        (n.iterations_total, n.energy_final.to_bits())
    );
    assert_eq!(
        history_difference(&ha, &hn, &same_columns(&["block.vx"])),
        0.0
    );
}
