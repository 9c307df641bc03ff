//! Time integration.

pub mod implicit;
pub mod state;

pub use implicit::{ImplicitSolver, StepReport};
pub use state::{ContactReport, Energies};
