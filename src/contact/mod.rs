//! Node-to-surface contact enforcement. The interfaces are data ([`crate::model::Interface`]),
//! the primary face in convected coordinates is geometry ([`crate::geometry::face`]).
//!
//! - [`search`]: broad phase (candidate primary faces of each secondary node).
//! - [`augmented_lagrange`]: the paper's multiplier update on the gap rate with the
//!   adaptive penalty of eqs. 18-20.
//! - [`anderson`]: Anderson acceleration of that iteration.
//! - [`friction`]: Coulomb stick and slip in the same iteration (tangential multipliers with
//!   their own adaptive penalty, return mapping onto the friction cone).
//! - the kinematics kernels themselves live in [`crate::kernels`] (CPU twins) and
//!   [`crate::gpu`] (WGSL).

pub mod anderson;
pub mod augmented_lagrange;
pub mod friction;
pub mod search;
