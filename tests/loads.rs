//! `[[load]]`: nodal forces and pressures with amplitudes, against wave theory and the
//! momentum law, with their work in the energy balance, on both integrators.

mod common;
use common::*;

/// Wave theory's end displacement of a bar held at its far end under a step pressure p on
/// its free end: it moves at p / (rho c) for 2 l / c, then back (rho c = 1 here).
fn step_tip(p: f64, t: f64) -> f64 {
    let t = t % 0.4;
    -p * if t <= 0.2 { t } else { 0.4 - t }
}

/// The largest difference between the tip's displacement and wave theory's, over the rows.
fn tip_error(h: &History, p: f64) -> f64 {
    (h.col("time").iter().zip(h.col("tip.ux")))
        .map(|(&t, u)| (u - step_tip(p, t)).abs())
        .fold(0.0, f64::max)
}

#[test]
fn a_step_pressure_on_a_held_bar_moves_its_end_as_wave_theory_explicit() {
    let (s, h) = run_text(
        "load_step_explicit",
        &held_bar("explicit", 0.0008, 100, PRESSURE),
    );
    assert_eq!(s.expect("runs").status, "completed");
    // the peak 2 p l / E = 0.4 at t = 0.2; a discrete bar rings about the ramp
    let err = tip_error(&h, 2.0);
    assert!(err < 0.02 * 0.4, "tip off wave theory by {err}");
    // the load's work p A u_tip, in the energy balance: total energy stays at zero
    let w = h.col("external_work");
    let at = h
        .col("time")
        .iter()
        .position(|&t| (t - 0.2).abs() < 1e-9)
        .unwrap();
    let exact = 2.0 * step_tip(2.0, 0.2).abs();
    assert!(
        (w[at] - exact).abs() < 0.02 * exact,
        "work {} vs {exact}",
        w[at]
    );
    // the first step's start from v_{-1/2} = v_0 sets the time-centred measure off by
    // -dt^2/8 a_0 M a_0 at once (6.4e-4 here, as for gravity); it holds after that
    let total = h.col("total_energy");
    let drift = total[1..]
        .iter()
        .fold(0.0f64, |m, e| m.max((e - total[1]).abs()));
    assert!(drift < 1e-9 * exact, "total energy moved by {drift}");
    assert!(
        (total[1] + 6.4e-4).abs() < 1e-9,
        "the start's offset is {}",
        total[1]
    );
}

#[test]
fn a_step_pressure_on_a_held_bar_moves_its_end_as_wave_theory_implicit() {
    let (s, h) = run_text(
        "load_step_implicit",
        &held_bar("implicit", 0.002, 100, PRESSURE),
    );
    assert_eq!(s.expect("runs").status, "completed");
    let err = tip_error(&h, 2.0);
    assert!(err < 0.03 * 0.4, "tip off wave theory by {err}");
    // the trapezoidal rule conserves energy with the load's trapezoid work
    let w = h.col("external_work");
    let scale = w.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let drift = h
        .col("total_energy")
        .iter()
        .fold(0.0f64, |m, e| m.max(e.abs()));
    assert!(
        drift < 1e-9 * scale,
        "total energy moved by {drift} of {scale}"
    );
}

/// A free block pushed by a force on every node that ramps up over 0.1 and then holds:
/// its velocity is the impulse over its mass, F t^2 / (2 * 0.1 M) and then F (t - 0.05) / M.
#[test]
fn a_ramped_force_on_a_free_block_gives_it_the_impulse_over_its_mass() {
    for method in ["explicit", "implicit"] {
        let text = held_bar(
            method,
            0.002,
            10,
            "[[load]]\nbody = \"bar\"\nregion = { min = [-1.0, -1.0, -1.0], max = [11.0, 2.0, 2.0] }\nforce = [0.0, 0.5, 0.0]\namplitude = [[0.0, 0.0], [0.1, 1.0]]\n",
        );
        let tag = format!("load_ramp_{method}");
        let (s, h) = run_text(&tag, &text);
        assert_eq!(s.expect("runs").status, "completed");
        // 44 nodes of 0.5 on a body of mass 0.1 (the fix holds x only)
        let (f, m) = (44.0 * 0.5, 0.01 * 10.0);
        let exact = |t: f64| match t < 0.1 {
            true => f * t * t / (2.0 * 0.1 * m),
            false => f * (t - 0.05) / m,
        };
        for (&t, v) in h.col("time").iter().zip(h.col("bar.vy")) {
            assert!(
                (v - exact(t)).abs() <= 1e-9 * exact(0.4),
                "{method}: vy {v} at {t}, impulse over mass {}",
                exact(t)
            );
        }
        // the work goes into motion and strain (the nodes' masses differ, so the block
        // shears): the total stays at zero
        let w = h.last("external_work");
        let drift = h
            .col("total_energy")
            .iter()
            .fold(0.0f64, |m, e| m.max(e.abs()));
        assert!(
            drift < 1e-9 * w,
            "{method}: total energy moved by {drift} of {w}"
        );
    }
}

/// Stopped mid-run and resumed: the history is the unbroken run's, byte for byte, on both
/// integrators.
#[test]
fn a_loaded_run_resumes_to_the_unbroken_history() {
    for (method, dt) in [("explicit", 0.002), ("implicit", 0.004)] {
        let (whole, parts) = (
            format!("loads_whole_{method}"),
            format!("loads_parts_{method}"),
        );
        let text = loaded_bar(method, dt, 0.4);
        let s = run_resumable(&whole, "loaded", &text, (false, None)).expect("whole");
        assert_eq!(s.status, "completed");
        run_resumable(
            &parts,
            "loaded",
            &loaded_bar(method, dt, 0.25),
            (false, None),
        )
        .expect("first part");
        let r = run_resumable(&parts, "loaded", &text, (true, None)).expect("resumed");
        assert_eq!(r.status, "completed");
        assert_eq!(
            history_text(&whole),
            history_text(&parts),
            "{method}: histories differ"
        );
    }
}

/// On a GPU the loads run in the host loop (the element forces on the device): the history
/// follows the CPU's within f32's reach.
#[test]
fn a_loaded_run_on_the_gpu_follows_the_cpu() {
    if skip_gpu("loads on the gpu") {
        return;
    }
    use impact::scene::DeviceChoice;
    let text = loaded_bar("explicit", 0.002, 0.4);
    let (sc, hc) = run_text_on("loads_cpu", &text, Some(DeviceChoice::Cpu));
    let (sg, hg) = run_text_on("loads_gpu", &text, Some(DeviceChoice::Gpu));
    assert_eq!(sc.expect("cpu").status, "completed");
    assert_eq!(sg.expect("gpu").status, "completed");
    compare_histories(&hc, &hg, 0.25, 1e-4);
    let (wc, wg) = (hc.last("external_work"), hg.last("external_work"));
    assert!(
        (wc - wg).abs() <= 1e-4 * wc.abs(),
        "the loads' work {wg} against {wc}"
    );
}

/// The error of `text` as the scene `bad_load.toml`, where it is refused when read or when
/// its model is built; every part must be in it.
fn refused(text: &str, parts: &[&str]) {
    let msg = refusal("bad_load", text);
    assert!(msg.contains("bad_load.toml"), "names the file: {msg}");
    for p in parts {
        assert!(msg.contains(p), "{msg:?} should contain {p:?}");
    }
}

#[test]
fn a_load_that_cannot_be_applied_is_refused_by_its_key() {
    let bar = |load: &str| held_bar("explicit", 0.0008, 10, load);
    let head = "[[load]]\nbody = \"bar\"\n";
    refused(
        &bar(&format!(
            "{head}face = \"x+\"\npressure = 1.0\nforce = [1.0, 0.0, 0.0]\n"
        )),
        &["load[0].force", "exactly one of `force`"],
    );
    refused(
        &bar(&format!("{head}face = \"x+\"\n")),
        &["load[0].force", "exactly one of `force`"],
    );
    refused(
        &bar(&format!("{head}region = {{ min = [9.0, -1.0, -1.0], max = [11.0, 2.0, 2.0] }}\npressure = 1.0\n")),
        &["load[0].pressure", "acts on a face"],
    );
    refused(
        &bar(&format!("{head}face = \"x+\"\npressure = 1.0\namplitude = [[0.0, 0.0], [0.2, 1.0], [0.1, 0.5]]\n")),
        &["load[0].amplitude", "point 2's time 0.1", "times must increase"],
    );
    refused(
        &bar(&format!(
            "{head}face = \"x+\"\npressure = 1.0\namplitude = []\n"
        )),
        &["load[0].amplitude", "has no point"],
    );
    refused(
        &bar(&format!("{head}face = \"x+\"\npressure = inf\n")),
        &["load[0].pressure", "must be finite"],
    );
    // a load on held components goes to the supports (as in CalculiX): the model leaves
    // those forces out and says how many
    let held = impact::scene::Scene::parse(
        &bar(&format!("{head}face = \"x-\"\nforce = [1.0, 1.0, 0.0]\n")),
        std::path::Path::new("held_load.toml"),
    )
    .expect("the scene reads");
    let model = impact::model::Model::from_scene(&held).expect("the model builds");
    assert_eq!(
        model.held_loads,
        vec![4],
        "the x forces of the held face's four nodes"
    );
    assert_eq!(
        model.loads[0].dofs.iter().filter(|&&d| d % 3 == 1).count(),
        4
    );
    assert!(model.loads[0].dofs.iter().all(|&d| d % 3 == 1));
    refused(
        &bar(&format!("{head}region = {{ min = [20.0, 0.0, 0.0], max = [30.0, 1.0, 1.0] }}\nforce = [1.0, 0.0, 0.0]\n")),
        &["load[0]", "selects no node of body `bar`"],
    );
    refused(
        &bar("[[load]]
body = \"rod\"
face = \"x+\"
pressure = 1.0
"),
        &["load[0].body", "rod"],
    );
}
