//! Host side of `shaders/tet4_forces.wgsl` (CPU twin: [`crate::kernels::tet4_forces`]); its launch and
//! buffer layouts are built by [`super::GpuKernels`] (see [`super::engine::ElementColumns`]).

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

/// The `tet4_forces` pipeline, built once per engine.
pub struct Tet4Forces(pub Kernel);

impl Tet4Forces {
    pub fn new(ctx: &GpuContext) -> Self {
        Tet4Forces(Kernel::new(ctx, "tet4_forces", shaders::TET4_FORCES))
    }
}
