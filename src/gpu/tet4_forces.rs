//! Host side of `shaders/tet4_forces.wgsl` (CPU twin: [`crate::kernels::tet4_forces`]).

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

/// The `tet4_forces` pipeline, built once per engine.
pub struct Tet4Forces(pub Kernel);

impl Tet4Forces {
    pub fn new(ctx: &GpuContext) -> Self {
        Tet4Forces(Kernel::new(ctx, "tet4_forces", shaders::TET4_FORCES))
    }

    /// Bind group in the shader's binding order (binding 0 is the params uniform).
    #[allow(clippy::too_many_arguments)]
    pub fn bind(
        &self,
        ctx: &GpuContext,
        reference: &wgpu::Buffer,
        displacement: &wgpu::Buffer,
        tets: &wgpu::Buffer,
        materials: &wgpu::Buffer,
        corner_forces: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        self.0.bind(
            ctx,
            &[reference, displacement, tets, materials, corner_forces],
        )
    }
}
