//! The kernels' CPU twins, in f64, and their flat inputs.
//!
//! Each kernel has a CPU version in f64 here (the "twin") and a WGSL version in
//! `shaders/<name>.wgsl` run by [`crate::gpu`]. Both take the same flat inputs:
//! reference coordinates plus displacements (so that f32 keeps its precision on the GPU),
//! velocities, connectivity, and for contact a list of queries (secondary node, candidate
//! primary faces).

// Index loops over nodes, corners and components keep the CPU twins line-by-line comparable
// with their WGSL kernels (vello does the same in its CPU shaders).
#![allow(clippy::needless_range_loop)]

pub mod body_gather;
pub mod bucket_count;
pub mod bucket_fill;
pub mod bucket_order;
pub mod cohesive_forces;
pub mod cohesive_pairs;
pub mod cohesive_reduce;
pub mod cohesive_scatter;
pub mod contact_apply;
pub mod contact_compliance;
pub mod contact_constraints;
pub mod contact_finish;
pub mod contact_gap;
pub mod contact_relax;
pub mod contact_report;
pub mod contact_search;
pub mod contact_sweep;
pub mod contact_touches;
pub mod contact_warm;
pub mod contact_zone;
pub mod corner_select;
pub mod corotated_forces;
pub mod damage_data;
pub(crate) mod damage_pass;
pub mod damage_reduce;
pub mod damage_sieve;
pub mod explicit_correct;
pub mod explicit_drift;
pub mod explicit_predict;
pub mod face_cells;
pub mod failure_reduce;
pub mod failure_survey;
pub mod fill_words;
pub mod gather_correct;
pub mod hex8_damage;
pub mod hex8_forces;
pub mod hex8i_damage;
pub mod hex8i_forces;
pub mod history_reduce;
pub mod impulse;
pub mod node_gather;
pub mod node_scatter;
pub mod node_select;
pub mod plane_contact;
pub mod predict_bounds;
pub mod prefix_sum;
pub mod scan_totals;
pub mod search_bounds;
pub mod search_grid;
pub mod slip_rate;
pub mod stable_step;
pub mod sweep_control;
pub mod tet4_damage;
pub mod tet4_forces;

pub use body_gather::body_gather;
pub use bucket_count::bucket_count;
pub use bucket_fill::bucket_fill;
pub use bucket_order::bucket_order;
pub use contact_apply::contact_apply;
pub use contact_compliance::contact_compliance;
pub use contact_constraints::{contact_constraints, Constraint, ContactPair, RigidSurface};
pub use contact_finish::{contact_finish, SweepInputs};
pub use contact_gap::{contact_gap, ContactPoint, ContactQueries};
pub use contact_relax::{contact_relax, Relax, Relaxation};
pub use contact_report::contact_report;
pub use contact_search::{contact_search, SearchGrid};
pub use contact_sweep::contact_sweep;
pub use contact_touches::{contact_touches, ContactNode};
pub use contact_warm::contact_warm;
pub use contact_zone::{contact_zone, ZoneInputs, ZoneState};
pub use corner_select::corner_select;
pub use explicit_correct::{explicit_correct, LumpedNode};
pub use explicit_drift::explicit_drift;
pub use explicit_predict::explicit_predict;
pub use face_cells::{face_box, face_cells, face_centre};
pub use failure_reduce::{failure_reduce, FAILURE_FIELDS};
pub use failure_survey::{failure_survey, SurveyPoint, SurveySetup};
pub use fill_words::fill_words;
pub use gather_correct::gather_correct;
pub use hex8_forces::hex8_forces;
pub use hex8i_forces::hex8i_forces;
pub use history_reduce::{history_reduce, ReduceColumn};
pub use node_gather::{node_gather, Incidence};
pub use node_scatter::node_scatter;
pub use node_select::node_select;
pub use plane_contact::{plane_contact, PlaneData, PlaneNode, SweepLimits};
pub use predict_bounds::predict_bounds;
pub use prefix_sum::prefix_sum;
pub use scan_totals::{scan_totals, SCAN_BLOCK};
pub use search_bounds::search_bounds;
pub use search_grid::{search_grid, SearchMode, SEARCH_SKIN};
pub use slip_rate::slip_rate;
pub use stable_step::stable_step;
pub use sweep_control::{sweep_control, SweepState};
pub use tet4_forces::tet4_forces;

use crate::element::{CornerLayout, ElementKind, Elements, Section};
use crate::material::damage::Dissipation;
use crate::material::{Elastic, Layup};

/// Element data every kernel backend is built from.
#[derive(Debug, Clone)]
pub struct ElementData {
    pub reference: Vec<[f64; 3]>,
    pub elements: Elements,
    pub materials: Vec<Elastic>,
    /// The plies of each material index that is a layered section (none or empty: all solid).
    pub layups: Vec<Option<Layup>>,
}

/// The section of material index `m`: its layup where it has one, else its law.
pub fn section_of<'a>(
    materials: &'a [Elastic],
    layups: &'a [Option<Layup>],
    m: u32,
) -> Section<'a> {
    match layups.get(m as usize) {
        Some(Some(l)) => Section::Layered(l),
        _ => Section::Solid(&materials[m as usize]),
    }
}

impl ElementData {
    /// The section of material index `m`.
    pub fn section(&self, m: u32) -> Section<'_> {
        section_of(&self.materials, &self.layups, m)
    }

    /// Element corners in the corner-force array ([`CornerLayout`]).
    pub fn corner_count(&self) -> usize {
        self.elements.corner_count()
    }

    /// Where each corner's force lives.
    pub fn layout(&self) -> CornerLayout {
        CornerLayout::of(&self.elements)
    }
}

/// What the force kernels keep of the elements besides their data, computed once: each
/// block's [`ElementKind::kept`] values, element after element.
#[derive(Debug, Clone, Default)]
pub struct KeptData {
    pub blocks: Vec<Vec<f64>>,
}

impl KeptData {
    /// The kept values of every block, on all threads.
    pub fn of(data: &ElementData) -> Self {
        use rayon::prelude::*;
        let blocks = (data.elements.blocks.iter())
            .map(|b| {
                if b.kind.kept_per_element() == 0 {
                    return Vec::new();
                }
                (0..b.len())
                    .into_par_iter()
                    .flat_map_iter(|e| {
                        let x: Vec<[f64; 3]> = (b.element(e).iter())
                            .map(|&n| data.reference[n as usize])
                            .collect();
                        b.kind.kept(&x, data.section(b.material[e]))
                    })
                    .collect()
            })
            .collect();
        KeptData { blocks }
    }

    /// The kept values of a kind's block.
    pub fn of_kind(&self, kind: ElementKind) -> &[f64] {
        self.blocks.get(kind.index()).map_or(&[], Vec::as_slice)
    }
}

/// Corner forces of every element at displacement `u`, in `layout` (the data's
/// [`CornerLayout`]; overwrites `corner_forces`): the per-kind force kernels, each on its
/// block's part. The elements `skip` marks (per block, by kind index; an empty mask marks
/// none) are left as they were: the damaged ones, whose forces the damage pass replaces.
pub(crate) fn element_forces(
    data: &ElementData,
    (layout, kept): (&CornerLayout, &KeptData),
    u: &[[f64; 3]],
    corner_forces: &mut [[f64; 3]],
    skip: &[Vec<bool>],
) {
    for block in &data.elements.blocks {
        let start = layout.offset(block.kind);
        let out = &mut corner_forces[start..start + block.nodes.len()];
        let skip = skip.get(block.kind.index()).map_or(&[][..], Vec::as_slice);
        match block.kind {
            ElementKind::Hex8 => hex8_forces::hex8_forces_but(data, u, out, skip),
            ElementKind::Tet4 => tet4_forces::tet4_forces_but(data, u, out, skip),
            ElementKind::Hex8i => {
                hex8i_forces::hex8i_forces_but(data, kept.of_kind(block.kind), u, out, skip)
            }
        }
    }
}

/// Marks, per block (by kind index), the elements the damage state holds as damaged: the
/// damage pass steps each of them and replaces its elastic forces.
pub(crate) fn mark_damaged(
    data: &ElementData,
    (damage, state): (&damage_data::DamageData, &damage_data::DamageState),
    marks: &mut Vec<Vec<bool>>,
) {
    // the element and damage blocks are both in kind order
    marks.resize(data.elements.blocks.len(), Vec::new());
    for (((mask, block), dblock), damaged) in (marks.iter_mut())
        .zip(&data.elements.blocks)
        .zip(&damage.blocks)
        .zip(&state.damaged)
    {
        mask.clear();
        if damaged.iter().any(|&d| d) {
            mask.resize(block.len(), false);
            for (&e, &d) in dblock.elements.iter().zip(damaged) {
                mask[e as usize] = d;
            }
        }
    }
}

/// The damage passes over every block's damageable elements, after [`element_forces`] gave
/// every element its elastic corner forces (`corner_forces`, in `layout`): with `advance`
/// the state steps over `dt` to `u` (from $u - \Delta t\, v$), else the forces are those of
/// the state as it is.
/// Returns the energy dissipated over the step, with the fibre modes' share (element by
/// element, in order).
pub(crate) fn damage_forces(
    data: &ElementData,
    (damage, state, memory): (
        &damage_data::DamageData,
        &mut damage_data::DamageState,
        &mut damage_sieve::SieveMemory,
    ),
    (layout, frames): (&CornerLayout, Option<&corotated_forces::Frames>),
    (u, v): (&[[f64; 3]], &[[f64; 3]]),
    corner_forces: &mut [[f64; 3]],
    (dt, advance): (f64, bool),
) -> Dissipation {
    let mut total = Dissipation::default();
    for block in &data.elements.blocks {
        let k = block.kind.index();
        let dblock = &damage.blocks[k];
        if dblock.is_empty() {
            continue;
        }
        let start = layout.offset(block.kind);
        let mut dissipated = vec![Dissipation::default(); dblock.len()];
        let out = damage_pass::BlockPass {
            corner_forces: &mut corner_forces[start..start + block.nodes.len()],
            state: &mut state.points[k],
            damaged: &mut state.damaged[k],
            first: &mut state.first[k],
            memory: &mut memory.blocks[k],
            dissipated: &mut dissipated,
            step: state.steps + 1,
            frames: frames.map(|f| f.of_kind(block.kind)),
        };
        let step = (dt, advance);
        match block.kind {
            ElementKind::Hex8 => hex8_damage::hex8_damage(data, damage, (u, v), out, step),
            ElementKind::Tet4 => tet4_damage::tet4_damage(data, damage, (u, v), out, step),
            ElementKind::Hex8i => hex8i_damage::hex8i_damage(data, damage, (u, v), out, step),
        }
        total += dissipated.iter().copied().sum::<Dissipation>();
    }
    if advance {
        state.steps += 1;
    }
    total
}

/// Views a flat dof vector as nodal 3-vectors.
pub fn as_vec3(x: &[f64]) -> &[[f64; 3]] {
    bytemuck::cast_slice(x)
}

/// Views a flat dof vector as nodal 3-vectors, mutably.
pub(crate) fn as_vec3_mut(x: &mut [f64]) -> &mut [[f64; 3]] {
    bytemuck::cast_slice_mut(x)
}
