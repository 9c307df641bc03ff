//! [`GpuSearch`]: the contact search on the device. Broad phase: a uniform grid of cells at
//! least as large as a face's box plus the margin, hashed into a table of buckets; the faces
//! are bucket-sorted by the cell of their centre (`face_cells`, `bucket_count`,
//! `prefix_sum`, `bucket_fill`). Narrow phase: `contact_search`, one secondary node per
//! invocation, over the 27 cells around it, with the host broad phase's candidate test (a
//! face's box grown by the margin holds the node) and `contact_gap`'s projection. The host
//! loop sorts the faces at every search; the resident step keeps a sort across steps while
//! the grid holds (`search_grid`: the cells have a skin, and the faces' centres are kept to
//! measure their drift), so that most of its steps run the narrow phase alone.

use super::bucket_sort::BucketSort;
use super::buffer::{staging, submit_and_read, Storage};
use super::context::GpuContext;
use super::kernel::Launch;
use super::scan::Scan;
use super::types::{self, to_device, ContactQuery, Quad};
use super::{BucketCount, BucketFill, ContactSearch, FaceCells, FillWords};
use crate::error::Result;
use crate::kernels::{ContactPoint, SearchGrid};

/// Buckets for `faces` faces: a power of two, at least twice as many.
pub(crate) fn table_size(faces: usize) -> usize {
    (2 * faces).next_power_of_two().max(64)
}

/// The search's kernels, built once.
struct SearchKernels {
    fill_words: FillWords,
    face_cells: FaceCells,
    bucket_count: BucketCount,
    bucket_fill: BucketFill,
    contact_search: ContactSearch,
}

impl SearchKernels {
    fn new(ctx: &GpuContext) -> Self {
        SearchKernels {
            fill_words: FillWords::new(ctx),
            face_cells: FaceCells::new(ctx),
            bucket_count: BucketCount::new(ctx),
            bucket_fill: BucketFill::new(ctx),
            contact_search: ContactSearch::new(ctx),
        }
    }

    /// Sets the item counts, which never change: `faces` faces, `table` buckets, `queries`
    /// queries.
    fn set_counts(&self, ctx: &GpuContext, faces: usize, table: usize, queries: usize) {
        self.fill_words.0.set_count(ctx, table as u32);
        self.face_cells.0.set_count(ctx, faces as u32);
        self.bucket_count.0.set_count(ctx, faces as u32);
        self.bucket_fill.0.set_count(ctx, faces as u32);
        self.contact_search.0.set_count(ctx, queries as u32);
    }
}

/// The search's buffers: the faces and the queries, uploaded once, the grid, and what the
/// stages write.
pub(super) struct SearchBuffers {
    grid: Storage,
    faces: Storage,
    face_first: Storage,
    queries: Storage,
    /// The faces sorted by the grid cell of their centre, and the centres at that sort.
    pub(super) sort: BucketSort,
    centres: Storage,
    /// The faces' boxes at the current displacement ([`types::FaceBox`]).
    pub(super) boxes: Storage,
    points: Storage,
}

impl SearchBuffers {
    /// Uploads the faces and the queries (see [`GpuSearch::new`]) and allocates the rest for
    /// a table of `table` buckets.
    fn new(
        ctx: &GpuContext,
        faces: &[[u32; 4]],
        face_first: &[u32],
        queries: &[(u32, u32, u32)],
        table: usize,
    ) -> Result<Self> {
        let nf = faces.len();
        let point_bytes = queries.len() * std::mem::size_of::<types::GpuContactPoint>();
        Ok(SearchBuffers {
            // a storage buffer: the host writes it (`record`) or kernels do (the resident
            // step's `search_grid`, or its narrow phase on a step that keeps the sort)
            grid: Storage::new(
                ctx,
                "search.grid",
                std::mem::size_of::<types::GpuSearchGrid>() as u64,
            )?,
            faces: Storage::with_data(ctx, "search.faces", &to_device::<_, Quad>(faces))?,
            face_first: Storage::with_data(ctx, "search.face_first", face_first)?,
            queries: Storage::with_data(
                ctx,
                "search.queries",
                &to_device::<_, ContactQuery>(queries),
            )?,
            sort: BucketSort::new(
                ctx,
                [
                    "search.keys",
                    "search.ranks",
                    "search.counts",
                    "search.starts",
                    "search.sorted",
                ],
                nf,
                table,
            )?,
            centres: Storage::new(ctx, "search.centres", (12 * nf.max(1)) as u64)?,
            boxes: Storage::new(ctx, "search.boxes", (24 * nf.max(1)) as u64)?,
            points: Storage::new(ctx, "search.points", point_bytes as u64)?,
        })
    }
}

/// The step's buffers the narrow phase reads where it keeps the last sort (see
/// [`GpuSearch::dispatch_narrow_keeping`]): the step uniform and the search bounds (6 words:
/// speed, side and drift, then their copy).
pub struct KeptBuffers<'a> {
    pub step: &'a wgpu::Buffer,
    pub bounds: &'a wgpu::Buffer,
}

/// The stages' bind groups, in order: `fill_words` (the bucket sizes zeroed),
/// `face_cells`, `bucket_count`, `bucket_fill`, `contact_search` (the bucket starts come from
/// the [`Scan`] between the last two).
fn binds(
    ctx: &GpuContext,
    k: &SearchKernels,
    b: &SearchBuffers,
    (reference, displacement, velocity): (&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer),
    kept: &KeptBuffers,
) -> [wgpu::BindGroup; 5] {
    [
        k.fill_words.bind(ctx, &b.sort.counts.buffer),
        k.face_cells.bind(
            ctx,
            &b.grid.buffer,
            reference,
            displacement,
            &b.faces.buffer,
            &b.face_first.buffer,
            &b.sort.keys.buffer,
            &b.centres.buffer,
            &b.boxes.buffer,
        ),
        k.bucket_count.bind(
            ctx,
            &b.sort.keys.buffer,
            &b.sort.counts.buffer,
            &b.sort.ranks.buffer,
        ),
        k.bucket_fill.bind(
            ctx,
            &b.sort.keys.buffer,
            &b.sort.ranks.buffer,
            &b.sort.starts.buffer,
            &b.sort.sorted.buffer,
        ),
        k.contact_search.0.bind(
            ctx,
            &narrow_buffers(b, (reference, displacement, velocity), kept),
        ),
    ]
}

/// `contact_search`'s buffers, in binding order.
fn narrow_buffers<'a>(
    b: &'a SearchBuffers,
    (reference, displacement, velocity): (&'a wgpu::Buffer, &'a wgpu::Buffer, &'a wgpu::Buffer),
    kept: &KeptBuffers<'a>,
) -> [&'a wgpu::Buffer; 12] {
    [
        &b.grid.buffer,
        reference,
        displacement,
        velocity,
        &b.queries.buffer,
        &b.faces.buffer,
        &b.sort.starts.buffer,
        &b.sort.sorted.buffer,
        &b.points.buffer,
        &b.boxes.buffer,
        kept.step,
        kept.bounds,
    ]
}

pub struct GpuSearch {
    kernels: SearchKernels,
    pub(super) buffers: SearchBuffers,
    pub(super) staging: Storage,
    binds: [wgpu::BindGroup; 5],
    /// The narrow phase on a step that keeps the last sort (`contact_search` with
    /// params.aux 1), where the search was given the step's [`KeptBuffers`].
    keeping: Option<Launch>,
    /// Placeholders for the step's buffers where there are none.
    _placeholders: (wgpu::Buffer, Storage),
    /// The faces' bucket starts from their sizes.
    scan: Scan,
    pub(super) faces: usize,
    queries: usize,
    pub(super) table: usize,
}

impl GpuSearch {
    /// `queries[i] = (secondary node, first face, end face)` of its interface;
    /// `face_first[f]` the first face of face f's interface; `face_size` the largest face
    /// size (the margin's base where the device computes the grid); `kept` the step's
    /// buffers where the device computes the grid (`search_grid`), so that a step that
    /// keeps the sort can run [`Self::dispatch_narrow_keeping`].
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &GpuContext,
        (reference, displacement, velocity): (&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer),
        faces: &[[u32; 4]],
        face_first: &[u32],
        queries: &[(u32, u32, u32)],
        face_size: f64,
        kept: Option<KeptBuffers>,
    ) -> Result<Self> {
        let table = table_size(faces.len());
        let buffers = SearchBuffers::new(ctx, faces, face_first, queries, table)?;
        let grid = types::GpuSearchGrid {
            face_size: face_size as f32,
            mask: (table - 1) as u32,
            ..Default::default()
        };
        ctx.queue
            .write_buffer(&buffers.grid.buffer, 0, bytemuck::bytes_of(&grid));
        let kernels = SearchKernels::new(ctx);
        let state = (reference, displacement, velocity);
        // bound where the search is given no step buffers (its launches then never read them)
        let placeholders = (
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("search.step"),
                size: std::mem::size_of::<types::Step>() as u64,
                usage: wgpu::BufferUsages::UNIFORM,
                mapped_at_creation: false,
            }),
            Storage::new(ctx, "search.bounds", 24)?,
        );
        let step_buffers = match &kept {
            Some(k) => KeptBuffers {
                step: k.step,
                bounds: k.bounds,
            },
            None => KeptBuffers {
                step: &placeholders.0,
                bounds: &placeholders.1.buffer,
            },
        };
        let binds = binds(ctx, &kernels, &buffers, state, &step_buffers);
        let keeping =
            kept.map(|k| keeping_launch(ctx, &kernels, &buffers, state, &k, queries.len()));
        kernels.set_counts(ctx, faces.len(), table, queries.len());
        let sort = &buffers.sort;
        let scan = Scan::new(ctx, &sort.counts.buffer, &sort.starts.buffer, table)?;
        Ok(GpuSearch {
            kernels,
            buffers,
            staging: staging(ctx)?,
            binds,
            keeping,
            _placeholders: placeholders,
            scan,
            faces: faces.len(),
            queries: queries.len(),
            table,
        })
    }

    /// Records a whole search with `grid` (set now, applied at the next submission; the
    /// table's mask is the search's own).
    pub fn record(&self, ctx: &GpuContext, enc: &mut wgpu::CommandEncoder, grid: SearchGrid) {
        let g = types::GpuSearchGrid {
            mask: self.mask(),
            ..types::GpuSearchGrid::of(&grid)
        };
        ctx.queue
            .write_buffer(&self.buffers.grid.buffer, 0, bytemuck::bytes_of(&g));
        self.record_stages(enc);
    }

    /// Records a whole search with the grid already in [`Self::grid_buffer`] when it runs,
    /// in a compute pass of its own.
    pub fn record_stages(&self, enc: &mut wgpu::CommandEncoder) {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("contact_search"),
            timestamp_writes: None,
        });
        self.dispatch_stages(&mut pass);
    }

    /// Dispatches a whole search's stages inside an open compute pass.
    pub fn dispatch_stages(&self, pass: &mut wgpu::ComputePass) {
        self.dispatch_sort(pass);
        self.dispatch_narrow(pass);
    }

    /// Dispatches the faces' sort into the grid's cells (the broad phase) inside an open
    /// compute pass.
    pub fn dispatch_sort(&self, pass: &mut wgpu::ComputePass) {
        let (k, b) = (&self.kernels, &self.binds);
        let f = self.faces as u32;
        let t = self.table as u32;
        k.fill_words
            .0
            .dispatch_with(pass, &b[0], k.fill_words.0.grid(t));
        k.face_cells
            .0
            .dispatch_with(pass, &b[1], k.face_cells.0.grid(f));
        k.bucket_count
            .0
            .dispatch_with(pass, &b[2], k.bucket_count.0.grid(f));
        self.scan.dispatch(pass);
        k.bucket_fill
            .0
            .dispatch_with(pass, &b[3], k.bucket_fill.0.grid(f));
    }

    /// Dispatches the narrow phase on the faces' last sort inside an open compute pass.
    pub fn dispatch_narrow(&self, pass: &mut wgpu::ComputePass) {
        let (k, b) = (&self.kernels, &self.binds);
        let q = self.queries as u32;
        k.contact_search
            .0
            .dispatch_with(pass, &b[4], k.contact_search.0.grid(q));
    }

    /// Dispatches the narrow phase of a step that keeps the faces' last sort, with
    /// `search_grid`'s keeping arithmetic in it (no `search_grid` before it); the plain
    /// narrow phase where the search was given no step buffers.
    pub fn dispatch_narrow_keeping(&self, pass: &mut wgpu::ComputePass) {
        match &self.keeping {
            Some(l) => self.kernels.contact_search.0.dispatch(pass, l),
            None => self.dispatch_narrow(pass),
        }
    }

    /// The search grid ([`types::GpuSearchGrid`]) the stages read.
    pub fn grid_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.grid.buffer
    }

    /// The contact point of each query after a search.
    pub fn points_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.points.buffer
    }

    /// The faces' centres at their last sort (3 floats per face).
    pub fn centres_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.centres.buffer
    }

    /// The faces' boxes ([`types::FaceBox`]) the narrow phase filters with.
    pub fn boxes_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.boxes.buffer
    }

    /// The primary faces ([`types::Quad`]).
    pub fn faces_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.faces.buffer
    }

    /// The table's mask (buckets - 1).
    pub fn mask(&self) -> u32 {
        (self.table - 1) as u32
    }

    /// Runs a search after `enc`'s work and reads the contact points back.
    pub fn run(
        &mut self,
        ctx: &GpuContext,
        mut enc: wgpu::CommandEncoder,
        grid: SearchGrid,
    ) -> Result<Vec<ContactPoint>> {
        self.record(ctx, &mut enc, grid);
        let pts: Vec<types::GpuContactPoint> = submit_and_read(
            ctx,
            &mut self.staging,
            enc,
            &self.buffers.points.buffer,
            self.queries,
        )?;
        Ok(pts.into_iter().map(ContactPoint::from).collect())
    }
}

/// The narrow phase's launch on the steps that keep the sort: `contact_search` with
/// params.aux 1 over `queries` queries.
fn keeping_launch(
    ctx: &GpuContext,
    k: &SearchKernels,
    b: &SearchBuffers,
    state: (&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer),
    kept: &KeptBuffers,
    queries: usize,
) -> Launch {
    let buffers = narrow_buffers(b, state, kept);
    k.contact_search
        .0
        .launch(ctx, queries as u32, 1, 0, &buffers)
}
