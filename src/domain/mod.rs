//! The explicit path decomposed over ranks: each rank steps its share of the elements and
//! the nodes they touch, sums the forces of the nodes it shares with its neighbours, finds
//! the contacts of the secondary nodes it owns, and works the impulse sweeps on the gathered
//! contact surfaces (`docs/mpi.md`).
//!
//! - [`partition`]: recursive coordinate bisection of the elements;
//! - [`subdomain`]: a rank's elements, nodes, neighbours and shared-node sums;
//! - [`forces`]: a rank's element forces, on the CPU or on its own GPU;
//! - [`cohesive`]: a rank's cohesive pairs;
//! - [`surface`]: the contact surfaces as a model of their own;
//! - [`ranks`]: what the decomposition asks of its ranks ([`ranks::Single`], and MPI with
//!   the `mpi` feature);
//! - [`contact`]: a rank's contact: the faces its secondary nodes may reach, its own
//!   search, the contacts gathered and the sweeps;
//! - [`explicit`]: the rank's explicit solver;
//! - [`resident`]: the rank's explicit solver with the whole step on its GPU (rigid planes
//!   as the only contacts);
//! - [`checkpoint`]: a rank's part of the single process's checkpoint, both ways;
//! - [`launch`]: what an MPI launcher tells a process.

pub mod checkpoint;
mod cohesive;
pub mod contact;
pub mod explicit;
pub mod forces;
pub mod launch;
#[cfg(feature = "mpi")]
pub mod mpi;
pub mod partition;
pub mod ranks;
pub mod resident;
mod resident_contact;
pub mod subdomain;
pub mod surface;

pub use explicit::{DomainSolver, RankFigures};
pub use partition::Partition;
pub use ranks::{Ranks, Single};
pub use resident::RankResident;
