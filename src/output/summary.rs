//! `summary.json`: what the run did, in one object.

use std::path::Path;

use serde::Serialize;

use crate::error::Result;
use crate::linalg::FactorStats;

#[derive(Debug, Clone, Serialize, Default)]
pub struct InterfaceSummary {
    pub name: String,
    /// Penalty eps_N at the end of the run (implicit runs; the explicit path has none).
    pub penalty_normal_final: Option<f64>,
    /// Penalty eps_T at the end of the run (interfaces with friction only).
    pub penalty_tangential_final: Option<f64>,
    /// Energy dissipated by friction over the run.
    pub friction_work: f64,
    /// Energy the normal impulses took over the run (explicit runs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub impact_loss: Option<f64>,
    pub penalty_increases: usize,
    pub penalty_decreases: usize,
    pub peak_normal_force: f64,
}

/// One stage of a run's setup and its wall time.
#[derive(Debug, Clone, Serialize, Default)]
pub struct SetupStage {
    pub stage: String,
    pub seconds: f64,
}

/// Wall time of the setup stages, in order.
#[derive(Debug, Clone)]
pub struct SetupClock {
    start: std::time::Instant,
    last: std::time::Instant,
    stages: Vec<SetupStage>,
}

impl SetupClock {
    pub fn start() -> Self {
        let now = std::time::Instant::now();
        SetupClock {
            start: now,
            last: now,
            stages: Vec::new(),
        }
    }

    /// Ends the stage `name` (begun at the end of the one before).
    pub fn lap(&mut self, name: &str) {
        let now = std::time::Instant::now();
        self.stages.push(SetupStage {
            stage: name.into(),
            seconds: (now - self.last).as_secs_f64(),
        });
        self.last = now;
    }

    /// Seconds since the start.
    pub fn total(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    pub fn stages(&self) -> Vec<SetupStage> {
        self.stages.clone()
    }
}

#[derive(Debug, Clone, Serialize, Default)]
pub struct Summary {
    /// "completed" (every step converged, no check fired), "completed_with_warnings" (see
    /// `warnings`), "diverged", "failed" (a write or the GPU failed part way) or
    /// "interrupted".
    pub status: String,
    pub scene: String,
    pub title: String,
    pub steps: usize,
    pub wall_seconds: f64,
    /// Of `wall_seconds`, the setup before the first step (model, device, stable step,
    /// solver and uploads), with its stages in order.
    pub setup_seconds: f64,
    pub setup_stages: Vec<SetupStage>,
    pub method: String,
    /// Under `method = "auto"`: which path the rule chose and why.
    pub method_choice: Option<String>,
    pub device: String,
    /// Where the step runs: "cpu" (the f64 twins), "gpu kernels, host loop" (element and
    /// contact kernels on the GPU, the rest on the host each step: implicit runs) or "gpu
    /// resident" (every stage of the explicit step on the GPU, contact included).
    pub engine: String,
    /// `run.kinematics`: "linear" or "corotational".
    #[serde(default)]
    pub kinematics: String,
    pub time_step: f64,
    /// Explicit runs: the stable step bound of the mesh (the step is at most this).
    pub stable_time_step: Option<f64>,
    pub end_time: f64,
    pub constraint: String,
    pub penalty: String,
    pub mass: String,
    pub elements: usize,
    pub nodes: usize,
    pub free_dofs: usize,
    pub iterations_total: usize,
    pub iterations_max: usize,
    pub iterations_mean: f64,
    /// Steps whose augmented Lagrange iteration hit max_iterations.
    pub unconverged_steps: usize,
    pub factorizations: usize,
    /// Implicit runs: the ordering, size and cost of the effective matrix's factor.
    pub linear_solver: Option<FactorStats>,
    /// Implicit runs with consistent mass: the mass matrix's factor (one solve pair per
    /// multiplier iteration under the gap-rate constraint).
    pub mass_factor: Option<FactorStats>,
    /// Implicit steps taken again in `event_substeps` sub-steps at a contact event.
    pub event_steps: usize,
    /// Implicit runs with `acceleration = "newton"`: its steps, the steps that went on with
    /// Anderson's update, and the flexibility's nodes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub newton: Option<crate::integrate::NewtonFigures>,
    /// The resident engine with contact between meshed bodies: the contact sweeps recorded
    /// as dispatches of their own over the run, and the sweeps the steps needed (the rest
    /// of each step's sweeps ran in `contact_finish`). Counted by this process (a resumed
    /// run counts from its resumption).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweeps_recorded: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweeps_needed: Option<u64>,
    /// The resident engine with contact between meshed bodies: whether the contact
    /// iteration's form at the end of the run is one workgroup (`contact_zone`, no sweeps
    /// recorded) rather than staged (`contact_forms` says which forms the steps ran).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact_zone: Option<bool>,
    /// The resident engine with contact between meshed bodies: the form of the contact
    /// iteration the run's trial chose (`zone`, `relax` or `staged`: one workgroup, or staged
    /// with one or two dispatches a recorded sweep), the steps each form ran, and the
    /// trial's rounds. The results do not depend on the form.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact_forms: Option<crate::integrate::ContactForms>,
    /// The resident engine on an adapter with timestamps: the device's own time for the
    /// steps taken (each submission's compute pass, start to end).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub device_seconds: Option<f64>,
    /// The resident engine's device contact search: the sorts of the primary faces into its
    /// grid over the run (the steps in between keep the last sort while the faces have
    /// moved less than the grid's skin), and the steps whose kept grid no longer held, which
    /// tested every face of their interfaces instead. Counted by this process.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search_rebuilds: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search_stale_steps: Option<u64>,
    pub energy_initial: f64,
    pub energy_final: f64,
    pub energy_max: f64,
    /// Explicit runs: the largest departure over the run of total energy + friction work +
    /// impact loss (every contact's) from `energy_initial`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy_balance: Option<f64>,
    /// With ply strengths: the largest of each failure index over the run, by name
    /// (`material::failure::INDICES`); absent where the engine does not survey every step
    /// (the resident GPU step, MPI ranks).
    /// An index that overflows a double is written `"inf"`, as the history writes it (JSON
    /// has no infinity).
    #[serde(
        skip_serializing_if = "Option::is_none",
        serialize_with = "indices_as_written"
    )]
    pub failure_index_max: Option<std::collections::BTreeMap<String, f64>>,
    /// With ply strengths: where and when a failure index first reached 1 (null if none
    /// did).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub first_failure: Option<Option<crate::output::failure_survey::FirstFailure>>,
    /// With ply damage or cohesive interfaces: the energy they dissipated over the run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damage_energy: Option<f64>,
    /// With ply damage or cohesive interfaces: `damage_energy` by kind.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damage_energy_by_kind: Option<DamageByKind>,
    /// With `[[load]]`s: the work they did over the run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub external_work: Option<f64>,
    /// With ply damage: where and when a ply first damaged (null if none did).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub first_damage: Option<Option<FirstDamageSummary>>,
    /// With cohesive interfaces: the projected separated area and each interface's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delamination: Option<crate::output::delamination::DelaminationSummary>,
    pub interfaces: Vec<InterfaceSummary>,
    /// What made the result doubtful (empty when `status = "completed"`).
    pub warnings: Vec<crate::check::Warning>,
    /// Every interface at t = 0: gap range, penetrating nodes, what was done about them.
    pub initial_contact: Vec<crate::check::penetration::InitialContact>,
    /// The lower-bound host memory estimate checked before the model was built.
    pub memory_estimate_bytes: u64,
    /// A run decomposed over MPI ranks: the partition and each rank's communication.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ranks: Option<crate::integrate::Decomposition>,
    pub message: Option<String>,
}

/// The energy damage dissipated by kind: the plies' fibre modes (tension and compression),
/// their matrix modes, and the cohesive interfaces (by damage and by the friction of their
/// separated faces).
#[derive(Debug, Clone, Copy, Default, Serialize, PartialEq)]
pub struct DamageByKind {
    pub fibre: f64,
    pub matrix: f64,
    pub interfaces: f64,
}

/// Where and when a ply first damaged: the time, the cell (global element number) and its
/// body, the ply (of the body's plies, from the lowest; none without plies) and the mode
/// (`material::damage::MODES`) with the most damage there.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FirstDamageSummary {
    pub time: f64,
    pub cell: usize,
    pub body: String,
    pub ply: Option<usize>,
    pub mode: String,
}

/// The room the first summary of a run reserves in its file (four times its own length
/// where that is more), so that the last one can be written over it on a full disk.
const RESERVE: usize = 64 * 1024;

impl Summary {
    fn text(&self) -> String {
        serde_json::to_string_pretty(self).expect("summary serialises") + "\n"
    }

    /// Writes `summary.json` whole (through a temporary file). Where that fails (a full
    /// disk), the summary is written over the file's own room instead, which the run's first
    /// summary reserved ([`Self::write_reserving`]); the error is the first failure's where
    /// that fails too.
    pub fn write(&self, dir: &Path) -> Result<()> {
        let path = dir.join("summary.json");
        let text = self.text();
        super::file::write_whole(&path, text.as_bytes())
            .or_else(|e| super::file::write_over(&path, text.as_bytes()).map_err(|_| e))
    }

    /// [`Self::write`] with trailing blanks that reserve the file's room for the summaries
    /// after it (JSON reads past them).
    pub fn write_reserving(&self, dir: &Path) -> Result<()> {
        let mut text = self.text();
        let room = RESERVE.max(4 * text.len());
        text.extend(std::iter::repeat_n(' ', room - text.len()));
        super::file::write_whole(&dir.join("summary.json"), text.as_bytes())
    }
}

/// Failure indices as numbers, those that are not finite as the history's text (`inf`).
fn indices_as_written<S: serde::Serializer>(
    indices: &Option<std::collections::BTreeMap<String, f64>>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    let as_written = |x: f64| match x.is_finite() {
        true => serde_json::json!(x),
        false => serde_json::json!(x.to_string()),
    };
    let map: Option<std::collections::BTreeMap<&String, serde_json::Value>> =
        (indices.as_ref()).map(|m| m.iter().map(|(k, v)| (k, as_written(*v))).collect());
    serde::Serialize::serialize(&map, s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failure_index_that_overflows_is_written_as_the_history_writes_it() {
        let indices = [("fibre_tension", f64::INFINITY), ("matrix_tension", 0.5)];
        let summary = Summary {
            failure_index_max: Some(indices.map(|(k, v)| (k.to_string(), v)).into()),
            ..Default::default()
        };
        let json: serde_json::Value = serde_json::to_value(&summary).unwrap();
        let m = &json["failure_index_max"];
        assert_eq!(m["fibre_tension"], serde_json::json!("inf"));
        assert_eq!(m["matrix_tension"], serde_json::json!(0.5));
    }

    /// Where the whole write fails (here a folder where its temporary file must go; on a
    /// full disk, no room for it), the last summary goes over the room the first reserved.
    #[test]
    fn the_last_summary_fits_the_room_the_first_reserved() {
        let dir = std::env::temp_dir().join(format!("impact-summary-room-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let running = Summary {
            status: "running".into(),
            ..Default::default()
        };
        running.write_reserving(&dir).unwrap();
        std::fs::create_dir_all(dir.join(".summary.json.tmp")).unwrap();
        let failed = Summary {
            status: "failed".into(),
            steps: 1234,
            message: Some("after step 1234: no space left on device".into()),
            ..Default::default()
        };
        failed.write(&dir).unwrap();
        let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        let json: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(json["status"], "failed");
        assert_eq!(json["steps"], 1234);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
