//! Host side of `shaders/contact_sweep.wgsl` (CPU twin: [`crate::kernels::contact_sweep`]); bound and
//! recorded by [`super::contact_iteration::ContactIteration`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct ContactSweep(pub Kernel);

impl ContactSweep {
    pub fn new(ctx: &GpuContext) -> Self {
        ContactSweep(Kernel::new(ctx, "contact_sweep", shaders::CONTACT_SWEEP))
    }
}
