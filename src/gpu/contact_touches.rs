//! Host side of `shaders/contact_touches.wgsl` (CPU twin: [`crate::kernels::contact_touches`]); bound and
//! recorded by [`super::contact_iteration::ContactIteration`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct ContactTouches(pub Kernel);

impl ContactTouches {
    pub fn new(ctx: &GpuContext) -> Self {
        ContactTouches(Kernel::new(
            ctx,
            "contact_touches",
            shaders::CONTACT_TOUCHES,
        ))
    }
}
