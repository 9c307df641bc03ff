//! Quantities an integrator reports after each step (the integrators' common vocabulary,
//! below them all); the state a checkpoint keeps is [`super::SolverState`].

/// What one step did.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepReport {
    /// Augmented Lagrange iterations (= linear solves) of the step.
    pub iterations: usize,
    pub converged: bool,
}

/// The probe values of one node: displacement and velocity.
pub type ProbeValues = ([f64; 3], [f64; 3]);

/// One interface at the end of a run, for the summary.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InterfaceEnd {
    /// Penalty eps_N at the end (implicit runs; the explicit paths have none).
    pub penalty_normal: Option<f64>,
    /// Penalty eps_T at the end (interfaces with friction only).
    pub penalty_tangential: Option<f64>,
    /// Energy dissipated by friction over the run.
    pub friction_work: f64,
    /// Energy the normal impulses took over the run (the explicit paths).
    pub impact_loss: Option<f64>,
    pub penalty_increases: usize,
    pub penalty_decreases: usize,
}

/// Energies of the whole model at the end of a step.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Energies {
    pub kinetic: f64,
    pub strain: f64,
    /// Potential of the constant body force (gravity): $-f_{ext} \cdot u$, less the work of
    /// the prescribed motions and of the loads.
    pub potential: f64,
    /// The energy the plies' damage and the cohesive interfaces dissipated so far.
    pub damage: f64,
    /// Of `damage`, the plies' part, with its fibre modes' share (the rest of `damage` is the
    /// cohesive interfaces').
    pub plies: crate::material::damage::Dissipation,
    /// The work the moving `[[fix]]`es did on the model so far (in `potential`; the run's
    /// energy scale grows with it).
    pub fix_work: f64,
    /// The work the `[[load]]`s did on the model so far (in `potential`; the run's energy
    /// scale grows with it too).
    pub load_work: f64,
}

impl Energies {
    /// Kinetic + strain + gravity potential + dissipated by damage: what the model had at
    /// the start and what moving supports did on it since.
    pub fn total(&self) -> f64 {
        self.kinetic + self.strain + self.potential + self.damage
    }
}

/// Where and when a ply first damaged: the time, the element (global number), the ply (of
/// its body's plies, from the lowest; none for a body without plies) and the mode.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FirstDamage {
    pub time: f64,
    pub cell: usize,
    pub ply: Option<usize>,
    pub mode: usize,
}

impl FirstDamage {
    /// The first damage at `p`, at `time` (its step's).
    pub fn of(
        model: &crate::model::Model,
        p: crate::kernels::damage_data::DamagedPoint,
        time: f64,
    ) -> Self {
        FirstDamage {
            time,
            cell: p.element,
            ply: model.ply_of(p.entry),
            mode: p.mode,
        }
    }
}

/// The damage of the state after the last step: the energy dissipated so far, the first
/// damage, and each element's acting damage by mode (the largest over its points).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DamageReport {
    pub energy: f64,
    /// Of `energy`, the fibre modes' share (the rest is the matrix modes').
    pub fibre: f64,
    pub first: Option<FirstDamage>,
    pub cells: Vec<[f64; 4]>,
}

/// One interface over one step.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactReport {
    /// Total compressive force: the step's normal impulses over the time they act
    /// ([`impulse_interval`](crate::integrate::explicit::impulse_interval) on explicit steps).
    pub normal_force: f64,
    /// Magnitude of the total friction force (impulse over the same time).
    pub tangential_force: f64,
    /// Secondary nodes carrying pressure.
    pub active: usize,
    /// Largest penetration at the end of the step (>= 0).
    pub max_penetration: f64,
    /// Secondary nodes whose traction is on the Coulomb cone (sliding).
    pub sliding: usize,
    /// Energy dissipated by friction since the start of the run.
    pub friction_work: f64,
    /// Energy the normal impulses took since the start of the run: their share of the
    /// change of the time-centred energy, $-\sum J_N (v_N(v_{n-1/2}) + v_N(v_{n+1/2}))/2$
    /// per step, as `friction_work` is the tangential impulses' (explicit steps; NaN where
    /// the engine does not measure it).
    pub impact_loss: f64,
    /// Work done on the model since the start of the run by the driver of a prescribed rigid
    /// body (the interface's contact impulses times the body's velocity); the energy
    /// balance counts it as external work.
    pub driver_work: f64,
    /// The contact force on the primary side over the last step (impulse over the same
    /// time), a vector: the force on a rigid body.
    pub force: [f64; 3],
}

/// Whether a checkpoint's state fits this model: its dof and interface counts against the
/// model's (`(checkpoint, model)` each).
pub(crate) fn check_restore(
    dofs: (usize, usize),
    interfaces: (usize, usize),
) -> std::result::Result<(), String> {
    if dofs.0 != dofs.1 || interfaces.0 != interfaces.1 {
        return Err(format!(
            "the checkpoint holds {} dofs and {} interfaces, the model {} and {}",
            dofs.0, interfaces.0, dofs.1, interfaces.1
        ));
    }
    Ok(())
}

/// How a run decomposed over ranks split the model, and what each rank spent communicating.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Decomposition {
    pub ranks: usize,
    /// How the elements were split.
    pub partition: String,
    /// How the contact is shared out.
    pub contact: String,
    /// Per rank: its elements, the nodes it holds, those it shares with other ranks, the
    /// ranks it exchanges forces with, its seconds in exchanges and collectives, its
    /// seconds in the steps' contact (its exchanges included), and the primary-face node
    /// states it received for its contact search over the run.
    pub elements: Vec<usize>,
    pub nodes: Vec<usize>,
    pub shared_nodes: Vec<usize>,
    pub neighbours: Vec<usize>,
    pub communication_seconds: Vec<f64>,
    pub contact_seconds: Vec<f64>,
    pub face_nodes_received: Vec<usize>,
}

/// A rank's piece of a decomposed run's VTU frames: its part of the model (its elements and
/// the nodes they touch, on its own node numbers), their displacements and velocities, and
/// the global number of each of its nodes.
pub struct Piece<'a> {
    pub model: &'a crate::model::Model,
    pub u: &'a [f64],
    pub v: &'a [f64],
    pub nodes: &'a [u32],
    /// The whole model's number of each of the piece's elements.
    pub elements: &'a [u32],
    /// Each of the piece's elements' damage by mode, where any material damages.
    pub damage: Option<Vec<[f64; 4]>>,
}
