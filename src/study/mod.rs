//! `impact study PROBLEM`: accuracy against speed on problems with exact answers, and the
//! atlas of where each method fails.
//!
//! A grid of methods x devices x meshes x time steps (as Courant numbers c dt / h) runs the
//! problem; each run's wall time and errors against the exact solution go into
//! `study.csv`, the errors against wall time into `study.svg/png`, and the failures against
//! the time step into `atlas.svg/png` and `atlas.md`. The measures and statuses are documented
//! in `docs/study.md`. `impact study crack_band` ([`crack_band`]) charts instead the energy a
//! damaging element dissipates against its size.

pub mod crack_band;
pub mod folder;
pub mod problems;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::error::{ImpactError, Result};
use crate::output::plot::{Chart, Series, Style, Table};
use crate::run::{run, RunOptions};
use crate::scene::Scene;
pub use problems::{Errors, Problem};

/// The methods a study compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StudyMethod {
    /// The paper's method: gap-rate constraint, adaptive penalty (Anderson-accelerated).
    ImplicitAdaptive,
    /// The gap-rate constraint with the penalty fixed at its initial estimate.
    ImplicitFixed,
    /// The classical gap constraint with the force at t_{n+1}.
    ImplicitGap,
    /// The classical gap constraint with Newmark's numerical damping, gamma = 0.7 and
    /// beta = (gamma + 1/2)^2 / 4 = 0.36: the least damping in steps of 0.1 with which it
    /// stops chattering on the two bars (`docs/study.md`).
    ImplicitGapDamped,
    /// Central difference with forward-increment impulses, run even above its stable step.
    Explicit,
}

impl StudyMethod {
    pub const ALL: [StudyMethod; 5] = [
        StudyMethod::ImplicitAdaptive,
        StudyMethod::ImplicitFixed,
        StudyMethod::ImplicitGap,
        StudyMethod::ImplicitGapDamped,
        StudyMethod::Explicit,
    ];

    pub fn name(self) -> &'static str {
        match self {
            StudyMethod::ImplicitAdaptive => "implicit-adaptive",
            StudyMethod::ImplicitFixed => "implicit-fixed",
            StudyMethod::ImplicitGap => "implicit-gap",
            StudyMethod::ImplicitGapDamped => "implicit-gap-damped",
            StudyMethod::Explicit => "explicit",
        }
    }

    /// The `[run]` and method tables of a scene at step dt on a device.
    fn settings(self, dt: f64, end: f64, device: &str) -> String {
        let run = |method: &str| {
            format!(
                "[run]\nend_time = {end}\ntime_step = {dt:e}\nmethod = \"{method}\"\ndevice = \"{device}\"\n"
            )
        };
        match self {
            StudyMethod::ImplicitAdaptive => run("implicit"),
            StudyMethod::ImplicitFixed => {
                format!("{}[implicit]\npenalty = \"fixed\"\n", run("implicit"))
            }
            StudyMethod::ImplicitGap => {
                format!("{}[implicit]\nconstraint = \"gap\"\n", run("implicit"))
            }
            StudyMethod::ImplicitGapDamped => format!(
                "{}[implicit]\nconstraint = \"gap\"\ngamma = 0.7\nbeta = 0.36\n",
                run("implicit")
            ),
            StudyMethod::Explicit => {
                format!("{}[explicit]\nallow_unstable = true\n", run("explicit"))
            }
        }
    }
}

/// One run of the grid.
#[derive(Debug, Clone)]
pub struct StudyRow {
    pub problem: Problem,
    pub method: StudyMethod,
    pub device: String,
    pub elements: usize,
    pub courant: f64,
    pub time_step: f64,
    pub errors: Errors,
    pub wall_seconds: f64,
    pub iterations: usize,
    pub status: &'static str,
}

/// Energy may rise by this fraction of E0 in one step before a run counts as unstable.
pub(crate) const ENERGY_GROWTH: f64 = 1e-3;
/// Penetration beyond this fraction of the element size is a failure.
pub(crate) const PENETRATION: f64 = 0.01;

/// The status of a run: "diverged" (stopped, or not finite), "energy_growth", "chatter"
/// (contact lost inside the exact contact window), "penetration", or "ok".
pub fn status(e: &Errors, completed: bool) -> &'static str {
    if !completed || !e.force.is_finite() {
        "diverged"
    } else if e.energy_rise > ENERGY_GROWTH {
        "energy_growth"
    } else if e.openings > 0 {
        "chatter"
    } else if e.penetration > PENETRATION {
        "penetration"
    } else {
        "ok"
    }
}

/// Runs the grid; `devices` lists "cpu" and, where an adapter exists, "gpu". Each run writes
/// into `out/runs/<tag>`.
pub(crate) fn run_grid(
    problem: Problem,
    out: &Path,
    quick: bool,
    devices: &[&str],
    progress: &mut dyn FnMut(&StudyRow),
) -> Result<Vec<StudyRow>> {
    let mut rows = Vec::new();
    for &n in &problem.meshes(quick) {
        for &courant in &problem.courant_numbers(quick) {
            for method in StudyMethod::ALL {
                for &device in devices {
                    let row = run_one(problem, method, n, courant, device, out)?;
                    progress(&row);
                    rows.push(row);
                }
            }
        }
    }
    Ok(rows)
}

/// One run of a study: `problem` with mesh parameter `n` at Courant number `courant`.
pub fn run_one(
    problem: Problem,
    method: StudyMethod,
    n: usize,
    courant: f64,
    device: &str,
    out: &Path,
) -> Result<StudyRow> {
    let (h, c) = problem.wave(n);
    let dt = courant * h / c;
    // the scene's top-level keys first, then the tables
    let text = format!(
        "{}\n{}",
        problem.scene(n),
        method.settings(dt, problem.end_time(), device)
    );
    let tag = format!(
        "{}_{}_{n}_{courant}_{device}",
        problem.name(),
        method.name()
    );
    let scene = Scene::parse(&text, Path::new(&format!("{tag}.toml")))?;
    let dir = out.join("runs").join(&tag);
    let opts = RunOptions {
        out: Some(dir.clone()),
        device: None,
        quiet: true,
        // a study repeats its grid into the same folders
        overwrite: true,
        ..Default::default()
    };
    let (wall, iterations, completed) = match run(&scene, &opts) {
        Ok(s) => (s.wall_seconds, s.iterations_total, true),
        Err(ImpactError::Diverged { .. }) => (read_wall(&dir).unwrap_or(f64::NAN), 0, false),
        Err(e) => return Err(e),
    };
    let table = Table::read(&dir.join("history.csv"))?;
    let errors = problems::errors(problem, &table, h);
    Ok(StudyRow {
        problem,
        method,
        device: device.to_string(),
        elements: study_elements(problem, n),
        courant,
        time_step: dt,
        errors,
        wall_seconds: wall,
        iterations,
        status: status(&errors, completed),
    })
}

fn study_elements(problem: Problem, n: usize) -> usize {
    match problem {
        Problem::TwoBars => 2 * n,
        Problem::BarOnWall => n,
        Problem::SlidingBlock => n * n,
    }
}

/// Wall time of a diverged run from its summary.
fn read_wall(dir: &Path) -> Option<f64> {
    let text = std::fs::read_to_string(dir.join("summary.json")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    v.get("wall_seconds")?.as_f64()
}

pub const CSV_HEADER: &str = "problem,method,device,elements,courant,time_step,force_error,event_error,velocity_error,energy_rise,energy_loss,openings,penetration,wall_seconds,iterations,status";

/// `study.csv`: one row per run.
pub fn csv(rows: &[StudyRow]) -> String {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for r in rows {
        let e = &r.errors;
        let _ = writeln!(
            s,
            "{},{},{},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e},{:e},{},{}",
            r.problem.name(),
            r.method.name(),
            r.device,
            r.elements,
            r.courant,
            r.time_step,
            e.force,
            e.event,
            e.velocity,
            e.energy_rise,
            e.energy_loss,
            e.openings,
            e.penetration,
            r.wall_seconds,
            r.iterations,
            r.status
        );
    }
    s
}

fn series_key(r: &StudyRow) -> String {
    format!("{} ({})", r.method.name(), r.device)
}

/// A run's tooltip: what it was and how it ended.
fn run_label(r: &StudyRow) -> String {
    format!(
        "{} on {}: {} elements, dt {:.3e} (c dt/h {}), {:.3} s, force error {:.3e}, {}",
        r.method.name(),
        r.device,
        r.elements,
        r.time_step,
        r.courant,
        r.wall_seconds,
        r.errors.force,
        r.status
    )
}

/// A series of `rows` at `(x, y)` of each, with each run's tooltip, sorted by x.
fn run_series(
    name: String,
    rows: &[&StudyRow],
    xy: &dyn Fn(&StudyRow) -> (f64, f64),
    style: Style,
) -> Series {
    let mut pts: Vec<(f64, f64, String)> = rows
        .iter()
        .map(|r| {
            let (x, y) = xy(r);
            (x, y, run_label(r))
        })
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    Series {
        name,
        x: pts.iter().map(|p| p.0).collect(),
        y: pts.iter().map(|p| p.1).collect(),
        labels: pts.into_iter().map(|p| p.2).collect(),
        style,
    }
}

/// The failed runs as crosses, one series per way of failing (named in the legend), at their
/// error capped at 10.
fn failed_series(rows: &[StudyRow], xy: &dyn Fn(&StudyRow) -> (f64, f64)) -> Vec<Series> {
    let mut kinds: Vec<&str> = rows
        .iter()
        .map(|r| r.status)
        .filter(|s| *s != "ok")
        .collect();
    kinds.sort_unstable();
    kinds.dedup();
    kinds
        .into_iter()
        .map(|kind| {
            let failed: Vec<&StudyRow> = rows.iter().filter(|r| r.status == kind).collect();
            let capped = |r: &StudyRow| {
                let (x, y) = xy(r);
                (x, y.min(10.0))
            };
            run_series(format!("failed: {kind}"), &failed, &capped, Style::Crosses)
        })
        .collect()
}

/// Final-state error (velocity for the impacts, distance for the block) against wall time,
/// log-log: one series of points per method and device (its "ok" runs), and the failed runs
/// as crosses, one series per way of failing. Each point's tooltip names its run.
pub(crate) fn speed_chart(rows: &[StudyRow]) -> Chart {
    // method-and-device keys in order of first appearance
    let mut seen: Vec<String> = Vec::new();
    for k in rows.iter().map(series_key) {
        if !seen.contains(&k) {
            seen.push(k);
        }
    }
    let xy = |r: &StudyRow| (r.wall_seconds, r.errors.velocity);
    let mut series: Vec<Series> = seen
        .iter()
        .map(|k| {
            let ok: Vec<&StudyRow> = (rows.iter())
                .filter(|r| &series_key(r) == k && r.status == "ok")
                .collect();
            run_series(k.clone(), &ok, &xy, Style::Markers)
        })
        .collect();
    series.extend(failed_series(rows, &xy));
    Chart {
        title: format!(
            "{}: error against wall time",
            rows.first().map_or("", |r| r.problem.name())
        ),
        x_label: "wall seconds (log); y: final velocity (distance) error (log)".into(),
        series,
        log_x: true,
        log_y: true,
    }
}

/// The atlas chart: error against the Courant number, one series per method (ok runs), the
/// failures as crosses, one series per way of failing. Each point's tooltip names its run.
pub(crate) fn atlas_chart(rows: &[StudyRow]) -> Chart {
    let xy = |r: &StudyRow| (r.courant, r.errors.force);
    let mut series: Vec<Series> = StudyMethod::ALL
        .iter()
        .map(|&m| {
            let ok: Vec<&StudyRow> = (rows.iter())
                .filter(|r| r.method == m && r.status == "ok")
                .collect();
            run_series(m.name().into(), &ok, &xy, Style::Markers)
        })
        .collect();
    series.extend(failed_series(rows, &xy));
    Chart {
        title: format!(
            "{}: where each method fails",
            rows.first().map_or("", |r| r.problem.name())
        ),
        x_label: "Courant number c dt / h (log); y: force error (log)".into(),
        series,
        log_x: true,
        log_y: true,
    }
}

/// `atlas.md`: for each method and Courant number, the statuses over meshes and devices.
pub(crate) fn atlas_table(rows: &[StudyRow]) -> String {
    let mut courants: Vec<f64> = rows.iter().map(|r| r.courant).collect();
    courants.sort_by(|a, b| b.total_cmp(a));
    courants.dedup();
    let mut s = String::from("| method |");
    for c in &courants {
        let _ = write!(s, " c dt/h = {c} |");
    }
    s.push_str("\n|---|");
    for _ in &courants {
        s.push_str("---|");
    }
    s.push('\n');
    for m in StudyMethod::ALL {
        let _ = write!(s, "| {} |", m.name());
        for c in &courants {
            let mut statuses: Vec<String> = rows
                .iter()
                .filter(|r| r.method == m && r.courant == *c)
                .map(|r| {
                    if r.status == "ok" {
                        format!("ok {:.1e}", r.errors.force)
                    } else {
                        r.status.to_string()
                    }
                })
                .collect();
            statuses.dedup();
            let _ = write!(s, " {} |", statuses.join(", "));
        }
        s.push('\n');
    }
    s
}

/// Runs the study and writes `study.csv`, `study.svg/png`, `atlas.svg/png` and `atlas.md`
/// into `out`; the runs' own folders (`out/runs`) are removed unless `keep_runs`.
pub fn study(
    problem: Problem,
    out: &Path,
    quick: bool,
    devices: &[&str],
    keep_runs: bool,
    progress: &mut dyn FnMut(&StudyRow),
) -> Result<Vec<StudyRow>> {
    std::fs::create_dir_all(out).map_err(|source| ImpactError::Write {
        path: out.to_path_buf(),
        source,
    })?;
    let rows = run_grid(problem, out, quick, devices, progress)?;
    let write = |name: &str, text: String| -> Result<()> {
        let path: PathBuf = out.join(name);
        std::fs::write(&path, text).map_err(|source| ImpactError::Write { path, source })
    };
    write("study.csv", csv(&rows))?;
    write("atlas.md", atlas_table(&rows))?;
    speed_chart(&rows).write(out, "study")?;
    atlas_chart(&rows).write(out, "atlas")?;
    if !keep_runs {
        let _ = std::fs::remove_dir_all(out.join("runs"));
    }
    Ok(rows)
}
