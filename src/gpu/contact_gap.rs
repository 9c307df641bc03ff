//! Host side of `shaders/contact_gap.wgsl` (CPU twin: [`crate::kernels::contact_gap`]).

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

/// The `contact_gap` pipeline, built once per engine.
pub struct ContactGap(pub Kernel);

impl ContactGap {
    pub fn new(ctx: &GpuContext) -> Self {
        ContactGap(Kernel::new(ctx, "contact_gap", shaders::CONTACT_GAP))
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
        candidates: &wgpu::Buffer,
        faces: &wgpu::Buffer,
        points: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        self.0.bind(
            ctx,
            &[
                reference,
                displacement,
                velocity,
                queries,
                candidates,
                faces,
                points,
            ],
        )
    }
}
