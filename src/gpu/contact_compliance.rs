//! Host side of `shaders/contact_compliance.wgsl` (CPU twin: [`crate::kernels::contact_compliance`]); bound and
//! recorded by [`super::contact_iteration::ContactIteration`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct ContactCompliance(pub Kernel);

impl ContactCompliance {
    pub fn new(ctx: &GpuContext) -> Self {
        ContactCompliance(Kernel::new(
            ctx,
            "contact_compliance",
            shaders::CONTACT_COMPLIANCE,
        ))
    }
}
