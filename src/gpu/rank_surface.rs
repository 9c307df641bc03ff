//! [`RankSurface`]: what the resident step of a rank of a decomposed run needs for the
//! contact between meshed bodies, which every rank works on the whole contact surfaces
//! ([`super::SurfaceStep`]): the state of the surface nodes it owns packed for the read-back
//! (`shaders/node_select.wgsl`, twin [`crate::kernels::node_select`]), its nodes' fastest
//! speed (`search_bounds` over its nodes alone: the single GPU's search reach takes the
//! fastest node of the model), and the velocities the iteration gave the surface nodes it
//! holds, taken from the surface step's buffer on the same device (`node_select`) and
//! written over the step's (`node_scatter`).

use super::buffer::Storage;
use super::engine::{at_least_one, bytes_of, GpuKernels};
use super::kernel::Launch;
use super::types::Split3;
use super::{FillWords, NodeScatter, NodeSelect, SearchBounds};
use crate::error::{ImpactError, Result};

pub struct RankSurface {
    select: NodeSelect,
    scatter: NodeScatter,
    speed: SearchBounds,
    zero: FillWords,
    pub(super) bounds: Storage,
    /// The packed displacements (hi and lo), velocities and accelerations of the owned
    /// surface nodes.
    pub(super) selected: [Storage; 3],
    select_launches: [Launch; 3],
    zero_launch: Launch,
    speed_launch: Launch,
    take_launch: Launch,
    scatter_launch: Launch,
    pub(super) owned: usize,
    held: usize,
    // kept alive for the bindings
    _buffers: Vec<Storage>,
}

impl RankSurface {
    /// The surface nodes the rank owns (`owned`, whose state it reads back) and holds
    /// (`held`, whose velocities it takes back), by `k`'s node numbers, and `acceleration`,
    /// the step's acceleration buffer; `surface`: the surface step's velocities (a buffer of
    /// `k`'s device) and each held node's place among them.
    pub fn new(
        k: &GpuKernels,
        acceleration: &wgpu::Buffer,
        (owned, held): (&[u32], &[u32]),
        (surface, places): (&wgpu::Buffer, &[u32]),
    ) -> Result<Self> {
        if let Some(&n) = owned.iter().chain(held).find(|&&n| n as usize >= k.nodes) {
            return Err(ImpactError::Gpu(format!(
                "surface node {n} of a mesh of {} nodes",
                k.nodes
            )));
        }
        let surface_nodes = surface.size() / 12;
        if places.len() != held.len() || places.iter().any(|&p| u64::from(p) >= surface_nodes) {
            return Err(ImpactError::Gpu(format!(
                "{} places among {surface_nodes} surface nodes for {} held nodes",
                places.len(),
                held.len()
            )));
        }
        let ctx = &k.ctx;
        let (select, scatter) = (NodeSelect::new(ctx), NodeScatter::new(ctx));
        let (speed, zero) = (SearchBounds::new(ctx), FillWords::new(ctx));
        let owned_list = Storage::with_data(ctx, "surface.owned", &at_least_one(owned.to_vec()))?;
        let held_list = Storage::with_data(ctx, "surface.held", &at_least_one(held.to_vec()))?;
        let c = owned.len();
        let selected = [
            Storage::new(ctx, "surface.u", bytes_of::<f32>(6 * c))?,
            Storage::new(ctx, "surface.v", bytes_of::<f32>(3 * c))?,
            Storage::new(ctx, "surface.a", bytes_of::<f32>(3 * c))?,
        ];
        let sources = [&k.u.buffer, &k.v.buffer, acceleration];
        let select_launches = [0, 1, 2].map(|f| {
            let width = if f == 0 { 6 } else { 3 };
            let (list, from, to) = (&owned_list.buffer, sources[f], &selected[f].buffer);
            select.launch(ctx, c as u32, width, 0, list, from, to)
        });
        let bounds = Storage::new(ctx, "surface.bounds", 16)?;
        // no face: placeholders (read, and written: two buffers)
        let none = Storage::new(ctx, "surface.none", 64)?;
        let boxes = Storage::new(ctx, "surface.boxes", 64)?;
        let zero_launch = zero.launch(ctx, 3, 0, 0, &bounds.buffer);
        // its nodes' speeds alone: no face (Params.aux the nodes, aux2 the faces)
        let speed_launch = speed.launch(
            ctx,
            k.nodes as u32,
            k.nodes as u32,
            0,
            &k.mesh.reference.buffer,
            &k.u.buffer,
            &k.v.buffer,
            &none.buffer,
            &none.buffer,
            &bounds.buffer,
            &boxes.buffer,
        );
        let values = Storage::new(ctx, "surface.values", bytes_of::<f32>(3 * held.len()))?;
        let places = Storage::with_data(ctx, "surface.places", &at_least_one(places.to_vec()))?;
        let h = held.len() as u32;
        let take_launch = select.launch(ctx, h, 3, 0, &places.buffer, surface, &values.buffer);
        let scatter_launch = scatter.launch(
            ctx,
            held.len() as u32,
            0,
            0,
            &held_list.buffer,
            &values.buffer,
            &k.v.buffer,
        );
        Ok(RankSurface {
            select,
            scatter,
            speed,
            zero,
            bounds,
            selected,
            select_launches,
            zero_launch,
            speed_launch,
            take_launch,
            scatter_launch,
            owned: c,
            held: held.len(),
            // (values: the held surface nodes' velocities as the surface step left them)
            _buffers: vec![owned_list, held_list, none, boxes, places, values],
        })
    }

    /// Dispatches the rank's fastest speed and the packing of its owned surface nodes'
    /// state (after the predictor).
    pub(super) fn dispatch_select(&self, pass: &mut wgpu::ComputePass) {
        self.zero.0.dispatch(pass, &self.zero_launch);
        self.speed.0.dispatch(pass, &self.speed_launch);
        if self.owned > 0 {
            for l in &self.select_launches {
                self.select.0.dispatch(pass, l);
            }
        }
    }

    /// What [`Self::dispatch_select`] leaves for the read-back, in its order: the speed
    /// bits, then the owned nodes' split displacements, velocities and accelerations.
    pub(super) fn state_parts(&self) -> [(&wgpu::Buffer, usize); 4] {
        let c = self.owned;
        [
            (&self.bounds.buffer, 1),
            (&self.selected[0].buffer, 6 * c),
            (&self.selected[1].buffer, 3 * c),
            (&self.selected[2].buffer, 3 * c),
        ]
    }

    /// The state read back from [`Self::state_parts`].
    pub(super) fn state_of(&self, out: &[f32]) -> SurfaceState {
        let c = self.owned;
        let (speed, rest) = out.split_at(1);
        let (u, rest) = rest.split_at(6 * c);
        let (v, a) = rest.split_at(3 * c);
        let three = |x: &[f32]| x.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        SurfaceState {
            speed: speed[0].to_bits(),
            u: (u.chunks_exact(6))
                .map(|c| Split3 {
                    hi: [c[0], c[1], c[2]],
                    lo: [c[3], c[4], c[5]],
                })
                .collect(),
            v: three(v),
            a: three(a),
        }
    }

    /// Dispatches the held surface nodes' velocities, taken from the surface step's after
    /// its iteration, over the step's.
    pub(super) fn dispatch_scatter(&self, pass: &mut wgpu::ComputePass) {
        if self.held > 0 {
            self.select.0.dispatch(pass, &self.take_launch);
            self.scatter.0.dispatch(pass, &self.scatter_launch);
        }
    }
}

/// The state of a rank's owned surface nodes after the predictor, as its device holds it,
/// and the fastest speed of its nodes (f32 bits).
#[derive(Debug, Clone, Default)]
pub struct SurfaceState {
    pub speed: u32,
    pub u: Vec<Split3>,
    pub v: Vec<[f32; 3]>,
    pub a: Vec<[f32; 3]>,
}
