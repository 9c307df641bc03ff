//! Host side of `shaders/bucket_fill.wgsl` (CPU twin: [`crate::kernels::bucket_fill`]); bound and recorded by
//! [`super::search::GpuSearch`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct BucketFill(pub Kernel);

impl BucketFill {
    pub fn new(ctx: &GpuContext) -> Self {
        BucketFill(Kernel::new(ctx, "bucket_fill", shaders::BUCKET_FILL))
    }
}
