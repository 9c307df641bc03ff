//! Sparse matrices, assembly and the Cholesky solver of the implicit path.

pub mod assembly;
pub mod cholesky;

pub use assembly::{assemble, Assembled, Csc};
pub use cholesky::SpdSolver;
