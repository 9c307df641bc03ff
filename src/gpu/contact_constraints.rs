//! Host side of `shaders/contact_constraints.wgsl` (CPU twin: [`crate::kernels::contact_constraints`]); bound and
//! recorded by [`super::contact_iteration::ContactIteration`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct ContactConstraints(pub Kernel);

impl ContactConstraints {
    pub fn new(ctx: &GpuContext) -> Self {
        ContactConstraints(Kernel::new(
            ctx,
            "contact_constraints",
            shaders::CONTACT_CONSTRAINTS,
        ))
    }
}
