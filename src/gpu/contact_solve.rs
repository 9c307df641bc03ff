//! Host side of `shaders/contact_solve.wgsl` (CPU twin: [`crate::kernels::contact_solve`]);
//! bound and recorded by [`super::contact_iteration::ContactIteration`] for contact sets of
//! at most [`MAX_PAIRS`] pairs.

use super::context::GpuContext;
use super::kernel::Kernel;
use super::shaders;

/// The largest contact set one workgroup sweeps: beyond it three dispatches a sweep over
/// the whole device are faster (about (pairs + 2 nodes) / group microseconds a sweep in
/// one workgroup, against about 15 for a dispatch on an H100).
pub const MAX_PAIRS: usize = 1 << 15;

pub struct ContactSolve {
    pub kernel: Kernel,
    /// Invocations of its one workgroup.
    pub group: u32,
}

impl ContactSolve {
    pub fn new(ctx: &GpuContext) -> Self {
        let group = group_size(&ctx.limits, ctx.adapter.software);
        ContactSolve {
            kernel: Kernel::with_constants(
                ctx,
                "contact_solve",
                shaders::CONTACT_SOLVE,
                &[("SOLVE_GROUP", group as f64)],
            ),
            group,
        }
    }
}

/// The largest power of two up to 1024 (the kernel's workgroup memory) that the adapter
/// runs in one workgroup; on software adapters at most 512 (lavapipe, Mesa 22.3, runs the
/// kernel wrong with 1024: its iteration never converged in the twin test, while 64 to 512
/// match the twin).
pub fn group_size(limits: &wgpu::Limits, software: bool) -> u32 {
    let most = limits
        .max_compute_invocations_per_workgroup
        .min(limits.max_compute_workgroup_size_x)
        .clamp(64, if software { 512 } else { 1024 });
    1 << (31 - most.leading_zeros())
}
