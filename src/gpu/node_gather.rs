//! Host side of `shaders/node_gather.wgsl` (CPU twin: [`crate::kernels::node_gather`]).

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

/// The `node_gather` pipeline, built once per engine.
pub struct NodeGather(pub Kernel);

impl NodeGather {
    pub fn new(ctx: &GpuContext) -> Self {
        NodeGather(Kernel::new(ctx, "node_gather", shaders::NODE_GATHER))
    }

    /// Bind group in the shader's binding order (binding 0 is the params uniform).
    #[allow(clippy::too_many_arguments)]
    pub fn bind(
        &self,
        ctx: &GpuContext,
        offsets: &wgpu::Buffer,
        incidence: &wgpu::Buffer,
        corner_forces: &wgpu::Buffer,
        forces: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        self.0
            .bind(ctx, &[offsets, incidence, corner_forces, forces])
    }
}
