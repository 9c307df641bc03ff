//! Host side of `shaders/bucket_order.wgsl` (CPU twin: [`crate::kernels::bucket_order`]);
//! bound and recorded by [`super::contact_iteration::ContactIteration`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct BucketOrder(pub Kernel);

impl BucketOrder {
    pub fn new(ctx: &GpuContext) -> Self {
        BucketOrder(Kernel::new(ctx, "bucket_order", shaders::BUCKET_ORDER))
    }
}
