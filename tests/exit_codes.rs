//! The binary's exit status for each outcome (docs/scene-format.md, "Exit status"), its error lines, the
//! model report of `impact check`, and a run stopped by SIGTERM and resumed.

mod common;
use common::*;
use std::path::PathBuf;
use std::process::Command;

/// Writes a scene text into a fresh folder `tag` (beside a copy of the shipped meshes).
fn scene_file(tag: &str, text: &str) -> PathBuf {
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn success_is_0_and_an_earlier_run_without_overwrite_is_2() {
    let scene = scene_file("exit_ok", &scene_text("two_bars.toml"));
    let out = out_path("exit_ok").join("run");
    let o = impact(&["run", s(&scene), "--out", s(&out), "--quiet"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("; completed;"));
    let o = impact(&["run", s(&scene), "--out", s(&out), "--quiet"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("--overwrite"));
    let o = impact(&["run", s(&scene), "--out", s(&out), "--quiet", "--overwrite"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
}

#[test]
fn usage_errors_are_2() {
    assert_eq!(code(&impact(&["run"])), 2);
    assert_eq!(code(&impact(&["run", "x.toml", "--no-such-flag"])), 2);
    assert_eq!(code(&impact(&["study", "no_such_problem"])), 2);
    // "study --devices tpu blames an internal generated scene"
    let o = impact(&["study", "two_bars", "--quick", "--devices", "tpu"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--devices: unknown device \"tpu\""),
        "{}",
        stderr(&o)
    );
}

#[test]
fn invalid_input_is_3_and_names_file_and_key() {
    let text = edit(
        &scene_text("two_bars.toml"),
        "density = 0.01",
        "densty = 0.01",
    );
    let scene = scene_file("exit_bad", &text);
    let o = impact(&["run", s(&scene), "--quiet"]);
    assert_eq!(code(&o), 3);
    assert!(stderr(&o).contains("scene.toml") && stderr(&o).contains("densty"));
}

#[test]
fn a_missing_file_is_3_with_its_os_error_printed_once() {
    let o = impact(&["run", "no_such_scene.toml"]);
    assert_eq!(code(&o), 3);
    let err = stderr(&o);
    assert!(err.contains("no_such_scene.toml"), "{err}");
    assert_eq!(err.matches("os error 2").count(), 1, "{err}");
}

#[test]
fn a_missing_mesh_file_names_the_scene_and_the_key() {
    let text = edit(
        &scene_text("block_hex_drop.toml"),
        "meshes/block_hex.inp",
        "meshes/no_such.inp",
    );
    let scene = scene_file("exit_no_mesh", &text);
    let o = impact(&["check", s(&scene)]);
    assert_eq!(code(&o), 3);
    let err = stderr(&o);
    for part in ["scene.toml", "body[0].mesh", "no_such.inp", "os error 2"] {
        assert!(err.contains(part), "{err:?} should contain {part:?}");
    }
    assert_eq!(err.matches("os error 2").count(), 1, "{err}");
}

#[test]
fn a_diverged_run_is_4() {
    // explicit at three times the stable step, allowed: it blows up
    let text = edit(
        &edit(
            &scene_text("two_bars.toml"),
            "method = \"implicit\"",
            "method = \"explicit\"",
        ),
        "time_step = 0.01",
        "time_step = 0.03",
    ) + "\n[explicit]\nallow_unstable = true\n";
    let scene = scene_file("exit_diverged", &text);
    let out = out_path("exit_diverged").join("run");
    let o = impact(&[
        "run",
        s(&scene),
        "--out",
        s(&out),
        "--quiet",
        "--device",
        "cpu",
    ]);
    assert_eq!(code(&o), 4, "{}", stderr(&o));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"diverged\""));
}

#[test]
fn an_unwritable_output_folder_is_5() {
    let scene = scene_file("exit_io", &scene_text("two_bars.toml"));
    // a folder below a regular file cannot be made
    let out = scene.join("out");
    let o = impact(&["run", s(&scene), "--out", s(&out), "--quiet"]);
    assert_eq!(code(&o), 5, "{}", stderr(&o));
    assert!(stderr(&o).contains("cannot write"), "{}", stderr(&o));
}

#[test]
fn warnings_under_strict_are_6() {
    let text = edit(
        &scene_text("two_bars.toml"),
        "penalty = \"adaptive\"",
        "penalty = \"adaptive\"\nmax_iterations = 2\nacceleration = \"anderson\"",
    );
    let scene = scene_file("exit_strict", &text);
    let out = out_path("exit_strict").join("run");
    let o = impact(&["run", s(&scene), "--out", s(&out), "--quiet"]);
    assert_eq!(code(&o), 0, "warnings alone do not fail a run");
    assert!(
        stderr(&o).contains("warning: unconverged_steps"),
        "{}",
        stderr(&o)
    );
    let o = impact(&[
        "run",
        s(&scene),
        "--out",
        s(&out),
        "--quiet",
        "--overwrite",
        "--strict",
    ]);
    assert_eq!(code(&o), 6, "{}", stderr(&o));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"completed_with_warnings\""));
}

#[test]
fn check_reports_the_model_without_running_it() {
    let o = impact(&[
        "check",
        s(&repo().join("scenes/cube_on_plate.toml")),
        "--device",
        "cpu",
    ]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    for part in [
        "cube: 64 elements (64 hex8), 125 nodes, 375 dofs",
        "plate: 256 elements",
        "mass 1.000000e-2",
        "method: implicit",
        "impact: 25 secondary nodes against a surface, friction 0.3; initial gap",
        "fix[0]: 5 nodes of body `plate`, components xyz",
        "memory: host at least",
        "implicit factors: effective matrix ",
        "with their workspace (from the symbolic analysis)",
    ] {
        assert!(out.contains(part), "{out}\nshould contain {part:?}");
    }
    // the factor check reports is the factor the run makes
    let values = |text: &str, after: &str| -> usize {
        let at = text
            .find(after)
            .unwrap_or_else(|| panic!("{after:?} in {text}"))
            + after.len();
        let digits: String = text[at..]
            .chars()
            .take_while(char::is_ascii_digit)
            .collect();
        digits.parse().unwrap()
    };
    let run = out_path("check_factor").join("run");
    let ran = impact(&[
        "run",
        s(&repo().join("scenes/cube_on_plate.toml")),
        "--out",
        s(&run),
        "--quiet",
        "--overwrite",
        "--device",
        "cpu",
    ]);
    assert_eq!(code(&ran), 0, "{}", stderr(&ran));
    let summary = std::fs::read_to_string(run.join("summary.json")).unwrap();
    assert_eq!(
        values(&out, "implicit factors: effective matrix "),
        values(&summary, "\"factor_nonzeros\": ")
    );
    let o = impact(&[
        "check",
        s(&repo().join("scenes/block_hex_drop.toml")),
        "--device",
        "cpu",
    ]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("stable explicit step: 7.905694e-4, set by element"),
        "{out}"
    );
    assert!(!out_path("check").exists());
}

/// `impact` with `args` under `ulimit -v kib`: it must exit 3, and its error must name each
/// of `parts`.
fn refused_under_limit(kib: u64, args: &[&str], parts: &[&str]) {
    let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
    let o = Command::new("bash")
        .arg("-c")
        .arg(format!(
            "ulimit -v {kib}; exec '{}' {}",
            env!("CARGO_BIN_EXE_impact"),
            quoted.join(" ")
        ))
        .output()
        .unwrap();
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    let err = stderr(&o);
    for part in parts {
        assert!(err.contains(part), "{err:?} should contain {part:?}");
    }
}

#[test]
fn a_model_too_large_for_the_process_is_refused_before_it_is_built() {
    // "a 1,000,000-element implicit box on a 4 GiB limit" aborted in assembly
    let text = edit(
        &scene_text("two_bars.toml"),
        "divisions = [10, 1, 1]",
        "divisions = [100, 100, 100]",
    );
    let scene = scene_file("exit_too_large", &text);
    refused_under_limit(
        4194304,
        &["check", s(&scene), "--device", "cpu"],
        &["needs about", "triplets", "4.0 GiB", "ulimit -v"],
    );
}

/// "a 196,608-element block under `ulimit -v 6 GiB` passes the memory check, then dies with
/// 'memory allocation of 10346014440 bytes failed'": the factor's size, known from the
/// symbolic analysis, is checked before any value is allocated (exit 3, the figure and the
/// limit). Here 96,000 hex8, whose factor holds 385 million values, under 3 GiB.
#[test]
fn an_implicit_factor_too_large_for_the_process_is_refused_before_it_is_allocated() {
    // both bars: 96,000 hex8
    let text =
        scene_text("two_bars.toml").replace("divisions = [10, 1, 1]", "divisions = [40, 40, 30]");
    let scene = scene_file("exit_factor_too_large", &text);
    let out = out_path("exit_factor_too_large").join("run");
    let run = [
        "run",
        s(&scene),
        "--out",
        s(&out),
        "--quiet",
        "--device",
        "cpu",
    ];
    refused_under_limit(
        3145728,
        &run,
        &[
            "Cholesky factors",
            "symbolic analysis",
            "effective matrix",
            "consistent mass",
            "3.0 GiB",
            "ulimit -v",
        ],
    );
    // `impact check` analyses the factors as the run does, and refuses them alike
    refused_under_limit(
        3145728,
        &["check", s(&scene), "--device", "cpu"],
        &["Cholesky factors", "symbolic analysis", "3.0 GiB"],
    );
}

#[test]
fn a_run_stopped_by_sigterm_resumes_to_the_unbroken_history() {
    let text = edit(
        &scene_text("cube_on_plate.toml"),
        "end_time = 0.1",
        "end_time = 0.3",
    ) + "\n[output]\ncheckpoint_every = 20\n";
    let scene = scene_file("sigterm", &text);
    let whole = out_path("sigterm").join("whole");
    let cut = out_path("sigterm").join("cut");
    let o = impact(&[
        "run",
        s(&scene),
        "--out",
        s(&whole),
        "--quiet",
        "--device",
        "cpu",
    ]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let child = Command::new(env!("CARGO_BIN_EXE_impact"))
        .args([
            "run",
            s(&scene),
            "--out",
            s(&cut),
            "--quiet",
            "--device",
            "cpu",
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // wait for a few steps, then stop it
    let history = cut.join("history.csv");
    let t0 = std::time::Instant::now();
    while std::fs::read_to_string(&history).map_or(0, |h| h.lines().count()) < 4 {
        assert!(t0.elapsed().as_secs() < 60, "the run never started");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    let o = child.wait_with_output().unwrap();
    assert_eq!(code(&o), 130, "{}", stderr(&o));
    assert!(stderr(&o).contains("--resume"), "{}", stderr(&o));
    let summary = std::fs::read_to_string(cut.join("summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"interrupted\""), "{summary}");
    let o = impact(&[
        "run",
        s(&scene),
        "--out",
        s(&cut),
        "--quiet",
        "--device",
        "cpu",
        "--resume",
    ]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(whole.join("history.csv")).unwrap(),
        std::fs::read_to_string(cut.join("history.csv")).unwrap()
    );
}

#[test]
fn a_run_killed_outright_resumes_from_its_last_checkpoint() {
    // SIGKILL leaves no chance to write anything: the periodic checkpoint and the history
    // rows it counts (flushed with it) are all there is
    let text = edit(
        &scene_text("cube_on_plate.toml"),
        "end_time = 0.1",
        "end_time = 0.3",
    ) + "\n[output]\ncheckpoint_every = 5\n";
    let scene = scene_file("sigkill", &text);
    let whole = out_path("sigkill").join("whole");
    let cut = out_path("sigkill").join("cut");
    let o = impact(&[
        "run",
        s(&scene),
        "--out",
        s(&whole),
        "--quiet",
        "--device",
        "cpu",
    ]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let mut child = Command::new(env!("CARGO_BIN_EXE_impact"))
        .args([
            "run",
            s(&scene),
            "--out",
            s(&cut),
            "--quiet",
            "--device",
            "cpu",
        ])
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    while !cut.join("checkpoint.bin").exists() {
        assert!(t0.elapsed().as_secs() < 60, "no checkpoint was written");
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let o = impact(&[
        "run",
        s(&scene),
        "--out",
        s(&cut),
        "--quiet",
        "--device",
        "cpu",
        "--resume",
    ]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(whole.join("history.csv")).unwrap(),
        std::fs::read_to_string(cut.join("history.csv")).unwrap()
    );
}
