//! Host side of `shaders/contact_report.wgsl` (CPU twin: [`crate::kernels::contact_report`]); bound and
//! recorded by [`super::contact_iteration::ContactIteration`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct ContactReportKernel(pub Kernel);

impl ContactReportKernel {
    pub fn new(ctx: &GpuContext) -> Self {
        ContactReportKernel(Kernel::new(ctx, "contact_report", shaders::CONTACT_REPORT))
    }
}
