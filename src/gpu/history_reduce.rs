//! Host side of `shaders/history_reduce.wgsl` (CPU twin: [`crate::kernels::history_reduce`]).

use super::context::GpuContext;
use super::kernel::{Kernel, Launch, WORKGROUP};
use super::shaders;

pub struct HistoryReduce(pub Kernel);

/// The buffers of a `history_reduce` launch, in the shader's binding order.
pub struct HistoryReduceBuffers<'a> {
    pub columns: &'a wgpu::Buffer,
    pub partials: &'a wgpu::Buffer,
    pub results: &'a wgpu::Buffer,
    pub displacement: &'a wgpu::Buffer,
    pub velocity: &'a wgpu::Buffer,
    /// The rows of a submission; this launch writes the row at float `first`.
    pub rows: &'a wgpu::Buffer,
}

impl HistoryReduce {
    pub fn new(ctx: &GpuContext) -> Self {
        HistoryReduce(Kernel::new(ctx, "history_reduce", shaders::HISTORY_REDUCE))
    }

    /// A launch of one workgroup per column that writes its row at `rows[first..]`.
    pub fn launch(
        &self,
        ctx: &GpuContext,
        columns: u32,
        first: u32,
        b: &HistoryReduceBuffers,
    ) -> Launch {
        // Params.count is the column count; the grid has one workgroup per column
        let mut l = self.0.launch(
            ctx,
            columns * WORKGROUP,
            first,
            0,
            &[
                b.columns,
                b.partials,
                b.results,
                b.displacement,
                b.velocity,
                b.rows,
            ],
        );
        l.set_count(ctx, columns, first);
        l
    }
}
