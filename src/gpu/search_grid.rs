//! Host side of `shaders/search_grid.wgsl` (CPU twin: [`crate::kernels::search_grid`]); bound and
//! recorded by [`super::contact_iteration::ContactIteration`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct SearchGridKernel(pub Kernel);

impl SearchGridKernel {
    pub fn new(ctx: &GpuContext) -> Self {
        SearchGridKernel(Kernel::new(ctx, "search_grid", shaders::SEARCH_GRID))
    }
}
