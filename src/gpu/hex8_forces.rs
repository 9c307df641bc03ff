//! Host side of `shaders/hex8_forces.wgsl` (CPU twin: [`crate::kernels::hex8_forces`]).

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

/// The `hex8_forces` pipeline, built once per engine.
pub struct Hex8Forces(pub Kernel);

impl Hex8Forces {
    pub fn new(ctx: &GpuContext) -> Self {
        Hex8Forces(Kernel::new(ctx, "hex8_forces", shaders::HEX8_FORCES))
    }

    /// Bind group in the shader's binding order (binding 0 is the params uniform).
    #[allow(clippy::too_many_arguments)]
    pub fn bind(
        &self,
        ctx: &GpuContext,
        reference: &wgpu::Buffer,
        displacement: &wgpu::Buffer,
        hexes: &wgpu::Buffer,
        materials: &wgpu::Buffer,
        corner_forces: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        self.0.bind(
            ctx,
            &[reference, displacement, hexes, materials, corner_forces],
        )
    }
}
