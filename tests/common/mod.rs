//! Helpers shared by the integration tests, by topic; everything is re-exported here.
#![allow(dead_code, unused_imports)]

pub mod bench_scenes;
pub mod ccx;
pub mod cli;
pub mod gpu;
pub mod history;
pub mod im7;
pub mod loads;
pub mod meshio;
pub mod random;
pub mod scenes;
pub mod source;
pub mod waves;

pub use bench_scenes::*;
pub use ccx::*;
pub use cli::*;
pub use gpu::*;
pub use history::*;
pub use loads::*;
pub use meshio::*;
pub use random::*;
pub use scenes::*;
pub use waves::*;
