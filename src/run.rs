//! Runs a scene: build the model, choose the device, integrate, write the results.

use std::path::PathBuf;
use std::time::Instant;

use crate::error::{ImpactError, Result};
use crate::gpu::{AdapterPolicy, GpuContext, GpuKernels};
use crate::integrate::stable_step::stable_step_on;
use crate::integrate::{
    ContactReport, Energies, ExplicitSolver, ImplicitSolver, ResidentSolver, StepReport,
};
use crate::kernels::{CpuKernels, Kernels};
use crate::model::Model;
use crate::output::progress::Progress;
use crate::output::summary::{InterfaceSummary, SetupClock};
use crate::output::vtu::{NodeContact, VtuWriter};
use crate::output::{History, Summary};
use crate::scene::{Constraint, DeviceChoice, MassKind, Method, PenaltyLaw, Scene};

/// A run whose total energy exceeds this multiple of its scale (the initial energy, or the
/// work gravity can do across the model) has diverged: elastic contact can only lose energy.
pub const DIVERGENCE_FACTOR: f64 = 100.0;

#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Overrides `output.dir`.
    pub out: Option<PathBuf>,
    /// Overrides `run.device`.
    pub device: Option<DeviceChoice>,
    /// No progress lines on stderr.
    pub quiet: bool,
}

/// The output folder a run will write to.
pub fn output_dir(scene: &Scene, opts: &RunOptions) -> PathBuf {
    opts.out.clone().unwrap_or_else(|| scene.output_dir.clone())
}

/// Under `device = "auto"`, scenes with at least this many elements run their kernels on a
/// hardware GPU when there is one. Smaller scenes stay on the CPU in f64: there the kernels
/// cost less than a few milliseconds per iteration, and f64 keeps the contact iteration's
/// convergence test at its tightest. Software adapters are never chosen by "auto": on the
/// same cores they are slower than the CPU twins (README, kernel benchmark).
pub const AUTO_GPU_MIN_ELEMENTS: usize = 20_000;

/// The GPU the requested device resolves to, or `None` for the CPU twins; `notice` receives
/// the one-line reason when "auto" falls back to the CPU.
pub fn gpu_context(
    scene: &Scene,
    elements: usize,
    device: DeviceChoice,
    notice: &mut dyn FnMut(&str),
) -> Result<Option<GpuContext>> {
    match device {
        DeviceChoice::Cpu => Ok(None),
        DeviceChoice::Gpu => GpuContext::new().map(Some).map_err(|e| gpu_error(scene, e)),
        DeviceChoice::Auto => {
            if elements < AUTO_GPU_MIN_ELEMENTS {
                notice(&format!(
                    "device auto: {elements} elements (< {AUTO_GPU_MIN_ELEMENTS}): kernels on the CPU in f64"
                ));
                return Ok(None);
            }
            let ctx = GpuContext::open(AdapterPolicy::HardwareOnly)?;
            if ctx.is_none() {
                notice("device auto: no hardware GPU found: kernels on the CPU in f64");
            }
            Ok(ctx)
        }
    }
}

fn gpu_error(scene: &Scene, e: ImpactError) -> ImpactError {
    match e {
        ImpactError::Gpu(message) => ImpactError::Unsupported {
            path: scene.path.clone(),
            key: "run.device".into(),
            message: format!("device = \"gpu\": {message}"),
        },
        other => other,
    }
}

/// Picks the kernels for the requested device; `notice` receives the one-line reason when
/// "auto" falls back to the CPU.
pub fn kernels<'m>(
    scene: &Scene,
    model: &'m Model,
    device: DeviceChoice,
    notice: &mut dyn FnMut(&str),
) -> Result<Box<dyn Kernels + 'm>> {
    let data = model.element_data();
    let elements = data.hexes.len() + data.tets.len();
    Ok(match gpu_context(scene, elements, device, notice)? {
        Some(ctx) => Box::new(GpuKernels::new(ctx, &data).map_err(|e| gpu_error(scene, e))?),
        None => Box::new(CpuKernels::new(data)),
    })
}

/// The integrator a scene asked for.
enum Solver<'m> {
    Implicit(Box<ImplicitSolver<'m>>),
    Explicit(Box<ExplicitSolver<'m>>),
    /// The explicit path with the whole step on the GPU.
    Resident(Box<ResidentSolver<'m>>),
}

impl Solver<'_> {
    fn step(&mut self) -> Result<StepReport> {
        match self {
            Solver::Implicit(s) => s.step(),
            Solver::Explicit(s) => s.step(),
            Solver::Resident(s) => s.step(),
        }
    }
    fn energies(&mut self) -> Result<Energies> {
        match self {
            Solver::Implicit(s) => s.energies(),
            Solver::Explicit(s) => s.energies(),
            Solver::Resident(s) => Ok(s.energies()),
        }
    }
    fn body_velocities(&self) -> Vec<[f64; 3]> {
        match self {
            Solver::Implicit(s) => s.body_velocities(),
            Solver::Explicit(s) => s.body_velocities(),
            Solver::Resident(s) => s.body_velocities(),
        }
    }
    fn time(&self) -> f64 {
        match self {
            Solver::Implicit(s) => s.time,
            Solver::Explicit(s) => s.time,
            Solver::Resident(s) => s.time,
        }
    }
    fn steps(&self) -> usize {
        match self {
            Solver::Implicit(s) => s.steps,
            Solver::Explicit(s) => s.steps,
            Solver::Resident(s) => s.steps,
        }
    }
    fn state(&self) -> (&[f64], &[f64]) {
        match self {
            Solver::Implicit(s) => (&s.u, &s.v),
            Solver::Explicit(s) => (&s.u, &s.v),
            Solver::Resident(s) => (&s.u, &s.v),
        }
    }
    fn reports(&self) -> Vec<ContactReport> {
        match self {
            Solver::Implicit(s) => s.interfaces.iter().map(|i| i.report).collect(),
            Solver::Explicit(s) => s.interfaces.iter().map(|i| i.report).collect(),
            Solver::Resident(s) => s.reports(),
        }
    }
    fn nodal_mass(&self) -> &[f64] {
        match self {
            Solver::Implicit(s) => s.nodal_mass(),
            Solver::Explicit(s) => s.nodal_mass(),
            Solver::Resident(s) => s.nodal_mass(),
        }
    }
    fn device_name(&self) -> String {
        match self {
            Solver::Implicit(s) => s.device_name(),
            Solver::Explicit(s) => s.device_name(),
            Solver::Resident(s) => s.device_name(),
        }
    }
    fn engine(&self) -> &'static str {
        match self {
            Solver::Resident(_) => "gpu resident",
            _ if self.device_name() == "cpu" => "cpu",
            _ => "gpu kernels, host loop",
        }
    }

    /// Displacement and velocity of every probe node after the last step.
    fn probes(&self, model: &Model) -> Vec<crate::output::history::ProbeValues> {
        if let Solver::Resident(s) = self {
            return s.probes();
        }
        let (u, v) = self.state();
        model
            .probes
            .iter()
            .map(|p| {
                let d = 3 * p.node as usize;
                ([u[d], u[d + 1], u[d + 2]], [v[d], v[d + 1], v[d + 2]])
            })
            .collect()
    }

    /// Contact pressure (summed) and gap (the largest) of every node, for VTU frames.
    fn node_contact(&self, model: &Model) -> Vec<NodeContact> {
        let mut out = vec![NodeContact::default(); model.mesh.node_count()];
        for (k, itf) in model.interfaces.iter().enumerate() {
            for (i, &n) in itf.nodes.iter().enumerate() {
                let (pressure, gap) = match self {
                    Solver::Implicit(s) => {
                        let st = &s.interfaces[k];
                        let p = st.points[i];
                        let gap = if p.face == crate::kernels::contact_gap::NO_FACE {
                            f64::NAN
                        } else {
                            p.gap
                        };
                        (st.step_pressure(i), gap)
                    }
                    Solver::Explicit(s) => {
                        let st = &s.interfaces[k];
                        (st.impulse[i] / (s.dt * itf.area[i]), st.gap[i])
                    }
                    Solver::Resident(s) => {
                        let (impulse, gap) = s.node_contact(k, i);
                        (impulse / (s.dt * itf.area[i]), gap)
                    }
                };
                let c = &mut out[n as usize];
                c.pressure += pressure;
                if gap.is_finite() && (c.gap.is_nan() || gap > c.gap) {
                    c.gap = gap;
                }
            }
        }
        out
    }
}

/// The time step of an explicit run given the mesh's stable bound `(step, element)` from
/// [`stable_step`]: the scene's, which must not exceed the bound (unless
/// `explicit.allow_unstable`), or `safety_factor` of the bound.
pub fn explicit_time_step(scene: &Scene, (stable, element): (f64, usize)) -> Result<f64> {
    match scene.run.time_step {
        // a step equal to the bound up to rounding is the bound
        Some(dt) if dt > stable * (1.0 + 1e-9) && !scene.explicit.allow_unstable => Err(ImpactError::SceneValue {
            path: scene.path.clone(),
            key: "run.time_step".into(),
            message: format!(
                "{dt:.4e} is above the stable explicit step {stable:.4e} (set by element {element}: 2/omega_max of its lumped-mass eigenproblem); use at most that, or leave time_step out for {:.4e} (explicit.safety_factor = {} of it)",
                scene.explicit.safety_factor * stable,
                scene.explicit.safety_factor
            ),
        }),
        Some(dt) => Ok(dt),
        None => Ok(scene.explicit.safety_factor * stable),
    }
}

/// The cost of one implicit step in explicit steps of the same mesh, from this project's
/// benchmarks on one machine (README, "Performance"): 95 at 3,072 elements and 180 at 18,000
/// (a factorised solve pair per contact iteration, about 15 iterations, against one element
/// sweep), so $K(n) = 95\,(n / 3072)^{0.36}$.
pub fn implicit_step_cost(elements: usize) -> f64 {
    95.0 * (elements.max(1) as f64 / 3072.0).powf(0.36)
}

/// `method = "auto"`: explicit unless the scene asks for a step so much longer than the
/// explicit one that the implicit path's fewer, dearer steps cost less. Without a
/// `time_step` the scene asks for no particular accuracy in time and the explicit path's
/// stable step is the wave-resolving one, so it is explicit. With one, implicit is chosen
/// when time_step / (explicit step) exceeds [`implicit_step_cost`]. Returns the method and a
/// sentence for `summary.json`.
/// `stable` is the mesh's stable explicit step ([`stable_step`]).
pub fn choose_method(scene: &Scene, model: &Model, stable: f64) -> (Method, String) {
    let explicit_dt = scene.explicit.safety_factor * stable;
    let cost = implicit_step_cost(model.mesh.element_count());
    match scene.run.time_step {
        None => (
            Method::Explicit,
            format!("explicit: no time_step asked; the explicit step is {explicit_dt:.4e}"),
        ),
        Some(dt) => {
            let ratio = dt / explicit_dt;
            let method = if ratio > cost {
                Method::Implicit
            } else {
                Method::Explicit
            };
            (
                method,
                format!(
                    "{}: time_step {dt:.4e} is {ratio:.3} explicit steps ({explicit_dt:.4e}); an implicit step costs about {cost:.0} explicit steps on {} elements",
                    method.name(),
                    model.mesh.element_count()
                ),
            )
        }
    }
}

/// Writes the run's charts into `dir`: `forces` (every interface's normal force) and
/// `energies` (kinetic, strain, total, and the friction work of interfaces with friction),
/// each with the scene's exact curves for its columns, and one chart `exact_<column>` for an
/// exact curve of any other column. SVG and PNG each.
pub fn write_charts(scene: &Scene, model: &Model, dir: &std::path::Path) -> Result<()> {
    use crate::output::plot::{chart, Series, Style, Table};
    let table = Table::read(&dir.join("history.csv"))?;
    let forces: Vec<String> = model
        .interfaces
        .iter()
        .map(|i| format!("{}.normal_force", i.name))
        .collect();
    let mut energies: Vec<String> = ["kinetic_energy", "strain_energy", "total_energy"]
        .map(String::from)
        .to_vec();
    energies.extend(
        model
            .interfaces
            .iter()
            .filter(|i| i.friction > 0.0)
            .map(|i| format!("{}.friction_work", i.name)),
    );
    let exact_of = |cols: &[String]| -> Vec<Series> {
        scene
            .exact
            .iter()
            .filter(|e| cols.contains(&e.column))
            .map(|e| Series {
                name: format!("{} ({})", e.column, e.label),
                x: e.points.iter().map(|p| p[0]).collect(),
                y: e.points.iter().map(|p| p[1]).collect(),
                style: Style::Exact,
            })
            .collect()
    };
    let mut charts = Vec::new();
    if !forces.is_empty() {
        charts.push(("forces".to_string(), "contact forces".to_string(), forces));
    }
    charts.push(("energies".into(), "energies".into(), energies));
    for e in &scene.exact {
        if !charts.iter().any(|(_, _, cols)| cols.contains(&e.column)) {
            let name = format!("exact_{}", e.column.replace(['.', '/'], "_"));
            charts.push((name, e.column.clone(), vec![e.column.clone()]));
        }
    }
    for (name, title, cols) in charts {
        let mut c = chart(&table, &title, &cols);
        c.series.extend(exact_of(&cols));
        c.write(dir, &name)?;
    }
    Ok(())
}

/// Runs the scene to its end time, writing `history.csv` and `summary.json`.
///
/// A diverging run stops with [`ImpactError::Diverged`] after flushing the history and
/// writing a summary with `status = "diverged"`.
pub fn run(scene: &Scene, opts: &RunOptions) -> Result<Summary> {
    let start = Instant::now();
    let dir = output_dir(scene, opts);
    std::fs::create_dir_all(&dir).map_err(|source| ImpactError::Write {
        path: dir.clone(),
        source,
    })?;
    let mut clock = SetupClock::start();
    let device = opts.device.unwrap_or(scene.run.device);
    let model = Model::from_scene(scene);
    clock.lap("model");
    let quiet = opts.quiet;
    let mut notice = |line: &str| {
        if !quiet {
            eprintln!("{line}");
        }
    };
    let ctx = gpu_context(scene, model.mesh.element_count(), device, &mut notice)?;
    clock.lap("device");
    // the stable explicit step, once, where the explicit path may run (on the GPU for a mesh
    // of many element shapes)
    let bound = match scene.run.method {
        Method::Explicit | Method::Auto => {
            Some(stable_step_on(&model, ctx.as_ref()).map_err(|e| gpu_error(scene, e))?)
        }
        Method::Implicit => None,
    };
    clock.lap("stable step");
    let (method, method_choice) = match (scene.run.method, bound) {
        (Method::Auto, Some((stable, _))) => {
            let (m, why) = choose_method(scene, &model, stable);
            (m, Some(why))
        }
        (m, _) => (m, None),
    };
    if let Some(why) = &method_choice {
        if !opts.quiet {
            eprintln!("method auto: {why}");
        }
    }
    let (dt, stable) = match (method, bound) {
        (Method::Explicit, Some(bound)) => {
            let stable = bound.0;
            let dt = if method_choice.is_some() {
                // auto: the scene's step if the explicit path can take it, else its own
                match scene.run.time_step {
                    Some(dt) if dt <= stable * (1.0 + 1e-9) => dt,
                    _ => scene.explicit.safety_factor * stable,
                }
            } else {
                explicit_time_step(scene, bound)?
            };
            (dt, Some(stable))
        }
        _ => (
            scene
                .run
                .time_step
                .expect("validated: implicit has a time step; auto picks implicit only with one"),
            None,
        ),
    };
    let steps = (scene.run.end_time / dt - 1e-9).ceil() as usize;
    let mut solver = match (method, ctx) {
        (Method::Explicit, Some(ctx)) => Solver::Resident(Box::new(
            ResidentSolver::new(
                ctx,
                &model,
                &scene.explicit,
                dt,
                scene.speed_scale(),
                steps,
                scene.vtu_every,
            )
            .map_err(|e| gpu_error(scene, e))?,
        )),
        (method, ctx) => {
            let kern: Box<dyn Kernels> = match ctx {
                Some(ctx) => Box::new(
                    GpuKernels::new(ctx, &model.element_data()).map_err(|e| gpu_error(scene, e))?,
                ),
                None => Box::new(CpuKernels::new(model.element_data())),
            };
            match method {
                Method::Explicit => Solver::Explicit(Box::new(ExplicitSolver::new(
                    &model,
                    scene.explicit.clone(),
                    dt,
                    scene.speed_scale(),
                    kern,
                )?)),
                _ => Solver::Implicit(Box::new(ImplicitSolver::new(
                    &model,
                    scene.implicit.clone(),
                    dt,
                    scene.speed_scale(),
                    kern,
                )?)),
            }
        }
    };
    clock.lap("solver");
    let explicit = !matches!(solver, Solver::Implicit(_));
    let columns = crate::output::history::column_names(&model);
    for (i, e) in scene.exact.iter().enumerate() {
        if !columns.contains(&e.column) {
            return Err(ImpactError::SceneValue {
                path: scene.path.clone(),
                key: format!("exact[{i}].column"),
                message: format!(
                    "\"{}\" is not a history column (they are: {})",
                    e.column,
                    columns.join(", ")
                ),
            });
        }
    }
    let mut history = History::create(&dir, &model)?;
    let mut summary = Summary {
        status: "running".into(),
        scene: scene.path.display().to_string(),
        title: scene.title.clone(),
        method: if explicit { "explicit" } else { "implicit" }.into(),
        method_choice,
        device: solver.device_name(),
        engine: solver.engine().into(),
        time_step: dt,
        stable_time_step: stable,
        end_time: steps as f64 * dt,
        constraint: if explicit {
            "gap_rate_impulse"
        } else {
            match scene.implicit.constraint {
                Constraint::GapRate => "gap_rate",
                Constraint::Gap => "gap",
            }
        }
        .into(),
        penalty: if explicit {
            "none"
        } else {
            match scene.implicit.penalty {
                PenaltyLaw::Adaptive => "adaptive",
                PenaltyLaw::Fixed => "fixed",
            }
        }
        .into(),
        mass: if explicit {
            "lumped"
        } else {
            match scene.implicit.mass {
                MassKind::Lumped => "lumped",
                MassKind::Consistent => "consistent",
            }
        }
        .into(),
        elements: model.mesh.element_count(),
        nodes: model.mesh.node_count(),
        free_dofs: model.fixed.iter().filter(|f| !**f).count(),
        ..Default::default()
    };
    let e0 = solver.energies()?;
    summary.energy_initial = e0.total();
    summary.energy_max = e0.total();
    let total_mass: f64 = solver.nodal_mass().iter().sum();
    let energy_scale = e0
        .total()
        .abs()
        .max(total_mass * crate::scene::norm3(scene.gravity) * bbox_diagonal(&model));
    let write_row = |solver: &mut Solver, history: &mut History| -> Result<f64> {
        let e = solver.energies()?;
        let contacts = solver.reports();
        let probes = solver.probes(&model);
        history.row(
            solver.time(),
            solver.steps(),
            &e,
            &solver.body_velocities(),
            &contacts,
            &probes,
        )?;
        Ok(e.total())
    };
    write_row(&mut solver, &mut history)?;
    let stem = scene
        .path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "frame".into());
    let mut frames = scene
        .vtu_every
        .map(|every| (every, VtuWriter::new(&dir, &stem)));
    let write_frame = |solver: &Solver, frames: &mut Option<(usize, VtuWriter)>| -> Result<()> {
        if let Some((every, w)) = frames {
            if solver.steps() % *every == 0 {
                let (u, v) = solver.state();
                w.frame(
                    &model,
                    solver.steps(),
                    solver.time(),
                    u,
                    v,
                    &solver.node_contact(&model),
                )?;
            }
        }
        Ok(())
    };
    write_frame(&solver, &mut frames)?;
    clock.lap("first row");
    summary.setup_seconds = clock.total();
    summary.setup_stages = clock.stages();
    let mut peak = vec![0.0f64; model.interfaces.len()];
    let mut progress = Progress::new(steps, opts.quiet);
    for n in 0..steps {
        let outcome = solver.step().and_then(|r| {
            let e = write_row(&mut solver, &mut history)?;
            write_frame(&solver, &mut frames)?;
            Ok((r, e))
        });
        let (r, e) = match outcome {
            Ok(x) => x,
            Err(err) => {
                let err = fail(
                    &mut summary,
                    &mut history,
                    &dir,
                    n + 1,
                    (n + 1) as f64 * dt,
                    err.to_string(),
                    start,
                );
                let _ = write_charts(scene, &model, &dir);
                return Err(err);
            }
        };
        summary.steps += 1;
        summary.iterations_total += r.iterations;
        summary.iterations_max = summary.iterations_max.max(r.iterations);
        summary.unconverged_steps += usize::from(!r.converged);
        summary.energy_final = e;
        summary.energy_max = summary.energy_max.max(e);
        if !e.is_finite() || e.abs() > DIVERGENCE_FACTOR * energy_scale.max(f64::MIN_POSITIVE) {
            let reason = format!(
                "total energy {e:.6e} against {:.6e} at the start",
                summary.energy_initial
            );
            let err = fail(
                &mut summary,
                &mut history,
                &dir,
                n + 1,
                solver.time(),
                reason,
                start,
            );
            let _ = write_charts(scene, &model, &dir);
            return Err(err);
        }
        for (p, r) in peak.iter_mut().zip(solver.reports()) {
            *p = p.max(r.normal_force);
        }
        progress.step(n + 1, solver.time(), r.iterations);
    }
    progress.finish();
    history.flush()?;
    write_charts(scene, &model, &dir)?;
    summary.status = "completed".into();
    summary.iterations_mean = summary.iterations_total as f64 / summary.steps.max(1) as f64;
    summary.interfaces = match &solver {
        Solver::Implicit(solver) => {
            summary.factorizations = solver.factorizations();
            summary.event_steps = solver.event_steps;
            model
                .interfaces
                .iter()
                .zip(&solver.interfaces)
                .zip(&peak)
                .map(|((itf, st), &p)| InterfaceSummary {
                    name: itf.name.clone(),
                    penalty_normal_final: Some(st.penalty.eps),
                    penalty_tangential_final: st.friction.as_ref().map(|f| f.penalty.eps),
                    friction_work: st.friction.as_ref().map_or(0.0, |f| f.work),
                    penalty_increases: st.penalty.increases,
                    penalty_decreases: st.penalty.decreases,
                    peak_normal_force: p,
                })
                .collect()
        }
        Solver::Explicit(_) | Solver::Resident(_) => model
            .interfaces
            .iter()
            .zip(solver.reports())
            .zip(&peak)
            .map(|((itf, r), &p)| InterfaceSummary {
                name: itf.name.clone(),
                penalty_normal_final: None,
                penalty_tangential_final: None,
                friction_work: r.friction_work,
                penalty_increases: 0,
                penalty_decreases: 0,
                peak_normal_force: p,
            })
            .collect(),
    };
    summary.wall_seconds = start.elapsed().as_secs_f64();
    summary.write(&dir)?;
    Ok(summary)
}

fn fail(
    summary: &mut Summary,
    history: &mut History,
    dir: &std::path::Path,
    step: usize,
    time: f64,
    reason: String,
    start: Instant,
) -> ImpactError {
    let _ = history.flush();
    summary.status = "diverged".into();
    summary.message = Some(reason.clone());
    summary.wall_seconds = start.elapsed().as_secs_f64();
    let _ = summary.write(dir);
    ImpactError::Diverged {
        step,
        time,
        reason,
        dir: dir.to_path_buf(),
    }
}

fn bbox_diagonal(model: &Model) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &model.mesh.nodes {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    crate::scene::norm3([hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]])
}
