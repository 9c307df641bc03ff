//! The kernels the integrators call, behind one interface ([`Kernels`]).
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
pub mod explicit_correct;
pub mod explicit_drift;
pub mod explicit_predict;
pub mod face_cells;
pub mod hex8_forces;
pub mod history_reduce;
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

use crate::error::Result;
use crate::material::Elastic;
use crate::model::Model;

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

/// What an integrator needs from the element and contact kernels.
pub trait Kernels {
    /// Name of the device the kernels run on ("cpu" or the adapter's name).
    fn device_name(&self) -> String;
    /// Relative accuracy of the kernels' arithmetic (1e-15 on the CPU, ~1e-7 for f32).
    fn unit_roundoff(&self) -> f64;
    /// Internal nodal forces $f = \int B^T \sigma(u)$ for the displacement `u` (3 per node).
    fn internal_forces_into(&mut self, u: &[f64], f: &mut [f64]) -> Result<()>;
    /// Closest-point projection, normal, gap and gap rate of every contact query.
    fn contact_gap_into(
        &mut self,
        u: &[f64],
        v: &[f64],
        queries: &ContactQueries,
        out: &mut [ContactPoint],
    ) -> Result<()>;
    /// Broad and narrow phase of every surface interface at (u, v): each query's candidates
    /// are the faces of its interface whose box, grown by `margin`, holds the node, and its
    /// point the closest of them (as [`Self::contact_gap_into`]). The default runs the host's
    /// grid (`contact::search`, filling `queries`' candidate lists) and then
    /// `contact_gap_into`; the GPU runs the whole search on the device.
    #[allow(clippy::too_many_arguments)]
    fn contact_search_into(
        &mut self,
        model: &Model,
        u: &[f64],
        v: &[f64],
        margin: f64,
        queries: &mut ContactQueries,
        lists: &mut [Vec<u32>],
        out: &mut [ContactPoint],
    ) -> Result<()> {
        crate::contact::search::surface_candidates(model, queries, lists, u, margin);
        self.contact_gap_into(u, v, queries, out)
    }
    /// Covariant slip rates of every contact point (zero where `face` is none).
    fn slip_rate_into(
        &mut self,
        u: &[f64],
        v: &[f64],
        queries: &ContactQueries,
        points: &[ContactPoint],
        out: &mut [[f64; 2]],
    ) -> Result<()>;
}

/// The kernels on the CPU, in f64.
pub struct CpuKernels {
    data: ElementData,
    incidence: Incidence,
    corner_forces: Vec<[f64; 3]>,
}

impl CpuKernels {
    pub fn new(data: ElementData) -> Self {
        let incidence = Incidence::new(&data.hexes, &data.tets, data.reference.len());
        let corner_forces = vec![[0.0; 3]; data.corner_count()];
        CpuKernels {
            data,
            incidence,
            corner_forces,
        }
    }

    pub fn data(&self) -> &ElementData {
        &self.data
    }
}

impl Kernels for CpuKernels {
    fn device_name(&self) -> String {
        "cpu".into()
    }
    fn unit_roundoff(&self) -> f64 {
        f64::EPSILON
    }
    fn internal_forces_into(&mut self, u: &[f64], f: &mut [f64]) -> Result<()> {
        let (hex, tet) = self.corner_forces.split_at_mut(8 * self.data.hexes.len());
        hex8_forces(&self.data, as_vec3(u), hex);
        tet4_forces(&self.data, as_vec3(u), tet);
        node_gather(&self.incidence, &self.corner_forces, as_vec3_mut(f));
        Ok(())
    }
    fn contact_gap_into(
        &mut self,
        u: &[f64],
        v: &[f64],
        queries: &ContactQueries,
        out: &mut [ContactPoint],
    ) -> Result<()> {
        contact_gap(&self.data.reference, as_vec3(u), as_vec3(v), queries, out);
        Ok(())
    }
    fn slip_rate_into(
        &mut self,
        u: &[f64],
        v: &[f64],
        queries: &ContactQueries,
        points: &[ContactPoint],
        out: &mut [[f64; 2]],
    ) -> Result<()> {
        slip_rate(
            &self.data.reference,
            as_vec3(u),
            as_vec3(v),
            queries,
            points,
            out,
        );
        Ok(())
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
