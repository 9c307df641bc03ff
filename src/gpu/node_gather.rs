//! Host side of `shaders/node_gather.wgsl` (CPU twin: [`crate::kernels::node_gather`]); its launch and
//! buffer layouts are built by [`super::GpuKernels`] (see [`super::engine::ElementColumns`]).

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

/// The `node_gather` pipeline, built once per engine.
pub struct NodeGather(pub Kernel);

impl NodeGather {
    pub fn new(ctx: &GpuContext) -> Self {
        NodeGather(Kernel::new(ctx, "node_gather", shaders::NODE_GATHER))
    }
}
