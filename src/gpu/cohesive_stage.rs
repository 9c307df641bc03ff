//! [`CohesiveStage`]: the cohesive interfaces on the device, in the resident step. After the
//! element and damage kernels, `cohesive_pairs` steps every bonded pair (its force, its
//! dissipation, its damage and slip moved on) and `cohesive_scatter` adds each bonded
//! node's share of its pairs' forces to one of its element corners, so that the gather sums
//! it into the node's force; `cohesive_reduce` writes each interface's areas, dissipation
//! and stored-energy offset into the step's history row. Twins in [`crate::kernels`].
//!
//! The state lives on the device: each pair's damage and slip (f32).

use super::buffer::{read_back, Storage};
use super::context::GpuContext;
use super::engine::at_least_one;
use super::kernel::Launch;
use super::kernels::{CohesivePairs, CohesiveReduce, CohesiveScatter};
use super::types::{self, to_device};
use crate::error::Result;
use crate::kernels::cohesive_pairs::{CohesiveSetup, PairOutput, PairState};
use crate::kernels::cohesive_scatter::BondedNodes;

/// The stage's pipelines.
struct CohesiveKernels {
    pairs: CohesivePairs,
    scatter: CohesiveScatter,
    reduce: CohesiveReduce,
}

/// Its buffers: the laws, pairs, states, outputs, bonded nodes, links and interfaces' ranges.
struct CohesiveBuffers {
    laws: Storage,
    pairs: Storage,
    state: Storage,
    outputs: Storage,
    nodes: Storage,
    links: Storage,
    ranges: Storage,
}

impl CohesiveBuffers {
    fn all(&self) -> [&Storage; 7] {
        [
            &self.laws,
            &self.pairs,
            &self.state,
            &self.outputs,
            &self.nodes,
            &self.links,
            &self.ranges,
        ]
    }
}

pub(crate) struct CohesiveStage {
    kernels: CohesiveKernels,
    buffers: CohesiveBuffers,
    step: Launch,
    scatter: Launch,
    /// One per row of a submission (none until [`Self::reduce_into_rows`]).
    reduce_rows: Vec<Launch>,
    pairs: usize,
    interfaces: u32,
}

/// What the stage reads and writes of the engine: the split displacements and the corner
/// forces, with the slots in all.
pub(crate) struct CohesiveTarget<'a> {
    pub displacement: &'a wgpu::Buffer,
    pub corner_forces: &'a wgpu::Buffer,
    pub slots: u32,
}

impl CohesiveStage {
    /// The stage of `setup`'s pairs, whose nodes `bonded` lists with their corners as the
    /// device's slots, on the engine's buffers `t`; every pair undamaged.
    pub(crate) fn new(
        ctx: &GpuContext,
        setup: &CohesiveSetup,
        bonded: &BondedNodes,
        t: &CohesiveTarget,
    ) -> Result<Self> {
        let kernels = CohesiveKernels {
            pairs: CohesivePairs::new(ctx),
            scatter: CohesiveScatter::new(ctx),
            reduce: CohesiveReduce::new(ctx),
        };
        let laws: Vec<types::CohesiveLaw> = to_device(&setup.laws);
        let pairs: Vec<types::CohesivePair> = to_device(&setup.pairs);
        let nodes: Vec<types::BondedNode> = (bonded.nodes.iter())
            .map(|b| types::BondedNode {
                node: b.node,
                corner: b.corner,
                first: b.first,
                end: b.end,
            })
            .collect();
        let ranges: Vec<[u32; 2]> = (setup.interfaces.iter())
            .map(|r| [r.start as u32, r.end as u32])
            .collect();
        let n = setup.pairs.len();
        let buffers = CohesiveBuffers {
            laws: Storage::with_data(ctx, "cohesive.laws", &at_least_one(laws))?,
            pairs: Storage::with_data(ctx, "cohesive.pairs", &at_least_one(pairs))?,
            state: Storage::with_data(ctx, "cohesive.state", &vec![0.0f32; 4 * n])?,
            outputs: Storage::new(ctx, "cohesive.outputs", (20 * n) as u64)?,
            nodes: Storage::with_data(ctx, "cohesive.nodes", &at_least_one(nodes))?,
            links: Storage::with_data(ctx, "cohesive.links", &at_least_one(bonded.links.clone()))?,
            ranges: Storage::with_data(ctx, "cohesive.ranges", &at_least_one(ranges))?,
        };
        let b = &buffers;
        let step = kernels.pairs.launch(
            ctx,
            n as u32,
            1,
            0,
            t.displacement,
            &b.laws.buffer,
            &b.pairs.buffer,
            &b.state.buffer,
            &b.outputs.buffer,
        );
        let scatter = kernels.scatter.launch(
            ctx,
            bonded.nodes.len() as u32,
            t.slots,
            0,
            &b.nodes.buffer,
            &b.links.buffer,
            &b.outputs.buffer,
            t.corner_forces,
        );
        Ok(CohesiveStage {
            kernels,
            buffers,
            step,
            scatter,
            reduce_rows: Vec::new(),
            pairs: n,
            interfaces: setup.interfaces.len() as u32,
        })
    }

    /// The reduces of the resident path: each interface's values into columns `column..` of
    /// each of `chunk_capacity` rows of `row_len` in `rows`.
    pub(crate) fn reduce_into_rows(
        &mut self,
        ctx: &GpuContext,
        rows: &wgpu::Buffer,
        (row_len, column, chunk_capacity): (usize, usize, usize),
    ) {
        let b = &self.buffers;
        self.reduce_rows = (0..chunk_capacity)
            .map(|j| {
                let at = (j * row_len + column) as u32;
                self.kernels.reduce.launch(
                    ctx,
                    self.interfaces,
                    at,
                    0,
                    &b.ranges.buffer,
                    &b.pairs.buffer,
                    &b.state.buffer,
                    &b.outputs.buffer,
                    rows,
                )
            })
            .collect();
    }

    /// Dispatches the pairs' step and the scatter of their forces (after the element and
    /// damage kernels, before the gather).
    pub(crate) fn dispatch(&self, pass: &mut wgpu::ComputePass) {
        self.kernels.pairs.0.dispatch(pass, &self.step);
        self.kernels.scatter.0.dispatch(pass, &self.scatter);
    }

    /// Dispatches the reduce of the resident path's row `j`.
    pub(crate) fn dispatch_row(&self, pass: &mut wgpu::ComputePass, j: usize) {
        let l = &self.reduce_rows[j];
        (self.kernels.reduce.0).dispatch_with(pass, &l.bind, [self.interfaces, 1]);
    }

    /// The buffer that carries the state from one step to the next.
    pub(crate) fn state_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.state.buffer
    }

    /// Every pair's state on the device.
    pub(crate) fn read_state(
        &self,
        ctx: &GpuContext,
        staging: &mut Storage,
    ) -> Result<Vec<PairState>> {
        let s: Vec<types::PairState> = read_back(
            ctx,
            staging,
            "cohesive.state",
            &self.buffers.state.buffer,
            self.pairs,
        )?;
        Ok(s.iter()
            .map(|s| PairState {
                damage: f64::from(s.damage),
                slip: s.slip.map(f64::from),
            })
            .collect())
    }

    /// Writes every pair's state.
    pub(crate) fn write_state(&self, ctx: &GpuContext, state: &[PairState]) {
        let s: Vec<types::PairState> = to_device(state);
        (ctx.queue).write_buffer(&self.buffers.state.buffer, 0, bytemuck::cast_slice(&s));
    }

    /// Every pair's output of the last step.
    pub(crate) fn read_outputs(
        &self,
        ctx: &GpuContext,
        staging: &mut Storage,
    ) -> Result<Vec<PairOutput>> {
        let o: Vec<types::PairOutput> = read_back(
            ctx,
            staging,
            "cohesive.outputs",
            &self.buffers.outputs.buffer,
            self.pairs,
        )?;
        Ok(o.iter()
            .map(|o| PairOutput {
                force: o.force.map(f64::from),
                dissipated: f64::from(o.dissipated),
                offset: f64::from(o.offset),
            })
            .collect())
    }

    /// Bytes held on the device.
    pub(crate) fn device_bytes(&self) -> u64 {
        self.buffers.all().iter().map(|s| s.capacity).sum()
    }
}
