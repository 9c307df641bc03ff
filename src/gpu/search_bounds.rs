//! Host side of `shaders/search_bounds.wgsl` (CPU twin: [`crate::kernels::search_bounds`]); bound and
//! recorded by [`super::contact_iteration::ContactIteration`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct SearchBounds(pub Kernel);

impl SearchBounds {
    pub fn new(ctx: &GpuContext) -> Self {
        SearchBounds(Kernel::new(ctx, "search_bounds", shaders::SEARCH_BOUNDS))
    }
}
