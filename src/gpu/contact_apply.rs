//! Host side of `shaders/contact_apply.wgsl` (CPU twin: [`crate::kernels::contact_apply`]); bound and
//! recorded by [`super::contact_iteration::ContactIteration`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct ContactApply(pub Kernel);

impl ContactApply {
    pub fn new(ctx: &GpuContext) -> Self {
        ContactApply(Kernel::new(ctx, "contact_apply", shaders::CONTACT_APPLY))
    }
}
