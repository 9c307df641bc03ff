//! Host side of `shaders/sweep_control.wgsl` (CPU twin: [`crate::kernels::sweep_control`]); bound and
//! recorded by [`super::contact_iteration::ContactIteration`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct SweepControl(pub Kernel);

impl SweepControl {
    pub fn new(ctx: &GpuContext) -> Self {
        SweepControl(Kernel::new(ctx, "sweep_control", shaders::SWEEP_CONTROL))
    }
}
