//! `impact`: a contact-impact finite-element solver implementing Duan & Ye (2002):
//! elastic hex8 bodies, node-to-surface contact in convected coordinates, implicit Newmark,
//! and contact forces from an adaptive-penalty augmented Lagrange iteration on the gap rate.
//!
//! The layout follows the flow of a run: [`scene`] (read and check) -> [`model`] (mesh,
//! constraints, interfaces) -> [`integrate`] (time loop, using [`kernels`] for element forces
//! and contact kinematics, [`linalg`] for the linear solves, [`contact`] for enforcement) ->
//! [`output`].

// Index loops over nodes, corners and components keep the CPU twins line-by-line comparable
// with their WGSL kernels (vello does the same in its CPU shaders).
#![allow(clippy::needless_range_loop)]

pub mod check;
pub mod checkpoint;
pub mod contact;
pub mod element;
pub mod error;
pub mod gpu;
pub mod integrate;
pub mod kernels;
pub mod linalg;
pub mod material;
pub mod mesh;
pub mod model;
pub mod output;
pub mod parallel;
pub mod run;
pub mod scene;
pub mod setup;
pub mod study;

pub use error::{ImpactError, Result};
