//! Runs a scene: build the model, choose the device, integrate, write the results.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

mod charts;
mod lock;
mod outputs;
mod ranks;
mod summary;

pub use charts::write_charts;
pub use lock::FolderLock;
pub use outputs::RUN_FILES;
pub use ranks::run_ranks;

use outputs::{
    check_resumable, count_failure, prepare_dir, save, start_fresh, start_resumed, write_frame,
    write_row, Outputs, RunIdentity,
};
use summary::{
    count_motion, count_step, energy_scale, fail, fill_summary, initial_summary, interrupted,
    warnings,
};

use crate::backend::{CpuKernels, Kernels};
use crate::checkpoint::{Checkpoint, Tally};
use crate::domain::{DomainSolver, Partition, RankResident, Ranks};
use crate::error::{ImpactError, Result};
use crate::gpu::GpuKernels;
use crate::integrate::integrator::Handover;
use crate::integrate::{
    resident, ExplicitSolver, ImplicitSolver, Integrator, ResidentSolver, StaticSolver, StepReport,
};
use crate::model::Model;
use crate::output::failure_survey::{FailureMaxima, FailureSurvey};
use crate::output::progress::Progress;
use crate::output::summary::SetupClock;
use crate::output::Summary;
use crate::scene::{DeviceChoice, Kinematics, Method, Scene};
use crate::setup::{self, gpu_error, Setup};

/// A run whose total energy exceeds this multiple of its scale (the initial energy, or the
/// work gravity can do across the model) has diverged: elastic contact can only lose energy.
pub(crate) const DIVERGENCE_FACTOR: f64 = 100.0;

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

/// Builds the integrator the setup chose for a stage of model `model`, method and time step
/// `(method, dt)`, starting after the run's step `origin.0` at time `origin.1`, with the
/// run's shortened last step and checkpoint interval.
fn build_solver<'m>(
    scene: &Scene,
    (setup, model): (&'m Setup, &'m Model),
    (method, dt, origin): (Method, f64, (usize, f64)),
    speed_scale: f64,
    ranks: Option<&'m dyn Ranks>,
) -> Result<Box<dyn Integrator + 'm>> {
    if let Some(ranks) = ranks {
        let partition = Partition::bisect(model, ranks.size());
        let settings = (&scene.explicit, dt, speed_scale);
        return Ok(match setup.ctx.clone() {
            // rigid bodies with a device form, as on one GPU: each rank's step on its GPU
            // (a model with damage or named or moving fixes: the rank's element forces there)
            Some(ctx)
                if resident::rigid_surfaces_on_device(model)
                    && !resident::needs_host_ranks(model) =>
            {
                Box::new(
                    RankResident::new(
                        model,
                        ranks,
                        &partition,
                        settings,
                        (ctx, setup.steps, scene.vtu_every),
                        FailureSurvey::new(model).map(|s| (s.device(model), s.point_cells())),
                    )
                    .map_err(|e| gpu_error(scene, e))?,
                )
            }
            ctx => Box::new(
                DomainSolver::new(
                    model,
                    ranks,
                    &partition,
                    settings,
                    (
                        ctx,
                        setup.damage.as_ref(),
                        scene.run.kinematics == Kinematics::Corotational,
                    ),
                )
                .map_err(|e| gpu_error(scene, e))?,
            ),
        });
    }
    let mut solver: Box<dyn Integrator + 'm> = match (method, setup.ctx.clone()) {
        // a meshed rigid surface has no device form: its contact runs on the host, the
        // element forces on the device; so do loads and displaced fixes (their forces and
        // velocities change over time on the host), and the stages of a run whose steps
        // change the method (their state handed on on the host)
        (Method::Explicit, Some(ctx))
            if resident::rigid_surfaces_on_device(model)
                && !scene.mixed_steps()
                && model.loads.is_empty()
                && model.fix_paths.is_empty() =>
        {
            Box::new(
                ResidentSolver::new(
                    ctx,
                    model,
                    &scene.explicit,
                    dt,
                    speed_scale,
                    setup.steps,
                    scene.vtu_every,
                    (
                        FailureSurvey::new(model).map(|s| s.device(model)),
                        setup.damage.clone(),
                    ),
                )
                .map_err(|e| gpu_error(scene, e))?,
            )
        }
        // a static step's solves are the host's, its residual in f64
        (Method::Static, _) => Box::new(StaticSolver::new(
            model,
            scene.statics,
            dt,
            Box::new(CpuKernels::new(model.element_data())),
        )?),
        (method, ctx) => {
            let kern: Box<dyn Kernels> = match ctx {
                Some(ctx) => Box::new(
                    GpuKernels::new(ctx, &model.element_data())
                        .and_then(|k| k.with_damage(setup.damage.clone()))
                        .map_err(|e| gpu_error(scene, e))?,
                ),
                None => Box::new(
                    CpuKernels::new(model.element_data())
                        .with_damage(setup.damage.clone())
                        .corotational(scene.run.kinematics == Kinematics::Corotational),
                ),
            };
            match method {
                Method::Explicit => Box::new(ExplicitSolver::new(
                    model,
                    scene.explicit.clone(),
                    dt,
                    speed_scale,
                    kern,
                )?),
                _ => Box::new(
                    ImplicitSolver::new(model, scene.implicit.clone(), dt, speed_scale, kern)
                        .map_err(|e| e.at_scene(&scene.path))?,
                ),
            }
        }
    };
    if let Some(p) = solver.pipelined() {
        p.schedule(setup.last_step, scene.checkpoint_every);
    }
    solver.start_stage_at(origin.0, origin.1);
    Ok(solver)
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

/// Runs the scene to its end time, writing `history.csv` and `summary.json`.
///
/// A run that finishes with every step converged and no check fired ends `completed`; one
/// with warnings ends `completed_with_warnings` (each in the summary). A diverging run stops
/// with [`ImpactError::Diverged`] after flushing the history and writing a summary with
/// `status = "diverged"`; an interrupted one with [`ImpactError::Interrupted`] after writing
/// a checkpoint. With `resume`, the run continues from the folder's checkpoint.
pub fn run(scene: &Scene, opts: &RunOptions) -> Result<Summary> {
    run_on(scene, opts, None)
}

/// [`run`], or one rank's part of [`run_ranks`].
fn run_on(scene: &Scene, opts: &RunOptions, ranks: Option<&dyn Ranks>) -> Result<Summary> {
    let start = Instant::now();
    let dir = output_dir(scene, opts);
    // rank 0 prepares the folder, and every rank stops where it cannot
    let prepared = match ranks.is_none_or(|r| r.rank() == 0) {
        true => prepare_dir(&dir, opts).map(Some),
        false => Ok(None),
    };
    // held until the run returns, however it ends
    let _lock = ranks::agreed(ranks, prepared)?;
    let resumed = opts
        .resume
        .then(|| Checkpoint::read(&dir, scene))
        .transpose();
    let resumed = ranks::agreed(ranks, resumed)?;
    let mut clock = SetupClock::start();
    let setup = set_up(scene, opts, ranks, &mut clock)?;
    let begun = Running::begin(scene, &setup, &dir, (resumed, ranks), &mut clock, start);
    let mut running = match begun {
        Err(ImpactError::Solver(m)) => {
            let writes = ranks.is_none_or(|r| r.rank() == 0);
            return Err(summary::unfactorised(scene, &setup, &dir, m, writes, start));
        }
        begun => begun?,
    };
    let mut progress = Progress::new(setup.steps, opts.quiet);
    for n in running.tally.steps..setup.steps {
        running.enter_stage(n)?;
        let iterations = running.step(n)?;
        if let Some(err) = running.interrupt(n, opts.interrupt.as_deref()) {
            return Err(err);
        }
        progress.step(n + 1, running.solver.time(), iterations);
    }
    progress.finish();
    running.finish()
}

/// The model and the run's settings ([`setup::prepare`]); on ranks, checked to be
/// explicit, set up on the CPU, and each rank's device opened ([`ranks::rank_context`]).
fn set_up(
    scene: &Scene,
    opts: &RunOptions,
    ranks: Option<&dyn Ranks>,
    clock: &mut SetupClock,
) -> Result<Setup> {
    let quiet = opts.quiet;
    let mut notice = |line: &str| {
        if !quiet {
            eprintln!("{line}");
        }
    };
    let device = opts.device.unwrap_or(scene.run.device);
    // the ranks' setup stays on the CPU: each rank then opens its own GPU
    let here = if ranks.is_some() {
        DeviceChoice::Cpu
    } else {
        device
    };
    let mut setup = setup::prepare(scene, here, &mut notice, clock)?;
    // said now, before a run they may make long; the summary lists them at the end
    for w in &setup.warnings {
        notice(&format!("warning: {}: {}", w.kind, w.message));
    }
    let Some(r) = ranks else {
        return Ok(setup);
    };
    if let Some(k) = (setup.stages.iter()).position(|s| s.method != Method::Explicit) {
        return Err(ImpactError::Unsupported {
            path: scene.path.clone(),
            key: format!("step[{k}].method"),
            message: format!("the {} path runs on one process (a distributed sparse solver is not built): run it without mpirun", setup.stages[k].method.name()),
        });
    }
    if setup.method != Method::Explicit {
        return Err(ImpactError::Unsupported {
            path: scene.path.clone(),
            key: "run.method".into(),
            message: format!("the {} path runs on one process (a distributed sparse solver is not built): run it without mpirun", setup.method.name()),
        });
    }
    let elements = setup.model.mesh.element_count();
    setup.ctx = ranks::rank_context(scene, device, r, elements, &mut notice)?;
    clock.lap("rank device");
    Ok(setup)
}

/// A run between its setup and its summary: the solver, what it has written and counted.
struct Running<'s> {
    scene: &'s Scene,
    setup: &'s Setup,
    solver: Box<dyn Integrator + 's>,
    out: Outputs,
    tally: Tally,
    summary: Summary,
    identity: RunIdentity,
    energy_scale: f64,
    /// The largest work the moving fixes or the loads did so far (since a resumption).
    fix_work: f64,
    start: Instant,
    /// The ranks of a decomposed run.
    ranks: Option<&'s dyn Ranks>,
    /// The `[[step]]` the solver runs (0: the first, `[run]`'s).
    stage: usize,
}

impl<'s> Running<'s> {
    /// Builds the solver, starts or resumes the outputs, and opens the summary.
    fn begin(
        scene: &'s Scene,
        setup: &'s Setup,
        dir: &Path,
        (resumed, ranks): (Option<Checkpoint>, Option<&'s dyn Ranks>),
        clock: &mut SetupClock,
        start: Instant,
    ) -> Result<Self> {
        let speed_scale = resumed
            .as_ref()
            .map_or_else(|| scene.speed_scale(), |c| c.speed_scale);
        // a resumed run goes on in the stage its checkpoint was written in (one written as a
        // stage ended is that stage's; the next is entered at its first step)
        let stage = resumed.as_ref().map_or(0, |c| {
            (setup.stages.iter())
                .filter(|s| s.from < c.tally.steps)
                .count()
        });
        let (stepping, model) = match stage {
            0 => ((setup.method, setup.dt, (0, 0.0)), &setup.model),
            k => {
                let s = &setup.stages[k - 1];
                ((s.method, s.dt, (s.from, s.start)), &s.model)
            }
        };
        let mut solver = build_solver(scene, (setup, model), stepping, speed_scale, ranks)?;
        if let Some(p) = solver.pipelined() {
            p.schedule(setup.last_step, scene.checkpoint_every);
        }
        clock.lap("solver");
        let model = &setup.model;
        check_exact_columns(scene, model)?;
        if let Some(c) = &resumed {
            let device = solver.device_name();
            check_resumable(dir, c, (setup, &device), ranks.map(|r| r.size()))?;
        }
        let rank = ranks.map(|r| (r.rank(), r.size()));
        let (out, tally) = match resumed {
            None => start_fresh(scene, model, solver.as_mut(), dir, rank)?,
            // nothing in the resumed start talks to the other ranks: they agree on it after
            Some(c) => {
                let started = start_resumed(scene, model, solver.as_mut(), dir, (c, rank));
                ranks::agreed(ranks, started)?
            }
        };
        let energy_scale = energy_scale(scene, model, solver.as_ref(), tally.energy_initial);
        let mut summary = initial_summary(scene, setup, solver.as_ref());
        clock.lap("first row");
        summary.setup_seconds = clock.total();
        summary.setup_stages = clock.stages();
        // `running` until the run ends: a process killed on the way leaves no stale ending
        ranks::agreed(ranks, out.first_summary(&summary))?;
        let identity = RunIdentity {
            scene_hash: crate::checkpoint::scene_hash(scene),
            speed_scale,
        };
        Ok(Running {
            stage,
            scene,
            setup,
            solver,
            out,
            tally,
            summary,
            identity,
            energy_scale,
            fix_work: 0.0,
            start,
            ranks,
        })
    }

    /// The energy scale now: the run's, or the work the prescribed rigid bodies' drivers, the
    /// moving fixes or the loads have done so far where that is larger (it is part of the
    /// energy balance).
    fn scale_now(&self) -> f64 {
        let driven: f64 = (self.solver.reports().iter()).map(|r| r.driver_work).sum();
        self.energy_scale.max(driven.abs()).max(self.fix_work)
    }

    /// A checkpoint of the current state (the ranks agree on its write); a failed write
    /// ends the run as failed.
    fn save(&mut self) -> Result<()> {
        let saved = save(
            self.solver.as_mut(),
            &mut self.out,
            &self.tally,
            &self.identity,
        );
        ranks::agreed(self.ranks, saved).map_err(|e| self.failed(e))
    }

    /// Ends the run as failed with `err` (a write, the GPU): the history flushed and a
    /// summary with `status = "failed"` and the reason, where it can still be written.
    fn failed(&mut self, err: ImpactError) -> ImpactError {
        let _ = self.out.history.flush();
        let model = &self.setup.model;
        fill_summary(&mut self.summary, &self.tally, model, self.solver.as_ref());
        self.summary.status = "failed".into();
        self.summary.message = Some(format!("after step {}: {err}", self.tally.steps));
        self.summary.wall_seconds = self.start.elapsed().as_secs_f64();
        let _ = self.out.summary(&self.summary);
        err
    }

    /// Before the run's step `n`: where a `[[step]]` holds from then on (or, resumed, from
    /// earlier), the solver is rebuilt on its model and goes on from the last one's state.
    fn enter_stage(&mut self, n: usize) -> Result<()> {
        let setup = self.setup;
        let stage = (setup.stages.iter()).filter(|s| s.from <= n).count();
        if stage == self.stage {
            return Ok(());
        }
        // a failure here ends the run as failed, its summary saying why
        let s = &setup.stages[stage - 1];
        if s.method != self.solver.method() {
            return self.change_method(stage, n);
        }
        let (from, model) = (&s.from, &s.model);
        let state = match self.solver.checkpoint_state() {
            Ok(Some(state)) => state,
            Ok(None) => {
                let e = ImpactError::Unsupported {
                    path: self.scene.path.clone(),
                    key: format!("step[{}]", stage - 1),
                    message: format!(
                        "the {} engine cannot hand its state to a next step",
                        self.solver.engine()
                    ),
                };
                return Err(self.failed(e));
            }
            Err(e) => return Err(self.failed(e)),
        };
        let speed_scale = self.identity.speed_scale;
        let stepping = (s.method, s.dt, (s.from, s.start));
        let built = build_solver(
            self.scene,
            (setup, model),
            stepping,
            speed_scale,
            self.ranks,
        );
        let mut solver = match built {
            Ok(solver) => solver,
            Err(e) => return Err(self.failed(e)),
        };
        let restored = solver.restore(state).map_err(ImpactError::Solver);
        // entered at its start (not resumed inside it): the acceleration is the new model's
        let begun = restored.and_then(|_| match *from == n {
            true => solver.begin_step(),
            false => Ok(()),
        });
        if let Err(e) = begun {
            return Err(self.failed(e));
        }
        self.solver = solver;
        self.stage = stage;
        Ok(())
    }

    /// Enters stage `stage` (at the run's step `n`) of another method than the solver's: a
    /// solver of its method built on its model takes the last one's state over
    /// ([`Integrator::take_over`]). A dynamic stage goes on with a dynamic one's velocity;
    /// after static stages it starts at rest, but for the run's initial velocities where no
    /// dynamic stage came before. A run resumed inside a stage was saved by that stage's
    /// method, and is restored by it.
    fn change_method(&mut self, stage: usize, n: usize) -> Result<()> {
        let (setup, s) = (self.setup, &self.setup.stages[stage - 1]);
        let dynamic = |m: Method| m != Method::Static;
        let old = self.solver.method();
        let v = match dynamic(old) {
            true => Some(self.solver.velocity().to_vec()),
            false => {
                let before = std::iter::once(setup.method)
                    .chain(setup.stages[..stage - 1].iter().map(|s| s.method));
                let first = !before.into_iter().any(dynamic);
                (!first).then(|| vec![0.0; setup.model.dofs()])
            }
        };
        let handed = Handover::of(self.solver.as_mut(), v);
        let speed_scale = self.identity.speed_scale;
        let built = build_solver(
            self.scene,
            (setup, &s.model),
            (s.method, s.dt, (s.from, s.start)),
            speed_scale,
            self.ranks,
        );
        let taken = handed.and_then(|h| {
            let mut solver = built?;
            solver.take_over(&h)?;
            Ok(solver)
        });
        match taken {
            Ok(solver) => {
                self.solver = solver;
                self.stage = stage;
                debug_assert!(
                    s.from == n,
                    "a run resumes inside a stage by its own method"
                );
                Ok(())
            }
            Err(e) => Err(self.failed(e)),
        }
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
                self.save()?;
            }
            if let Some(dt) = self.setup.last_step {
                self.solver.shorten_step(dt);
            }
        }
        let t0 = self.solver.time();
        let (r, energies, failure) = self.advance(n)?;
        let e = energies.total();
        self.fix_work = (self.fix_work)
            .max(energies.fix_work.abs())
            .max(energies.load_work.abs());
        let at = (n + 1, self.solver.time());
        count_step(&mut self.tally, at, r, e, &self.solver.reports());
        self.tally.external_work = energies.load_work;
        // the engines that hold every node's velocity after each step
        use crate::integrate::integrator::{ENGINE_CPU, ENGINE_GPU_KERNELS};
        if matches!(self.solver.engine(), ENGINE_CPU | ENGINE_GPU_KERNELS) {
            let (model, v) = (&self.setup.model, self.solver.velocity());
            count_motion(&mut self.tally, model, v, at.1 - t0, at);
        }
        count_failure(&mut self.tally, &self.setup.model, failure, at);
        if !e.is_finite() || e.abs() > DIVERGENCE_FACTOR * self.scale_now() {
            let reason = format!(
                "total energy {e:.6e} against {:.6e} at the start",
                self.tally.energy_initial
            );
            return Err(self.fail(at, reason));
        }
        let due = (self.scene.checkpoint_every).is_some_and(|k| (n + 1) % k == 0 || last);
        if due && !self.shortened(n) {
            self.save()?;
        }
        Ok(r.iterations)
    }

    /// The solver's step with its row and frame. The linear solver failing is the run
    /// diverging; anything else (a write, the GPU) ends it as failed, with its own error.
    fn advance(
        &mut self,
        n: usize,
    ) -> Result<(
        StepReport,
        crate::integrate::Energies,
        Option<FailureMaxima>,
    )> {
        let (model, end_time) = (&self.setup.model, self.summary.end_time);
        let last = n + 1 == self.setup.steps;
        let shortened = self.shortened(n);
        let solver = self.solver.as_mut();
        let out = &mut self.out;
        let outcome = solver.step().and_then(|r| {
            if shortened {
                solver.end_at(end_time);
            }
            let (e, failure) = write_row(solver, out)?;
            write_frame(solver, model, &mut out.frames, last)?;
            Ok((r, e, failure))
        });
        match outcome {
            Ok(x) => Ok(x),
            Err(err @ ImpactError::Solver(_)) => {
                let time = self.setup.time_after(n + 1);
                Err(self.fail((n + 1, time), err.to_string()))
            }
            Err(err) => Err(self.failed(err)),
        }
    }

    /// Ends a diverged run (see [`fail`]).
    fn fail(&mut self, at: (usize, f64), reason: String) -> ImpactError {
        // every rank of a decomposed run diverges at the same step
        self.summary.ranks = self.solver.decomposed_mut().map(|d| d.decomposition());
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
    /// rest (and this was not the last step) ends the run as interrupted. The ranks of a
    /// decomposed run stop together after the step in which any of them was signalled.
    fn interrupt(&mut self, n: usize, flag: Option<&AtomicBool>) -> Option<ImpactError> {
        let mine = flag.is_some_and(|f| f.load(Ordering::SeqCst));
        let signalled = match self.ranks {
            Some(r) => r.max(f64::from(u8::from(mine))) > 0.0,
            None => mine,
        };
        if signalled {
            // the resident engine hands out the steps it has in flight first
            if let Some(p) = self.solver.pipelined() {
                p.stop_submitting();
            }
        }
        let last = n + 1 == self.setup.steps;
        (signalled && !last && self.solver.pipelined().is_none_or(|p| p.at_rest())).then(|| {
            interrupted(
                &self.setup.model,
                self.solver.as_mut(),
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
        let written = self
            .out
            .history
            .flush()
            .and_then(|()| match self.out.writes {
                true => write_charts(self.scene, model, &self.out.dir),
                false => Ok(()),
            })
            .and_then(|()| match (self.out.writes, self.solver.cohesive_state()) {
                (true, Some(state)) => {
                    let map = crate::output::delamination::DelaminationMap::of(model, &state);
                    map.write(&self.out.dir, &self.scene.title)
                }
                _ => Ok(()),
            });
        if let Err(e) = written {
            return Err(self.failed(e));
        }
        fill_summary(&mut self.summary, &self.tally, model, self.solver.as_ref());
        self.summary.ranks = self.solver.decomposed_mut().map(|d| d.decomposition());
        self.summary.warnings = self.setup.warnings.clone();
        self.summary.warnings.extend(warnings(
            self.scene,
            model,
            &self.tally,
            self.summary.method != Method::Explicit.name(),
            &self.setup.initial,
            self.scale_now(),
        ));
        if let (Some(data), Some(d)) = (&self.setup.damage, self.solver.damage()) {
            let past =
                crate::check::crack_band::damaged_past_limit(self.scene, model, data, &d.cells);
            self.summary.warnings.extend(past);
        }
        self.summary.status = if self.summary.warnings.is_empty() {
            "completed"
        } else {
            "completed_with_warnings"
        }
        .into();
        self.summary.wall_seconds = self.start.elapsed().as_secs_f64();
        self.out.summary(&self.summary)?;
        Ok(self.summary)
    }
}
