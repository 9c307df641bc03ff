//! What a run asks of an integrator, whichever it is: the implicit Newmark solver, the
//! explicit central-difference solver with its step on the host, or the explicit step
//! resident on the GPU. The run loop holds a `Box<dyn Integrator>` and nothing more.

use super::state::{
    ContactReport, DamageReport, Decomposition, Energies, InterfaceEnd, Piece, ProbeValues,
    StepReport,
};
use super::SolverState;
use crate::error::Result;
use crate::linalg::FactorStats;
use crate::model::Model;
use crate::scene::Method;

/// The engine names of the summary's `engine`.
pub(crate) const ENGINE_CPU: &str = "cpu";
pub(crate) const ENGINE_GPU_KERNELS: &str = "gpu kernels, host loop";
pub(crate) const ENGINE_GPU_RESIDENT: &str = "gpu resident";
pub(crate) const ENGINE_RANKS: &str = "cpu, decomposed over mpi ranks";
pub(crate) const ENGINE_RANKS_GPU: &str = "gpu kernels, decomposed over mpi ranks";

/// The implicit contact iteration's Newton steps (`implicit.acceleration = "newton"`), for
/// the summary; counted by this process (a resumed run counts from its resumption).
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct NewtonFigures {
    /// Newton steps taken as the multiplier update.
    pub steps: usize,
    /// Steps and sub-steps that went on with Anderson's update: their Newton steps stopped
    /// bringing the residual down, or their candidates touched more nodes than a
    /// flexibility holds.
    pub steps_left: usize,
    /// Nodes in the flexibilities (the step's and the sub-step's): each costs three
    /// columns, solved in blocks of 16 nodes on the contact space.
    pub flexibility_nodes: usize,
    /// Iterations that moved the contact nodes by the flexibility's columns alone, without
    /// a solve (no contact space, f64 kernels, the trapezoidal rule, no friction).
    pub flexibility_moves: usize,
    /// An interface has friction, so every update is Anderson's.
    pub friction_keeps_anderson: bool,
}

/// The resident step's forms of the device contact iteration over a run, for the summary
/// (`contact_forms`; counted by this process).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactForms {
    /// The form the run's trial chose last (`zone`, `relax` or `staged`), or the one fixed.
    pub chosen: String,
    /// Steps each form ran, by name.
    pub steps: std::collections::BTreeMap<String, u64>,
    /// The trial's rounds (none without timestamps on the adapter, or with one form).
    pub rounds: usize,
}

/// The implicit solver's linear-algebra figures for the summary.
#[derive(Debug, Clone)]
pub struct ImplicitFigures {
    pub factorizations: usize,
    /// The effective matrix's factor over all step sizes.
    pub linear_solver: FactorStats,
    /// The consistent mass matrix's factor (None with lumped mass).
    pub mass_factor: Option<FactorStats>,
    /// Steps taken again in sub-steps because they held a contact event.
    pub event_steps: usize,
    /// With `acceleration = "newton"`: its steps.
    pub newton: Option<NewtonFigures>,
}

pub trait Integrator {
    fn model(&self) -> &Model;
    fn method(&self) -> Method;
    /// The adapter the kernels run on ("cpu" without one).
    fn device_name(&self) -> String;

    /// One step.
    fn step(&mut self) -> Result<StepReport>;
    /// Energies of the state after the last step (before the first: the initial state).
    fn energies(&mut self) -> Result<Energies>;
    /// Each interface over the last step.
    fn reports(&self) -> Vec<ContactReport>;
    /// Contact pressure and gap of secondary point `point` of interface `interface` at the
    /// last state (the gap is not finite where no surface is in reach).
    fn node_contact(&self, interface: usize, point: usize) -> (f64, f64);

    fn time(&self) -> f64;
    /// Steps taken.
    fn steps(&self) -> usize;
    /// Displacement of every dof at the last state read (every step on the host; every
    /// frame on the resident GPU path). A rank of a decomposed run has its own nodes' only
    /// (see [`Integrator::piece`]).
    fn displacement(&self) -> &[f64];
    /// Velocity, as [`Integrator::displacement`].
    fn velocity(&self) -> &[f64];
    /// The lumped mass of every node of the whole model (on every rank of a decomposed run).
    fn nodal_mass(&self) -> &[f64];

    /// The state a checkpoint keeps; `None` on a process that writes no checkpoint (a rank
    /// of a decomposed run other than the first, which gathers the state).
    fn checkpoint_state(&mut self) -> Result<Option<SolverState>>;
    /// Continues from a checkpoint's state (of this model and integrator).
    fn restore(&mut self, state: SolverState) -> std::result::Result<(), String>;

    fn engine(&self) -> &'static str {
        if self.device_name() == "cpu" {
            ENGINE_CPU
        } else {
            ENGINE_GPU_KERNELS
        }
    }

    /// Centre-of-mass velocity of each body.
    fn body_velocities(&self) -> Vec<[f64; 3]> {
        super::body_velocities(self.model(), self.nodal_mass(), self.velocity())
    }

    /// Displacement and velocity of every probe node after the last step.
    fn probes(&self) -> Vec<ProbeValues> {
        let (u, v) = (self.displacement(), self.velocity());
        let at = |x: &[f64], d: usize| [x[d], x[d + 1], x[d + 2]];
        (self.model().probes.iter())
            .map(|p| (at(u, 3 * p.node as usize), at(v, 3 * p.node as usize)))
            .collect()
    }

    /// Each rotating rigid body's rotation vector (axis times angle) and angular velocity
    /// (none on the engines that refuse rotating bodies).
    fn body_spins(&self) -> Vec<ProbeValues> {
        Vec::new()
    }

    /// Each named `[[fix]]`'s reaction after the last step (NaN in the history where an
    /// engine gives none).
    fn reactions(&self) -> Vec<[f64; 3]> {
        Vec::new()
    }

    /// The plies' damage after the last step, where any material damages.
    fn damage(&self) -> Option<DamageReport> {
        None
    }

    /// Each cohesive interface after the last step (none on the engines without them).
    fn cohesive(&self) -> Vec<crate::kernels::cohesive_forces::CohesiveReport> {
        Vec::new()
    }

    /// The cohesive interfaces' damage and dissipation, where the model has any.
    fn cohesive_state(&self) -> Option<crate::kernels::cohesive_forces::CohesiveState> {
        None
    }

    /// Each interface at the end of the run (no penalties: the explicit paths).
    fn interface_ends(&self) -> Vec<InterfaceEnd> {
        (self.reports().iter())
            .map(|r| InterfaceEnd {
                friction_work: r.friction_work,
                impact_loss: Some(r.impact_loss).filter(|x| !x.is_nan()),
                ..Default::default()
            })
            .collect()
    }

    /// The implicit solver's factorisations and solves.
    fn implicit_figures(&self) -> Option<ImplicitFigures> {
        None
    }

    /// The resident step's device contact iteration: the sweeps recorded as dispatches of
    /// their own and the sweeps needed, over the steps taken.
    fn recorded_sweeps(&self) -> Option<(u64, u64)> {
        None
    }

    /// The resident step's device contact iteration: whether it runs in one workgroup
    /// (`contact_zone`) rather than staged.
    fn contact_zone(&self) -> Option<bool> {
        None
    }

    /// The resident step's device contact iteration: the form its trial chose, the steps
    /// each form ran and the trial's rounds ([`super::form_trial::FormTrial`]).
    fn contact_forms(&self) -> Option<ContactForms> {
        None
    }

    /// The device's own time for the steps taken (the resident step, where the adapter has
    /// timestamps).
    fn device_seconds(&self) -> Option<f64> {
        None
    }

    /// The resident step's device contact search: the sorts of the faces into its grid and
    /// the steps whose kept grid no longer held (they tested every face), over the steps
    /// taken.
    fn search_rebuilds(&self) -> Option<(u64, u64)> {
        None
    }

    /// The device's ply failure record of the last step (the resident step surveys every
    /// step itself: [`crate::kernels::failure_reduce`]'s record); `None` where the host
    /// surveys the state.
    fn failure_record(&self) -> Option<[f64; crate::kernels::FAILURE_FIELDS]> {
        None
    }

    /// Makes the next step `dt` long (the shortened last step).
    fn shorten_step(&mut self, _dt: f64) {}

    /// At the start of a `[[step]]` that changed the model: the state's acceleration made
    /// the one the new model gives (the explicit and static paths keep none between steps).
    fn begin_step(&mut self) -> Result<()> {
        Ok(())
    }

    /// The stage this integrator steps starts after the run's step `steps`, at `time`:
    /// its clock counts its steps from there (the static and implicit paths time a step by
    /// the steps taken).
    fn start_stage_at(&mut self, _steps: usize, _time: f64) {}

    /// At the start of a `[[step]]` of another method: goes on from the state `from` hands
    /// on, its total energy kept ([`Handover`]).
    fn take_over(&mut self, _from: &Handover) -> Result<()> {
        Err(crate::error::ImpactError::Solver(format!(
            "the {} engine cannot go on from a step of another method",
            self.engine()
        )))
    }

    /// Puts the clock exactly on `time` after the shortened last step.
    fn end_at(&mut self, _time: f64) {}

    /// The integrator as one whose steps run ahead of the host, if it is.
    fn pipelined(&mut self) -> Option<&mut dyn Pipelined> {
        None
    }

    /// The integrator as a rank of a decomposed run, if it is.
    fn decomposed(&self) -> Option<&dyn Decomposed> {
        None
    }

    /// [`Self::decomposed`], mutably.
    fn decomposed_mut(&mut self) -> Option<&mut dyn Decomposed> {
        None
    }
}

/// What a stage of one method hands to the next stage's of another (a preload, then an
/// impact): its clock and step count, the displacement, the velocity a dynamic stage goes on
/// with, the work the fixes and loads did, and the total energy of the history.
#[derive(Debug, Clone)]
pub struct Handover {
    pub time: f64,
    pub steps: usize,
    pub u: Vec<f64>,
    /// The velocity to go on with: a dynamic stage's; none after static stages where no
    /// dynamic stage came before (the new stage starts with the run's initial velocities,
    /// their kinetic energy counted as work done on the model).
    pub v: Option<Vec<f64>>,
    pub fix_work: f64,
    pub load_work: f64,
    pub energy: f64,
}

impl Handover {
    /// Puts the handed velocity into `v` on the dofs `fixed` leaves free (a held dof keeps
    /// its own); where none is handed on, `v` keeps the run's initial velocities, and their
    /// kinetic energy with the nodal masses `mass` is returned: the work of giving them.
    pub fn velocity_into(&self, fixed: &[bool], mass: &[f64], v: &mut [f64]) -> f64 {
        let Some(handed) = &self.v else {
            return (v.iter().enumerate())
                .map(|(d, x)| 0.5 * mass[d / 3] * x * x)
                .sum();
        };
        for (d, x) in v.iter_mut().enumerate() {
            if !fixed[d] {
                *x = handed[d];
            }
        }
        0.0
    }

    /// The state `from` has after its last step, with the velocity `v`.
    pub fn of(from: &mut dyn Integrator, v: Option<Vec<f64>>) -> Result<Handover> {
        let e = from.energies()?;
        Ok(Handover {
            time: from.time(),
            steps: from.steps(),
            u: from.displacement().to_vec(),
            v,
            fix_work: e.fix_work,
            load_work: e.load_work,
            energy: e.total(),
        })
    }
}

/// An integrator whose steps run ahead of the host (the resident GPU step): the run plans
/// its submissions, stops them on a signal and waits until it is at rest.
pub trait Pipelined {
    /// The run's shortened last step and checkpoint interval, before the first step.
    fn schedule(&mut self, last_step: Option<f64>, checkpoint_every: Option<usize>);
    /// Submits no more device work.
    fn stop_submitting(&mut self);
    /// Whether the state of the last step handed out is all there is (nothing in flight).
    fn at_rest(&self) -> bool;
}

/// A rank of a run decomposed over ranks.
pub trait Decomposed {
    /// The rank's piece of the frames (its `displacement` and `velocity` are its own
    /// nodes').
    fn piece(&self) -> Piece<'_>;
    /// How the run is decomposed, and each rank's communication time. Every rank calls it at
    /// the end of a run (it may gather from the others).
    fn decomposition(&mut self) -> Decomposition;
    /// Every rank's `mine`, in rank order, on every rank (a collective).
    fn gather_all(&self, mine: &[f64]) -> Vec<Vec<f64>>;
}

/// The message of a checkpoint written by another integrator.
pub(crate) fn other_integrator() -> String {
    "the checkpoint was written by another integrator than this run's".into()
}
