//! The explicit path on 2 and 4 MPI ranks (`mpirun --oversubscribe`, built with
//! `--features mpi`) against the single-process run: block on a plate with friction, the
//! fine two bars (their contact face on the rank boundary) and a bar on a rigid wall.
//!
//! Every column of the history that follows the state itself (probes, contact force, active
//! nodes, penetration, time) is the same bits: each rank takes the same operations on the same
//! values in the same order as one process. The sums over the model (the energies and the
//! bodies' velocities) add each rank's part, then the ranks in order: within 1e-12 of the
//! largest value of their kind.
#![cfg(feature = "mpi")]

mod common;
use common::*;

use std::path::Path;
use std::process::Command;

use impact::domain::subdomain::Subdomain;
use impact::domain::Partition;
use impact::model::Model;
use impact::scene::Scene;

/// `impact run scene --out dir` on `ranks` MPI processes (one process where `ranks` is 0),
/// on the CPU.
fn impact_run(ranks: usize, scene: &Path, out: &Path) {
    impact_run_on(ranks, scene, out, "cpu");
}

/// [`impact_run`] on `device`.
fn impact_run_on(ranks: usize, scene: &Path, out: &Path, device: &str) {
    impact_run_with(ranks, scene, out, ["--overwrite", "--device", device]);
}

/// `impact run scene --out dir --quiet` with `extra` on `ranks` MPI processes (one process
/// where `ranks` is 0); the run must succeed.
fn impact_run_with(ranks: usize, scene: &Path, out: &Path, extra: [&str; 3]) {
    let status = impact_command(ranks, scene, out, extra)
        .status()
        .expect("mpirun (Open MPI) on the PATH");
    assert!(status.success(), "{ranks} ranks: {status}");
}

/// The command of [`impact_run_with`], one thread per rank.
fn impact_command(ranks: usize, scene: &Path, out: &Path, extra: [&str; 3]) -> Command {
    let bin = env!("CARGO_BIN_EXE_impact");
    let mut cmd = if ranks == 0 {
        Command::new(bin)
    } else {
        let mut c = Command::new("mpirun");
        c.args(["--oversubscribe", "-n", &ranks.to_string(), bin]);
        c
    };
    let args = [
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    cmd.args(args)
        .arg("--quiet")
        .args(extra)
        // Open MPI refuses root unless told (CI runs as root)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("RAYON_NUM_THREADS", "1");
    cmd
}

/// Whether a column is a sum over the model (the energies and the loads' work, a body's velocity, a named fix's
/// reaction, `reaction:NAME` among `bodies`; on the resident GPU step the contact forces
/// and impact losses too, which its device adds over the plane nodes), and its kind.
fn sum_kind(column: &str, bodies: &[String], resident: bool) -> Option<&'static str> {
    let reaction = |b: &String| {
        b.strip_prefix("reaction:")
            .is_some_and(|n| column.starts_with(&format!("{n}.")))
    };
    if bodies.iter().any(reaction) {
        return Some("reaction");
    }
    let body_velocity = |b: &String| {
        ["vx", "vy", "vz"]
            .map(|v| format!("{b}.{v}"))
            .contains(&column.to_string())
    };
    // the damage energy's parts by kind are sums over the model like it
    let energy_part = column.starts_with("damage_energy.");
    if column.ends_with("_energy")
        || energy_part
        || column == "external_work"
        || column.ends_with(".energy")
    {
        Some("energy")
    } else if column.ends_with(".delaminated_area") || column.ends_with(".damaged_area") {
        Some("area")
    } else if bodies.iter().any(body_velocity) {
        Some("body velocity")
    } else if resident
        && (column.ends_with(".normal_force") || column.ends_with(".tangential_force"))
    {
        Some("contact force")
    } else if resident && column.ends_with(".impact_loss") {
        Some("impact loss")
    } else {
        None
    }
}

/// `h` against the single process's `one`: the columns that follow the state bit for bit,
/// the sums over the model within 1e-12 of the largest value of their kind.
fn same_history(tag: &str, one: &History, h: &History, bodies: &[String]) {
    same_history_within(tag, one, h, (bodies, false), 1e-12);
}

/// [`same_history`] with the sums within `tolerance` of the largest value of their kind
/// (`resident`: the contact forces are sums too).
fn same_history_within(
    tag: &str,
    one: &History,
    h: &History,
    (bodies, resident): (&[String], bool),
    tolerance: f64,
) {
    assert_eq!(h.columns, one.columns, "{tag}: columns");
    assert_eq!(h.rows.len(), one.rows.len(), "{tag}: rows");
    for (j, c) in one.columns.iter().enumerate() {
        let kind = sum_kind(c, bodies, resident);
        let scale = (one.columns.iter().enumerate())
            .filter(|(_, d)| sum_kind(d, bodies, resident) == kind)
            .flat_map(|(k, _)| one.rows.iter().map(move |r| r[k].abs()))
            .fold(0.0f64, f64::max);
        for (a, b) in one.rows.iter().zip(&h.rows) {
            match kind {
                None => assert_eq!(
                    a[j].to_bits(),
                    b[j].to_bits(),
                    "{tag}, {c}: {} against {}",
                    b[j],
                    a[j]
                ),
                Some(_) => assert!(
                    (a[j] - b[j]).abs() <= tolerance * scale,
                    "{tag}, {c}: {} against {}",
                    b[j],
                    a[j]
                ),
            }
        }
    }
}

/// Runs `text` on one process and on 2 and 4 ranks; checks the histories as the module
/// says. Returns the 2-rank history.
fn same_on_ranks(tag: &str, text: &str) -> History {
    same_on_ranks_on(tag, text, "cpu")
}

/// [`same_on_ranks`] with every rank on `device`. On a GPU the reference is one rank on the
/// GPU (the decomposed solver in this process): a single process on a GPU takes the
/// resident step, another engine.
fn same_on_ranks_on(tag: &str, text: &str, device: &str) -> History {
    same_on_these_ranks(tag, text, device, &[2, 4])
}

/// [`same_on_ranks_on`] on each number of `ranks` (2 among them); returns the 2-rank history.
fn same_on_these_ranks(tag: &str, text: &str, device: &str, ranks: &[usize]) -> History {
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let parsed = Scene::parse(text, &dir.join(format!("{tag}.toml"))).expect("valid scene");
    let reactions =
        (parsed.fixes.iter()).filter_map(|f| Some(format!("reaction:{}", f.name.as_ref()?)));
    let bodies: Vec<String> = (parsed.bodies.iter().map(|b| b.name.clone()))
        .chain(reactions)
        .collect();
    let scene = dir.join(format!("{tag}.toml"));
    std::fs::write(&scene, text).unwrap();
    if device == "cpu" {
        impact_run(0, &scene, &dir.join("process"));
    } else {
        let opts = impact::run::RunOptions {
            out: Some(dir.join("process")),
            quiet: true,
            overwrite: true,
            device: Some(impact::scene::DeviceChoice::Gpu),
            ..Default::default()
        };
        let s = impact::run::run_ranks(&parsed, &opts, &impact::domain::Single)
            .expect("one rank on the GPU");
        assert_eq!(s.engine, "gpu kernels, decomposed over mpi ranks");
    }
    let one = History::read(&dir.join("process/history.csv"));
    let read_summary = |d: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap()).unwrap()
    };
    // completed, or with the warnings the single process gives
    let status = read_summary(&dir.join("process"))["status"].clone();
    assert!(
        status.as_str().unwrap().starts_with("completed"),
        "{tag}: {status}"
    );
    let mut two = None;
    for &ranks in ranks {
        let out = dir.join(format!("ranks{ranks}"));
        impact_run_on(ranks, &scene, &out, device);
        let h = History::read(&out.join("history.csv"));
        let summary = read_summary(&out);
        assert_eq!(summary["status"], status, "{tag} on {ranks} ranks");
        let engine = summary["engine"].as_str().unwrap_or_default();
        assert_eq!(
            engine.starts_with("gpu"),
            device == "gpu",
            "{tag}: {engine}"
        );
        assert_eq!(summary["ranks"]["ranks"], ranks, "{tag}");
        same_history(&format!("{tag}, {ranks} ranks"), &one, &h, &bodies);
        if ranks == 2 {
            two = Some(h);
        }
    }
    two.expect("a 2-rank run")
}

/// A run stopped at half its end time on 2 ranks writes the single process's checkpoint (the
/// state bit for bit: every rank's owned nodes gathered, the interfaces whole); resumed on 4
/// ranks and on one process, it continues to the unbroken single-process history (the state's
/// columns bit for bit, the sums as above), and on 4 ranks its collection indexes the 2-rank
/// frames and its own.
#[test]
fn a_run_checkpointed_on_2_ranks_resumes_on_4_and_on_one_process() {
    let tag = "mpi_checkpoints";
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let text = explicit_at_default_step(&scene_text("cube_on_plate.toml"))
        + "\n[output]\ncheckpoint_every = 7\nvtu_every = 10\n";
    let half = edit(&text, "end_time = 0.1", "end_time = 0.05");
    let (whole_scene, half_scene) = (dir.join("whole.toml"), dir.join("half.toml"));
    std::fs::write(&whole_scene, &text).unwrap();
    std::fs::write(&half_scene, &half).unwrap();
    let parsed = Scene::parse(&text, &whole_scene).unwrap();
    let bodies: Vec<String> = parsed.bodies.iter().map(|b| b.name.clone()).collect();
    impact_run(0, &whole_scene, &dir.join("unbroken"));
    impact_run(0, &half_scene, &dir.join("process_half"));
    let one = History::read(&dir.join("unbroken/history.csv"));
    let read = |d: &str| impact::checkpoint::Checkpoint::read(&dir.join(d), &parsed).unwrap();
    let state = |c: &impact::checkpoint::Checkpoint| bincode::serialize(&c.solver).unwrap();
    let reference = read("process_half");
    resume_across(&dir, (&half_scene, &whole_scene), (&one, &bodies), |d| {
        let c = read(d);
        assert_eq!(c.tally.steps, reference.tally.steps, "{d}");
        assert!(
            state(&c) == state(&reference),
            "{d}: the 2-rank state differs"
        );
    });
    // a resumed run keeps the first part's file names (its stem, `half`)
    let pvd = std::fs::read_to_string(dir.join("resumed_on_4/half.pvd")).unwrap();
    let unbroken = std::fs::read_to_string(dir.join("unbroken/whole.pvd")).unwrap();
    assert_eq!(
        pvd.matches("<DataSet").count(),
        unbroken.matches("<DataSet").count()
    );
    // the last frame on 4 ranks, the first half's on 2
    let step = one.rows.len() - 1;
    assert!(dir
        .join(format!("resumed_on_4/half_{step:06}_0003.vtu"))
        .exists());
    assert!(dir.join("resumed_on_4/half_000010_0001.vtu").exists());
    assert!(!dir.join("resumed_on_4/half_000010_0002.vtu").exists());
}

/// `--resume` where no checkpoint is: an error every rank meets alike, said once by rank 0,
/// with the usage status (2), not an abort of the job.
#[test]
fn a_missing_checkpoint_stops_every_rank_with_one_message() {
    let dir = out_dir("mpi_no_checkpoint");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        explicit_at_default_step(&scene_text("cube_on_plate.toml")),
    )
    .unwrap();
    let o = impact_command(2, &scene, &dir, ["--resume", "--device", "cpu"])
        .output()
        .expect("mpirun (Open MPI) on the PATH");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.matches("cannot resume").count(), 1, "{stderr}");
    assert!(!stderr.contains("MPI_ABORT"), "{stderr}");
}

/// The corotational swinging strip (`tests/corotation.rs`) on 2 and 4 ranks: one process's
/// history (the state's columns bit for bit, the sums within 1e-12, the turn energy's among
/// them); stopped on 2 ranks mid-swing and resumed on 4 ranks and on one process to the
/// unbroken history.
#[test]
fn a_corotational_strip_swings_the_same_on_2_and_4_ranks_and_resumes_across_them() {
    let tag = "mpi_corotational";
    let checkpoints = "\n[output]\ncheckpoint_every = 300\n";
    let text = swinging_strip("corotational", 6e-4) + checkpoints;
    let one = same_on_ranks(tag, &text);
    let reach = one.col("tip.uz").iter().fold(0.0f64, |a, v| a.max(*v));
    assert!(reach > 10.0, "the tip travels {reach} mm");
    let dir = out_path(tag);
    let half = dir.join("half.toml");
    std::fs::write(&half, swinging_strip("corotational", 3e-4) + checkpoints).unwrap();
    let whole = dir.join(format!("{tag}.toml"));
    let bodies = ["strip", "reaction:root"].map(String::from).to_vec();
    resume_across(&dir, (&half, &whole), (&one, &bodies), |_| {});
}

/// The process of `job`'s MPI rank `rank` (Open MPI's `mpirun` starts its ranks as its
/// children, each told its rank in `OMPI_COMM_WORLD_RANK`).
fn rank_process(job: u32, rank: usize) -> Option<u32> {
    let told = format!("OMPI_COMM_WORLD_RANK={rank}");
    std::fs::read_dir("/proc").ok()?.find_map(|e| {
        let pid: u32 = e.ok()?.file_name().to_str()?.parse().ok()?;
        let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
        // the parent is the second field after the command's closing parenthesis
        let ppid: u32 = stat[stat.rfind(')')? + 2..]
            .split(' ')
            .nth(1)?
            .parse()
            .ok()?;
        let environ = std::fs::read(format!("/proc/{pid}/environ")).ok()?;
        let mine = (environ.split(|&b| b == 0)).any(|v| v == told.as_bytes());
        (ppid == job && mine).then_some(pid)
    })
}

/// SIGTERM to rank 1 alone: the ranks agree on the signal after each step, so every rank
/// stops after the same step; rank 0 writes the checkpoint and a summary `interrupted`,
/// and the job ends with status 130. Resumed on 2 ranks, the history is the unbroken
/// single-process run's (as the module says).
#[test]
fn a_signal_to_one_rank_stops_every_rank_with_a_checkpoint() {
    signal_case("mpi_sigterm", "cpu", "end_time = 2.0");
}

/// [`a_signal_to_one_rank_stops_every_rank_with_a_checkpoint`] with every rank resident on
/// its GPU, where a step's correctors run in one submission with the next step's first
/// part: the ranks finish the step they have begun, then stop at rest. Resumed on 2 ranks,
/// the history is one GPU's unbroken run (the state's columns bit for bit, the sums within
/// 1e-6).
#[test]
fn a_signal_to_one_resident_rank_stops_every_rank_at_rest_with_a_checkpoint() {
    if skip_gpu("mpi resident signal") {
        return;
    }
    signal_case("mpi_sigterm_resident", "gpu", "end_time = 0.5");
}

/// The signal cases: the explicit cube on the plate run to `end` on 2 ranks on `device`,
/// rank 1 signalled after a few steps.
fn signal_case(tag: &str, device: &str, end: &str) {
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let text = edit(
        &explicit_at_default_step(&scene_text("cube_on_plate.toml")),
        "end_time = 0.1",
        end,
    ) + "\n[output]\nvtu_every = 100\n";
    let scene = dir.join("sigterm.toml");
    std::fs::write(&scene, &text).unwrap();
    let parsed = Scene::parse(&text, &scene).unwrap();
    let bodies: Vec<String> = parsed.bodies.iter().map(|b| b.name.clone()).collect();
    impact_run_on(0, &scene, &dir.join("unbroken"), device);
    let cut = dir.join("cut");
    let mut job = impact_command(2, &scene, &cut, ["--overwrite", "--device", device])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("mpirun (Open MPI) on the PATH");
    // wait for some steps, then signal rank 1 alone
    let t0 = std::time::Instant::now();
    let rows = || std::fs::read_to_string(cut.join("history.csv")).map_or(0, |h| h.lines().count());
    while rows() < 4 {
        assert!(t0.elapsed().as_secs() < 60, "the run never started");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let rank1 = rank_process(job.id(), 1).expect("rank 1's process");
    let killed = Command::new("kill")
        .args(["-TERM", &rank1.to_string()])
        .status();
    assert!(killed.unwrap().success());
    // a rank left waiting for the others would hang the job: give it a minute
    let status = loop {
        if let Some(status) = job.try_wait().unwrap() {
            break status;
        }
        if t0.elapsed().as_secs() > 60 {
            for pid in (0..2).filter_map(|r| rank_process(job.id(), r)) {
                let _ = Command::new("kill")
                    .args(["-KILL", &pid.to_string()])
                    .status();
            }
            let _ = job.kill();
            panic!("the job did not end within a minute of the signal");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut job.stderr.take().unwrap(), &mut stderr).unwrap();
    assert_eq!(status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("--resume"), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(cut.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "interrupted");
    assert_eq!(summary["ranks"]["ranks"], 2, "the summary's ranks");
    let one = History::read(&dir.join("unbroken/history.csv"));
    let steps = summary["steps"].as_u64().unwrap() as usize;
    assert!(
        steps + 1 < one.rows.len(),
        "stopped at step {steps}, the end"
    );
    impact_run_with(2, &scene, &cut, ["--resume", "--device", device]);
    let resumed = History::read(&cut.join("history.csv"));
    match device {
        "cpu" => same_history(tag, &one, &resumed, &bodies),
        _ => same_history_within(tag, &one, &resumed, (&bodies, true), 1e-6),
    }
    // the collection: the frames up to the checkpoint, then the resumed run's, once each
    let frames = |d: &Path| {
        let pvd = std::fs::read_to_string(d.join("sigterm.pvd")).unwrap();
        pvd.matches("<DataSet").count()
    };
    assert_eq!(frames(&cut), frames(&dir.join("unbroken")));
}

#[test]
fn block_on_plate_with_friction_is_the_same_on_2_and_4_ranks() {
    same_on_ranks(
        "mpi_cube_on_plate",
        &explicit_at_default_step(&scene_text("cube_on_plate.toml")),
    );
}

/// A pressure and nodal forces with amplitudes: the ranks' shared nodes take each load
/// whole, and the work is summed once.
#[test]
fn a_loaded_bar_is_the_same_on_2_and_4_ranks() {
    let h = same_on_ranks("mpi_loaded_bar", &loaded_bar("explicit", 0.002, 0.4));
    assert!(h.last("external_work") > 0.0);
}

/// A fix moving the bar's end along an amplitude table: each rank drives the nodes it holds
/// and counts the work on those it owns.
#[test]
fn a_pushed_bar_is_the_same_on_2_and_4_ranks() {
    let motion =
        "displacement = [-0.05, 0.0, 0.0]\namplitude = [[0.0, 0.0], [0.1, 1.0], [0.3, 0.0]]\n";
    let h = same_on_ranks("mpi_pushed_bar", &pushed_bar(0.4, motion));
    assert!(h.col("strain_energy").into_iter().fold(0.0, f64::max) > 0.0);
}

/// Tet4 on both sides: the faces that cross rank boundaries are triangles.
#[test]
fn tet4_cube_on_tet4_plate_is_the_same_on_2_and_4_ranks() {
    same_on_ranks(
        "mpi_tet4_cube_on_plate",
        &explicit_at_default_step(&tet4_cube_on_plate()),
    );
}

/// Every rank with its element forces on its own GPU (here each opens the machine's one
/// adapter; the model has a rigid body, which the resident step on ranks does not take):
/// the state columns on 2 and 4 ranks are the bits of one rank on the GPU, as on the CPU;
/// the element forces are f32, the shared nodes' corners added in f32 in global corner
/// order as the GPU's gather adds them.
#[test]
fn block_on_plate_on_gpus_is_the_same_on_2_and_4_ranks() {
    if skip_gpu("mpi ranks on gpus") {
        return;
    }
    same_on_ranks_on(
        "mpi_gpu_cube_on_plate",
        &with_idle_rigid_body(&explicit_at_default_step(&scene_text("cube_on_plate.toml"))),
        "gpu",
    );
}

/// Every rank's whole step on its GPU (here each opens the machine's one adapter), against
/// one process on the GPU, resident too: the state's columns (probes, penetration, active
/// nodes, time; the contact forces where the contact is on the surfaces) are the single
/// GPU's bits on 2 and 4 ranks; the sums (energies, body velocities, a rigid plane's contact
/// forces), which each rank's device adds in f32 over its owned nodes before the ranks are
/// added in order, are within 1e-6 of the largest value of their kind. Blocks dropped on a
/// rigid floor (hex8 as imported, and tet4: the plane their only contact), the cube on the
/// plate (the contact iteration on the surfaces, which every rank works, each timing its
/// forms: rank 0's trial runs its rounds where the adapter has timestamps), a rigid ball
/// dropped on a block (its node rank 0's) and the coarse drop-weight coupon (rigid tup,
/// support and clamps; its ply failure survey on each rank's cells, the records merged: the
/// failure columns and `first_failure` are the single GPU's).
#[test]
fn resident_ranks_on_gpus_are_one_gpu_on_2_and_4_ranks() {
    if skip_gpu("mpi ranks resident on gpus") {
        return;
    }
    for name in [
        "block_hex_drop",
        "block_tet_drop",
        "cube_on_plate",
        "rigid_ball",
        "drop_weight_d7136_elastic",
    ] {
        let tag = format!("mpi_resident_{name}");
        let dir = out_dir(&tag);
        std::fs::create_dir_all(&dir).unwrap();
        let text = match name {
            "rigid_ball" => rigid_ball_on_block(),
            _ => scene_text(&format!("{name}.toml")),
        };
        let text = match name {
            "rigid_ball" => text,
            "drop_weight_d7136_elastic" => coarse_drop_weight(&text),
            "cube_on_plate" => explicit_at_default_step(&text),
            "block_hex_drop" => edit(
                &text,
                "\"meshes/block_hex.inp\"",
                &format!(
                    "{:?}",
                    repo()
                        .join("scenes/meshes/block_hex.inp")
                        .display()
                        .to_string()
                ),
            ),
            _ => edit(
                &text,
                "\"meshes/block_tet.msh\"",
                &format!(
                    "{:?}",
                    repo()
                        .join("scenes/meshes/block_tet.msh")
                        .display()
                        .to_string()
                ),
            ),
        };
        let parsed = Scene::parse(&text, &dir.join(format!("{tag}.toml"))).expect("valid scene");
        let bodies: Vec<String> = parsed.bodies.iter().map(|b| b.name.clone()).collect();
        let scene = dir.join(format!("{tag}.toml"));
        std::fs::write(&scene, &text).unwrap();
        impact_run_on(0, &scene, &dir.join("process"), "gpu");
        let one = History::read(&dir.join("process/history.csv"));
        for ranks in [0, 2, 4] {
            let out = match ranks {
                0 => dir.join("process"),
                _ => dir.join(format!("ranks{ranks}")),
            };
            if ranks > 0 {
                impact_run_on(ranks, &scene, &out, "gpu");
            }
            let summary: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                    .unwrap();
            assert_eq!(summary["status"], "completed", "{tag} on {ranks} ranks");
            assert_eq!(summary["engine"], "gpu resident", "{tag} on {ranks} ranks");
            // the ply failure survey's first failure (the coupon's) is the single GPU's
            let single = std::fs::read_to_string(dir.join("process/summary.json")).unwrap();
            let single: serde_json::Value = serde_json::from_str(&single).unwrap();
            assert_eq!(summary["first_failure"], single["first_failure"], "{tag}");
            assert_eq!(
                summary["first_failure"].is_object(),
                name == "drop_weight_d7136_elastic",
                "{tag}"
            );
            if ranks > 0 && name == "cube_on_plate" {
                // rank 0 times the surface iteration's forms on its steps where the adapter
                // has timestamps (the single process then reports its device time): a round
                // ends within the run, and the forms' steps are the run's
                let forms = &summary["contact_forms"];
                let steps: u64 = (forms["steps"].as_object().expect("contact_forms.steps"))
                    .values()
                    .map(|n| n.as_u64().unwrap())
                    .sum();
                assert_eq!(Some(steps), summary["steps"].as_u64(), "{tag}: {forms}");
                if single["device_seconds"].is_number() {
                    assert!(forms["rounds"].as_u64() >= Some(1), "{tag}: {forms}");
                    let ran = forms["steps"].as_object().unwrap().len();
                    assert!(ran >= 2, "{tag}: {forms}");
                }
            }
            if ranks > 0 {
                assert_eq!(summary["ranks"]["ranks"], ranks, "{tag}");
                let h = History::read(&out.join("history.csv"));
                let what = format!("{tag}, {ranks} ranks");
                same_history_within(&what, &one, &h, (&bodies, true), 1e-6);
            }
        }
    }
}

/// The resident ranks' checkpoint is the single GPU's: a block dropped on a floor, stopped
/// at half its end time on 2 ranks resident on their GPUs, writes the device state of one
/// GPU's run stopped there, word for word (every rank's owned nodes and plane nodes
/// gathered); resumed on 4 resident ranks and on one process, it continues to the unbroken
/// one-GPU history (the state's columns bit for bit, the sums within 1e-6 as above).
#[test]
fn a_resident_run_checkpointed_on_2_ranks_resumes_on_4_and_on_one_gpu() {
    if skip_gpu("mpi resident checkpoints") {
        return;
    }
    let mesh = repo().join("scenes/meshes/block_hex.inp");
    let block = edit(
        &scene_text("block_hex_drop.toml"),
        "\"meshes/block_hex.inp\"",
        &format!("{:?}", mesh.display().to_string()),
    ) + "\n[output]\ncheckpoint_every = 20\n";
    let cube = explicit_at_default_step(&scene_text("cube_on_plate.toml"))
        + "\n[output]\ncheckpoint_every = 7\n";
    let cases = [
        ("block", block, ("end_time = 0.06", "end_time = 0.03")),
        ("cube", cube, ("end_time = 0.1", "end_time = 0.05")),
    ];
    for (name, text, (end, half_end)) in cases {
        resident_checkpoint_case(
            &format!("mpi_resident_checkpoints_{name}"),
            &text,
            end,
            half_end,
        );
    }
}

/// The case of [`a_resident_run_checkpointed_on_2_ranks_resumes_on_4_and_on_one_gpu`]:
/// `text`, cut at `half_end` in place of `end`.
fn resident_checkpoint_case(tag: &str, text: &str, end: &str, half_end: &str) {
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let half = edit(text, end, half_end);
    let (whole_scene, half_scene) = (dir.join("whole.toml"), dir.join("half.toml"));
    std::fs::write(&whole_scene, text).unwrap();
    std::fs::write(&half_scene, &half).unwrap();
    let parsed = Scene::parse(text, &whole_scene).unwrap();
    let bodies: Vec<String> = parsed.bodies.iter().map(|b| b.name.clone()).collect();
    impact_run_on(0, &whole_scene, &dir.join("unbroken"), "gpu");
    impact_run_on(0, &half_scene, &dir.join("gpu_half"), "gpu");
    let one = History::read(&dir.join("unbroken/history.csv"));
    let read = |d: &str| impact::checkpoint::Checkpoint::read(&dir.join(d), &parsed).unwrap();
    let state = |c: &impact::checkpoint::Checkpoint| bincode::serialize(&c.solver).unwrap();
    let reference = read("gpu_half");
    assert!(matches!(
        reference.solver,
        impact::integrate::SolverState::Resident(_)
    ));
    for (resumed_on, d) in [(4, "resumed_on_4"), (0, "resumed_on_one")] {
        impact_run_on(2, &half_scene, &dir.join(d), "gpu");
        let c = read(d);
        assert_eq!(c.tally.steps, reference.tally.steps, "{tag}, {d}");
        assert!(
            state(&c) == state(&reference),
            "{tag}, {d}: the 2-rank state differs from one gpu's"
        );
        impact_run_with(
            resumed_on,
            &whole_scene,
            &dir.join(d),
            ["--resume", "--device", "gpu"],
        );
        same_history_within(
            &format!("{tag}, {d}"),
            &one,
            &History::read(&dir.join(d).join("history.csv")),
            (&bodies, true),
            1e-6,
        );
    }
}

/// An imported tet4 mesh dropped on a rigid floor: many plane nodes, some within reach of
/// the floor and some not, owned by different ranks.
#[test]
fn imported_tet4_block_dropped_on_a_floor_is_the_same_on_2_and_4_ranks() {
    let text = scene_text("block_tet_drop.toml");
    let mesh = repo().join("scenes/meshes/block_tet.msh");
    let text = edit(
        &text,
        "\"meshes/block_tet.msh\"",
        &format!("{:?}", mesh.display().to_string()),
    );
    same_on_ranks("mpi_block_tet_drop", &text);
}

/// Rigid bodies: the coarse drop-weight coupon (a free tup, a windowed support and four
/// clamps, each a rigid body whose contacts every rank gathers) through the impact's onset,
/// with its ply failure indices surveyed on each rank's cells (the history's maxima and
/// `summary.json`'s first failure are the single process's), and the rigid sphere pressed
/// into the graded block by a prescribed motion.
#[test]
fn rigid_bodies_are_the_same_on_2_and_4_ranks() {
    let drop = coarse_drop_weight(&scene_text("drop_weight_d7136_elastic.toml"));
    let h = same_on_ranks("mpi_drop_weight", &drop);
    let f = h.col("impact.fz");
    assert!(f.iter().any(|&x| x > 0.0), "the tup strikes the coupon");
    let worst = h.col("failure_index.max_stress");
    assert!(
        worst.iter().any(|&x| x > 1.0),
        "an index reaches 1: {worst:?}"
    );
    let first = |d: &str| -> serde_json::Value {
        let text =
            std::fs::read_to_string(out_path("mpi_drop_weight").join(d).join("summary.json"));
        let s: serde_json::Value = serde_json::from_str(&text.unwrap()).unwrap();
        s["first_failure"].clone()
    };
    assert!(first("process").is_object(), "{}", first("process"));
    for ranks in ["ranks2", "ranks4"] {
        assert_eq!(first(ranks), first("process"), "first failure on {ranks}");
    }
    let sphere = scene_text("rigid_sphere_on_block.toml");
    let mesh = repo().join("scenes/meshes/graded_block.inp");
    let sphere = edit(
        &sphere,
        "\"meshes/graded_block.inp\"",
        &format!("{:?}", mesh.display().to_string()),
    );
    let sphere = edit(&sphere, "end_time = 0.62", "end_time = 0.05");
    let sphere = edit(
        &sphere,
        "name = \"ball\"",
        "name = \"ball\"\nmotion = \"prescribed\"",
    );
    same_on_ranks("mpi_rigid_sphere", &sphere);
}

/// The drop-weight coupon `text` (`scenes/drop_weight_d7136_elastic.toml`) coarsened to 20 x 14 x 2
/// and run through the impact's onset (a ply reaches failure), without frames.
fn coarse_drop_weight(text: &str) -> String {
    let drop = edit(text, "divisions = [50, 34, 4]", "divisions = [20, 14, 2]");
    let drop = edit(&drop, "end_time = 4.5e-3", "end_time = 6.0e-4");
    (drop.lines())
        .filter(|l| !l.starts_with("vtu_every"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// A rotating rigid body on ranks: the shipped spinning roller, prescribed and made free
/// (its spin slowed by the friction on the block, the block's contacts split over the
/// ranks); every rank holds the rotation, so the rotation columns are the single process's
/// bits and the sums within rounding.
#[test]
fn rotating_rigid_bodies_are_the_same_on_2_and_4_ranks() {
    let roller = scene_text("spinning_roller.toml");
    let h = same_on_ranks("mpi_roller", &roller);
    assert!(h.col("roll.fx").iter().any(|&f| f != 0.0), "friction acts");
    let free = edit(
        &roller,
        "motion = \"prescribed\"",
        "mass = 0.02\ninertia = [[4e-4, 0.0, 0.0], [0.0, 4e-4, 0.0], [0.0, 0.0, 4e-4]]",
    );
    let h = same_on_ranks("mpi_roller_free", &free);
    let w = h.col("roller.wy");
    assert!(w.last() < w.first(), "the friction slows the spin: {w:?}");
}

#[test]
fn bar_on_rigid_wall_is_the_same_on_2_and_4_ranks() {
    same_on_ranks(
        "mpi_bar_on_wall",
        &explicit_at_default_step(&scene_text("bar_on_wall.toml")),
    );
}

/// Issue 62's wrong step on ranks: the paper's bars with B in half cubes, explicit at the
/// default step. Every rank takes the half cubes' step (0.9 x 5e-3), the histories are the
/// single process's, and the plateau is wave theory's 0.5 within 3%.
#[test]
fn two_sizes_of_one_shape_take_the_smaller_elements_step_on_ranks() {
    let text = explicit_at_default_step(&two_bars_at_two_sizes());
    let h = same_on_ranks("mpi_two_sizes", &text);
    for ranks in [2, 4] {
        let path = out_path("mpi_two_sizes").join(format!("ranks{ranks}/summary.json"));
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let stable = v["stable_time_step"].as_f64().unwrap();
        assert!(
            (stable - 5e-3).abs() <= 1e-12,
            "{ranks} ranks: stable step {stable}"
        );
    }
    let dt = h.col("time")[1];
    let m = measures(&h, "impact", 0.5, dt);
    assert!(
        (m.plateau_mean - 0.5).abs() <= 0.03 * 0.5,
        "plateau {}",
        m.plateau_mean
    );
}

/// The plate of `tests/threads.rs` pulled across its fibres until its plies crack, on 2 and
/// 4 ranks on the CPU and on GPUs (each rank's element forces and damage on its GPU): one
/// process's history (the state's columns bit for bit, the sums, the damage energy and the
/// pull's reaction among them, within 1e-12; on GPUs, one GPU rank's), and damage there.
#[test]
fn ply_damage_is_the_same_on_2_and_4_ranks() {
    let text = damaging_plate();
    let h = same_on_ranks("mpi_ply_damage", &text);
    assert!(h.last("damage_energy") > 0.0, "the plate damaged");
    if skip_gpu("ply damage on GPU ranks") {
        return;
    }
    let h = same_on_ranks_on("mpi_ply_damage_gpu", &text, "gpu");
    assert!(
        h.last("damage_energy") > 0.0,
        "the plate damaged on the GPUs"
    );
}

/// A run of the damaging plate stopped on 2 ranks in its softening resumes on 4 ranks and
/// on one process to the unbroken history: the damage state gathered into the single
/// process's checkpoint.
#[test]
fn a_damaging_run_checkpointed_on_2_ranks_resumes_on_4_and_on_one_process() {
    let tag = "mpi_damage_checkpoints";
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let text = damaging_plate() + "\n[output]\ncheckpoint_every = 100\n";
    let half = edit(&text, "end_time = 3.5e-5", "end_time = 2.6e-5");
    let (whole_scene, half_scene) = (dir.join("whole.toml"), dir.join("half.toml"));
    std::fs::write(&whole_scene, &text).unwrap();
    std::fs::write(&half_scene, &half).unwrap();
    let parsed = Scene::parse(&text, &whole_scene).unwrap();
    let bodies: Vec<String> = vec!["plate".into(), "reaction:pull".into()];
    impact_run(0, &whole_scene, &dir.join("unbroken"));
    impact_run(0, &half_scene, &dir.join("process_half"));
    let one = History::read(&dir.join("unbroken/history.csv"));
    let read = |d: &str| impact::checkpoint::Checkpoint::read(&dir.join(d), &parsed).unwrap();
    let damage = |c: &impact::checkpoint::Checkpoint| match &c.solver {
        impact::integrate::SolverState::Explicit(s) => s.damage.clone(),
        _ => panic!("an explicit checkpoint"),
    };
    let reference = read("process_half");
    assert!(
        damage(&reference).iter().any(|&d| d > 0.0),
        "damaged at the checkpoint"
    );
    resume_across(&dir, (&half_scene, &whole_scene), (&one, &bodies), |d| {
        assert!(
            damage(&read(d)) == damage(&reference),
            "{d}: the 2-rank damage differs"
        );
    });
}

/// Runs `half` (the scene stopped before its end) on 2 ranks into the folders
/// `resumed_on_4` and `resumed_on_one` of `dir`, checks each with `check` (given its
/// name), then resumes them with `whole` on 4 ranks and on one process: the unbroken
/// history `one`, as [`same_history`] holds it.
fn resume_across(
    dir: &Path,
    (half, whole): (&Path, &Path),
    (one, bodies): (&History, &[String]),
    check: impl Fn(&str),
) {
    for (resumed_on, d) in [(4, "resumed_on_4"), (0, "resumed_on_one")] {
        impact_run(2, half, &dir.join(d));
        check(d);
        impact_run_with(
            resumed_on,
            whole,
            &dir.join(d),
            ["--resume", "--device", "cpu"],
        );
        let h = History::read(&dir.join(d).join("history.csv"));
        same_history(d, one, &h, bodies);
    }
}

/// A double cantilever beam (`tests/cohesive.rs`'s quick one, 21 elements long), opened
/// until its crack grows. Its bisections fall inside a column of elements: a rank holds an
/// arm's node at the cut and, through the pair, the other arm's node there too.
fn opened_beam(end: &str) -> String {
    format!(
        r#"[run]
end_time = {end}
method = "explicit"
[[material]]
name = "im7"
density = 1.57e-9
orthotropic = {{ e1 = 171420.0, e2 = 9080.0, e3 = 9080.0, nu12 = 0.32, nu13 = 0.32, nu23 = 0.52, g12 = 5290.0, g13 = 5290.0, g23 = 2987.0 }}
[[body]]
name = "upper"
material = "im7"
box = {{ min = [0.0, 0.0, 1.0], max = [21.0, 1.0, 2.0], divisions = [21, 1, 2], element = "hex8i" }}
[[body]]
name = "lower"
material = "im7"
box = {{ min = [0.0, 0.0, 0.0], max = [21.0, 1.0, 1.0], divisions = [21, 1, 2], element = "hex8i" }}
[[cohesive]]
name = "crack"
between = [{{ body = "upper", face = "z-" }}, {{ body = "lower", face = "z+" }}]
region = {{ min = [8.0, -1.0, -1.0], max = [22.0, 2.0, 3.0] }}
stiffness = 1e5
strength = {{ normal = 20.0, shear = 30.0 }}
toughness = {{ normal = 0.3, shear = 0.79, bk = 2.1 }}
[[fix]]
name = "open"
body = "upper"
face = "x-"
components = ["z"]
velocity = [0.0, 0.0, 500.0]
[[fix]]
name = "hold"
body = "lower"
face = "x-"
components = ["z"]
velocity = [0.0, 0.0, -500.0]
[[fix]]
body = "upper"
region = {{ min = [-1.0, -1.0, -1.0], max = [22.0, 2.0, 3.0] }}
components = ["y"]
[[fix]]
body = "lower"
region = {{ min = [-1.0, -1.0, -1.0], max = [22.0, 2.0, 3.0] }}
components = ["y"]
[output]
checkpoint_every = 400
"#
    )
}

/// The opened beam on 2 and 4 ranks: one process's history (the state's columns bit for
/// bit; the sums, the interface's areas and dissipation among them, within 1e-12) and its
/// delamination; stopped on 2 ranks while the crack grows, it resumes on 4 ranks and on one
/// process to the unbroken history, the pairs' damage gathered into the single process's
/// checkpoint.
#[test]
fn a_beam_delaminates_the_same_on_2_and_4_ranks_and_resumes_across_them() {
    let tag = "mpi_cohesive";
    let text = opened_beam("9e-4");
    // some rank holds a node that none of its elements touches: its partner's
    let scene = Scene::parse(&text, &repo().join("scenes/opened_beam.toml")).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    for ranks in [2, 4] {
        let partition = Partition::bisect(&model, ranks);
        let bonded_only = (0..ranks).any(|r| {
            let sub = Subdomain::new(&model, &partition, r);
            let mut touched = vec![false; sub.nodes.len()];
            for n in sub.data.elements.corner_nodes() {
                touched[n as usize] = true;
            }
            touched.contains(&false)
        });
        assert!(
            bonded_only,
            "{ranks} ranks: no rank holds a node by its pair alone"
        );
    }
    let h = same_on_ranks(tag, &text);
    let dir = out_path(tag);
    let delaminated = |d: &str| {
        let v: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(d).join("summary.json")).unwrap(),
        )
        .unwrap();
        v["delamination"]["projected_area"].as_f64().unwrap()
    };
    let area = delaminated("process");
    assert!(
        h.last("crack.delaminated_area") > 0.0 && area > 0.0,
        "the crack grew"
    );
    for d in ["ranks2", "ranks4"] {
        assert_eq!(delaminated(d), area, "{d}: the projected delamination");
    }
    let half = dir.join("half.toml");
    std::fs::write(&half, opened_beam("6e-4")).unwrap();
    let whole = dir.join(format!("{tag}.toml"));
    let bodies: Vec<String> = ["upper", "lower", "reaction:open", "reaction:hold"]
        .map(String::from)
        .to_vec();
    let one = History::read(&dir.join("process/history.csv"));
    resume_across(&dir, (&half, &whole), (&one, &bodies), |d| {
        let e = History::read(&dir.join(d).join("history.csv")).last("crack.energy");
        assert!(
            e > 0.0 && e < 0.9 * one.last("crack.energy"),
            "the cut is not in the growth"
        );
    });
}

/// The coarse damaged drop weight that `tests/drop_weight.rs` sets on the GPU beside the
/// CPU ([`damaged_coarse_viscous`], to 2.1 ms) on 2 ranks: one process's history (the
/// state's columns bit for bit, the sums within 1e-12), so the peak force and the
/// delaminated area within 2% and more.
#[test]
fn the_damaged_coupon_is_the_same_on_2_ranks() {
    let text = damaged_coarse_viscous(2.1e-3);
    let h = same_on_these_ranks("mpi_damaged_coupon", &text, "cpu", &[2]);
    let one = History::read(&out_path("mpi_damaged_coupon").join("process/history.csv"));
    let ((p1, a1), (p2, a2)) = (peak_and_area(&one), peak_and_area(&h));
    assert!(a1 > 0.0, "the coupon delaminated");
    assert!((p2 - p1).abs() <= 0.02 * p1, "peak {p2} against {p1}");
    assert!(
        (a2 - a1).abs() <= 0.02 * a1,
        "delaminated {a2} against {a1}"
    );
}

/// Blocks broken in shear under pressure, then slid with friction, on 2 and 4 ranks: one
/// process's history (the state's columns bit for bit, the sums within 1e-12); stopped on
/// 2 ranks while they slide, resumed on 4 ranks and on one process to the unbroken history,
/// the pairs' slips gathered into the single process's checkpoint.
#[test]
fn sheared_blocks_slide_the_same_on_2_and_4_ranks_and_resume_across_them() {
    let tag = "mpi_friction";
    let checkpoints = "[output]\ncheckpoint_every = 2000\n";
    let text = sheared_blocks(0.2, 50.0, 9e-4) + checkpoints;
    let one = same_on_ranks(tag, &text);
    assert!(
        one.last("crack.delaminated_area") > 0.0,
        "the blocks broke apart"
    );
    let dir = out_path(tag);
    let half = dir.join("half.toml");
    std::fs::write(&half, sheared_blocks(0.2, 50.0, 6e-4) + checkpoints).unwrap();
    let whole = dir.join(format!("{tag}.toml"));
    let bodies: Vec<String> = ["upper", "lower", "reaction:push"]
        .map(String::from)
        .to_vec();
    resume_across(&dir, (&half, &whole), (&one, &bodies), |d| {
        let h = History::read(&dir.join(d).join("history.csv"));
        assert_eq!(
            h.last("crack.delaminated_area"),
            64.0,
            "{d}: sliding at the cut"
        );
    });
}

/// The opened beam with every rank's element forces on its GPU (the pairs on the host), to
/// the crack's start: on 2 and 4 ranks, one rank on the GPU's history (the state's columns
/// bit for bit, the sums within 1e-12).
#[test]
fn a_beam_delaminates_the_same_on_gpu_ranks() {
    if skip_gpu("cohesive interfaces on GPU ranks") {
        return;
    }
    let h = same_on_ranks_on("mpi_cohesive_gpu", &opened_beam("6e-4"), "gpu");
    assert!(
        h.last("crack.energy") > 0.0,
        "the crack started on the GPUs"
    );
}

/// The plate of `tests/threads.rs`'s damage test.
fn damaging_plate() -> String {
    r#"
[run]
method = "explicit"
end_time = 3.5e-5

[[material]]
name = "im7"
density = 1.57e-9
transversely_isotropic = { e1 = 171420.0, e2 = 9080.0, nu12 = 0.32, nu23 = 0.52, g12 = 5290.0 }
strength = { xt = 2326.2, xc = 1200.1, yt = 62.3, yc = 199.8, s12 = 92.3, s23 = 75.3 }
fracture_energy = { ft = 133.3, fc = 47.5, mt = 0.277, mc = 0.788 }

[[body]]
name = "plate"
material = "im7"
box = { min = [0.0, 0.0, 0.0], max = [4.0, 4.0, 1.0], divisions = [12, 12, 2], element = "hex8i", refine = { min = [1.5, 1.5, 0.0], max = [2.5, 2.5, 1.0], size = [0.25, 0.25, 1.0] } }

[[fix]]
body = "plate"
face = "y-"
components = ["y"]

[[fix]]
body = "plate"
region = { min = [0.0, 0.0, 0.0], max = [0.0, 0.0, 1.0] }
components = ["x", "z"]

[[fix]]
name = "pull"
body = "plate"
face = "y+"
components = ["y"]
velocity = [0.0, 1200.0, 0.0]
"#
    .into()
}

/// The fine two bars on 2 ranks: the bisection puts bar A on rank 0 and bar B on rank 1, so
/// the contact face is the rank boundary; the history is the single process's and matches 1D
/// wave theory within the fine-mesh tolerances.
#[test]
fn two_bars_split_at_their_contact_face_match_wave_theory_on_ranks() {
    let text = explicit_at_default_step(&scene_text("two_bars_fine.toml"));
    let scene = Scene::parse(&text, &repo().join("scenes/mpi_two_bars.toml")).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    let partition = Partition::bisect(&model, 2);
    let itf = &model.interfaces[0];
    let faces = &model.queries.faces;
    let (a, b) = (
        Subdomain::new(&model, &partition, 0),
        Subdomain::new(&model, &partition, 1),
    );
    let holds = |s: &Subdomain, n: u32| s.nodes.binary_search(&n).is_ok();
    assert!(
        itf.nodes.iter().all(|&n| holds(&a, n) && !holds(&b, n)),
        "A's face on rank 0 only"
    );
    assert!(
        faces
            .iter()
            .flatten()
            .all(|&n| holds(&b, n) && !holds(&a, n)),
        "B's face on rank 1 only"
    );
    let h = same_on_ranks("mpi_two_bars", &text);
    let s: impact::output::Summary = {
        let v: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(out_path("mpi_two_bars").join("ranks2/summary.json")).unwrap(),
        )
        .unwrap();
        impact::output::Summary {
            time_step: v["time_step"].as_f64().unwrap(),
            iterations_mean: v["iterations_mean"].as_f64().unwrap(),
            iterations_max: v["iterations_max"].as_u64().unwrap() as usize,
            unconverged_steps: v["unconverged_steps"].as_u64().unwrap() as usize,
            ..Default::default()
        }
    };
    check_two_bars_history("two bars on 2 ranks", &h, &s, s.time_step, &FINE);
}

/// The cube on the plate with a frame every 10 steps on 3 ranks: every point and cell of
/// every piece holds the values of the single process's frame, bit for bit, and the pieces
/// cover every node and hold every cell once (`scripts/compare_pieces.py`, with meshio).
#[test]
fn frames_on_3_ranks_are_pieces_of_the_single_process_frames() {
    let tag = "mpi_frames";
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("cube.toml");
    let text = explicit_at_default_step(&scene_text("cube_on_plate.toml"))
        + "\n[output]\nvtu_every = 10\n";
    std::fs::write(&scene, text).unwrap();
    impact_run(0, &scene, &dir.join("process"));
    impact_run(3, &scene, &dir.join("ranks3"));
    assert!(
        dir.join("ranks3/cube_000010_0002.vtu").exists(),
        "rank 2's piece"
    );
    let out = Command::new("python3")
        .arg(repo().join("scripts/compare_pieces.py"))
        .args([dir.join("process"), dir.join("ranks3")])
        .arg("cube")
        .output()
        .expect("python3 with meshio");
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("6 frames"), "{text}");
}

/// The frames of ranks resident on their GPUs are pieces of one GPU's frames, bit for bit
/// (displacements, velocities, stresses, contact pressures and gaps): the cube on the plate
/// (the contact on the surfaces) on 3 ranks, and the rigid ball on the block on 2.
#[test]
fn resident_frames_on_ranks_are_pieces_of_one_gpus_frames() {
    if skip_gpu("mpi resident frames") {
        return;
    }
    let cube = explicit_at_default_step(&scene_text("cube_on_plate.toml"));
    for (name, text, ranks) in [("cube", cube, 3), ("ball", rigid_ball_on_block(), 2)] {
        let dir = out_dir(&format!("mpi_resident_frames_{name}"));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(&scene, text + "\n[output]\nvtu_every = 10\n").unwrap();
        impact_run_on(0, &scene, &dir.join("process"), "gpu");
        impact_run_on(ranks, &scene, &dir.join("ranks"), "gpu");
        let summary = std::fs::read_to_string(dir.join("ranks/summary.json")).unwrap();
        assert!(summary.contains("\"engine\": \"gpu resident\""), "{name}");
        let out = Command::new("python3")
            .arg(repo().join("scripts/compare_pieces.py"))
            .args([dir.join("process"), dir.join("ranks")])
            .arg(name)
            .output()
            .expect("python3 with meshio");
        let text = String::from_utf8_lossy(&out.stdout).to_string()
            + &String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{name}: {text}");
        assert!(text.contains("every piece equals"), "{name}: {text}");
    }
}

/// A rank that finds no GPU (here rank 1, its wgpu told to look for DirectX 12 alone, which
/// Linux has not) stops every rank: the job ends with an error naming that rank and the key
/// `run.device`, and no rank waits for it.
#[test]
fn a_rank_without_a_gpu_stops_every_rank() {
    if skip_gpu("a rank without a gpu") {
        return;
    }
    let dir = out_dir("mpi_no_gpu");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("cube.toml");
    std::fs::write(
        &scene,
        explicit_at_default_step(&scene_text("cube_on_plate.toml")),
    )
    .unwrap();
    let bin = env!("CARGO_BIN_EXE_impact");
    let args = |out: &str| {
        let out = dir.join(out);
        let run = [
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        let tail = ["--quiet", "--overwrite", "--device", "gpu"];
        run.iter()
            .chain(&tail)
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
    };
    let out = Command::new("timeout")
        .args(["120", "mpirun", "--oversubscribe", "-n", "1", bin])
        .args(args("ranks"))
        .args([":", "-n", "1", "env", "WGPU_BACKEND=dx12", bin])
        .args(args("ranks"))
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .expect("mpirun (Open MPI) on the PATH");
    let text = String::from_utf8_lossy(&out.stderr);
    assert_ne!(out.status.code(), Some(124), "the job hung: {text}");
    assert!(!out.status.success(), "{text}");
    assert!(
        text.contains("run.device")
            && text.contains("rank 1 of 2: ")
            && !text.contains("rank 0 of 2"),
        "{text}"
    );
}
