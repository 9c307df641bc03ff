//! Sparse matrices, assembly, fill-reducing orderings and the Cholesky solver of the implicit
//! path.

pub mod assembly;
pub mod cholesky;
pub mod contact_space;
pub mod dense;
pub mod ordering;
pub mod supernodal_solve;
#[cfg(test)]
pub(crate) mod test_matrices;

pub use assembly::{assemble, Assembled, Csc};
pub use cholesky::{FactorStats, SpdAnalysis, SpdSolver};
pub use ordering::Ordering;
