//! Storage buffers that grow on demand, and the read-back path.

use std::sync::mpsc;

use super::context::GpuContext;
use crate::error::{ImpactError, Result};

/// A storage buffer with room for `capacity` bytes; [`Self::ensure`] replaces it with a larger
/// one when needed (and says so, so that bind groups can be rebuilt).
pub struct Storage {
    pub buffer: wgpu::Buffer,
    pub capacity: u64,
    label: &'static str,
    usage: wgpu::BufferUsages,
}

/// Every buffer has at least this many bytes (a binding cannot be empty).
const MIN_BYTES: u64 = 32;

/// The bytes a buffer asked for `bytes` holds.
pub fn padded_bytes(bytes: u64) -> u64 {
    bytes.max(MIN_BYTES).next_multiple_of(16)
}

impl Storage {
    pub fn new(ctx: &GpuContext, label: &'static str, bytes: u64) -> Result<Self> {
        Self::with_usage(
            ctx,
            label,
            bytes,
            wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
        )
    }

    pub fn with_usage(
        ctx: &GpuContext,
        label: &'static str,
        bytes: u64,
        usage: wgpu::BufferUsages,
    ) -> Result<Self> {
        let capacity = padded_bytes(bytes);
        if usage.contains(wgpu::BufferUsages::STORAGE) && capacity > ctx.max_binding() {
            return Err(ImpactError::Gpu(format!(
                "{}: buffer `{label}` needs {capacity} bytes but the adapter binds at most {} bytes; use a smaller mesh or device = \"cpu\"",
                ctx.adapter.name,
                ctx.max_binding()
            )));
        }
        let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: capacity,
            usage,
            mapped_at_creation: false,
        });
        Ok(Storage {
            buffer,
            capacity,
            label,
            usage,
        })
    }

    /// A storage buffer holding `data`.
    pub fn with_data<T: bytemuck::Pod>(
        ctx: &GpuContext,
        label: &'static str,
        data: &[T],
    ) -> Result<Self> {
        let mut s = Self::new(ctx, label, std::mem::size_of_val(data) as u64)?;
        s.upload(ctx, data)?;
        Ok(s)
    }

    /// Makes room for `bytes`; true if the buffer was replaced.
    pub fn ensure(&mut self, ctx: &GpuContext, bytes: u64) -> Result<bool> {
        if bytes <= self.capacity {
            return Ok(false);
        }
        *self = Self::with_usage(ctx, self.label, bytes.max(2 * self.capacity), self.usage)?;
        Ok(true)
    }

    /// Uploads `data` at the start (growing first if needed); true if the buffer was replaced.
    pub fn upload<T: bytemuck::Pod>(&mut self, ctx: &GpuContext, data: &[T]) -> Result<bool> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let grew = self.ensure(ctx, bytes.len() as u64)?;
        if !bytes.is_empty() {
            ctx.queue.write_buffer(&self.buffer, 0, bytes);
        }
        Ok(grew)
    }

    /// Fills the first `bytes` with f32 NaN (the kernel tests use this so that an entry a
    /// kernel fails to write cannot pass).
    pub fn fill_nan(&self, ctx: &GpuContext, bytes: u64) {
        let words = (bytes.min(self.capacity) / 4) as usize;
        let nan = vec![f32::NAN.to_bits(); words];
        ctx.queue
            .write_buffer(&self.buffer, 0, bytemuck::cast_slice(&nan));
    }
}

/// Copies `bytes` of `source` to the host after `encoder`'s work, submitting it.
pub(crate) fn submit_and_read<T: bytemuck::Pod>(
    ctx: &GpuContext,
    staging: &mut Storage,
    encoder: wgpu::CommandEncoder,
    source: &wgpu::Buffer,
    count: usize,
) -> Result<Vec<T>> {
    submit_and_read_parts(ctx, staging, encoder, &[(source, count)])
}

/// [`submit_and_read`] of the first `count` values of each `(source, count)`, one after the
/// other, in one mapping (one wait for the device).
pub(crate) fn submit_and_read_parts<T: bytemuck::Pod>(
    ctx: &GpuContext,
    staging: &mut Storage,
    mut encoder: wgpu::CommandEncoder,
    parts: &[(&wgpu::Buffer, usize)],
) -> Result<Vec<T>> {
    let size = std::mem::size_of::<T>() as u64;
    let bytes: u64 = parts.iter().map(|&(_, n)| n as u64 * size).sum();
    staging.ensure(ctx, bytes)?;
    let mut at = 0;
    for &(source, count) in parts {
        let b = count as u64 * size;
        if b > 0 {
            encoder.copy_buffer_to_buffer(source, 0, &staging.buffer, at, b);
        }
        at += b;
    }
    ctx.queue.submit([encoder.finish()]);
    if bytes == 0 {
        return Ok(Vec::new());
    }
    let mapping = map_read(&staging.buffer, bytes);
    ctx.wait()?;
    take_mapped(
        ctx,
        &staging.buffer,
        bytes,
        &mapping,
        "the read-back buffer",
    )
}

/// The receiving end of a [`map_read`]: says when the mapping is done, or why it failed.
pub(crate) type Mapping = mpsc::Receiver<std::result::Result<(), wgpu::BufferAsyncError>>;

/// Starts mapping the first `bytes` of `buffer` for reading (done once the device has run
/// the submissions before); [`take_mapped`] copies them out.
pub(crate) fn map_read(buffer: &wgpu::Buffer, bytes: u64) -> Mapping {
    let (tx, rx) = mpsc::channel();
    buffer
        .slice(..bytes)
        .map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
    rx
}

/// The first `bytes` of `buffer`, mapped by [`map_read`] (after the device has been waited
/// for), copied out; then unmaps `buffer`. `what` names the buffer in the errors.
pub(crate) fn take_mapped<T: bytemuck::Pod>(
    ctx: &GpuContext,
    buffer: &wgpu::Buffer,
    bytes: u64,
    mapping: &Mapping,
    what: &str,
) -> Result<Vec<T>> {
    mapping
        .recv()
        .map_err(|_| ImpactError::Gpu("read-back callback dropped".into()))?
        .map_err(|e| ImpactError::Gpu(format!("{}: cannot map {what}: {e}", ctx.adapter.name)))?;
    let out = {
        let view = buffer
            .slice(..bytes)
            .get_mapped_range()
            .map_err(|e| ImpactError::Gpu(format!("cannot read {what} back: {e}")))?;
        bytemuck::pod_collect_to_vec::<u8, T>(&view)
    };
    buffer.unmap();
    Ok(out)
}

/// Reads `count` values of `source` back in a submission of its own (named `label`).
pub(crate) fn read_back<T: bytemuck::Pod>(
    ctx: &GpuContext,
    staging: &mut Storage,
    label: &str,
    source: &wgpu::Buffer,
    count: usize,
) -> Result<Vec<T>> {
    submit_and_read(ctx, staging, ctx.encoder(label), source, count)
}

/// [`read_back`] of `count` f32 values, as f64.
pub(crate) fn read_floats(
    ctx: &GpuContext,
    staging: &mut Storage,
    label: &str,
    source: &wgpu::Buffer,
    count: usize,
) -> Result<Vec<f64>> {
    let x: Vec<f32> = read_back(ctx, staging, label, source, count)?;
    Ok(x.into_iter().map(f64::from).collect())
}

/// A staging buffer for read-back.
pub(crate) fn staging(ctx: &GpuContext) -> Result<Storage> {
    Storage::with_usage(
        ctx,
        "readback",
        1 << 16,
        wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
    )
}
