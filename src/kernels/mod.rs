//! The kernels' CPU twins, in f64, and their flat inputs.
//!
//! Each kernel has a CPU version in f64 here (the "twin") and a WGSL version in
//! `shaders/<name>.wgsl` run by [`crate::gpu`]. Both take the same flat inputs:
//! reference coordinates plus displacements (so that f32 keeps its precision on the GPU),
//! velocities, connectivity, and for contact a list of queries (secondary node, candidate
//! primary faces).

pub mod bucket_count;
pub mod bucket_fill;
pub mod bucket_order;
pub mod contact_apply;
pub mod contact_compliance;
pub mod contact_constraints;
pub mod contact_gap;
pub mod contact_report;
pub mod contact_search;
pub mod contact_sweep;
pub mod contact_touches;
pub mod corner_select;
pub mod explicit_correct;
pub mod explicit_drift;
pub mod explicit_predict;
pub mod face_cells;
pub mod hex8_forces;
pub mod history_reduce;
pub mod impulse;
pub mod node_gather;
pub mod plane_contact;
pub mod prefix_sum;
pub mod search_bounds;
pub mod search_grid;
pub mod slip_rate;
pub mod stable_step;
pub mod sweep_control;
pub mod tet4_forces;

pub use bucket_count::bucket_count;
pub use bucket_fill::bucket_fill;
pub use bucket_order::bucket_order;
pub use contact_apply::contact_apply;
pub use contact_compliance::contact_compliance;
pub use contact_constraints::{contact_constraints, Constraint, ContactPair};
pub use contact_gap::{contact_gap, ContactPoint, ContactQueries};
pub use contact_report::contact_report;
pub use contact_search::{contact_search, SearchGrid};
pub use contact_sweep::contact_sweep;
pub use contact_touches::{contact_touches, ContactNode};
pub use corner_select::corner_select;
pub use explicit_correct::{explicit_correct, LumpedNode};
pub use explicit_drift::explicit_drift;
pub use explicit_predict::explicit_predict;
pub use face_cells::face_cells;
pub use hex8_forces::hex8_forces;
pub use history_reduce::{history_reduce, ReduceColumn};
pub use node_gather::{node_gather, Incidence};
pub use plane_contact::{plane_contact, PlaneData, PlaneNode, SweepLimits};
pub use prefix_sum::prefix_sum;
pub use search_bounds::search_bounds;
pub use search_grid::search_grid;
pub use slip_rate::slip_rate;
pub use stable_step::stable_step;
pub use sweep_control::{sweep_control, SweepState};
pub use tet4_forces::tet4_forces;

use crate::material::Elastic;

/// Element data every kernel backend is built from.
#[derive(Debug, Clone)]
pub struct ElementData {
    pub reference: Vec<[f64; 3]>,
    pub hexes: Vec<[u32; 8]>,
    pub hex_material: Vec<u32>,
    pub tets: Vec<[u32; 4]>,
    pub tet_material: Vec<u32>,
    pub materials: Vec<Elastic>,
}

impl ElementData {
    /// Element corners in the corner-force array: 8 per hex8, then 4 per tet4.
    pub fn corner_count(&self) -> usize {
        8 * self.hexes.len() + 4 * self.tets.len()
    }
}

/// Views a flat dof vector as nodal 3-vectors.
pub fn as_vec3(x: &[f64]) -> &[[f64; 3]] {
    bytemuck::cast_slice(x)
}

/// Views a flat dof vector as nodal 3-vectors, mutably.
pub fn as_vec3_mut(x: &mut [f64]) -> &mut [[f64; 3]] {
    bytemuck::cast_slice_mut(x)
}
