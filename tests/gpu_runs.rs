//! A GPU run and a CPU run of the same scene agree row by row: contact force, body and probe
//! velocities and energies within 1e-4 of each quantity's scale (the largest magnitude the
//! CPU run reaches; the components of a vector share the vector's scale).

mod common;
use common::*;

use impact::scene::DeviceChoice;

const TOL: f64 = 1e-4;

/// The largest scaled difference of the named columns (or column groups: `A.v` means A.vx,
/// A.vy, A.vz) between two histories.
fn worst(cpu: &History, gpu: &History, groups: &[&str]) -> (f64, String) {
    assert_eq!(cpu.rows.len(), gpu.rows.len(), "row counts");
    let mut out = (0.0, String::new());
    for g in groups {
        let cols: Vec<String> = if g.ends_with(".v") {
            ["x", "y", "z"].iter().map(|c| format!("{g}{c}")).collect()
        } else {
            vec![g.to_string()]
        };
        let scale = cols
            .iter()
            .flat_map(|c| cpu.col(c))
            .fold(0.0f64, |m, x| m.max(x.abs()))
            .max(f64::MIN_POSITIVE);
        for c in &cols {
            for (row, (a, b)) in cpu.col(c).iter().zip(gpu.col(c)).enumerate() {
                let d = (a - b).abs() / scale;
                if d.is_nan() || d > out.0 {
                    out = (
                        if d.is_nan() { f64::INFINITY } else { d },
                        format!("{c} row {row}"),
                    );
                }
            }
        }
    }
    out
}

fn compare(tag: &str, text: &str, groups: &[&str]) {
    if skip_gpu(tag) {
        return;
    }
    let (sc, hc) = run_text_on(&format!("{tag}_cpu"), text, Some(DeviceChoice::Cpu));
    let (sg, hg) = run_text_on(&format!("{tag}_gpu"), text, Some(DeviceChoice::Gpu));
    let (sc, sg) = (sc.expect("cpu run"), sg.expect("gpu run"));
    assert_eq!(sc.device, "cpu");
    assert_ne!(sg.device, "cpu", "the summary names the adapter");
    let (d, at) = worst(&hc, &hg, groups);
    eprintln!(
        "{tag}: worst difference {d:.2e} of scale at {at}; iterations/step cpu {:.2} gpu {:.2} on {}",
        sc.iterations_mean, sg.iterations_mean, sg.device
    );
    assert!(
        d <= TOL,
        "{tag}: gpu and cpu differ by {d:.3e} of scale at {at}"
    );
}

#[test]
fn bar_on_wall_gpu_and_cpu_agree_row_by_row() {
    compare(
        "bar_on_wall_devices",
        &scene_text("bar_on_wall.toml"),
        &[
            "wall.normal_force",
            "kinetic_energy",
            "strain_energy",
            "total_energy",
            "bar.v",
            "tip.v",
        ],
    );
}

/// The two bars: force, energies and body velocities. The single-node probe velocities are
/// left out: under consistent mass the velocity-level constraint lets a transverse mode of the
/// contacting tip grow from round-off during the contact (docs/method-notes.md), so those
/// columns depend on the last bits of either run, not on the kernels' accuracy.
#[test]
fn two_bars_gpu_and_cpu_agree_row_by_row() {
    compare(
        "two_bars_devices",
        &scene_text("two_bars.toml"),
        &[
            "impact.normal_force",
            "kinetic_energy",
            "strain_energy",
            "total_energy",
            "A.v",
            "B.v",
        ],
    );
}

/// The cube on the plate's columns compared: contact forces, friction work, energies, the
/// bodies' velocities and the cube's bottom probe.
const CUBE_ON_PLATE_COLUMNS: [&str; 10] = [
    "impact.normal_force",
    "impact.tangential_force",
    "impact.friction_work",
    "kinetic_energy",
    "strain_energy",
    "total_energy",
    "cube.v",
    "plate.v",
    "bottom.ux",
    "bottom.uz",
];

/// The oblique cube on a plate with friction: the surface contact's slip rates come from the
/// `slip_rate` kernel, so this compares the frictional path on both devices.
#[test]
fn cube_on_plate_gpu_and_cpu_agree_row_by_row() {
    compare(
        "cube_on_plate_devices",
        &scene_text("cube_on_plate.toml"),
        &CUBE_ON_PLATE_COLUMNS,
    );
}

/// The explicit path over 1,000 steps: the cube on the plate with friction at a fifth of the
/// stable step (5e-5 for 0.05), the whole step on the device (f32; the contact between the
/// meshed bodies by the device contact iteration) against the CPU twin (f64).
#[test]
fn explicit_cube_on_plate_gpu_and_cpu_agree_over_1000_steps() {
    let text = edit(
        &scene_text("cube_on_plate.toml"),
        "time_step = 0.002",
        "time_step = 0.00005",
    )
    .replace("end_time = 0.1", "end_time = 0.05")
    .replace("[run]", "[run]\nmethod = \"explicit\"");
    assert!(text.contains("end_time = 0.05") && text.contains("\"explicit\""));
    compare(
        "explicit_cube_on_plate_devices",
        &text,
        &CUBE_ON_PLATE_COLUMNS,
    );
}

/// The cube on the plate meshed with tet4 (`tet4_cube_on_plate`): the device projects onto
/// the plate's triangles and takes their convected basis for the friction, against the f64
/// twins.
#[test]
fn tet4_cube_on_plate_gpu_and_cpu_agree_row_by_row() {
    compare(
        "tet4_cube_on_plate_devices",
        &tet4_cube_on_plate(),
        &CUBE_ON_PLATE_COLUMNS,
    );
}

/// The same explicit, the whole step on the device, 400 steps at 5e-5.
#[test]
fn explicit_tet4_cube_on_plate_gpu_and_cpu_agree_row_by_row() {
    let text = edit(
        &tet4_cube_on_plate(),
        "time_step = 0.002",
        "time_step = 0.00005",
    )
    .replace("end_time = 0.1", "end_time = 0.02")
    .replace("[run]", "[run]\nmethod = \"explicit\"");
    assert!(text.contains("end_time = 0.02") && text.contains("\"explicit\""));
    compare(
        "explicit_tet4_cube_on_plate_devices",
        &text,
        &CUBE_ON_PLATE_COLUMNS,
    );
}

/// A tet4 body from a Gmsh file (the tet4_forces kernel in a run): the cube dropped on a
/// plane, explicit, 392 steps.
#[test]
fn tet4_block_drop_gpu_and_cpu_agree_row_by_row() {
    compare(
        "gpu_block_tet",
        &scene_text("block_tet_drop.toml"),
        &["ground.normal_force", "block.v", "top.v", "total_energy"],
    );
}

/// Several scenes run on several threads at once, again and again, share the process's GPU
/// device: every run completes and gives the history a run alone gives, bit for bit. (With
/// an instance per run, a thread that dropped its instance could unload the Vulkan driver
/// while another thread still ran in it: SIGSEGV in 3 of 4 runs on an H100.)
#[test]
fn scenes_on_several_threads_share_the_device() {
    if skip_gpu("threads") {
        return;
    }
    let gpu = Some(DeviceChoice::Gpu);
    // an implicit run (device kernels, host loop) and an explicit one resident on the device
    let scenes = [
        ("threads_bar", scene_text("bar_on_wall.toml")),
        (
            "threads_drop",
            edit(
                &scene_text("block_hex_drop.toml"),
                "end_time = 0.06",
                "end_time = 0.02",
            ),
        ),
    ];
    let alone: Vec<History> = scenes
        .iter()
        .map(|(tag, text)| {
            let (s, h) = run_text_on(&format!("{tag}_alone"), text, gpu);
            s.expect("run alone");
            h
        })
        .collect();
    for round in 0..3 {
        std::thread::scope(|scope| {
            for t in 0..4 {
                let (scenes, alone) = (&scenes, &alone);
                scope.spawn(move || {
                    for (k, (tag, text)) in scenes.iter().enumerate() {
                        let (s, h) = run_text_on(&format!("{tag}_{round}_{t}"), text, gpu);
                        let s = s.unwrap_or_else(|e| panic!("{tag} round {round} thread {t}: {e}"));
                        assert_eq!(s.status, "completed", "{tag}");
                        assert_eq!(h.bits(), alone[k].bits(), "{tag} round {round} thread {t}");
                    }
                });
            }
        });
    }
}

/// Runs `text` on the GPU into `tag`'s folder (fresh unless `resume`), with `interrupt` as
/// the run's signal flag.
fn gpu_run(
    tag: &str,
    text: &str,
    resume: bool,
    interrupt: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
) -> impact::Result<impact::output::Summary> {
    let scene = impact::scene::Scene::parse(text, &repo().join("scenes").join("resumed.toml"))
        .expect("valid scene");
    let opts = impact::run::RunOptions {
        out: Some(if resume { out_path(tag) } else { out_dir(tag) }),
        device: Some(DeviceChoice::Gpu),
        quiet: true,
        resume,
        interrupt,
        ..Default::default()
    };
    impact::run::run(&scene, &opts)
}

/// The resident engine's checkpoint is its device state word for word: a resident run
/// stopped part way (at half its end time; by a signal, after handing out the steps in
/// flight) and resumed gives the unbroken run's history exactly, on the rigid-plane path
/// (the block drop), on the meshed-contact path (the cube on the plate, explicit) and with
/// rigid bodies and the ply failure survey (the drop-weight coupon, 12 x 8 x 2, through the
/// tup's first contact: the forces on the bodies and the failure maxima).
#[test]
fn resident_runs_resume_to_the_unbroken_history() {
    if skip_gpu("resident resume") {
        return;
    }
    let cube = edit(
        &scene_text("cube_on_plate.toml"),
        "time_step = 0.002",
        "method = \"explicit\"",
    );
    let drop = edit(
        &edit(
            &scene_text("drop_weight_d7136_elastic.toml"),
            "divisions = [50, 34, 4]",
            "divisions = [12, 8, 2]",
        ),
        "end_time = 4.5e-3",
        "end_time = 3.0e-4",
    );
    // its own [output] table takes the checkpoints below, not frames
    let drop = edit(&drop, "[output]\nvtu_every = 500\n", "");
    for (name, text, half) in [
        (
            "planes",
            scene_text("block_hex_drop.toml"),
            ("end_time = 0.06", "end_time = 0.031"),
        ),
        ("contact", cube, ("end_time = 0.1", "end_time = 0.05")),
        ("rigid", drop, ("end_time = 3.0e-4", "end_time = 1.5e-4")),
    ] {
        let text = text + "\n[output]\ncheckpoint_every = 10\n";
        let whole = format!("resident_whole_{name}");
        let part = format!("resident_half_{name}");
        let cut = format!("resident_cut_{name}");
        let s = gpu_run(&whole, &text, false, None).expect("unbroken");
        assert_eq!(s.engine, "gpu resident");
        gpu_run(&part, &edit(&text, half.0, half.1), false, None).expect("half");
        let r = gpu_run(&part, &text, true, None).expect("resumed");
        assert_eq!(
            history_text(&whole),
            history_text(&part),
            "{name}: half, resumed"
        );
        assert_eq!(r.energy_final.to_bits(), s.energy_final.to_bits());
        assert_eq!(
            format!("{:?}", r.first_failure),
            format!("{:?}", s.first_failure),
            "{name}: first failure"
        );
        // a signal before the first step: the run hands out its first submission and stops
        let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(true));
        let e = gpu_run(&cut, &text, false, Some(flag)).expect_err("interrupted");
        assert!(matches!(e, impact::ImpactError::Interrupted { .. }), "{e}");
        let summary = std::fs::read_to_string(out_path(&cut).join("summary.json")).unwrap();
        assert!(summary.contains("\"status\": \"interrupted\""), "{summary}");
        gpu_run(&cut, &text, true, None).expect("resumed after the signal");
        assert_eq!(
            history_text(&whole),
            history_text(&cut),
            "{name}: cut, resumed"
        );
    }
}

/// A CPU (f64) run's checkpoint does not resume on the GPU (f32), nor a GPU run's on the
/// CPU: the history would change precision part way and the summary name one device for
/// both. Refused (a usage error naming both devices), the folder left as it was.
#[test]
fn a_checkpoint_resumes_only_on_the_kind_of_device_that_wrote_it() {
    if skip_gpu("resume across devices") {
        return;
    }
    let text = scene_text("two_bars.toml") + "\n[output]\ncheckpoint_every = 5\n";
    let half = edit(&text, "end_time = 0.4", "end_time = 0.2");
    let run_on = |tag: &str, text: &str, resume: bool, device: DeviceChoice| {
        let scene = impact::scene::Scene::parse(text, &repo().join("scenes/two_bars.toml"))
            .expect("valid scene");
        let opts = impact::run::RunOptions {
            out: Some(if resume { out_path(tag) } else { out_dir(tag) }),
            device: Some(device),
            quiet: true,
            resume,
            ..Default::default()
        };
        impact::run::run(&scene, &opts)
    };
    for (first, then) in [
        (DeviceChoice::Cpu, DeviceChoice::Gpu),
        (DeviceChoice::Gpu, DeviceChoice::Cpu),
    ] {
        let tag = format!("resume_across_{first:?}");
        run_on(&tag, &half, false, first).expect("the first part");
        let before = history_text(&tag);
        let e = run_on(&tag, &text, true, then).expect_err("refused");
        assert_eq!(e.exit_code(), 2, "{e}");
        assert!(
            e.to_string().contains("precision") && e.to_string().contains("--device"),
            "{e}"
        );
        assert_eq!(history_text(&tag), before, "the history was changed");
        run_on(&tag, &text, true, first).expect("resumed on the first device");
    }
}

/// "Every GPU run prints `error: XDG_RUNTIME_DIR is invalid or not set` on a machine without
/// a desktop session" (Mesa's Vulkan device-select layer): a GPU run without a session says
/// nothing of it.
#[test]
fn a_gpu_run_without_a_desktop_session_prints_no_session_error() {
    if skip_gpu("a_gpu_run_without_a_desktop_session_prints_no_session_error") {
        return;
    }
    let out = out_dir("gpu_no_session");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_impact"))
        .args([
            "run",
            "scenes/two_bars.toml",
            "--device",
            "gpu",
            "--quiet",
            "--out",
        ])
        .arg(&out)
        .current_dir(repo())
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("NODEVICE_SELECT")
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{stderr}");
}
