//! Time integration.

pub(crate) mod constraints;
pub mod explicit;
pub mod form_trial;
pub mod implicit;
pub mod integrator;
pub mod kept_search;
pub(crate) mod loads;
pub(crate) mod reaction_columns;
pub mod recorded_sweeps;
pub mod resident;
pub mod stable_step;
pub mod state;
pub mod statics;

pub use explicit::ExplicitSolver;
pub use implicit::ImplicitSolver;
pub use integrator::{
    ContactForms, Decomposed, ImplicitFigures, Integrator, NewtonFigures, Pipelined,
};
pub use resident::ResidentSolver;
pub use state::{
    ContactReport, Decomposition, Energies, InterfaceEnd, Piece, ProbeValues, StepReport,
};
pub use statics::StaticSolver;

use serde::{Deserialize, Serialize};

use crate::model::Model;

/// The integrator's part of a checkpoint: the state of each integrator, which the folder's
/// root holds as it holds the integrators.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum SolverState {
    /// The explicit step's state (boxed: it is the largest by far).
    Explicit(Box<explicit::ExplicitState>),
    Implicit(implicit::ImplicitState),
    /// The explicit step resident on the GPU (the device's f32 state, exactly).
    Resident(resident::ResidentState),
    /// A static run's displacement, multipliers and work.
    Static(statics::StaticState),
}

/// Centre-of-mass velocity of each body from the nodal masses and velocities.
pub fn body_velocities(model: &Model, nodal_mass: &[f64], v: &[f64]) -> Vec<[f64; 3]> {
    model
        .mesh
        .bodies
        .iter()
        .map(|b| {
            let mut p = [0.0; 3];
            let mut m = 0.0;
            for n in b.nodes.clone() {
                let mn = nodal_mass[n];
                m += mn;
                for a in 0..3 {
                    p[a] += mn * v[3 * n + a];
                }
            }
            p.map(|x| x / m)
        })
        .collect()
}
