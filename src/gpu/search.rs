//! [`GpuSearch`]: the contact search on the device. Broad phase: a uniform grid of cells at
//! least as large as a face's box plus the margin, hashed into a table of buckets; the faces
//! are bucket-sorted by the cell of their centroid (`face_cells`, `bucket_count`,
//! `prefix_sum`, `bucket_fill`), rebuilt at every search (the faces are few beside the
//! elements). Narrow phase: `contact_search`, one secondary node per invocation, over the 27
//! cells around it, with the host broad phase's candidate test (a face's box grown by the
//! margin holds the node) and `contact_gap`'s projection.

use super::buffer::{staging, submit_and_read, Storage};
use super::context::GpuContext;
use super::types::{self, ContactQuery, Quad};
use super::{BucketCount, BucketFill, ContactSearch, FaceCells, PrefixSum};
use crate::error::Result;
use crate::kernels::{ContactPoint, SearchGrid};

/// Buckets for `faces` faces: a power of two, at least twice as many.
pub fn table_size(faces: usize) -> usize {
    (2 * faces).next_power_of_two().max(64)
}

pub struct GpuSearch {
    face_cells: FaceCells,
    bucket_count: BucketCount,
    prefix_sum: PrefixSum,
    bucket_fill: BucketFill,
    contact_search: ContactSearch,
    grid: Storage,
    faces_buffer: Storage,
    counts: Storage,
    points: Storage,
    staging: Storage,
    keys: Storage,
    ranks: Storage,
    starts: Storage,
    sorted: Storage,
    // kept alive for the bind groups
    _buffers: Vec<Storage>,
    binds: [wgpu::BindGroup; 5],
    faces: usize,
    queries: usize,
    table: usize,
}

impl GpuSearch {
    /// `queries[i] = (secondary node, first face, end face)` of its interface;
    /// `face_first[f]` the first face of face f's interface.
    pub fn new(
        ctx: &GpuContext,
        reference: &wgpu::Buffer,
        displacement: &wgpu::Buffer,
        velocity: &wgpu::Buffer,
        faces: &[[u32; 4]],
        face_first: &[u32],
        queries: &[(u32, u32, u32)],
    ) -> Result<Self> {
        let table = table_size(faces.len());
        let quads: Vec<Quad> = faces.iter().map(|&nodes| Quad { nodes }).collect();
        let face_buf = Storage::with_data(ctx, "search.faces", &quads)?;
        let first_buf = Storage::with_data(ctx, "search.face_first", face_first)?;
        let q: Vec<ContactQuery> = queries
            .iter()
            .map(|&(secondary, first, end)| ContactQuery {
                secondary,
                first,
                end,
            })
            .collect();
        let query_buf = Storage::with_data(ctx, "search.queries", &q)?;
        let words = |n: usize| (4 * n) as u64;
        let keys = Storage::new(ctx, "search.keys", words(faces.len()))?;
        let ranks = Storage::new(ctx, "search.ranks", words(faces.len()))?;
        let counts = Storage::new(ctx, "search.counts", words(table))?;
        let starts = Storage::new(ctx, "search.starts", words(table + 1))?;
        let sorted = Storage::new(ctx, "search.sorted", words(faces.len()))?;
        let points = Storage::new(
            ctx,
            "search.points",
            (queries.len() * std::mem::size_of::<types::ContactPoint>()) as u64,
        )?;
        // a storage buffer: the host writes it (`record`) or a kernel does (the resident
        // step's `search_grid`)
        let grid = Storage::new(
            ctx,
            "search.grid",
            std::mem::size_of::<types::SearchGrid>() as u64,
        )?;
        let face_cells = FaceCells::new(ctx);
        let bucket_count = BucketCount::new(ctx);
        let prefix_sum = PrefixSum::new(ctx);
        let bucket_fill = BucketFill::new(ctx);
        let contact_search = ContactSearch::new(ctx);
        let binds = [
            face_cells.bind(
                ctx,
                &grid.buffer,
                reference,
                displacement,
                &face_buf.buffer,
                &first_buf.buffer,
                &keys.buffer,
            ),
            bucket_count.bind(ctx, &keys.buffer, &counts.buffer, &ranks.buffer),
            prefix_sum.bind(ctx, &counts.buffer, &starts.buffer),
            bucket_fill.bind(
                ctx,
                &keys.buffer,
                &ranks.buffer,
                &starts.buffer,
                &sorted.buffer,
            ),
            contact_search.bind(
                ctx,
                &grid.buffer,
                reference,
                displacement,
                velocity,
                &query_buf.buffer,
                &face_buf.buffer,
                &starts.buffer,
                &sorted.buffer,
                &points.buffer,
            ),
        ];
        // the counts never change: set them once
        face_cells.0.set_count(ctx, faces.len() as u32);
        bucket_count.0.set_count(ctx, faces.len() as u32);
        prefix_sum.0.set_count(ctx, table as u32);
        bucket_fill.0.set_count(ctx, faces.len() as u32);
        contact_search.0.set_count(ctx, queries.len() as u32);
        Ok(GpuSearch {
            face_cells,
            bucket_count,
            prefix_sum,
            bucket_fill,
            contact_search,
            grid,
            counts,
            points,
            staging: staging(ctx)?,
            keys,
            ranks,
            starts,
            sorted,
            faces_buffer: face_buf,
            _buffers: vec![first_buf, query_buf],
            binds,
            faces: faces.len(),
            queries: queries.len(),
            table,
        })
    }

    /// Records a whole search with `grid` (set now, applied at the next submission).
    pub fn record(&self, ctx: &GpuContext, enc: &mut wgpu::CommandEncoder, grid: SearchGrid) {
        let g = types::SearchGrid {
            cell: grid.cell as f32,
            margin: grid.margin as f32,
            mask: (self.table - 1) as u32,
            pad: 0,
        };
        ctx.queue
            .write_buffer(&self.grid.buffer, 0, bytemuck::bytes_of(&g));
        self.record_stages(enc);
    }

    /// Records a whole search with the grid already in [`Self::grid_buffer`] when it runs.
    pub fn record_stages(&self, enc: &mut wgpu::CommandEncoder) {
        enc.clear_buffer(&self.counts.buffer, 0, None);
        let f = self.faces as u32;
        self.face_cells
            .0
            .record(enc, &self.binds[0], self.face_cells.0.grid(f));
        self.bucket_count
            .0
            .record(enc, &self.binds[1], self.bucket_count.0.grid(f));
        // one workgroup scans the whole table
        self.prefix_sum.0.record(enc, &self.binds[2], [1, 1]);
        self.bucket_fill
            .0
            .record(enc, &self.binds[3], self.bucket_fill.0.grid(f));
        self.contact_search.0.record(
            enc,
            &self.binds[4],
            self.contact_search.0.grid(self.queries as u32),
        );
    }

    /// The search grid ([`types::SearchGrid`]) the stages read.
    pub fn grid_buffer(&self) -> &wgpu::Buffer {
        &self.grid.buffer
    }

    /// The contact point of each query after a search.
    pub fn points_buffer(&self) -> &wgpu::Buffer {
        &self.points.buffer
    }

    /// The primary faces ([`types::Quad`]).
    pub fn faces_buffer(&self) -> &wgpu::Buffer {
        &self.faces_buffer.buffer
    }

    /// The table's mask (buckets - 1).
    pub fn mask(&self) -> u32 {
        (self.table - 1) as u32
    }

    /// The last search's sort, for the kernel tests: each face's key and rank, the bucket
    /// sizes, the bucket starts (one more than buckets) and the sorted faces.
    pub fn read_sort(&mut self, ctx: &GpuContext) -> Result<[Vec<u32>; 5]> {
        let f = self.faces;
        let t = self.table;
        let mut read = |b: &Storage, n: usize| -> Result<Vec<u32>> {
            let enc = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("search.read"),
                });
            submit_and_read(ctx, &mut self.staging, enc, &b.buffer, n)
        };
        Ok([
            read(&self.keys, f)?,
            read(&self.ranks, f)?,
            read(&self.counts, t)?,
            read(&self.starts, t + 1)?,
            read(&self.sorted, f)?,
        ])
    }

    /// Runs a search after `enc`'s work and reads the contact points back.
    pub fn run(
        &mut self,
        ctx: &GpuContext,
        mut enc: wgpu::CommandEncoder,
        grid: SearchGrid,
    ) -> Result<Vec<ContactPoint>> {
        self.record(ctx, &mut enc, grid);
        let pts: Vec<types::ContactPoint> = submit_and_read(
            ctx,
            &mut self.staging,
            enc,
            &self.points.buffer,
            self.queries,
        )?;
        Ok(pts.into_iter().map(ContactPoint::from).collect())
    }
}
