//! Host side of `shaders/slip_rate.wgsl` (CPU twin: [`crate::kernels::slip_rate`]).

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

/// The `slip_rate` pipeline, built once per engine.
pub struct SlipRate(pub Kernel);

impl SlipRate {
    pub fn new(ctx: &GpuContext) -> Self {
        SlipRate(Kernel::new(ctx, "slip_rate", shaders::SLIP_RATE))
    }

    /// Bind group in the shader's binding order (binding 0 is the params uniform).
    #[allow(clippy::too_many_arguments)]
    pub fn bind(
        &self,
        ctx: &GpuContext,
        reference: &wgpu::Buffer,
        displacement: &wgpu::Buffer,
        velocity: &wgpu::Buffer,
        queries: &wgpu::Buffer,
        faces: &wgpu::Buffer,
        points: &wgpu::Buffer,
        slip: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        self.0.bind(
            ctx,
            &[
                reference,
                displacement,
                velocity,
                queries,
                faces,
                points,
                slip,
            ],
        )
    }
}
