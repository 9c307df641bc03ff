//! [`capture`]: the dispatches a recording makes, each with its kernel's name, pipeline,
//! bind group and grid, so that the benchmarks can replay a submission's dispatches in their
//! order with a timestamp after each ([`super::ResidentStep::profile_dispatches`]). Every
//! dispatch goes through
//! [`super::kernel::Kernel::dispatch_with`], which notes it here while a capture is open on
//! its thread; outside a capture noting costs one thread-local check.

use std::cell::RefCell;

/// One dispatch as a recording made it.
#[derive(Clone)]
pub struct Captured {
    pub name: &'static str,
    pipeline: wgpu::ComputePipeline,
    bind: wgpu::BindGroup,
    pub grid: [u32; 2],
}

impl Captured {
    /// Dispatches it again inside an open compute pass.
    pub fn dispatch(&self, pass: &mut wgpu::ComputePass) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind, &[]);
        pass.dispatch_workgroups(self.grid[0], self.grid[1], 1);
    }

    /// Workgroups dispatched.
    pub fn groups(&self) -> u32 {
        self.grid[0] * self.grid[1]
    }
}

thread_local! {
    static OPEN: RefCell<Option<Vec<Captured>>> = const { RefCell::new(None) };
}

/// Runs `record` and returns the dispatches it made on this thread, in order (they are
/// recorded as usual too).
pub fn capture(record: impl FnOnce()) -> Vec<Captured> {
    OPEN.with_borrow_mut(|open| *open = Some(Vec::new()));
    record();
    OPEN.with_borrow_mut(Option::take).unwrap_or_default()
}

/// Notes a dispatch where a capture is open.
pub(super) fn note(
    name: &'static str,
    pipeline: &wgpu::ComputePipeline,
    bind: &wgpu::BindGroup,
    grid: [u32; 2],
) {
    OPEN.with_borrow_mut(|open| {
        if let Some(list) = open {
            list.push(Captured {
                name,
                pipeline: pipeline.clone(),
                bind: bind.clone(),
                grid,
            });
        }
    });
}
