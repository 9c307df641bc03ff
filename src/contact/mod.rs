//! Node-to-surface contact: the laws and the pieces of the paper's multiplier iteration that
//! do not depend on the model. Contact code is grouped by concept, each in one place:
//!
//! - **laws** ([`law`]): what tangential force a pressed node may carry, as kinds
//!   (frictionless, Coulomb), used by every iteration and, through their WGSL twins
//!   (`shaders/shared/law_*.wgsl`), by the device kernels;
//! - **search**: the host's broad phase ([`crate::search`]), its device version
//!   ([`crate::gpu::GpuSearch`]) and their twins (`kernels::{search_bounds, search_grid,
//!   face_cells, bucket_*, contact_search}`);
//! - **kinematics**: the contact point in convected coordinates
//!   ([`crate::geometry::point::ContactPoint`]), the gap and slip-rate kernels
//!   (`kernels::{contact_gap, slip_rate}`, `shaders/{contact_gap, slip_rate}.wgsl`), and the
//!   explicit step's constraints (`kernels::contact_constraints`);
//! - **iterations**: the implicit augmented Lagrange iteration on the gap rate
//!   ([`augmented_lagrange`]: the multiplier update with the adaptive penalty of eqs. 18-20;
//!   [`friction`]: the tangential multipliers; [`anderson`]: Anderson acceleration), driven
//!   by `integrate::implicit::contact::MultiplierIteration`; and the explicit step's impulse
//!   sweeps (`kernels::impulse`, the update every path shares), driven on the host by
//!   `integrate::explicit::contact::ExplicitContact`, on the device by
//!   `gpu::impulse_sweeps::ImpulseSweeps` and on ranks by `domain::contact`.
//!
//! The drivers sit with their integrators because each holds its integrator's state (the
//! implicit solve's matrix, the explicit step's velocities, a rank's halo); the layers of
//! `docs/architecture.md` keep this module below the kernels that use its laws.

pub mod anderson;
pub mod augmented_lagrange;
pub mod friction;
pub mod law;
