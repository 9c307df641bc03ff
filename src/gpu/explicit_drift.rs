//! Host side of `shaders/explicit_drift.wgsl` (CPU twin: [`crate::kernels::explicit_drift`]).

use super::context::GpuContext;
use super::kernel::{Kernel, Launch};
use super::shaders;

pub struct ExplicitDrift(pub Kernel);

impl ExplicitDrift {
    pub fn new(ctx: &GpuContext) -> Self {
        ExplicitDrift(Kernel::new(ctx, "explicit_drift", shaders::EXPLICIT_DRIFT))
    }

    /// A launch over `nodes` nodes, buffers in the shader's binding order.
    pub fn launch(
        &self,
        ctx: &GpuContext,
        nodes: u32,
        step: &wgpu::Buffer,
        velocity: &wgpu::Buffer,
        displacement: &wgpu::Buffer,
    ) -> Launch {
        self.0
            .launch(ctx, nodes, 0, 0, &[step, velocity, displacement])
    }
}
