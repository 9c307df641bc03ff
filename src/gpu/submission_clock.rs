//! [`SubmissionClock`]: the device's own time for each submission of the resident step, from
//! timestamps written at the start and the end of its one compute pass, where the adapter
//! has timestamp queries. The resident solver's trial of the contact iteration's forms
//! compares them (`integrate::form_trial`), and `summary.json` sums them (`device_seconds`).

use super::buffer::Storage;
use super::context::GpuContext;
use crate::error::Result;

/// Bytes a submission's two timestamps take in its read-back buffer.
pub const STAMP_BYTES: u64 = 16;

/// Two timestamps for each of the two read-back slots, and the buffer they resolve into.
pub struct SubmissionClock {
    set: wgpu::QuerySet,
    resolved: Storage,
    /// Nanoseconds per timestamp tick.
    period: f64,
}

impl SubmissionClock {
    /// The clock, or `None` where the device has no timestamp queries.
    pub fn new(ctx: &GpuContext) -> Result<Option<Self>> {
        if !ctx.has_timestamps() {
            return Ok(None);
        }
        let set = ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("submission_clock"),
            ty: wgpu::QueryType::Timestamp,
            count: 4,
        });
        // each slot's pair at its own resolve offset (a multiple of 256 bytes)
        let resolved = Storage::with_usage(
            ctx,
            "submission_clock",
            wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT + STAMP_BYTES,
            wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        )?;
        Ok(Some(SubmissionClock {
            set,
            resolved,
            period: ctx.queue.get_timestamp_period() as f64,
        }))
    }

    /// The timestamp writes of slot `slot`'s compute pass.
    pub fn writes(&self, slot: usize) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: Some(2 * slot as u32),
            end_of_pass_write_index: Some(2 * slot as u32 + 1),
        }
    }

    /// Resolves slot `slot`'s timestamps after its pass and copies them to `target` at
    /// `offset` ([`STAMP_BYTES`]).
    pub fn copy(
        &self,
        enc: &mut wgpu::CommandEncoder,
        slot: usize,
        target: &wgpu::Buffer,
        offset: u64,
    ) {
        let at = self.resolve(enc, slot);
        enc.copy_buffer_to_buffer(&self.resolved.buffer, at, target, offset, STAMP_BYTES);
    }

    /// Resolves slot `slot`'s timestamps after its pass; returns their offset in the
    /// resolve buffer (0 for slot 0: [`Self::first_slot`] reads them from there).
    pub fn resolve(&self, enc: &mut wgpu::CommandEncoder, slot: usize) -> u64 {
        let at = slot as u64 * wgpu::QUERY_RESOLVE_BUFFER_ALIGNMENT;
        let first = 2 * slot as u32;
        enc.resolve_query_set(&self.set, first..first + 2, &self.resolved.buffer, at);
        at
    }

    /// Slot 0's resolved timestamps as a read-back part: the buffer and its four words.
    pub fn first_slot(&self) -> (&wgpu::Buffer, usize) {
        (&self.resolved.buffer, (STAMP_BYTES / 4) as usize)
    }

    /// Seconds between a pass's two timestamps (their four words as read back); `None` where
    /// they do not run forward (a device whose clock was reset between them).
    pub fn seconds(&self, words: &[u32]) -> Option<f64> {
        let stamp = |w: &[u32]| w[0] as u64 | (w[1] as u64) << 32;
        let (start, end) = (stamp(&words[0..2]), stamp(&words[2..4]));
        (end > start).then(|| (end - start) as f64 * self.period * 1e-9)
    }
}
