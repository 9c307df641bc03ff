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

/// The kernels of one rank.
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
    /// `sub`'s exchanged corners).
    pub fn new(sub: &mut Subdomain, ctx: Option<GpuContext>) -> Result<Self> {
        let Some(ctx) = ctx else {
            return Ok(RankForces::Cpu(CpuKernels::new(sub.data.clone())));
        };
        let chosen = sub.exchanged_corners();
        let kernels = Box::new(GpuKernels::new(ctx, &sub.data)?);
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
