//! Runs a scene: build the model, choose the device, integrate, write the results.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use crate::backend::{CpuKernels, Kernels};
use crate::check::penetration::InitialContact;
use crate::check::{self, Warning};
use crate::checkpoint::{Checkpoint, SolverState, Tally};
use crate::error::{ImpactError, Result};
use crate::gpu::GpuKernels;
use crate::integrate::{
    ContactReport, Energies, ExplicitSolver, ImplicitSolver, ResidentSolver, StepReport,
};
use crate::model::Model;
use crate::output::progress::Progress;
use crate::output::summary::{InterfaceSummary, SetupClock};
use crate::output::vtu::{NodeContact, VtuWriter};
use crate::output::{History, Summary};
use crate::scene::{DeviceChoice, Method, Scene};
use crate::setup::{self, gpu_error, Setup};

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
    /// Replace an earlier run's files in the output folder.
    pub overwrite: bool,
    /// Continue the run in the output folder from its latest checkpoint.
    pub resume: bool,
    /// Set (by a signal handler) to stop the run after the current step with a checkpoint.
    pub interrupt: Option<Arc<AtomicBool>>,
}

/// The output folder a run will write to.
pub fn output_dir(scene: &Scene, opts: &RunOptions) -> PathBuf {
    opts.out.clone().unwrap_or_else(|| scene.output_dir.clone())
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
    /// Submits no more device work (the resident engine; the others have none in flight).
    fn stop_submitting(&mut self) {
        if let Solver::Resident(s) = self {
            s.stop_submitting();
        }
    }

    /// Whether the state of the last step handed out is all there is (nothing in flight).
    fn at_rest(&self) -> bool {
        match self {
            Solver::Resident(s) => s.at_rest(),
            _ => true,
        }
    }

    /// Puts the clock exactly on the end time after a shortened last step (the explicit
    /// solver sums its steps; the resident one computes the time itself).
    fn end_at(&mut self, time: f64) {
        if let Solver::Explicit(s) = self {
            s.time = time;
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

/// The files an earlier run leaves in its folder; a new run refuses a folder holding any of
/// them unless told to overwrite or resume.
pub const RUN_FILES: [&str; 3] = ["summary.json", "history.csv", "checkpoint.bin"];

/// Refuses a folder that holds an earlier run's files (unless `--overwrite` or `--resume`),
/// and creates it.
fn prepare_dir(dir: &Path, opts: &RunOptions) -> Result<()> {
    let found: Vec<&str> = RUN_FILES
        .iter()
        .copied()
        .filter(|f| dir.join(f).exists())
        .collect();
    if !found.is_empty() && !opts.overwrite && !opts.resume {
        return Err(ImpactError::OutputExists {
            dir: dir.to_path_buf(),
            found: found.join(", "),
        });
    }
    if opts.overwrite {
        // an earlier run's summary or checkpoint must not outlive it beside the new files
        for f in found {
            let path = dir.join(f);
            std::fs::remove_file(&path).map_err(|source| ImpactError::Write { path, source })?;
        }
    }
    std::fs::create_dir_all(dir).map_err(|source| ImpactError::Write {
        path: dir.to_path_buf(),
        source,
    })
}

/// Builds the integrator the setup chose.
fn build_solver<'m>(scene: &Scene, setup: &'m Setup, speed_scale: f64) -> Result<Solver<'m>> {
    let model = &setup.model;
    let dt = setup.dt;
    Ok(match (setup.method, setup.ctx.clone()) {
        (Method::Explicit, Some(ctx)) => Solver::Resident(Box::new(
            ResidentSolver::new(
                ctx,
                model,
                &scene.explicit,
                dt,
                speed_scale,
                setup.steps,
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
                    model,
                    scene.explicit.clone(),
                    dt,
                    speed_scale,
                    kern,
                )?)),
                _ => Solver::Implicit(Box::new(ImplicitSolver::new(
                    model,
                    scene.implicit.clone(),
                    dt,
                    speed_scale,
                    kern,
                )?)),
            }
        }
    })
}

/// Every `[[exact]]` curve must name a history column.
fn check_exact_columns(scene: &Scene, model: &Model) -> Result<()> {
    let columns = crate::output::history::column_names(model);
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
    Ok(())
}

/// The summary's fields known before the first step.
fn initial_summary(scene: &Scene, setup: &Setup, solver: &Solver) -> Summary {
    let explicit = !matches!(solver, Solver::Implicit(_));
    let model = &setup.model;
    Summary {
        status: "running".into(),
        scene: scene.path.display().to_string(),
        title: scene.title.clone(),
        method: if explicit {
            Method::Explicit
        } else {
            Method::Implicit
        }
        .name()
        .into(),
        method_choice: setup.method_choice.clone(),
        device: solver.device_name(),
        engine: solver.engine().into(),
        time_step: setup.dt,
        stable_time_step: setup.bound.filter(|_| explicit).map(|b| b.0),
        end_time: match setup.last_step {
            Some(last) => (setup.steps - 1) as f64 * setup.dt + last,
            None => setup.steps as f64 * setup.dt,
        },
        constraint: if explicit {
            "gap_rate_impulse"
        } else {
            scene.implicit.constraint.name()
        }
        .into(),
        penalty: if explicit {
            "none"
        } else {
            scene.implicit.penalty.name()
        }
        .into(),
        mass: if explicit {
            "lumped"
        } else {
            scene.implicit.mass.name()
        }
        .into(),
        elements: model.mesh.element_count(),
        nodes: model.mesh.node_count(),
        free_dofs: model.fixed.iter().filter(|f| !**f).count(),
        initial_contact: setup.initial.clone(),
        memory_estimate_bytes: setup.estimate.host,
        ..Default::default()
    }
}

/// Adds a finished step to the tally.
fn count_step(
    tally: &mut Tally,
    step: (usize, f64),
    r: StepReport,
    e: f64,
    reports: &[ContactReport],
) {
    tally.steps += 1;
    tally.iterations_total += r.iterations;
    tally.iterations_max = tally.iterations_max.max(r.iterations);
    tally.unconverged_steps += usize::from(!r.converged);
    tally.energy_final = e;
    tally.energy_max = tally.energy_max.max(e);
    if !r.converged && tally.first_unconverged.is_none() {
        tally.first_unconverged = Some(step);
    }
    for (k, c) in reports.iter().enumerate() {
        tally.peak_force[k] = tally.peak_force[k].max(c.normal_force);
        if c.max_penetration > tally.deepest[k].0 {
            tally.deepest[k] = (c.max_penetration, step.0, step.1);
        }
    }
}

/// The warnings of a finished run.
fn warnings(
    scene: &Scene,
    model: &Model,
    tally: &Tally,
    implicit: bool,
    initial: &[InitialContact],
    energy_scale: f64,
) -> Vec<Warning> {
    let cap = if implicit {
        format!(
            "implicit.max_iterations = {} per solve",
            scene.implicit.max_iterations
        )
    } else {
        format!(
            "explicit.max_iterations = {} sweeps",
            scene.explicit.max_iterations
        )
    };
    let mut w: Vec<Warning> = check::unconverged(
        tally.unconverged_steps,
        tally.steps,
        tally.first_unconverged,
        &cap,
    )
    .into_iter()
    .collect();
    for (k, itf) in model.interfaces.iter().enumerate() {
        let (depth, step, time) = tally.deepest[k];
        w.extend(check::deep_penetration(
            &itf.name,
            depth,
            (step, time),
            check::face_size(&itf.area, itf.secondary_faces.len()),
        ));
    }
    w.extend(check::energy_rise(
        tally.energy_initial,
        tally.energy_max,
        energy_scale,
        scene.run.energy_tolerance,
    ));
    for r in initial {
        if r.penetrating > 0 && r.policy == "ignore" {
            w.push(Warning::new(
                "initial_penetration",
                format!(
                    "interface `{}`: {} nodes started behind the primary surface (deepest {:.4e}) and initial_penetration = \"ignore\" ran them as given",
                    r.interface, r.penetrating, r.depth
                ),
            ));
        }
    }
    w
}

/// The energy a run's divergence and energy-rise tests measure against: the initial energy,
/// or the work gravity can do across the model, whichever is larger.
fn energy_scale(scene: &Scene, model: &Model, solver: &Solver, initial: f64) -> f64 {
    let total_mass: f64 = solver.nodal_mass().iter().sum();
    initial
        .abs()
        .max(total_mass * crate::scene::norm3(scene.gravity) * bbox_diagonal(model))
        .max(f64::MIN_POSITIVE)
}

/// The outputs a run writes as it goes.
struct Outputs {
    dir: PathBuf,
    /// The VTU frames' file-name stem (kept across a resume).
    stem: String,
    history: History,
    frames: Option<(usize, VtuWriter)>,
}

/// Starts a new run's outputs (the t = 0 row and frame) and its tally.
fn start_fresh(
    scene: &Scene,
    model: &Model,
    solver: &mut Solver,
    dir: &Path,
) -> Result<(Outputs, Tally)> {
    let e0 = solver.energies()?;
    if !e0.total().is_finite() {
        return Err(ImpactError::SceneValue {
            path: scene.path.clone(),
            key: "body".into(),
            message: format!(
                "the initial energy is {:e} (kinetic {:e}, potential {:e}): check the bodies' velocities, the materials and gravity",
                e0.total(),
                e0.kinetic,
                e0.potential
            ),
        });
    }
    let mut out = Outputs {
        dir: dir.to_path_buf(),
        stem: frame_stem(scene),
        history: History::create(dir, model)?,
        frames: scene
            .vtu_every
            .map(|every| (every, VtuWriter::new(dir, &frame_stem(scene)))),
    };
    write_row(solver, model, &mut out.history)?;
    write_frame(solver, model, &mut out.frames, false)?;
    let n = model.interfaces.len();
    let tally = Tally {
        energy_initial: e0.total(),
        energy_final: e0.total(),
        energy_max: e0.total(),
        peak_force: vec![0.0; n],
        deepest: vec![(0.0, 0, 0.0); n],
        ..Default::default()
    };
    Ok((out, tally))
}

/// Continues a run's outputs and tally from a checkpoint (the history and the frame
/// collection cut back to its step).
fn start_resumed(
    scene: &Scene,
    model: &Model,
    solver: &mut Solver,
    dir: &Path,
    c: Checkpoint,
) -> Result<(Outputs, Tally)> {
    let refuse = |message: String| ImpactError::Resume {
        dir: dir.to_path_buf(),
        message,
    };
    match (solver, c.solver) {
        (Solver::Explicit(s), SolverState::Explicit(st)) => s.restore(st).map_err(refuse)?,
        (Solver::Implicit(s), SolverState::Implicit(st)) => s.restore(st).map_err(refuse)?,
        (Solver::Resident(s), SolverState::Resident(st)) => s.restore(st).map_err(refuse)?,
        _ => {
            return Err(refuse(
                "the checkpoint was written by another integrator than this run's".into(),
            ))
        }
    }
    let out = Outputs {
        dir: dir.to_path_buf(),
        stem: c.frame_stem.clone(),
        history: History::resume(dir, model, c.tally.steps + 1)?,
        frames: scene
            .vtu_every
            .map(|every| (every, VtuWriter::resume(dir, &c.frame_stem, &c.frames))),
    };
    Ok((out, c.tally))
}

/// Refuses a checkpoint the run cannot continue from, before anything in the folder changes:
/// one at or past the scene's last step, or one taken with another step length (the stable
/// step found on another device).
fn check_resumable(dir: &Path, c: &Checkpoint, setup: &Setup) -> Result<()> {
    let refuse = |message: String| ImpactError::Resume {
        dir: dir.to_path_buf(),
        message,
    };
    let (steps, time, dt) = match &c.solver {
        SolverState::Explicit(s) => (s.steps, s.time, Some(s.dt)),
        SolverState::Implicit(s) => (s.steps, s.time, None),
        SolverState::Resident(s) => (s.steps, s.time, Some(s.dt)),
    };
    if steps >= setup.steps {
        return Err(refuse(format!(
            "the checkpoint is at step {steps} (t = {time:.6e}) and the scene ends at step {}: nothing is left to run (raise run.end_time)",
            setup.steps
        )));
    }
    if let Some(dt) = dt.filter(|dt| (dt - setup.dt).abs() > 1e-12 * setup.dt) {
        return Err(refuse(format!(
            "the checkpoint's step is {dt:e} and this run's {:e} (the stable step was found on another device): resume with the first run's --device",
            setup.dt
        )));
    }
    Ok(())
}

/// Writes the checkpoint of the solver's current state.
/// The history is flushed first, so that the file holds every row the checkpoint counts
/// whatever happens to the process afterwards.
fn save(solver: &mut Solver, out: &mut Outputs, tally: &Tally, run: &RunIdentity) -> Result<()> {
    out.history.flush()?;
    let state = match solver {
        Solver::Explicit(s) => SolverState::Explicit(s.state()),
        Solver::Implicit(s) => SolverState::Implicit(s.state()),
        Solver::Resident(s) => SolverState::Resident(s.state()?),
    };
    Checkpoint {
        format: crate::checkpoint::FORMAT,
        scene_hash: run.scene_hash,
        speed_scale: run.speed_scale,
        tally: tally.clone(),
        frames: out
            .frames
            .as_ref()
            .map(|(_, w)| w.written())
            .unwrap_or_default(),
        frame_stem: out.stem.clone(),
        solver: state,
    }
    .write(&out.dir)
}

/// What a checkpoint records of the run itself: the scene's hash (computed once) and the
/// speed scale its tolerances follow.
struct RunIdentity {
    scene_hash: u64,
    speed_scale: f64,
}

/// Runs the scene to its end time, writing `history.csv` and `summary.json`.
///
/// A run that finishes with every step converged and no check fired ends `completed`; one
/// with warnings ends `completed_with_warnings` (each in the summary). A diverging run stops
/// with [`ImpactError::Diverged`] after flushing the history and writing a summary with
/// `status = "diverged"`; an interrupted one with [`ImpactError::Interrupted`] after writing
/// a checkpoint. With `resume`, the run continues from the folder's checkpoint.
pub fn run(scene: &Scene, opts: &RunOptions) -> Result<Summary> {
    let start = Instant::now();
    let dir = output_dir(scene, opts);
    prepare_dir(&dir, opts)?;
    let resumed = opts
        .resume
        .then(|| Checkpoint::read(&dir, scene))
        .transpose()?;
    let mut clock = SetupClock::start();
    let quiet = opts.quiet;
    let mut notice = |line: &str| {
        if !quiet {
            eprintln!("{line}");
        }
    };
    let device = opts.device.unwrap_or(scene.run.device);
    let setup = setup::prepare(scene, device, &mut notice, &mut clock)?;
    let mut running = Running::begin(scene, &setup, &dir, resumed, &mut clock, start)?;
    let mut progress = Progress::new(setup.steps, opts.quiet);
    for n in running.tally.steps..setup.steps {
        let iterations = running.step(n)?;
        if let Some(err) = running.interrupt(n, opts.interrupt.as_deref()) {
            return Err(err);
        }
        progress.step(n + 1, running.solver.time(), iterations);
    }
    progress.finish();
    running.finish()
}

/// A run between its setup and its summary: the solver, what it has written and counted.
struct Running<'s> {
    scene: &'s Scene,
    setup: &'s Setup,
    solver: Solver<'s>,
    out: Outputs,
    tally: Tally,
    summary: Summary,
    identity: RunIdentity,
    energy_scale: f64,
    start: Instant,
}

impl<'s> Running<'s> {
    /// Builds the solver, starts or resumes the outputs, and opens the summary.
    fn begin(
        scene: &'s Scene,
        setup: &'s Setup,
        dir: &Path,
        resumed: Option<Checkpoint>,
        clock: &mut SetupClock,
        start: Instant,
    ) -> Result<Self> {
        let speed_scale = resumed
            .as_ref()
            .map_or_else(|| scene.speed_scale(), |c| c.speed_scale);
        let mut solver = build_solver(scene, setup, speed_scale)?;
        if let Solver::Resident(s) = &mut solver {
            if let Some(dt) = setup.last_step {
                s.shorten_last_step(dt);
            }
            if let Some(every) = scene.checkpoint_every {
                s.cut_every(every);
            }
        }
        clock.lap("solver");
        let model = &setup.model;
        check_exact_columns(scene, model)?;
        if let Some(c) = &resumed {
            check_resumable(dir, c, setup)?;
        }
        let (out, tally) = match resumed {
            None => start_fresh(scene, model, &mut solver, dir)?,
            Some(c) => start_resumed(scene, model, &mut solver, dir, c)?,
        };
        let energy_scale = energy_scale(scene, model, &solver, tally.energy_initial);
        let mut summary = initial_summary(scene, setup, &solver);
        clock.lap("first row");
        summary.setup_seconds = clock.total();
        summary.setup_stages = clock.stages();
        let identity = RunIdentity {
            scene_hash: crate::checkpoint::scene_hash(scene),
            speed_scale,
        };
        Ok(Running {
            scene,
            setup,
            solver,
            out,
            tally,
            summary,
            identity,
            energy_scale,
            start,
        })
    }

    /// Whether step `n` is the run's last, shortened to end at `end_time`.
    fn shortened(&self, n: usize) -> bool {
        n + 1 == self.setup.steps && self.setup.last_step.is_some()
    }

    /// Step `n`: the solver's step, its history row and frame, the tally, the divergence
    /// check and a due checkpoint. Returns the step's iterations.
    fn step(&mut self, n: usize) -> Result<usize> {
        let last = n + 1 == self.setup.steps;
        if self.shortened(n) {
            if self.scene.checkpoint_every.is_some() {
                // the checkpoint stays on whole steps: a later end time continues from here
                save(&mut self.solver, &mut self.out, &self.tally, &self.identity)?;
            }
            if let (Some(dt), Solver::Explicit(s)) = (self.setup.last_step, &mut self.solver) {
                s.shorten_step(dt);
            }
        }
        let (r, e) = self.advance(n)?;
        let at = (n + 1, self.solver.time());
        count_step(&mut self.tally, at, r, e, &self.solver.reports());
        if !e.is_finite() || e.abs() > DIVERGENCE_FACTOR * self.energy_scale {
            let reason = format!(
                "total energy {e:.6e} against {:.6e} at the start",
                self.tally.energy_initial
            );
            return Err(self.fail(at, reason));
        }
        let due = (self.scene.checkpoint_every).is_some_and(|k| (n + 1) % k == 0 || last);
        if due && !self.shortened(n) {
            save(&mut self.solver, &mut self.out, &self.tally, &self.identity)?;
        }
        Ok(r.iterations)
    }

    /// The solver's step with its row and frame. The linear solver failing is the run
    /// diverging; anything else (a write, the GPU) ends it as failed, with its own error.
    fn advance(&mut self, n: usize) -> Result<(StepReport, f64)> {
        let (model, end_time) = (&self.setup.model, self.summary.end_time);
        let last = n + 1 == self.setup.steps;
        let shortened = self.shortened(n);
        let solver = &mut self.solver;
        let out = &mut self.out;
        let outcome = solver.step().and_then(|r| {
            if shortened {
                solver.end_at(end_time);
            }
            let e = write_row(solver, model, &mut out.history)?;
            write_frame(solver, model, &mut out.frames, last)?;
            Ok((r, e))
        });
        match outcome {
            Ok(x) => Ok(x),
            Err(err @ ImpactError::Solver(_)) => {
                let time = (n + 1) as f64 * self.setup.dt;
                Err(self.fail((n + 1, time), err.to_string()))
            }
            Err(err) => {
                let _ = self.out.history.flush();
                fill_summary(&mut self.summary, &self.tally, model, &self.solver);
                self.summary.status = "failed".into();
                self.summary.message = Some(format!("at step {}: {err}", n + 1));
                self.summary.wall_seconds = self.start.elapsed().as_secs_f64();
                let _ = self.summary.write(&self.out.dir);
                Err(err)
            }
        }
    }

    /// Ends a diverged run (see [`fail`]).
    fn fail(&mut self, at: (usize, f64), reason: String) -> ImpactError {
        fail(
            self.scene,
            &self.setup.model,
            &mut self.summary,
            &self.tally,
            &mut self.out,
            at,
            reason,
            self.start,
        )
    }

    /// After step `n`: when `flag` is set, stops submitting, and once the solver is at
    /// rest (and this was not the last step) ends the run as interrupted.
    fn interrupt(&mut self, n: usize, flag: Option<&AtomicBool>) -> Option<ImpactError> {
        let signalled = flag.is_some_and(|f| f.load(Ordering::SeqCst));
        if signalled {
            // the resident engine hands out the steps it has in flight first
            self.solver.stop_submitting();
        }
        let last = n + 1 == self.setup.steps;
        (signalled && !last && self.solver.at_rest()).then(|| {
            interrupted(
                &self.setup.model,
                &mut self.solver,
                &mut self.summary,
                &self.tally,
                &mut self.out,
                &self.identity,
                self.start,
            )
        })
    }

    /// Writes the charts and the summary of a run that reached its end time.
    fn finish(mut self) -> Result<Summary> {
        let model = &self.setup.model;
        self.out.history.flush()?;
        write_charts(self.scene, model, &self.out.dir)?;
        fill_summary(&mut self.summary, &self.tally, model, &self.solver);
        self.summary.warnings = warnings(
            self.scene,
            model,
            &self.tally,
            self.summary.method == Method::Implicit.name(),
            &self.setup.initial,
            self.energy_scale,
        );
        self.summary.status = if self.summary.warnings.is_empty() {
            "completed"
        } else {
            "completed_with_warnings"
        }
        .into();
        self.summary.wall_seconds = self.start.elapsed().as_secs_f64();
        self.summary.write(&self.out.dir)?;
        Ok(self.summary)
    }
}

/// The summary's counts and energies from the tally.
fn copy_tally(summary: &mut Summary, tally: &Tally) {
    summary.steps = tally.steps;
    summary.iterations_total = tally.iterations_total;
    summary.iterations_max = tally.iterations_max;
    summary.unconverged_steps = tally.unconverged_steps;
    summary.energy_initial = tally.energy_initial;
    summary.energy_final = tally.energy_final;
    summary.energy_max = tally.energy_max;
}

/// The summary's fields from the tally and the solver.
fn fill_summary(summary: &mut Summary, tally: &Tally, model: &Model, solver: &Solver) {
    copy_tally(summary, tally);
    summary.iterations_mean = tally.iterations_total as f64 / tally.steps.max(1) as f64;
    summary.interfaces = interface_summaries(model, solver, &tally.peak_force);
    if let Solver::Implicit(s) = solver {
        summary.factorizations = s.factorizations();
        summary.linear_solver = Some(s.linear_solver());
        summary.mass_factor = s.mass_factor();
        summary.event_steps = s.event_steps;
    }
}

/// Ends an interrupted run: a checkpoint (CPU integrators), the history, a summary with
/// `status = "interrupted"`, and the error.
#[allow(clippy::too_many_arguments)]
fn interrupted(
    model: &Model,
    solver: &mut Solver,
    summary: &mut Summary,
    tally: &Tally,
    out: &mut Outputs,
    identity: &RunIdentity,
    start: Instant,
) -> ImpactError {
    let saved = save(solver, out, tally, identity);
    let _ = out.history.flush();
    fill_summary(summary, tally, model, solver);
    summary.status = "interrupted".into();
    summary.message = Some(match &saved {
        Ok(()) => format!(
            "interrupted by a signal; continue with --resume (checkpoint at step {})",
            tally.steps
        ),
        Err(e) => format!("interrupted by a signal; the checkpoint could not be written: {e}"),
    });
    summary.wall_seconds = start.elapsed().as_secs_f64();
    if let Err(e) = summary.write(&out.dir) {
        return e;
    }
    if let Err(e) = saved {
        return e;
    }
    ImpactError::Interrupted {
        step: tally.steps,
        time: solver.time(),
        dir: out.dir.clone(),
    }
}

/// Appends the current state's row; returns the total energy.
fn write_row(solver: &mut Solver, model: &Model, history: &mut History) -> Result<f64> {
    let e = solver.energies()?;
    let contacts = solver.reports();
    let probes = solver.probes(model);
    history.row(
        solver.time(),
        solver.steps(),
        &e,
        &solver.body_velocities(),
        &contacts,
        &probes,
    )?;
    Ok(e.total())
}

/// Writes a VTU frame on every `every`-th step, and on the last step (`last`) whatever its
/// number.
fn write_frame(
    solver: &Solver,
    model: &Model,
    frames: &mut Option<(usize, VtuWriter)>,
    last: bool,
) -> Result<()> {
    if let Some((every, w)) = frames {
        if solver.steps() % *every == 0 || last {
            let (u, v) = solver.state();
            w.frame(
                model,
                solver.steps(),
                solver.time(),
                u,
                v,
                &solver.node_contact(model),
            )?;
        }
    }
    Ok(())
}

fn frame_stem(scene: &Scene) -> String {
    scene
        .path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "frame".into())
}

/// Each interface's line of the summary.
fn interface_summaries(model: &Model, solver: &Solver, peak: &[f64]) -> Vec<InterfaceSummary> {
    match solver {
        Solver::Implicit(solver) => model
            .interfaces
            .iter()
            .zip(&solver.interfaces)
            .zip(peak)
            .map(|((itf, st), &p)| InterfaceSummary {
                name: itf.name.clone(),
                penalty_normal_final: Some(st.penalty.eps),
                penalty_tangential_final: st.friction.as_ref().map(|f| f.penalty.eps),
                friction_work: st.friction.as_ref().map_or(0.0, |f| f.work),
                penalty_increases: st.penalty.increases,
                penalty_decreases: st.penalty.decreases,
                peak_normal_force: p,
            })
            .collect(),
        Solver::Explicit(_) | Solver::Resident(_) => model
            .interfaces
            .iter()
            .zip(solver.reports())
            .zip(peak)
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
    }
}

/// Ends a diverged run: flushes the history, writes the summary and the charts, and returns
/// the error.
#[allow(clippy::too_many_arguments)]
fn fail(
    scene: &Scene,
    model: &Model,
    summary: &mut Summary,
    tally: &Tally,
    out: &mut Outputs,
    (step, time): (usize, f64),
    reason: String,
    start: Instant,
) -> ImpactError {
    let _ = out.history.flush();
    copy_tally(summary, tally);
    summary.status = "diverged".into();
    summary.message = Some(reason.clone());
    summary.wall_seconds = start.elapsed().as_secs_f64();
    let _ = summary.write(&out.dir);
    let _ = write_charts(scene, model, &out.dir);
    ImpactError::Diverged {
        step,
        time,
        reason,
        dir: out.dir.clone(),
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
