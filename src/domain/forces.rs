//! A rank's element forces: on the CPU in f64, or on the rank's own GPU in f32. Either way
//! the rank's nodes that no neighbour holds take the forces its kernels gather, and the
//! shared nodes the sum of their corners in global corner order
//! ([`Subdomain::sum_shared`]), in the precision the corners were computed in. The GPU's
//! gather adds a node's corners in that order too, in f32, so a rank on a GPU gives every
//! node the same bits as one rank on the same kind of GPU, whatever the number of ranks.

use super::subdomain::Subdomain;
use crate::backend::{CpuKernels, Kernels};
use crate::error::Result;
use crate::gpu::{CornerSelection, GpuContext, GpuKernels};
use crate::kernels::damage_data::DamageData;

/// The kernels of one rank.
// one per rank, held for the run: the CPU variant's inline size costs nothing
#[allow(clippy::large_enum_variant)]
pub enum RankForces {
    Cpu(CpuKernels),
    /// The GPU reads back, with the nodal forces, the corners the exchange needs
    /// (`chosen`, as [`Subdomain::pack_corners`] numbers them).
    Gpu {
        kernels: Box<GpuKernels>,
        selection: CornerSelection,
        chosen: Vec<[f32; 3]>,
    },
}

impl RankForces {
    /// The kernels of `sub`'s elements on `ctx`, or on the CPU without one (a GPU renumbers
    /// `sub`'s exchanged corners), with the damage of its elements (`damage`), their forces
    /// turned with them where `corotational` (on the CPU: the setup gives no GPU then).
    pub fn new(
        sub: &mut Subdomain,
        ctx: Option<GpuContext>,
        (damage, corotational): (Option<DamageData>, bool),
    ) -> Result<Self> {
        let Some(ctx) = ctx else {
            return Ok(RankForces::Cpu(
                CpuKernels::new(sub.data.clone())
                    .with_damage(damage)
                    .corotational(corotational),
            ));
        };
        let chosen = sub.exchanged_corners();
        let kernels = Box::new(GpuKernels::new(ctx, &sub.data)?.with_damage(damage)?);
        let selection = CornerSelection::new(&kernels, &chosen)?;
        sub.pack_corners(&chosen);
        Ok(RankForces::Gpu {
            kernels,
            selection,
            chosen: Vec::new(),
        })
    }

    pub fn device_name(&self) -> String {
        match self {
            RankForces::Cpu(k) => k.device_name(),
            RankForces::Gpu { kernels, .. } => kernels.device_name(),
        }
    }

    /// The forces the rank's elements give its nodes at `u` (shared nodes not yet summed).
    pub fn internal_forces(&mut self, u: &[f64], f: &mut [f64]) -> Result<()> {
        match self {
            RankForces::Cpu(k) => k.internal_forces_into(u, f),
            RankForces::Gpu {
                kernels,
                selection,
                chosen,
            } => kernels.internal_forces_selecting(u, f, selection, chosen),
        }
    }

    /// [`Self::internal_forces`] for an explicit step: the damage stepped over `dt` to `u`
    /// (`v` the mid-step velocities); returns the energy it dissipated on the rank, with the
    /// fibre modes' share.
    pub fn step_forces(
        &mut self,
        uv: (&[f64], &[f64]),
        dt: f64,
        f: &mut [f64],
    ) -> Result<crate::material::damage::Dissipation> {
        match self {
            RankForces::Cpu(k) => k.step_forces_into(uv, dt, f),
            RankForces::Gpu {
                kernels,
                selection,
                chosen,
            } => kernels.step_forces_selecting(uv, dt, f, (selection, chosen)),
        }
    }

    /// Each of the rank's elements' damage by mode and its first damaged point (none
    /// without damage).
    pub fn damage_cells(
        &self,
    ) -> Option<(
        Vec<[f64; 4]>,
        Option<crate::kernels::damage_data::DamagedPoint>,
    )> {
        match self {
            RankForces::Cpu(k) => k.damage_cells(),
            RankForces::Gpu { kernels, .. } => kernels.damage_cells(),
        }
    }

    /// The rank's elements' turn energy at their last forces ([`Kernels::turn_energy`]).
    pub fn turn_energy(&self) -> f64 {
        match self {
            RankForces::Cpu(k) => k.turn_energy(),
            RankForces::Gpu { kernels, .. } => kernels.turn_energy(),
        }
    }

    /// The kernels (the damage's state and cells).
    pub fn kernels(&mut self) -> &mut dyn Kernels {
        match self {
            RankForces::Cpu(k) => k,
            RankForces::Gpu { kernels, .. } => kernels.as_mut(),
        }
    }

    /// The corners `sub` sends each neighbour, in its order, as f64 (an f32 corner exactly).
    pub fn sends(&self, sub: &Subdomain) -> Vec<Vec<f64>> {
        match self {
            RankForces::Cpu(k) => sub.sends(k.corner_forces()),
            RankForces::Gpu { chosen, .. } => sub.sends(chosen),
        }
    }

    /// The shared nodes' forces in `f` from the rank's corners and the `received` ones.
    pub fn sum_shared(&self, sub: &Subdomain, received: &[f64], f: &mut [f64]) {
        match self {
            RankForces::Cpu(k) => sub.sum_shared(k.corner_forces(), received, f),
            RankForces::Gpu { chosen, .. } => sub.sum_shared(chosen, received, f),
        }
    }
}
