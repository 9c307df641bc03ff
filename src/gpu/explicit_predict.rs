//! Host side of `shaders/explicit_predict.wgsl` (CPU twin: [`crate::kernels::explicit_predict`]).

use super::context::GpuContext;
use super::kernel::{Kernel, Launch};
use super::shaders;

pub struct ExplicitPredict(pub Kernel);

impl ExplicitPredict {
    pub fn new(ctx: &GpuContext) -> Self {
        ExplicitPredict(Kernel::new(
            ctx,
            "explicit_predict",
            shaders::EXPLICIT_PREDICT,
        ))
    }

    /// A launch over `dofs` dofs, buffers in the shader's binding order.
    pub fn launch(
        &self,
        ctx: &GpuContext,
        dofs: u32,
        step: &wgpu::Buffer,
        acceleration: &wgpu::Buffer,
        velocity: &wgpu::Buffer,
    ) -> Launch {
        self.0
            .launch(ctx, dofs, 0, 0, &[step, acceleration, velocity])
    }
}
