//! The buffers of a counting sort on the device (`bucket_count`, `prefix_sum`,
//! `bucket_fill`): the contact search sorts faces by grid cell, the contact iteration sorts
//! pairs by primary face.

use super::buffer::Storage;
use super::context::GpuContext;
use crate::error::Result;

/// Each item's bucket key and rank within its bucket, the bucket sizes, the bucket starts
/// (one more than the buckets) and the items in bucket order.
pub(super) struct BucketSort {
    pub(super) keys: Storage,
    pub(super) ranks: Storage,
    pub(super) counts: Storage,
    pub(super) starts: Storage,
    pub(super) sorted: Storage,
}

impl BucketSort {
    /// Buffers for `items` items in `buckets` buckets, labelled keys, ranks, counts, starts
    /// and sorted by `labels`.
    pub(super) fn new(
        ctx: &GpuContext,
        labels: [&'static str; 5],
        items: usize,
        buckets: usize,
    ) -> Result<Self> {
        let words = |n: usize| (4 * n) as u64;
        Ok(BucketSort {
            keys: Storage::new(ctx, labels[0], words(items))?,
            ranks: Storage::new(ctx, labels[1], words(items))?,
            counts: Storage::new(ctx, labels[2], words(buckets))?,
            starts: Storage::new(ctx, labels[3], words(buckets + 1))?,
            sorted: Storage::new(ctx, labels[4], words(items))?,
        })
    }
}
