//! Host side of `shaders/hex8_forces.wgsl` (CPU twin: [`crate::kernels::hex8_forces`]); its launch and
//! buffer layouts are built by [`super::GpuKernels`] (see [`super::engine::ElementColumns`]).

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

/// The `hex8_forces` pipeline, built once per engine.
pub struct Hex8Forces(pub Kernel);

impl Hex8Forces {
    pub fn new(ctx: &GpuContext) -> Self {
        Hex8Forces(Kernel::new(ctx, "hex8_forces", shaders::HEX8_FORCES))
    }
}
