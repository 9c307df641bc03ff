//! Host side of `shaders/face_cells.wgsl` (CPU twin: [`crate::kernels::face_cells`]); bound and recorded by
//! [`super::search::GpuSearch`].

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

pub struct FaceCells(pub Kernel);

impl FaceCells {
    pub fn new(ctx: &GpuContext) -> Self {
        FaceCells(Kernel::new(ctx, "face_cells", shaders::FACE_CELLS))
    }
}
