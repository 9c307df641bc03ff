//! Helpers shared by the integration tests: run a scene text, read its history back.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use impact::output::Summary;
use impact::run::{run, RunOptions};
use impact::scene::Scene;

pub struct History {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl History {
    pub fn read(path: &Path) -> History {
        let text = std::fs::read_to_string(path).expect("history.csv exists");
        let mut lines = text.lines();
        let columns: Vec<String> = lines
            .next()
            .expect("header")
            .split(',')
            .map(String::from)
            .collect();
        let rows = lines
            .map(|l| {
                l.split(',')
                    .map(|v| v.parse::<f64>().expect("number"))
                    .collect()
            })
            .collect();
        History { columns, rows }
    }

    pub fn col(&self, name: &str) -> Vec<f64> {
        let i = self
            .columns
            .iter()
            .position(|c| c == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.columns));
        self.rows.iter().map(|r| r[i]).collect()
    }

    pub fn last(&self, name: &str) -> f64 {
        *self.col(name).last().expect("rows")
    }
}

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn scene_text(name: &str) -> String {
    std::fs::read_to_string(repo().join("scenes").join(name)).expect("shipped scene")
}

/// Replaces `from` (which must occur) by `to`.
pub fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "scene text lacks {from:?}");
    text.replacen(from, to, 1)
}

/// Where the run tagged `tag` writes.
pub fn out_path(tag: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(tag)
}

/// [`out_path`], emptied for a new run.
pub fn out_dir(tag: &str) -> PathBuf {
    let d = out_path(tag);
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs a scene given as text; returns the summary (or error) and the history written.
pub fn run_text(tag: &str, text: &str) -> (impact::Result<Summary>, History) {
    run_text_on(tag, text, None)
}

/// Wave-theory measures of a history's contact force.
pub struct ForceMeasures {
    pub plateau_mean: f64,
    pub plateau_max_dev: f64,
    pub last_contact: f64,
    pub impulse: f64,
    pub max_energy_rise: f64,
    pub energy_loss: f64,
}

pub fn measures(h: &History, contact: &str, exact: f64, dt: f64) -> ForceMeasures {
    let t = h.col("time");
    let f = h.col(&format!("{contact}.normal_force"));
    let e = h.col("total_energy");
    let plateau: Vec<f64> = t
        .iter()
        .zip(&f)
        .filter(|(t, _)| **t >= 0.02 - 1e-9 && **t <= 0.18 + 1e-9)
        .map(|(_, f)| *f)
        .collect();
    let mean = plateau.iter().sum::<f64>() / plateau.len() as f64;
    ForceMeasures {
        plateau_mean: mean,
        plateau_max_dev: plateau
            .iter()
            .map(|p| (p - exact).abs() / exact)
            .fold(0.0, f64::max),
        last_contact: t
            .iter()
            .zip(&f)
            .filter(|(_, f)| **f > 0.0)
            .map(|(t, _)| *t)
            .fold(0.0, f64::max),
        impulse: f.iter().sum::<f64>() * dt,
        max_energy_rise: e.windows(2).map(|w| w[1] - w[0]).fold(f64::MIN, f64::max) / e[0],
        energy_loss: (e[0] - e[e.len() - 1]) / e[0],
    }
}

/// A GPU context for a test, or `None` when `IMPACT_SKIP_GPU_TESTS=1` says to skip (printed).
/// With no adapter and no skip request the test fails with a message naming the packages.
pub fn gpu_context(test: &str) -> Option<impact::gpu::GpuContext> {
    if std::env::var("IMPACT_SKIP_GPU_TESTS").as_deref() == Ok("1") {
        eprintln!("{test}: SKIPPED because IMPACT_SKIP_GPU_TESTS=1");
        return None;
    }
    match impact::gpu::GpuContext::new() {
        Ok(ctx) => {
            eprintln!("{test}: adapter {}", ctx.adapter.describe());
            Some(ctx)
        }
        Err(e) => panic!(
            "{test} needs a GPU adapter (hardware or software) and found none: {e}. \
             Set IMPACT_SKIP_GPU_TESTS=1 to skip the GPU tests deliberately."
        ),
    }
}

/// True when the GPU tests are deliberately skipped (see [`gpu_context`]).
pub fn skip_gpu(test: &str) -> bool {
    gpu_context(test).is_none()
}

/// A fresh seed for randomised tests (or `IMPACT_TEST_SEED`), printed so a failure can be
/// replayed.
pub fn seed(test: &str) -> u64 {
    let s = std::env::var("IMPACT_TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            // a fixed seed per test (FNV-1a of its name): every run draws the same inputs
            test.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
                (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
            })
        });
    eprintln!("{test}: seed {s} (replay with IMPACT_TEST_SEED={s})");
    s
}

/// Runs a scene text, on the given device if one is named (else the scene's).
pub fn run_text_on(
    tag: &str,
    text: &str,
    device: Option<impact::scene::DeviceChoice>,
) -> (impact::Result<Summary>, History) {
    let dir = out_dir(tag);
    // as if it were the file scenes/<tag>.toml, so that mesh paths resolve against scenes/
    let path = repo().join("scenes").join(format!("{tag}.toml"));
    let scene = Scene::parse(text, &path).expect("valid scene");
    let opts = RunOptions {
        out: Some(dir.clone()),
        device,
        quiet: true,
        ..Default::default()
    };
    let s = run(&scene, &opts);
    (s, History::read(&dir.join("history.csv")))
}

/// The two bars' exact contact force, rho c S v0 / 2.
pub const TWO_BARS_FORCE: f64 = 0.5;

/// Release at 0.2 +- 2 dt, no step raising the energy by more than 1e-6 of E0, and a loss
/// in [0, loss_max].
pub fn check_release_and_energy(h: &History, dt: f64, loss_max: f64) -> ForceMeasures {
    let m = measures(h, "impact", TWO_BARS_FORCE, dt);
    assert!(
        (m.last_contact - 0.2).abs() <= 2.0 * dt + 1e-9,
        "release at {} (exact 0.2 +- 2 dt)",
        m.last_contact
    );
    assert!(
        m.max_energy_rise <= 1e-6,
        "total energy rose by {:.3e} of its initial value in one step",
        m.max_energy_rise
    );
    assert!(
        m.energy_loss >= 0.0 && m.energy_loss <= loss_max,
        "energy loss {}",
        m.energy_loss
    );
    m
}

/// Tolerances of one two-bar check (relative unless named otherwise).
pub struct Tolerances {
    pub mean: f64,
    pub row: f64,
    pub impulse: f64,
    /// Largest |v_A| after release.
    pub rest_a: f64,
    /// Largest |v_B - 1| after release.
    pub speed_b: f64,
    pub loss: f64,
}

/// The two bars' history against wave theory with the given tolerances (and every step's
/// contact iteration converged).
pub fn check_two_bars_history(
    tag: &str,
    h: &History,
    s: &Summary,
    dt: f64,
    tol: &Tolerances,
) -> ForceMeasures {
    let m = check_release_and_energy(h, dt, tol.loss);
    eprintln!(
        "{tag}: plateau mean {:.5} max dev {:.4} release {} impulse {:.5} loss {:.4} iterations/step {:.2} (max {})",
        m.plateau_mean, m.plateau_max_dev, m.last_contact, m.impulse, m.energy_loss, s.iterations_mean, s.iterations_max
    );
    assert!((m.plateau_mean - TWO_BARS_FORCE).abs() <= tol.mean * TWO_BARS_FORCE);
    assert!(
        m.plateau_max_dev <= tol.row,
        "row deviation {}",
        m.plateau_max_dev
    );
    assert!(
        (m.impulse - 0.1).abs() <= tol.impulse * 0.1,
        "impulse {}",
        m.impulse
    );
    assert!(
        h.last("A.vx").abs() <= tol.rest_a,
        "A keeps {}",
        h.last("A.vx")
    );
    assert!(
        (h.last("B.vx") - 1.0).abs() <= tol.speed_b,
        "B moves at {}",
        h.last("B.vx")
    );
    assert_eq!(s.unconverged_steps, 0);
    m
}

/// The core issue's fine-mesh tolerances.
pub const FINE: Tolerances = Tolerances {
    mean: 0.01,
    row: 0.03,
    impulse: 0.02,
    rest_a: 0.03,
    speed_b: 0.03,
    loss: 0.015,
};

/// [`run_text`]; the name says that the text's mesh paths resolve against `scenes/`.
pub fn run_scene_text(tag: &str, text: &str) -> (impact::Result<Summary>, History) {
    run_text(tag, text)
}

/// Element size and origin of [`jittered_box`]: far from the origin, so that the f32 kernels
/// must keep the precision of the element scale.
pub const JITTER_H: f64 = 0.5;
pub const JITTER_ORIGIN: [f64; 3] = [120.0, -64.0, 30.0];

/// A box of `divisions` cells of size [`JITTER_H`] from [`JITTER_ORIGIN`], every node moved by
/// up to 0.2 of the cell size along each axis (a distorted mesh).
pub fn jittered_box(rng: &mut impl rand::Rng, divisions: [usize; 3]) -> impact::mesh::BodyParts {
    let (h, origin) = (JITTER_H, JITTER_ORIGIN);
    let spec = impact::scene::BoxSpec {
        min: origin,
        max: std::array::from_fn(|a| origin[a] + h * divisions[a] as f64),
        divisions,
    };
    let mut parts = impact::mesh::box_mesh::box_mesh(&spec);
    for x in &mut parts.nodes {
        for c in x.iter_mut() {
            *c += rng.random_range(-0.2..0.2) * h;
        }
    }
    parts
}

/// Two runs' histories agree: each column within `bound` of its family's scale (energies and
/// friction work, velocities, displacements, forces; penetrations against the element size
/// `h`); the contact counts differ in at most 1% of the rows or by at most 1% of their total
/// over the run, and by at most 2 nodes in any row (a node at zero pressure or on the cone's
/// edge may flip).
pub fn compare_histories(hc: &History, hg: &History, h: f64, bound: f64) {
    assert_eq!(hc.rows.len(), hg.rows.len());
    assert_eq!(hc.columns, hg.columns);
    let energy = family_scale(hc, &["_energy", "friction_work"]);
    let speed = family_scale(hc, &[".vx", ".vy", ".vz"]);
    let disp = family_scale(hc, &[".ux", ".uy", ".uz"]);
    let force = family_scale(hc, &["normal_force", "tangential_force"]);
    for (j, c) in hc.columns.iter().enumerate() {
        let scale = if c.ends_with("_energy") || c.ends_with("friction_work") {
            energy
        } else if c.ends_with(".vx") || c.ends_with(".vy") || c.ends_with(".vz") {
            speed
        } else if c.ends_with(".ux") || c.ends_with(".uy") || c.ends_with(".uz") {
            disp
        } else if c.ends_with("_force") {
            force
        } else if c.ends_with("max_penetration") {
            h
        } else {
            continue; // time, step, counts (below)
        };
        let worst = hc
            .rows
            .iter()
            .zip(&hg.rows)
            .map(|(a, b)| (a[j] - b[j]).abs())
            .fold(0.0, f64::max)
            / scale;
        eprintln!("{c}: {worst:.2e} of {scale:.3e} (bound {bound:.0e})");
        assert!(
            worst <= bound,
            "{c}: GPU and CPU differ by {worst:.2e} of the scale {scale:.3e}"
        );
    }
    // contact counts: a node at zero pressure or on the cone's edge may flip
    for c in hc
        .columns
        .iter()
        .filter(|c| c.ends_with(".active") || c.ends_with(".sliding"))
    {
        let (a, b) = (hc.col(c), hg.col(c));
        let flips = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        let moved: f64 = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).sum();
        let worst = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        let total: f64 = a.iter().sum();
        eprintln!(
            "{c}: {flips} of {} rows differ, by {moved} of {total} node-steps (at most {worst})",
            a.len()
        );
        assert!(total > 0.0, "{c}: the scene must exercise it");
        assert!(
            (flips * 100 <= a.len() || moved <= 0.01 * total) && worst <= 2.0,
            "{c}: {flips} rows differ, by {moved} node-steps, at most {worst} in a row"
        );
    }
}

pub fn family_scale(h: &History, suffixes: &[&str]) -> f64 {
    h.columns
        .iter()
        .filter(|c| suffixes.iter().any(|s| c.ends_with(s)))
        .flat_map(|c| h.col(c))
        .fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Runs `text` on the CPU twin and with the whole step on the device ("gpu resident"), at
/// least 1,000 steps: the same contact iteration (sweeps within 2%, unconverged steps within
/// one) and the same history ([`compare_histories`] with `h` and `bound`).
pub fn resident_against_cpu(tag: &str, text: &str, h: f64, bound: f64) {
    let (cpu, hc) = run_text_on(
        &format!("{tag}_cpu"),
        text,
        Some(impact::scene::DeviceChoice::Cpu),
    );
    let (gpu, hg) = run_text_on(
        &format!("{tag}_gpu"),
        text,
        Some(impact::scene::DeviceChoice::Gpu),
    );
    let (cpu, gpu) = (cpu.expect("cpu run"), gpu.expect("gpu run"));
    assert_eq!(gpu.engine, "gpu resident");
    assert_eq!(cpu.engine, "cpu");
    assert!(cpu.steps >= 1000, "{} steps", cpu.steps);
    // the sweeps differ only where f32 stops an iteration a sweep earlier or later
    eprintln!(
        "sweeps: cpu {} (max {}, {} unconverged), gpu {} (max {}, {} unconverged)",
        cpu.iterations_total,
        cpu.iterations_max,
        cpu.unconverged_steps,
        gpu.iterations_total,
        gpu.iterations_max,
        gpu.unconverged_steps
    );
    let sweeps = (cpu.iterations_total as f64, gpu.iterations_total as f64);
    assert!(
        (sweeps.0 - sweeps.1).abs() <= 0.02 * sweeps.0,
        "sweeps {sweeps:?}"
    );
    assert!(gpu.unconverged_steps.abs_diff(cpu.unconverged_steps) <= 1);
    compare_histories(&hc, &hg, h, bound);
}

/// Relative 2-norm error of a device result against its CPU twin's, entries equal and
/// infinite (a gap out of reach) left out; a NaN counts as infinite error.
pub fn rel_err(gpu: &[f64], cpu: &[f64]) -> f64 {
    assert_eq!(gpu.len(), cpu.len());
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for (g, c) in gpu.iter().zip(cpu) {
        if g.is_infinite() && g == c {
            continue;
        }
        num += (g - c) * (g - c);
        den += c * c;
    }
    if num.is_nan() {
        return f64::INFINITY;
    }
    (num / den.max(f64::MIN_POSITIVE)).sqrt()
}
