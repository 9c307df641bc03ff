//! Sparse matrices, assembly, fill-reducing orderings and the Cholesky solver of the implicit
//! path.

pub mod assembly;
pub mod cholesky;
pub mod ordering;
pub mod supernodal_solve;

pub use assembly::{assemble, Assembled, Csc};
pub use cholesky::{FactorStats, SpdSolver};
pub use ordering::Ordering;
