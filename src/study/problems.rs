//! The study's benchmark problems: scene text for a method, mesh and step, and the error
//! measures of a run against the exact solution.

use crate::output::plot::Table;

/// A benchmark problem with an exact solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Problem {
    /// Duan & Ye's example 1: bars of length 10 (E 100, rho 0.01, nu 0), A strikes B at 1.
    /// Exact: force 0.5 for 0.2, then A at rest and B at 1.
    TwoBars,
    /// A bar of length 10 strikes an analytic rigid wall at 1. Exact: force 1 for 0.2, then
    /// the bar at -1.
    BarOnWall,
    /// A stiff block slides on a floor at 2 with mu 0.2 under g = 9.81. Exact: it stops at
    /// v0 / (mu g) = 1.0194 after v0^2 / (2 mu g) = 1.0194.
    SlidingBlock,
}

/// The material of the 1D wave problems' bars.
const BAR_MATERIAL: &str = r#"[[material]]
name = "elastic"
density = 0.01
youngs_modulus = 100.0
poissons_ratio = 0.0
"#;

impl Problem {
    pub fn parse(name: &str) -> Option<Problem> {
        match name {
            "two_bars" => Some(Problem::TwoBars),
            "bar_on_wall" => Some(Problem::BarOnWall),
            "sliding_block" => Some(Problem::SlidingBlock),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Problem::TwoBars => "two_bars",
            Problem::BarOnWall => "bar_on_wall",
            Problem::SlidingBlock => "sliding_block",
        }
    }

    pub const NAMES: &'static str = "two_bars, bar_on_wall, sliding_block";

    /// Element counts of the grid (per bar; for the block, divisions along x and y).
    pub fn meshes(self, quick: bool) -> Vec<usize> {
        match (self, quick) {
            (Problem::SlidingBlock, true) => vec![2],
            (Problem::SlidingBlock, false) => vec![2, 4],
            (_, true) => vec![10, 20],
            (_, false) => vec![10, 20, 40, 80],
        }
    }

    /// Courant numbers c dt / h of the grid: around the explicit limit (1 for these meshes),
    /// and the long steps that only an implicit method can take.
    pub fn courant_numbers(self, quick: bool) -> Vec<f64> {
        match (self, quick) {
            (Problem::SlidingBlock, true) => vec![4.0, 0.95],
            (Problem::SlidingBlock, false) => vec![8.0, 4.0, 1.05, 0.95],
            (_, true) => vec![1.05, 0.95, 0.5],
            (_, false) => vec![4.0, 2.0, 1.05, 0.95, 0.5, 0.25],
        }
    }

    /// (element size h along the wave, dilatational wave speed c).
    pub fn wave(self, n: usize) -> (f64, f64) {
        match self {
            Problem::TwoBars | Problem::BarOnWall => (10.0 / n as f64, 100.0),
            // nu = 0.25: lambda + 2 mu = 1.2 E; h the smallest element side (height 0.1)
            Problem::SlidingBlock => (0.1f64.min(0.2 / n as f64), (1.2e8f64 / 1000.0).sqrt()),
        }
    }

    pub fn end_time(self) -> f64 {
        match self {
            Problem::SlidingBlock => 1.5,
            _ => 0.4,
        }
    }

    /// The scene's text, without `[run]` method settings (the caller appends them).
    pub fn scene(self, n: usize) -> String {
        // the 1D wave problems' bar: c = 100, impedance 1 per unit area, struck at 1
        let moving_bar = format!(
            "box = {{ min = [-10.0, 0.0, 0.0], max = [0.0, 1.0, 1.0], divisions = [{n}, 1, 1] }}\nvelocity = [1.0, 0.0, 0.0]"
        );
        match self {
            Problem::TwoBars => format!(
                r#"title = "two bars, {n} elements per bar"
{BAR_MATERIAL}
[[body]]
name = "A"
material = "elastic"
{moving_bar}

[[body]]
name = "B"
material = "elastic"
box = {{ min = [0.0, 0.0, 0.0], max = [10.0, 1.0, 1.0], divisions = [{n}, 1, 1] }}

[[contact]]
name = "impact"
secondary = {{ body = "A", face = "x+" }}
primary = {{ body = "B", face = "x-" }}
"#
            ),
            Problem::BarOnWall => format!(
                r#"title = "bar on a rigid wall, {n} elements"
{BAR_MATERIAL}
[[body]]
name = "bar"
material = "elastic"
{moving_bar}

[[rigid_plane]]
name = "wall"
point = [0.0, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
"#
            ),
            Problem::SlidingBlock => format!(
                r#"title = "block sliding on a floor, {n} x {n} elements"
gravity = [0.0, 0.0, -9.81]
[[material]]
name = "stiff"
density = 1000.0
youngs_modulus = 1.0e8
poissons_ratio = 0.25

[[body]]
name = "block"
material = "stiff"
box = {{ min = [0.0, 0.0, 0.0], max = [0.2, 0.2, 0.1], divisions = [{n}, {n}, 1] }}
velocity = [2.0, 0.0, 0.0]

[[rigid_plane]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
friction = 0.2

[[probe]]
name = "base"
body = "block"
point = [0.1, 0.1, 0.0]
"#
            ),
        }
    }
}

/// Errors of one run against the exact solution (all relative, documented in
/// `docs/study.md`), and the failure it shows, if any.
#[derive(Debug, Clone, Copy, Default)]
pub struct Errors {
    /// Relative L2 error of the contact force over the run (impact problems), or of the
    /// velocity history (sliding block).
    pub force: f64,
    /// |t_release - t_exact| / t_exact (impact), |t_stop - t_exact| / t_exact (block).
    pub event: f64,
    /// Final velocity error over the impact speed (impact), distance error (block).
    pub velocity: f64,
    /// Largest step-to-step rise of the total energy over E0.
    pub energy_rise: f64,
    /// (E0 - E_end) / E0, or (E0 - E_end - W_friction) / E0 for the block.
    pub energy_loss: f64,
    /// Contact lost on the plateau (rows with no force inside the exact contact window).
    pub openings: usize,
    /// Largest penetration over the element size.
    pub penetration: f64,
}

fn col(t: &Table, name: &str) -> Vec<f64> {
    t.col(name).unwrap_or_default()
}

/// Errors of a history against the problem's exact solution; `h` is the element size.
pub fn errors(problem: Problem, t: &Table, h: f64) -> Errors {
    let time = col(t, "time");
    let e = col(t, "total_energy");
    let e0 = e
        .first()
        .copied()
        .unwrap_or(1.0)
        .abs()
        .max(f64::MIN_POSITIVE);
    let energy_rise = e.windows(2).map(|w| w[1] - w[0]).fold(0.0f64, f64::max) / e0;
    let last = |name: &str| col(t, name).last().copied().unwrap_or(f64::NAN);
    match problem {
        Problem::TwoBars | Problem::BarOnWall => {
            let (name, exact, end_v) = if problem == Problem::TwoBars {
                ("impact", 0.5, None)
            } else {
                ("wall", 1.0, Some(-1.0))
            };
            let f = col(t, &format!("{name}.normal_force"));
            let pen = col(t, &format!("{name}.max_penetration"));
            let window = 0.2;
            let (mut num, mut den) = (0.0, 0.0);
            for (&ti, &fi) in time.iter().zip(&f).skip(1) {
                let fe = if ti <= window + 1e-12 { exact } else { 0.0 };
                num += (fi - fe) * (fi - fe);
                den += fe * fe;
            }
            let release = time
                .iter()
                .zip(&f)
                .filter(|(_, f)| **f > 0.0)
                .map(|(t, _)| *t)
                .fold(0.0, f64::max);
            let openings = time
                .iter()
                .zip(&f)
                .filter(|(t, f)| **t >= 0.02 && **t <= 0.18 && **f <= 0.0)
                .count();
            let velocity = match end_v {
                None => last("A.vx").abs().max((last("B.vx") - 1.0).abs()),
                Some(v) => (last("bar.vx") - v).abs(),
            };
            Errors {
                force: (num / den.max(f64::MIN_POSITIVE)).sqrt(),
                event: (release - window).abs() / window,
                velocity,
                energy_rise,
                energy_loss: (e[0] - e[e.len() - 1]) / e0,
                openings,
                penetration: pen.iter().fold(0.0f64, |a, b| a.max(*b)) / h,
            }
        }
        Problem::SlidingBlock => {
            let (v0, mu, g) = (2.0, 0.2, 9.81);
            let t_stop = v0 / (mu * g);
            let vx = col(t, "block.vx");
            let (mut num, mut den) = (0.0, 0.0);
            for (&ti, &vi) in time.iter().zip(&vx).skip(1) {
                let ve = (v0 - mu * g * ti).max(0.0);
                num += (vi - ve) * (vi - ve);
                den += ve * ve;
            }
            let stop = time
                .iter()
                .zip(&vx)
                .find(|(_, v)| **v <= 0.01 * v0)
                .map(|(t, _)| *t)
                .unwrap_or(f64::INFINITY);
            let d_exact = v0 * v0 / (2.0 * mu * g);
            let pen = col(t, "floor.max_penetration");
            Errors {
                force: (num / den.max(f64::MIN_POSITIVE)).sqrt(),
                event: (stop - t_stop).abs() / t_stop,
                velocity: (last("base.ux") - d_exact).abs() / d_exact,
                energy_rise,
                energy_loss: (e[0] - e[e.len() - 1] - last("floor.friction_work")) / e0,
                openings: 0,
                penetration: pen.iter().fold(0.0f64, |a, b| a.max(*b)) / h,
            }
        }
    }
}
