//! Weak scaling of the explicit path over MPI ranks: the elements per rank fixed, the model
//! growing with the ranks. Prints a table of the time per step, the time per element-step
//! and each run's share of time in communication (exchanges and collectives, waiting
//! included).
//!
//! The scene is a plate supported along its bottom edges, with one block per rank dropped on
//! it at 1 with friction 0.2 (each block its own contact interface), so that the plate's
//! elements, the contact surfaces and the impacts all grow with the ranks. P = 1 is the
//! single-process run; P > 1 runs `mpirun --oversubscribe -n P impact run` with one thread
//! per rank.
//!
//! A second table splits one fixed scene over the ranks (strong scaling): the same plate
//! as two ranks' worth with a single block over its middle, so that the contact zone lies
//! across the cut and the ranks exchange primary-face nodes every step.
//!
//! `cargo bench --features mpi --bench ranks` (14,528 elements per rank, about 150 steps,
//! ranks 1, 2 and every power of two up to the cores); `-- --quick` for 1,816 elements per
//! rank on 1 and 2 ranks; `-- --gpu` with every rank on its GPU (the machine's GPUs shared
//! out by local rank), its whole step resident there (`domain::RankResident`: the contact
//! iteration on the whole surfaces on every rank), where P = 1 is the single process on
//! the GPU (a column names each run's engine, and in brackets the form of the contact
//! iteration its trial took last, rank 0's on ranks).
//!
//! With `--gpu` a third table drops a slab of `P` ranks' worth on a rigid floor: the plane
//! is its only contact, so every rank exchanges only its shared nodes' corners, once a
//! step. Several ranks on one card show what the exchange and the two submissions a step
//! cost.
//! `-- --gpu --floor N` refines it (800 N^3 elements per rank; N = 2 by default, 1 with
//! `--quick`); `-- --gpu --floor-only` runs that table alone.
//!
//! `-- --ranks 1,2,8` runs those rank counts in place of the default ones.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The plate `4 P x 4 x 0.4` in `(20 P) x 20 x 4` n^3 cells (n the refinement), with P blocks
/// of `0.6^3` in `(6 n)^3` cells, one centred over each `4 x 4` square of the plate.
fn scene(ranks: usize, n: usize) -> String {
    scene_with_blocks(ranks, n, (0..ranks).map(|k| 4.0 * k as f64 + 1.7).collect())
}

/// The plate of [`scene`] for `ranks` ranks with one block at each x in `blocks`.
fn scene_with_blocks(ranks: usize, n: usize, blocks: Vec<f64>) -> String {
    let mut s = format!(
        r#"
[run]
method = "explicit"
end_time = {end}

[[material]]
name = "steel"
density = 7.8e-3
youngs_modulus = 200.0
poissons_ratio = 0.3

[[body]]
name = "plate"
material = "steel"
box = {{ min = [0.0, 0.0, -0.4], max = [{lx}, 4.0, 0.0], divisions = [{px}, {py}, {pz}] }}

[[fix]]
body = "plate"
region = {{ min = [0.0, 0.0, -0.4], max = [{lx}, 0.0, -0.4] }}
components = ["x", "y", "z"]

[[fix]]
body = "plate"
region = {{ min = [0.0, 4.0, -0.4], max = [{lx}, 4.0, -0.4] }}
components = ["z"]
"#,
        end = 0.06 / n as f64,
        lx = 4.0 * ranks as f64,
        px = 20 * ranks * n,
        py = 20 * n,
        pz = 4 * n,
    );
    for (k, x0) in blocks.into_iter().enumerate() {
        s += &format!(
            r#"
[[body]]
name = "block{k}"
material = "steel"
box = {{ min = [{x0}, 1.7, 0.0], max = [{x1}, 2.3, 0.6], divisions = [{b}, {b}, {b}] }}
velocity = [0.0, 0.0, -1.0]

[[contact]]
name = "impact{k}"
secondary = {{ body = "block{k}", face = "z-" }}
primary = {{ body = "plate", face = "z+" }}
friction = 0.2
"#,
            x1 = x0 + 0.6,
            b = 6 * n,
        );
    }
    s
}

/// A slab `4 P x 4 x 0.4` in `(20 P n) x (20 n) x (2 n)` hex8 (800 n^3 elements per rank)
/// dropped at 1 on a rigid floor: the plane is its only contact.
fn floor_scene(ranks: usize, n: usize) -> String {
    format!(
        r#"
[run]
method = "explicit"
end_time = {end}

[[material]]
name = "steel"
density = 7.8e-3
youngs_modulus = 200.0
poissons_ratio = 0.3

[[body]]
name = "slab"
material = "steel"
box = {{ min = [0.0, 0.0, 0.01], max = [{lx}, 4.0, 0.41], divisions = [{px}, {py}, {pz}] }}
velocity = [0.0, 0.0, -1.0]

[[rigid_plane]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
"#,
        end = 0.1 / n as f64,
        lx = 4.0 * ranks as f64,
        px = 20 * ranks * n,
        py = 20 * n,
        pz = 2 * n,
    )
}

/// The figures of one run from its summary.
struct Figures {
    elements: usize,
    steps: usize,
    step_seconds: f64,
    communication: f64,
    /// Each rank's seconds in the contact per step, averaged over the ranks (none for one
    /// process).
    contact: Option<f64>,
    received: u64,
    engine: String,
}

/// Runs `text` (named `name`) on `ranks` ranks, each on `device`.
fn run(ranks: usize, name: &str, text: &str, dir: &Path, device: &str) -> Figures {
    std::fs::create_dir_all(dir).expect("bench folder");
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).expect("scene written");
    let out = dir.join(name);
    let bin = env!("CARGO_BIN_EXE_impact");
    let mut cmd = if ranks == 1 {
        Command::new(bin)
    } else {
        let mut c = Command::new("mpirun");
        c.args(["--oversubscribe", "-n", &ranks.to_string(), bin]);
        c
    };
    // one thread per CPU rank; a rank on a GPU keeps its share of the cores for its host loop
    if device == "cpu" {
        cmd.args(["--threads", "1"]);
    }
    let status = cmd
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .args(["--quiet", "--overwrite", "--device", device])
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .stdout(std::process::Stdio::null())
        .status()
        .expect("impact (and mpirun) run");
    assert!(status.success(), "{ranks} ranks: {status}");
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    let s: serde_json::Value = serde_json::from_str(&text).expect("summary");
    assert_eq!(s["status"], "completed", "{ranks} ranks");
    let steps = s["steps"].as_u64().expect("steps") as usize;
    let stepping = s["wall_seconds"].as_f64().unwrap() - s["setup_seconds"].as_f64().unwrap();
    let communication = match s["ranks"]["communication_seconds"].as_array() {
        Some(c) => c.iter().filter_map(|x| x.as_f64()).sum::<f64>() / c.len() as f64,
        None => 0.0,
    };
    let contact = (s["ranks"]["contact_seconds"].as_array())
        .map(|c| c.iter().filter_map(|x| x.as_f64()).sum::<f64>() / c.len() as f64 / steps as f64);
    let received = (s["ranks"]["face_nodes_received"].as_array())
        .map_or(0, |r| r.iter().filter_map(|x| x.as_u64()).sum());
    Figures {
        elements: s["elements"].as_u64().expect("elements") as usize,
        steps,
        step_seconds: stepping / steps as f64,
        communication: communication / stepping,
        contact,
        received,
        engine: engine_and_form(&s),
    }
}

/// The run's engine, and the form of the contact iteration rank 0 (or the process) took
/// last where the run has one (`contact_forms.chosen`).
fn engine_and_form(s: &serde_json::Value) -> String {
    let engine = s["engine"].as_str().unwrap_or_default();
    match s["contact_forms"]["chosen"].as_str() {
        Some(form) => format!("{engine} ({form})"),
        None => engine.to_string(),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let quick = args.iter().any(|a| a == "--quick");
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let (n, mut ranks) = if quick {
        (1, vec![1, 2])
    } else {
        (2, vec![1, 2])
    };
    let mut p = 4;
    while !quick && p <= cores {
        ranks.push(p);
        p *= 2;
    }
    if let Some(list) = rank_list(&args) {
        ranks = list;
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bench_ranks");
    let gpu = args.iter().any(|a| a == "--gpu");
    let device = if gpu { "gpu" } else { "cpu" };
    let path = if gpu {
        "every rank resident on its GPU, as the single process"
    } else {
        "explicit CPU path, one thread per rank"
    };
    let floor = (args.iter().position(|a| a == "--floor"))
        .and_then(|i| args.get(i + 1)?.parse().ok())
        .unwrap_or(n.max(2) - usize::from(quick));
    if gpu && args.iter().any(|a| a == "--floor-only") {
        floor_table(&ranks, floor, &dir);
        return;
    }
    println!("weak scaling, {path} ({cores} cores here)");
    println!(
        "| ranks | elements | per rank | steps | ms per step | ns per element-step | communication | contact ms per step | engine |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---|");
    for &r in &ranks {
        let f = run(r, &format!("weak_{r}"), &scene(r, n), &dir, device);
        println!(
            "| {r} | {} | {} | {} | {:.2} | {:.0} | {:.1}% | {} | {} |",
            f.elements,
            f.elements / r,
            f.steps,
            1e3 * f.step_seconds,
            1e9 * f.step_seconds / f.elements as f64 * r as f64,
            100.0 * f.communication,
            milliseconds(f.contact),
            f.engine
        );
    }
    println!();
    println!("one block over the cut: the scene of 2 ranks with a single block at its middle");
    println!("| ranks | elements | steps | ms per step | speed-up | communication | contact ms per step | face nodes received per step | engine |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---|");
    let text = scene_with_blocks(2, n, vec![3.7]);
    let mut one = None;
    for &r in &ranks {
        let f = run(r, &format!("across_{r}"), &text, &dir, device);
        let base = *one.get_or_insert(f.step_seconds);
        println!(
            "| {r} | {} | {} | {:.2} | {:.2} | {:.1}% | {} | {:.0} | {} |",
            f.elements,
            f.steps,
            1e3 * f.step_seconds,
            base / f.step_seconds,
            100.0 * f.communication,
            milliseconds(f.contact),
            f.received as f64 / f.steps as f64,
            f.engine
        );
    }
    if gpu {
        floor_table(&ranks, floor, &dir);
    }
}

/// `-- --ranks 1,2,8`: the rank counts to run, in that order (none where the option is
/// absent; the bench stops, naming the value, where it is not a list of counts).
fn rank_list(args: &[String]) -> Option<Vec<usize>> {
    let at = args.iter().position(|a| a == "--ranks")?;
    let value = args.get(at + 1).map_or("", String::as_str);
    let list: Option<Vec<usize>> = (value.split(','))
        .map(|r| r.trim().parse().ok().filter(|&r| r > 0))
        .collect();
    match list {
        Some(l) if !l.is_empty() => Some(l),
        _ => panic!("--ranks {value:?}: expected rank counts such as 1,2,4"),
    }
}

/// The third table: the slab on a rigid floor, refined `n`, every rank resident on its GPU.
fn floor_table(ranks: &[usize], n: usize, dir: &Path) {
    println!();
    println!(
        "a slab on a rigid floor (the plane its only contact), every rank resident on its GPU"
    );
    println!(
        "| ranks | elements | per rank | steps | ms per step | ns per element-step | against one rank | communication | engine |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---|");
    let mut one = None;
    for &r in ranks {
        let f = run(r, &format!("floor_{r}"), &floor_scene(r, n), dir, "gpu");
        let base = *one.get_or_insert(f.step_seconds);
        println!(
            "| {r} | {} | {} | {} | {:.2} | {:.2} | {:.2}x | {:.1}% | {} |",
            f.elements,
            f.elements / r,
            f.steps,
            1e3 * f.step_seconds,
            1e9 * f.step_seconds / f.elements as f64,
            f.step_seconds / base,
            100.0 * f.communication,
            f.engine
        );
    }
}

/// Seconds as milliseconds with two decimals, or "-".
fn milliseconds(s: Option<f64>) -> String {
    s.map_or_else(|| "-".into(), |s| format!("{:.2}", 1e3 * s))
}
