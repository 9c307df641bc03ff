//! `impact study crack_band`: the energy a damaging element dissipates against its size, for
//! each of the four ply damage modes, against the crack band's exact G A.
//!
//! One IM7/8552 hex8i element (NASA CompDam's constants), a cube of side h, is held on one
//! face and pulled (or pushed, for the compression modes) from the opposite one by a named
//! `[[fix]]` with a velocity, the other two faces on symmetry supports, through its whole
//! softening. Its dissipated energy over G h^2 is 1 while h is within the mode's snap-back
//! width 2 E G / X^2; past it the softening drops at once and the element dissipates its
//! elastic energy at the strength, X^2 h^3 / (2 E), instead. The study writes
//! `crack_band.csv` (one row per run: mode, device, size, dissipated energy, work, G A, the
//! ratio, the snap-back width, wall seconds) and `crack_band.svg/png` (the ratio against h,
//! one series per mode and device, with the exact ratio).

use std::fmt::Write as _;
use std::path::Path;

use crate::error::{ImpactError, Result};
use crate::output::plot::{Chart, Series, Style, Table};
use crate::run::{run, RunOptions};
use crate::scene::Scene;

/// IM7/8552 (NASA CompDam's `IM7-8552.props`; MPa, N/mm, tonne/mm^3).
const IM7: &str = r#"[[material]]
name = "im7"
density = 1.57e-9
transversely_isotropic = { e1 = 171420.0, e2 = 9080.0, nu12 = 0.32, nu23 = 0.52, g12 = 5290.0 }
strength = { xt = 2326.2, xc = 1200.1, yt = 62.3, yc = 199.8, s12 = 92.3, s23 = 75.3 }
fracture_energy = { ft = 133.3, fc = 47.5, mt = 0.277, mc = 0.788 }
"#;

/// A mode the study loads: its name, the axis (0 along the fibres, 1 across), the sign of
/// the load, its uniaxial modulus, strength and fracture energy.
#[derive(Debug, Clone, Copy)]
pub struct LoadedMode {
    pub name: &'static str,
    pub axis: usize,
    pub sign: f64,
    pub modulus: f64,
    pub strength: f64,
    pub energy: f64,
}

pub const MODES: [LoadedMode; 4] = [
    LoadedMode {
        name: "fibre_tension",
        axis: 0,
        sign: 1.0,
        modulus: 171_420.0,
        strength: 2326.2,
        energy: 133.3,
    },
    LoadedMode {
        name: "fibre_compression",
        axis: 0,
        sign: -1.0,
        modulus: 171_420.0,
        strength: 1200.1,
        energy: 47.5,
    },
    LoadedMode {
        name: "matrix_tension",
        axis: 1,
        sign: 1.0,
        modulus: 9_080.0,
        strength: 62.3,
        energy: 0.277,
    },
    LoadedMode {
        name: "matrix_compression",
        axis: 1,
        sign: -1.0,
        modulus: 9_080.0,
        strength: 199.8,
        energy: 0.788,
    },
];

impl LoadedMode {
    /// $2 E G / X^2$.
    pub fn snap_back_width(&self) -> f64 {
        2.0 * self.modulus * self.energy / (self.strength * self.strength)
    }

    /// The scene of a cube of side `side` on `device`, loaded to 1.15 times the end of its
    /// softening (or of its vertical drop) at a strain rate of 500 / s along the fibres and
    /// 100 / s across them; and the loaded face's speed.
    pub fn scene(&self, side: f64, device: &str) -> (String, f64) {
        let axis = ["x", "y", "z"][self.axis];
        let eps0 = self.strength / self.modulus;
        let rf = (self.snap_back_width() / side).max(1.0);
        let rate = if self.axis == 0 { 500.0 } else { 100.0 };
        let v = rate * side;
        let end = 1.15 * rf * eps0 * side / v;
        let mut velocity = [0.0; 3];
        velocity[self.axis] = self.sign * v;
        let text = format!(
            r#"title = "one IM7/8552 hex8i of side {side} mm, {name}"
[run]
method = "explicit"
end_time = {end:e}
device = "{device}"

{IM7}
[[body]]
name = "cube"
material = "im7"
box = {{ min = [0.0, 0.0, 0.0], max = [{side}, {side}, {side}], divisions = [1, 1, 1], element = "hex8i" }}

[[fix]]
body = "cube"
face = "x-"
components = ["x"]

[[fix]]
body = "cube"
face = "y-"
components = ["y"]

[[fix]]
body = "cube"
face = "z-"
components = ["z"]

[[fix]]
name = "pull"
body = "cube"
face = "{axis}+"
components = ["{axis}"]
velocity = {velocity:?}
"#,
            name = self.name
        );
        (text, v)
    }
}

/// One run of the study.
#[derive(Debug, Clone)]
pub struct BandRow {
    pub mode: &'static str,
    pub device: String,
    pub size: f64,
    /// The energy damage dissipated, and the work of the loaded face's reaction.
    pub dissipated: f64,
    pub work: f64,
    /// G h^2.
    pub exact: f64,
    pub snap_back_width: f64,
    pub wall_seconds: f64,
}

/// The sizes of the grid (mm).
pub fn sizes(quick: bool) -> Vec<f64> {
    match quick {
        true => vec![0.25, 1.0],
        false => vec![0.125, 0.25, 0.5, 1.0, 1.5, 2.0, 4.0],
    }
}

/// One run: `mode` on a cube of side `size` on `device`, in `out/runs`.
pub fn run_band(mode: &LoadedMode, size: f64, device: &str, out: &Path) -> Result<BandRow> {
    let (text, v) = mode.scene(size, device);
    let tag = format!("crack_band_{}_{size}_{device}", mode.name);
    let scene = Scene::parse(&text, Path::new(&format!("{tag}.toml")))?;
    let dir = out.join("runs").join(&tag);
    let opts = RunOptions {
        out: Some(dir.clone()),
        quiet: true,
        overwrite: true,
        ..Default::default()
    };
    let s = run(&scene, &opts)?;
    let table = Table::read(&dir.join("history.csv"))?;
    let at = |name: &str| table.columns.iter().position(|c| c == name);
    let column = format!("pull.f{}", ["x", "y", "z"][mode.axis]);
    let (Some(t), Some(f)) = (at("time"), at(&column)) else {
        return Err(ImpactError::Malformed {
            path: dir.join("history.csv"),
            line: Some(1),
            message: format!("no columns time and {column}"),
        });
    };
    let r = &table.rows;
    let work: f64 = (1..r.len())
        .map(|i| 0.5 * (r[i][f] + r[i - 1][f]) * mode.sign * v * (r[i][t] - r[i - 1][t]))
        .sum();
    Ok(BandRow {
        mode: mode.name,
        device: device.into(),
        size,
        dissipated: s.damage_energy.unwrap_or(f64::NAN),
        work,
        exact: mode.energy * size * size,
        snap_back_width: mode.snap_back_width(),
        wall_seconds: s.wall_seconds,
    })
}

pub const CSV_HEADER: &str =
    "mode,device,size,dissipated,work,exact,ratio,snap_back_width,wall_seconds";

/// `crack_band.csv`.
pub fn csv(rows: &[BandRow]) -> String {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{:e},{:e},{:e},{:e},{:e},{:e}",
            r.mode,
            r.device,
            r.size,
            r.dissipated,
            r.work,
            r.exact,
            r.dissipated / r.exact,
            r.snap_back_width,
            r.wall_seconds
        );
    }
    s
}

/// The dissipated energy over G h^2 against h, one series per mode and device, and the
/// exact ratio 1.
pub fn chart(rows: &[BandRow]) -> Chart {
    let mut keys: Vec<(&str, &str)> = Vec::new();
    for r in rows {
        if !keys.contains(&(r.mode, r.device.as_str())) {
            keys.push((r.mode, r.device.as_str()));
        }
    }
    let mut series: Vec<Series> = keys
        .iter()
        .map(|&(mode, device)| {
            let mine: Vec<&BandRow> = (rows.iter())
                .filter(|r| r.mode == mode && r.device == device)
                .collect();
            Series {
                name: format!("{mode} ({device})"),
                x: mine.iter().map(|r| r.size).collect(),
                y: mine.iter().map(|r| r.dissipated / r.exact).collect(),
                style: Style::Line,
                labels: (mine.iter())
                    .map(|r| {
                        format!(
                            "{mode} on {device}: h {} mm, dissipated {:.4e} (G A {:.4e}), snap-back width {:.3} mm, {:.3} s",
                            r.size, r.dissipated, r.exact, r.snap_back_width, r.wall_seconds
                        )
                    })
                    .collect(),
            }
        })
        .collect();
    let (lo, hi) = rows.iter().fold((f64::INFINITY, 0.0f64), |(a, b), r| {
        (a.min(r.size), b.max(r.size))
    });
    series.push(Series {
        name: "exact: G A (within the snap-back width)".into(),
        x: vec![lo, hi],
        y: vec![1.0, 1.0],
        style: Style::Exact,
        labels: Vec::new(),
    });
    Chart {
        title: "crack band: energy dissipated over G A against the element size".into(),
        x_label: "element size h, mm (log); y: dissipated / (G h^2) (log)".into(),
        series,
        log_x: true,
        log_y: true,
    }
}

/// Runs the grid (every mode, `sizes(quick)`, `devices`) and writes `crack_band.csv` and
/// `crack_band.svg/png` into `out` (the runs' folders, `out/runs`, removed unless
/// `keep_runs`).
pub fn study(
    out: &Path,
    quick: bool,
    devices: &[&str],
    keep_runs: bool,
    progress: &mut dyn FnMut(&BandRow),
) -> Result<Vec<BandRow>> {
    std::fs::create_dir_all(out).map_err(|source| ImpactError::Write {
        path: out.to_path_buf(),
        source,
    })?;
    let modes: Vec<&LoadedMode> = match quick {
        true => vec![&MODES[0], &MODES[2]],
        false => MODES.iter().collect(),
    };
    let mut rows = Vec::new();
    for mode in modes {
        for &device in devices {
            for size in sizes(quick) {
                let row = run_band(mode, size, device, out)?;
                progress(&row);
                rows.push(row);
            }
        }
    }
    let path = out.join("crack_band.csv");
    std::fs::write(&path, csv(&rows)).map_err(|source| ImpactError::Write { path, source })?;
    chart(&rows).write(out, "crack_band")?;
    if !keep_runs {
        let _ = std::fs::remove_dir_all(out.join("runs"));
    }
    Ok(rows)
}
