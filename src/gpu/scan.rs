//! [`Scan`]: the exclusive prefix sum of a buffer of counts on the device (`scan_totals`,
//! then `prefix_sum`), one 256-wide workgroup per block of 1,024 counts: the counting sorts
//! of the contact search and of the contact iteration turn their bucket sizes into bucket
//! starts with it. A single block needs no first pass.

use super::buffer::Storage;
use super::context::GpuContext;
use super::kernel::Launch;
use super::{PrefixSum, ScanTotals};
use crate::error::{ImpactError, Result};
use crate::kernels::SCAN_BLOCK;

/// The scan of `n` values of one buffer into another, its pipelines and launches built once.
pub struct Scan {
    totals_kernel: ScanTotals,
    prefix_kernel: PrefixSum,
    /// The first pass, where there is more than one block.
    totals: Option<Launch>,
    prefix: Launch,
    pub(super) blocks: u32,
    /// Each block's total (written by the first pass).
    pub(super) block_totals: Storage,
}

impl Scan {
    /// The scan of the `n` values of `values` into `starts` (n + 1 entries).
    pub fn new(
        ctx: &GpuContext,
        values: &wgpu::Buffer,
        starts: &wgpu::Buffer,
        n: usize,
    ) -> Result<Self> {
        let blocks = n.div_ceil(SCAN_BLOCK).max(1);
        let most = ctx.limits.max_compute_workgroups_per_dimension as usize;
        if blocks > most {
            return Err(ImpactError::Gpu(format!(
                "a prefix sum of {n} values needs {blocks} workgroups in a row; the adapter allows {most}"
            )));
        }
        let block_totals = Storage::new(ctx, "scan.totals", 4 * blocks as u64)?;
        let totals_kernel = ScanTotals::new(ctx);
        let prefix_kernel = PrefixSum::new(ctx);
        let totals = (blocks > 1)
            .then(|| totals_kernel.launch(ctx, n as u32, 0, 0, values, &block_totals.buffer));
        let prefix =
            prefix_kernel.launch(ctx, n as u32, 0, 0, values, &block_totals.buffer, starts);
        Ok(Scan {
            totals_kernel,
            prefix_kernel,
            totals,
            prefix,
            blocks: blocks as u32,
            block_totals,
        })
    }

    /// Dispatches the scan inside an open compute pass: a workgroup per block.
    pub fn dispatch(&self, pass: &mut wgpu::ComputePass) {
        if let Some(t) = &self.totals {
            self.totals_kernel
                .0
                .dispatch_with(pass, &t.bind, [self.blocks, 1]);
        }
        self.prefix_kernel
            .0
            .dispatch_with(pass, &self.prefix.bind, [self.blocks, 1]);
    }
}
