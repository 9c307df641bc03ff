//! [`RankExchange`]: what the resident step of a rank of a decomposed run needs to give the
//! nodes it shares with its neighbours their whole internal force: the corners the exchange
//! reads ([`CornerSelection`], read back after the element kernels) and the shared nodes'
//! sums over every rank's corners, written over the node gather's partial sums
//! (`shaders/node_scatter.wgsl`, CPU twin [`crate::kernels::node_scatter`]).

use super::buffer::{submit_and_read, Storage};
use super::corner_select::CornerSelection;
use super::engine::{at_least_one, bytes_of, GpuKernels};
use super::kernel::Launch;
use super::NodeScatter;
use crate::error::{ImpactError, Result};

pub struct RankExchange {
    pub(super) selection: CornerSelection,
    /// Kept alive for the launch's bindings.
    _shared_nodes: Storage,
    sums: Storage,
    kernel: NodeScatter,
    launch: Launch,
    shared: usize,
}

impl RankExchange {
    /// The corners `chosen` of `k`'s mesh (by corner id) and the nodes `shared_nodes` whose
    /// sums the host gives (by `k`'s node numbers).
    pub fn new(k: &GpuKernels, chosen: &[u32], shared_nodes: &[u32]) -> Result<Self> {
        if let Some(&n) = shared_nodes.iter().find(|&&n| n as usize >= k.nodes) {
            return Err(ImpactError::Gpu(format!(
                "shared node {n} of a mesh of {} nodes",
                k.nodes
            )));
        }
        let ctx = &k.ctx;
        let selection = CornerSelection::new(k, chosen)?;
        let nodes = Storage::with_data(ctx, "shared_nodes", &at_least_one(shared_nodes.to_vec()))?;
        let floats = (3 * shared_nodes.len()).max(1);
        let sums = Storage::new(ctx, "shared_sums", bytes_of::<f32>(floats))?;
        let kernel = NodeScatter::new(ctx);
        let launch = kernel.launch(
            ctx,
            shared_nodes.len() as u32,
            0,
            0,
            &nodes.buffer,
            &sums.buffer,
            &k.forces.buffer,
        );
        Ok(RankExchange {
            selection,
            _shared_nodes: nodes,
            sums,
            kernel,
            launch,
            shared: shared_nodes.len(),
        })
    }

    /// The shared nodes.
    pub fn shared(&self) -> usize {
        self.shared
    }

    /// Dispatches the selection of the exchanged corners (after the element kernels).
    pub(super) fn dispatch_select(&self, k: &GpuKernels, pass: &mut wgpu::ComputePass) {
        self.selection.dispatch(k, pass);
    }

    /// Writes the shared nodes' sums (one per shared node, in order) for the next
    /// [`Self::dispatch_sums`].
    pub(super) fn write_sums(&self, k: &GpuKernels, sums: &[[f32; 3]]) -> Result<()> {
        if sums.len() != self.shared {
            return Err(ImpactError::Gpu(format!(
                "{} shared sums for {} shared nodes",
                sums.len(),
                self.shared
            )));
        }
        if self.shared > 0 {
            k.ctx
                .queue
                .write_buffer(&self.sums.buffer, 0, bytemuck::cast_slice(sums));
        }
        Ok(())
    }

    /// Dispatches the shared nodes' sums over the gathered forces (after the gather).
    pub(super) fn dispatch_sums(&self, pass: &mut wgpu::ComputePass) {
        if self.shared > 0 {
            self.kernel.0.dispatch(pass, &self.launch);
        }
    }

    /// The kernel alone on `k`'s forces as they are (for the twin test): writes `sums`, runs
    /// `node_scatter` and reads every node's forces back.
    pub(super) fn run_alone(&self, k: &mut GpuKernels, sums: &[[f32; 3]]) -> Result<Vec<f32>> {
        self.write_sums(k, sums)?;
        let mut enc = k.ctx.encoder("node_scatter");
        self.kernel.0.record_launch(&mut enc, &self.launch);
        submit_and_read(&k.ctx, &mut k.staging, enc, &k.forces.buffer, 3 * k.nodes)
    }
}
