//! The totals of blocks of [`SCAN_BLOCK`] values (CPU twin of `shaders/scan_totals.wgsl`):
//! the first pass of the device's prefix sum over several blocks ([`super::prefix_sum`]).

/// Values per block (a 256-wide workgroup, four values per invocation).
pub const SCAN_BLOCK: usize = 1024;

pub fn scan_totals(values: &[u32]) -> Vec<u32> {
    values.chunks(SCAN_BLOCK).map(|b| b.iter().sum()).collect()
}
