//! What a run writes as it goes: its folder, the history, the VTU frames and the checkpoints.

use std::path::{Path, PathBuf};

use super::lock::FolderLock;
use super::RunOptions;
use crate::checkpoint::{Checkpoint, Tally};
use crate::error::{ImpactError, Result};
use crate::integrate::Integrator;
use crate::integrate::SolverState;
use crate::model::Model;
use crate::output::failure_survey::{FailureMaxima, FailureSurvey};
use crate::output::vtu::{NodeContact, VtuWriter};
use crate::output::History;
use crate::scene::Scene;
use crate::setup::Setup;

/// The files an earlier run leaves in its folder; a new run refuses a folder holding any of
/// them unless told to overwrite or resume.
pub const RUN_FILES: [&str; 3] = ["summary.json", "history.csv", "checkpoint.bin"];

/// Creates the folder (a resumed run's must exist) and takes its lock, then refuses it if it
/// holds an earlier run's files (unless `--overwrite` or `--resume`). The lock is held until
/// the returned guard is dropped, at the run's end.
pub(super) fn prepare_dir(dir: &Path, opts: &RunOptions) -> Result<FolderLock> {
    if opts.resume && !dir.is_dir() {
        return Err(ImpactError::Resume {
            dir: dir.to_path_buf(),
            message: "the folder does not exist".into(),
        });
    }
    if let Some(target) = std::fs::read_link(dir).ok().filter(|_| !dir.exists()) {
        return Err(ImpactError::Write {
            path: dir.to_path_buf(),
            source: std::io::Error::other(format!(
                "it is a symbolic link to {}, which does not exist",
                target.display()
            )),
        });
    }
    std::fs::create_dir_all(dir).map_err(|source| ImpactError::Write {
        path: dir.to_path_buf(),
        source,
    })?;
    let lock = FolderLock::acquire(dir)?;
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
    Ok(lock)
}

/// The outputs a run writes as it goes.
pub(super) struct Outputs {
    pub(super) dir: PathBuf,
    /// The VTU frames' file-name stem (kept across a resume).
    pub(super) stem: String,
    pub(super) history: History,
    pub(super) frames: Option<(usize, VtuWriter)>,
    /// The ply failure indices of every row (materials with strengths, on the engines that
    /// hold the displacement of every step on the host: one process, CPU or device kernels).
    pub(super) failure: Option<FailureSurvey>,
    /// Whether this process writes the files (every rank but the first of a decomposed run
    /// computes the rows with the others and writes nothing).
    pub(super) writes: bool,
}

impl Outputs {
    /// Writes the summary, where this process writes the files.
    pub(super) fn summary(&self, summary: &crate::output::Summary) -> Result<()> {
        match self.writes {
            true => summary.write(&self.dir),
            false => Ok(()),
        }
    }

    /// Writes the run's first summary, reserving the room its last one needs on a full disk.
    pub(super) fn first_summary(&self, summary: &crate::output::Summary) -> Result<()> {
        match self.writes {
            true => summary.write_reserving(&self.dir),
            false => Ok(()),
        }
    }
}

/// Starts a new run's outputs (the t = 0 row and frame) and its tally.
pub(super) fn start_fresh(
    scene: &Scene,
    model: &Model,
    solver: &mut dyn Integrator,
    dir: &Path,
    rank: Option<(usize, usize)>,
) -> Result<(Outputs, Tally)> {
    let writes = rank.is_none_or(|(r, _)| r == 0);
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
        history: match writes {
            true => History::create(dir, model)?,
            false => History::discard(model),
        },
        frames: scene.vtu_every.map(|every| {
            let stem = frame_stem(scene);
            let w = match rank {
                Some((r, ranks)) => VtuWriter::pieces(dir, &stem, r, ranks),
                None => VtuWriter::new(dir, &stem),
            };
            (every, w)
        }),
        failure: failure_survey(model, solver, rank),
        writes,
    };
    let (_, failure) = write_row(solver, &mut out)?;
    write_frame(solver, model, &mut out.frames, false)?;
    let n = model.interfaces.len();
    let tally = Tally {
        energy_initial: e0.total(),
        energy_final: e0.total(),
        energy_max: e0.total(),
        peak_force: vec![0.0; n],
        deepest: vec![(0.0, 0, 0.0); n],
        fastest: vec![(0.0, 0, 0.0); n],
        ..Default::default()
    };
    let mut tally = tally;
    count_failure(&mut tally, model, failure, (0, 0.0));
    Ok((out, tally))
}

/// Continues a run's outputs and tally from a checkpoint (the history and the frame
/// collection cut back to its step); `rank` as for [`start_fresh`].
pub(super) fn start_resumed(
    scene: &Scene,
    model: &Model,
    solver: &mut dyn Integrator,
    dir: &Path,
    (c, rank): (Checkpoint, Option<(usize, usize)>),
) -> Result<(Outputs, Tally)> {
    let refuse = |message: String| ImpactError::Resume {
        dir: dir.to_path_buf(),
        message,
    };
    solver.restore(c.solver).map_err(refuse)?;
    let writes = rank.is_none_or(|(r, _)| r == 0);
    let out = Outputs {
        dir: dir.to_path_buf(),
        stem: c.frame_stem.clone(),
        history: match writes {
            true => History::resume(dir, model, c.tally.steps + 1, solver.time())?,
            false => History::discard(model),
        },
        frames: (scene.vtu_every).map(|every| {
            (
                every,
                VtuWriter::resume(dir, &c.frame_stem, &c.frames, rank),
            )
        }),
        failure: failure_survey(model, solver, rank),
        writes,
    };
    Ok((out, c.tally))
}

/// Refuses a checkpoint the run cannot continue from, before anything in the folder changes:
/// one at or past the scene's last step, one taken with another step length (the stable
/// step found on another device), or on `ranks` one of the GPU resident engine where the
/// ranks do not run resident on their GPUs.
pub(super) fn check_resumable(
    dir: &Path,
    c: &Checkpoint,
    (setup, device): (&Setup, &str),
    ranks: Option<usize>,
) -> Result<()> {
    let refuse = |message: String| ImpactError::Resume {
        dir: dir.to_path_buf(),
        message,
    };
    use crate::integrate::resident::{needs_host_ranks, rigid_surfaces_on_device};
    let model = &setup.model;
    let resident_ranks =
        setup.ctx.is_some() && rigid_surfaces_on_device(model) && !needs_host_ranks(model);
    if let (Some(p), SolverState::Resident(_), false) = (ranks, &c.solver, resident_ranks) {
        return Err(refuse(format!(
            "the checkpoint holds the GPU resident engine's device state, which resumes on one process, or on ranks each resident on its GPU (a model whose only contacts are rigid planes), on the same kind of adapter, not on {p} ranks on this device"
        )));
    }
    let kind = |d: &str| match d {
        "cpu" => "the CPU (f64)",
        _ => "a GPU (f32)",
    };
    if kind(&c.device) != kind(device) {
        return Err(refuse(format!(
            "the checkpoint was written on {} ({}) and this run computes on {} ({device}): its history would change precision part way; resume with the first run's --device",
            kind(&c.device),
            c.device,
            kind(device)
        )));
    }
    let (steps, time, dt) = match &c.solver {
        SolverState::Explicit(s) => (s.steps, s.time, Some(s.dt)),
        SolverState::Implicit(s) => (s.steps, s.time, None),
        SolverState::Static(s) => (s.steps, s.time, None),
        SolverState::Resident(s) => (s.steps, s.time, Some(s.dt)),
    };
    if steps >= setup.steps {
        return Err(refuse(format!(
            "the checkpoint is at step {steps} (t = {time:.6e}) and the scene ends at step {}: nothing is left to run (raise run.end_time)",
            setup.steps
        )));
    }
    // the step the checkpoint's stage takes (its last step's)
    let own = setup.step_at(steps.saturating_sub(1));
    if let Some(dt) = dt.filter(|dt| (dt - own).abs() > 1e-12 * own) {
        return Err(refuse(format!(
            "the checkpoint's step is {dt:e} and this run's {own:e} (the stable step was found on another device): resume with the first run's --device"
        )));
    }
    check_tally(c, (steps, time), setup).map_err(refuse)
}

/// The checkpoint's tally against its solver state and the model: the same step count, a
/// time that is that many steps, one entry per interface, finite energies. (The checksum
/// catches a damaged file; this catches a whole file whose parts disagree.)
fn check_tally(
    c: &Checkpoint,
    (steps, time): (usize, f64),
    setup: &Setup,
) -> std::result::Result<(), String> {
    let t = &c.tally;
    if t.steps != steps {
        return Err(format!(
            "its tally counts {} steps and its solver state {steps}",
            t.steps
        ));
    }
    let expected = setup.time_after(steps);
    if !time.is_finite() || (time - expected).abs() > 1e-6 * expected.max(setup.dt) {
        return Err(format!(
            "its time {time:e} is not the run's time after {steps} steps ({expected:e})"
        ));
    }
    let n = setup.model.interfaces.len();
    if t.peak_force.len() != n || t.deepest.len() != n {
        return Err(format!(
            "its tally holds {} interfaces and the model {n}",
            t.peak_force.len()
        ));
    }
    let energies = [t.energy_initial, t.energy_final, t.energy_max];
    if energies.iter().any(|e| !e.is_finite()) || t.iterations_max > t.iterations_total {
        return Err("its tally's energies or iteration counts are not a run's".into());
    }
    Ok(())
}

/// Writes the checkpoint of the solver's current state (a decomposed run's every rank
/// gathers it; the rank that writes the files writes it). The history is flushed first, so
/// that the file holds every row the checkpoint counts whatever happens to the process
/// afterwards.
pub(super) fn save(
    solver: &mut dyn Integrator,
    out: &mut Outputs,
    tally: &Tally,
    run: &RunIdentity,
) -> Result<()> {
    let Some(state) = solver.checkpoint_state()? else {
        return Ok(());
    };
    out.history.flush()?;
    Checkpoint {
        format: crate::checkpoint::FORMAT,
        scene_hash: run.scene_hash,
        speed_scale: run.speed_scale,
        tally: tally.clone(),
        frames: (out.frames.as_ref())
            .map(|(_, w)| w.written().to_vec())
            .unwrap_or_default(),
        frame_stem: out.stem.clone(),
        solver: state,
        device: solver.device_name(),
    }
    .write(&out.dir)
}

/// What a checkpoint records of the run itself: the scene's hash (computed once) and the
/// speed scale its tolerances follow.
pub(super) struct RunIdentity {
    pub(super) scene_hash: u64,
    pub(super) speed_scale: f64,
}

/// Appends the current state's row; returns the energies and the state's failure indices
/// (where surveyed).
pub(super) fn write_row(
    solver: &mut dyn Integrator,
    out: &mut Outputs,
) -> Result<(crate::integrate::Energies, Option<FailureMaxima>)> {
    let e = solver.energies()?;
    let contacts = solver.reports();
    let probes = solver.probes();
    let failure = failure_maxima(out, solver);
    out.history.row(
        solver.time(),
        solver.steps(),
        &e,
        (&solver.body_velocities(), &contacts, &probes),
        (
            &solver.body_spins(),
            failure.as_ref().map(|f| &f.max),
            &solver.reactions(),
            &solver.cohesive(),
        ),
    )?;
    Ok((e, failure))
}

/// The state's failure indices: the survey's on one process; on ranks each rank's piece,
/// gathered on every rank (a collective: every rank calls it).
fn failure_maxima(out: &Outputs, solver: &dyn Integrator) -> Option<FailureMaxima> {
    let survey = out.failure.as_ref()?;
    if let Some(r) = solver.failure_record() {
        return Some(survey.of_record(solver.model(), &r));
    }
    Some(match solver.decomposed() {
        Some(d) => {
            let p = d.piece();
            let mine = survey.maxima(p.model, p.u).values();
            FailureMaxima::of_ranks(&d.gather_all(&mine))
        }
        None => survey.maxima(solver.model(), solver.displacement()),
    })
}

/// The failure survey of a model with ply strengths, on one process (the CPU, the device's
/// element forces with the host's loop, or the resident step, which surveys on the device
/// and whose records the survey locates), or each rank's piece.
fn failure_survey(
    model: &Model,
    solver: &dyn Integrator,
    rank: Option<(usize, usize)>,
) -> Option<FailureSurvey> {
    use crate::integrate::integrator::{ENGINE_CPU, ENGINE_GPU_KERNELS, ENGINE_GPU_RESIDENT};
    let engine = solver.engine();
    if let Some(d) = solver.decomposed() {
        // resident ranks survey on their devices and merge their records: the model's
        // survey locates the worst point
        if engine == ENGINE_GPU_RESIDENT {
            return FailureSurvey::new(model);
        }
        let p = d.piece();
        return FailureSurvey::of_piece(p.model, p.elements);
    }
    let engines = [ENGINE_CPU, ENGINE_GPU_KERNELS, ENGINE_GPU_RESIDENT];
    let surveyed = rank.is_none() && engines.contains(&engine);
    surveyed.then(|| FailureSurvey::new(model)).flatten()
}

/// Counts a row's failure indices in the tally: their largest values, and where and when
/// one first reached 1.
pub(super) fn count_failure(
    tally: &mut Tally,
    model: &Model,
    failure: Option<FailureMaxima>,
    at: (usize, f64),
) {
    let Some(m) = failure else {
        return;
    };
    let max = tally.failure_max.get_or_insert([0.0; 5]);
    for (a, b) in max.iter_mut().zip(m.max) {
        *a = a.max(b);
    }
    if tally.first_failure.is_none() {
        tally.first_failure = m.first_failure(model, at);
    }
}

/// Writes a VTU frame on every `every`-th step, and on the last step (`last`) whatever its
/// number.
pub(super) fn write_frame(
    solver: &dyn Integrator,
    model: &Model,
    frames: &mut Option<(usize, VtuWriter)>,
    last: bool,
) -> Result<()> {
    if let Some((every, w)) = frames {
        if solver.steps() % *every == 0 || last {
            let (step, time) = (solver.steps(), solver.time());
            let contact = node_contact(solver);
            match solver.decomposed().map(|d| d.piece()) {
                Some(p) => {
                    let mine: Vec<NodeContact> =
                        p.nodes.iter().map(|&n| contact[n as usize]).collect();
                    let frame = (p.model, Some(p.nodes));
                    w.frame(frame, step, time, p.u, p.v, (&mine, p.damage.as_deref()))?;
                }
                None => {
                    let (u, v) = (solver.displacement(), solver.velocity());
                    let damage = solver.damage().map(|d| d.cells);
                    let cells = (&contact[..], damage.as_deref());
                    w.frame((model, None), step, time, u, v, cells)?;
                }
            }
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

/// Contact pressure (summed) and gap (the largest) of every node, for VTU frames.
fn node_contact(solver: &dyn Integrator) -> Vec<NodeContact> {
    let model = solver.model();
    let mut out = vec![NodeContact::default(); model.mesh.node_count()];
    for (k, itf) in model.interfaces.iter().enumerate() {
        for (i, &n) in itf.nodes.iter().enumerate() {
            let (pressure, gap) = solver.node_contact(k, i);
            let c = &mut out[n as usize];
            c.pressure += pressure;
            if gap.is_finite() && (c.gap.is_nan() || gap > c.gap) {
                c.gap = gap;
            }
        }
    }
    if let Some(state) = solver.cohesive_state() {
        for (c, d) in model.cohesive.iter().zip(&state.damage) {
            let nodes = c.pairs.upper.iter().zip(&c.pairs.lower);
            for ((&a, &b), &d) in nodes.zip(d) {
                for n in [a, b] {
                    let c = &mut out[n as usize].cohesive_damage;
                    *c = if c.is_nan() { d } else { c.max(d) };
                }
            }
        }
    }
    out
}
