//! `impact`: a contact-impact finite-element solver implementing Duan & Ye (2002):
//! elastic hex8, hex8i and tet4 bodies, node-to-surface contact in convected coordinates, implicit Newmark,
//! and contact forces from an adaptive-penalty augmented Lagrange iteration on the gap rate.
//!
//! The modules form one-way layers, each using only those before it (checked by
//! `tests/layers.rs`; `docs/architecture.md` walks through them):
//!
//! 1. [`error`], [`limits`], [`parallel`], [`material`]: errors, what the process may use and
//!    read, ordered parallel loops, elastic constants;
//! 2. [`geometry`]: vectors, bilinear quads, closest-point projection, the contact point;
//! 3. [`element`], [`mesh`], [`scene`]: element matrices, meshes (boxes, Gmsh, Abaqus), the
//!    checked scene;
//! 4. [`contact`]: the contact laws as kinds, the augmented Lagrange update, the tangential
//!    multipliers, Anderson acceleration; [`kernels`]: the CPU twins (f64) of the WGSL
//!    kernels, on flat inputs;
//! 5. [`model`]: the mesh, constraints and contact interfaces as data;
//! 6. [`search`]: the host's broad phase of contact;
//! 7. [`backend`] and [`gpu`]: the kernels behind one trait, on the CPU or a GPU;
//! 8. [`linalg`], [`integrate`]: assembly and Cholesky; the implicit, explicit and resident
//!    integrators;
//! 9. [`check`], [`output`], [`checkpoint`], [`setup`], [`report`], [`run`], [`study`]: model
//!    checks, writers, restart files, the run's preparation, its report, the run itself and
//!    the accuracy-against-speed study.

pub mod backend;
pub mod check;
pub mod checkpoint;
pub mod contact;
pub mod domain;
pub mod element;
pub mod error;
pub mod geometry;
pub mod gpu;
pub mod integrate;
pub mod kernels;
pub mod limits;
pub mod linalg;
pub mod material;
pub mod mesh;
pub mod model;
pub mod output;
pub mod parallel;
pub mod report;
pub mod run;
pub mod scene;
pub mod search;
pub mod setup;
pub mod study;

pub use error::{ImpactError, Result};
