//! Host side of `shaders/prefix_sum.wgsl` (CPU twin: [`crate::kernels::prefix_sum`]); bound and recorded by
//! [`super::search::GpuSearch`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct PrefixSum(pub Kernel);

impl PrefixSum {
    pub fn new(ctx: &GpuContext) -> Self {
        PrefixSum(Kernel::new(ctx, "prefix_sum", shaders::PREFIX_SUM))
    }
}
