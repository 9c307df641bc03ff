//! Host side of `shaders/bucket_count.wgsl` (CPU twin: [`crate::kernels::bucket_count`]); bound and recorded by
//! [`super::search::GpuSearch`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct BucketCount(pub Kernel);

impl BucketCount {
    pub fn new(ctx: &GpuContext) -> Self {
        BucketCount(Kernel::new(ctx, "bucket_count", shaders::BUCKET_COUNT))
    }
}
