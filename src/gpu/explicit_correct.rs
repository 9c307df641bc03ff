//! Host side of `shaders/explicit_correct.wgsl` (CPU twin: [`crate::kernels::explicit_correct`]).

use super::context::GpuContext;
use super::kernel::{Kernel, Launch};
use super::shaders;

pub struct ExplicitCorrect(pub Kernel);

/// The buffers of an `explicit_correct` launch, in the shader's binding order.
pub struct ExplicitCorrectBuffers<'a> {
    pub step: &'a wgpu::Buffer,
    pub displacement: &'a wgpu::Buffer,
    pub forces: &'a wgpu::Buffer,
    pub lumped: &'a wgpu::Buffer,
    pub velocity: &'a wgpu::Buffer,
    pub acceleration: &'a wgpu::Buffer,
    pub partials: &'a wgpu::Buffer,
}

impl ExplicitCorrect {
    pub fn new(ctx: &GpuContext) -> Self {
        ExplicitCorrect(Kernel::new(
            ctx,
            "explicit_correct",
            shaders::EXPLICIT_CORRECT,
        ))
    }

    /// A launch over nodes `first..first + count`, writing its workgroups' sums from
    /// workgroup slot `base` of the partials on.
    pub fn launch(
        &self,
        ctx: &GpuContext,
        first: u32,
        count: u32,
        base: u32,
        b: &ExplicitCorrectBuffers,
    ) -> Launch {
        self.0.launch(
            ctx,
            count,
            first,
            base,
            &[
                b.step,
                b.displacement,
                b.forces,
                b.lumped,
                b.velocity,
                b.acceleration,
                b.partials,
            ],
        )
    }
}
