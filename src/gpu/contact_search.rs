//! Host side of `shaders/contact_search.wgsl` (CPU twin: [`crate::kernels::contact_search`]); bound and recorded by
//! [`super::search::GpuSearch`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct ContactSearch(pub Kernel);

impl ContactSearch {
    pub fn new(ctx: &GpuContext) -> Self {
        ContactSearch(Kernel::new(ctx, "contact_search", shaders::CONTACT_SEARCH))
    }
}
