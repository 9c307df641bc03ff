//! [`ContactIteration`]: the contact impulses of the explicit step on the device, for scenes
//! with contact between meshed bodies (and any number of rigid planes). The same constraints
//! and the same projected Jacobi sweeps as the host path (`integrate::explicit`), staged so
//! that every value has one writer (the bounds and the state words aside, which are
//! atomics) and every sum is gathered in a fixed order:
//!
//! 1. the search grid from the step's bounds (`search_bounds`, `search_grid`) and the device
//!    search ([`GpuSearch`]), if any interface has a primary surface;
//! 2. `contact_constraints`, one per pair (secondary node of an interface), then the pairs
//!    in reach bucket-sorted by their primary face (`bucket_count`, `prefix_sum`,
//!    `bucket_fill`, as the search sorts faces by cell) and each bucket put in pair order
//!    (`bucket_order`: the atomics rank them in a different order every run);
//! 3. the row-sum compliance: `contact_touches` per contact node (it gathers the pairs of
//!    its faces from the buckets) and `contact_compliance` per pair, then a first
//!    `sweep_control`;
//! 4. the sweeps: `contact_sweep` per pair (impulse changes), then `contact_apply` per
//!    contact node (it gathers them into its velocity; its first invocation applies the
//!    stopping rule). The caller says how many sweeps to record; once the iteration has
//!    stopped, a sweep does nothing and arms an empty grid for the apply after it, which is
//!    dispatched indirectly (each sweep recorded after that still costs two dispatches);
//! 5. `contact_report`, one per pair: the results `history_reduce` sums per interface.

use std::ops::Range;

use super::buffer::{submit_and_read, Storage};
use super::context::GpuContext;
use super::kernel::Launch;
use super::kernels::{
    BucketCount, BucketFill, BucketOrder, ContactApply, ContactCompliance, ContactConstraints,
    ContactReportKernel, ContactSweep, ContactTouches, PrefixSum, SearchBounds, SearchGridKernel,
    SweepControl,
};
use super::search::GpuSearch;
use super::types::{self, Split3};
use crate::error::Result;
use crate::kernels::plane_contact::SLOT;
use crate::kernels::{Constraint, ContactNode, ContactPair, ContactPoint, SweepState};

/// What the device contact iteration needs, in f64 (the CPU twins take the same).
#[derive(Debug, Clone, Default)]
pub struct ContactSetup {
    /// Every (interface, secondary node) of the model, interface after interface.
    pub pairs: Vec<ContactPair>,
    /// Pair range of each interface.
    pub interfaces: Vec<Range<usize>>,
    /// The nodes the iteration moves and their links (see [`ContactNode`]).
    pub nodes: Vec<ContactNode>,
    pub links: Vec<u32>,
    /// The primary faces of the surface interfaces, the first face of each face's
    /// interface, and each query's (secondary node, first face, end face).
    pub faces: Vec<[u32; 4]>,
    pub face_first: Vec<u32>,
    pub queries: Vec<(u32, u32, u32)>,
    /// The largest face diagonal (the search margin's base).
    pub face_size: f64,
}

/// The device buffers of the explicit step the iteration reads and writes.
pub struct StepBuffers<'a> {
    pub step: &'a wgpu::Buffer,
    pub reference: &'a wgpu::Buffer,
    pub displacement: &'a wgpu::Buffer,
    pub velocity: &'a wgpu::Buffer,
    pub acceleration: &'a wgpu::Buffer,
    pub lumped: &'a wgpu::Buffer,
}

struct Kernels {
    bounds: SearchBounds,
    grid: SearchGridKernel,
    constraints: ContactConstraints,
    count: BucketCount,
    prefix: PrefixSum,
    fill: BucketFill,
    order: BucketOrder,
    touches: ContactTouches,
    compliance: ContactCompliance,
    sweep: ContactSweep,
    apply: ContactApply,
    control: SweepControl,
    report: ContactReportKernel,
}

struct Launches {
    bounds: Option<Launch>,
    grid: Option<Launch>,
    constraints: Launch,
    count: Launch,
    prefix: Launch,
    fill: Launch,
    order: Launch,
    touches: Launch,
    compliance: Launch,
    sweep: Launch,
    apply: Launch,
    control: Launch,
    report: Launch,
}

pub struct ContactIteration {
    search: Option<GpuSearch>,
    kernels: Kernels,
    launches: Launches,
    bounds: Storage,
    constraints: Storage,
    keys: Storage,
    counts: Storage,
    starts: Storage,
    sorted: Storage,
    touches: Storage,
    dj: Storage,
    state: Storage,
    /// The apply's indirect grid.
    args: Storage,
    results: Storage,
    staging: Storage,
    // kept alive for the bind groups
    _buffers: Vec<Storage>,
    pairs: usize,
    faces: usize,
    max_iterations: u32,
}

impl ContactIteration {
    pub fn new(
        ctx: &GpuContext,
        b: &StepBuffers,
        setup: &ContactSetup,
        nodes: usize,
        tolerance: f64,
        max_iterations: u32,
    ) -> Result<Self> {
        let search = if setup.queries.is_empty() {
            None
        } else {
            Some(GpuSearch::new(
                ctx,
                b.reference,
                b.displacement,
                b.velocity,
                &setup.faces,
                &setup.face_first,
                &setup.queries,
            )?)
        };
        let kernels = Kernels {
            bounds: SearchBounds::new(ctx),
            grid: SearchGridKernel::new(ctx),
            constraints: ContactConstraints::new(ctx),
            count: BucketCount::new(ctx),
            prefix: PrefixSum::new(ctx),
            fill: BucketFill::new(ctx),
            order: BucketOrder::new(ctx),
            touches: ContactTouches::new(ctx),
            compliance: ContactCompliance::new(ctx),
            sweep: ContactSweep::new(ctx),
            apply: ContactApply::new(ctx),
            control: SweepControl::new(ctx),
            report: ContactReportKernel::new(ctx),
        };
        let np = setup.pairs.len();
        let nf = setup.faces.len();
        let nc = setup.nodes.len();
        let words = |n: usize| (4 * n) as u64;
        let pairs: Vec<types::ContactPair> = setup
            .pairs
            .iter()
            .map(|p| types::ContactPair {
                node: p.node,
                query: p.query,
                mu: p.mu as f32,
                point: Split3::split(p.point),
                normal: p.normal.map(|x| x as f32),
            })
            .collect();
        let pairs = Storage::with_data(ctx, "contact.pairs", &pairs)?;
        let cnodes: Vec<types::ContactNode> = setup
            .nodes
            .iter()
            .map(|c| types::ContactNode {
                node: c.node,
                pair_first: c.pair_first,
                pair_end: c.pair_end,
                face_first: c.face_first,
                face_end: c.face_end,
            })
            .collect();
        let cnodes = Storage::with_data(ctx, "contact.nodes", &cnodes)?;
        let links = Storage::with_data(ctx, "contact.links", &setup.links)?;
        let bounds = Storage::new(ctx, "contact.bounds", 8)?;
        let constraints = Storage::new(
            ctx,
            "contact.constraints",
            (np * std::mem::size_of::<types::Constraint>()) as u64,
        )?;
        let keys = Storage::new(ctx, "contact.keys", words(np))?;
        let ranks = Storage::new(ctx, "contact.ranks", words(np))?;
        // buckets 0..faces hold the pairs on each face, bucket `faces` the others
        let counts = Storage::new(ctx, "contact.counts", words(nf + 1))?;
        let starts = Storage::new(ctx, "contact.starts", words(nf + 2))?;
        let sorted = Storage::new(ctx, "contact.sorted", words(np))?;
        let touches = Storage::new(ctx, "contact.touches", words(nodes))?;
        let dj = Storage::new(ctx, "contact.dj", words(3 * np))?;
        let state = Storage::new(ctx, "contact.state", 16)?;
        // the apply's grid, armed by each sweep (empty once the iteration has stopped)
        let args = Storage::with_usage(
            ctx,
            "contact.apply_args",
            12,
            wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::INDIRECT
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
        )?;
        let results = Storage::with_data(ctx, "contact.results", &vec![0.0f32; SLOT * np])?;
        // placeholders where no interface has a primary surface
        let none = Storage::new(ctx, "contact.none", 64)?;
        let (grid_buf, points_buf, faces_buf) = match &search {
            Some(s) => (s.grid_buffer(), s.points_buffer(), s.faces_buffer()),
            None => (&none.buffer, &none.buffer, &none.buffer),
        };
        let k = &kernels;
        // the apply's grid, which the sweep arms
        let ag = k.apply.0.grid(nc as u32);
        let item_count = nodes.max(nf) as u32;
        let launches = Launches {
            bounds: search.as_ref().map(|s| {
                k.bounds.launch(
                    ctx,
                    item_count,
                    nodes as u32,
                    nf as u32,
                    b.reference,
                    b.displacement,
                    b.velocity,
                    s.faces_buffer(),
                    &bounds.buffer,
                )
            }),
            grid: search.as_ref().map(|s| {
                k.grid.launch(
                    ctx,
                    1,
                    s.mask(),
                    (setup.face_size as f32).to_bits(),
                    b.step,
                    &bounds.buffer,
                    s.grid_buffer(),
                )
            }),
            constraints: k.constraints.launch(
                ctx,
                np as u32,
                nf as u32,
                0,
                b.step,
                grid_buf,
                b.reference,
                b.displacement,
                b.velocity,
                b.acceleration,
                &pairs.buffer,
                points_buf,
                faces_buf,
                &constraints.buffer,
                &keys.buffer,
            ),
            count: k.count.launch(
                ctx,
                np as u32,
                0,
                0,
                &keys.buffer,
                &counts.buffer,
                &ranks.buffer,
            ),
            prefix: k
                .prefix
                .launch(ctx, (nf + 1) as u32, 0, 0, &counts.buffer, &starts.buffer),
            fill: k.fill.launch(
                ctx,
                np as u32,
                0,
                0,
                &keys.buffer,
                &ranks.buffer,
                &starts.buffer,
                &sorted.buffer,
            ),
            // the face buckets only: the sentinel bucket is never gathered
            order: k
                .order
                .launch(ctx, nf as u32, 0, 0, &starts.buffer, &sorted.buffer),
            touches: k.touches.launch(
                ctx,
                nc as u32,
                0,
                0,
                &cnodes.buffer,
                &links.buffer,
                &constraints.buffer,
                &starts.buffer,
                &sorted.buffer,
                &touches.buffer,
                &state.buffer,
            ),
            compliance: k.compliance.launch(
                ctx,
                np as u32,
                0,
                0,
                &constraints.buffer,
                &touches.buffer,
                b.lumped,
                &pairs.buffer,
            ),
            sweep: k.sweep.launch(
                ctx,
                np as u32,
                ag[0],
                ag[1],
                b.step,
                &constraints.buffer,
                &pairs.buffer,
                b.velocity,
                &dj.buffer,
                &state.buffer,
                &args.buffer,
            ),
            apply: k.apply.launch(
                ctx,
                nc as u32,
                max_iterations,
                (tolerance as f32).to_bits(),
                &cnodes.buffer,
                &links.buffer,
                &constraints.buffer,
                &starts.buffer,
                &sorted.buffer,
                &dj.buffer,
                b.lumped,
                b.velocity,
                &state.buffer,
            ),
            control: k.control.launch(ctx, 1, 0, 0, &state.buffer),
            report: k.report.launch(
                ctx,
                np as u32,
                0,
                0,
                b.step,
                &constraints.buffer,
                &pairs.buffer,
                b.velocity,
                &state.buffer,
                &results.buffer,
            ),
        };
        Ok(ContactIteration {
            search,
            kernels,
            launches,
            bounds,
            constraints,
            keys,
            counts,
            starts,
            sorted,
            touches,
            dj,
            state,
            args,
            results,
            staging: super::buffer::staging(ctx)?,
            _buffers: vec![pairs, cnodes, links, ranks, none],
            pairs: np,
            faces: nf,
            max_iterations,
        })
    }

    /// The contact results, [`SLOT`] floats per pair (see `contact_report.wgsl`).
    pub fn results_buffer(&self) -> &wgpu::Buffer {
        &self.results.buffer
    }

    pub fn pair_count(&self) -> usize {
        self.pairs
    }

    /// Bytes held on the device.
    pub fn device_bytes(&self) -> u64 {
        [
            &self.bounds,
            &self.constraints,
            &self.keys,
            &self.counts,
            &self.starts,
            &self.sorted,
            &self.touches,
            &self.dj,
            &self.state,
            &self.args,
            &self.results,
        ]
        .iter()
        .map(|s| s.capacity)
        .chain(self._buffers.iter().map(|s| s.capacity))
        .sum()
    }

    /// Records the search (if any), the constraints up to their compliance and the first
    /// `sweep_control`.
    pub fn record_setup(&self, enc: &mut wgpu::CommandEncoder) {
        let (k, l) = (&self.kernels, &self.launches);
        if let (Some(search), Some(bounds), Some(grid)) = (&self.search, &l.bounds, &l.grid) {
            enc.clear_buffer(&self.bounds.buffer, 0, None);
            k.bounds.0.record_launch(enc, bounds);
            k.grid.0.record_launch(enc, grid);
            search.record_stages(enc);
        }
        k.constraints.0.record_launch(enc, &l.constraints);
        enc.clear_buffer(&self.counts.buffer, 0, None);
        k.count.0.record_launch(enc, &l.count);
        // one workgroup scans the whole table
        k.prefix.0.record(enc, &l.prefix.bind, [1, 1]);
        k.fill.0.record_launch(enc, &l.fill);
        k.order.0.record_launch(enc, &l.order);
        enc.clear_buffer(&self.state.buffer, 0, None);
        k.touches.0.record_launch(enc, &l.touches);
        k.compliance.0.record_launch(enc, &l.compliance);
        // before the first sweep: load the sweep grids, or stop with no pair in reach
        k.control.0.record_launch(enc, &l.control);
    }

    /// Records `sweeps` sweeps (at most `max_iterations`), each a `contact_sweep` and a
    /// `contact_apply` (which applies the stopping rule after the sweep), in one compute pass.
    pub fn record_sweeps(&self, enc: &mut wgpu::CommandEncoder, sweeps: u32) {
        let (k, l) = (&self.kernels, &self.launches);
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("contact_sweeps"),
            timestamp_writes: None,
        });
        for _ in 0..sweeps.min(self.max_iterations) {
            k.sweep.0.dispatch(&mut pass, &l.sweep);
            k.apply
                .0
                .dispatch_indirect(&mut pass, &l.apply, &self.args.buffer, 0);
        }
    }

    /// Records the report of the step's results.
    pub fn record_report(&self, enc: &mut wgpu::CommandEncoder) {
        self.kernels
            .report
            .0
            .record_launch(enc, &self.launches.report);
    }

    /// Records the whole iteration of a step.
    pub fn record(&self, enc: &mut wgpu::CommandEncoder) {
        self.record_setup(enc);
        self.record_sweeps(enc, self.max_iterations);
        self.record_report(enc);
    }

    /// Records `part` of the iteration alone, submits it and waits (the kernel tests).
    pub fn run(
        &self,
        ctx: &GpuContext,
        part: impl FnOnce(&Self, &mut wgpu::CommandEncoder),
    ) -> Result<()> {
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("contact_iteration"),
            });
        part(self, &mut enc);
        ctx.queue.submit([enc.finish()]);
        ctx.wait()
    }

    fn read<T: bytemuck::Pod>(
        &mut self,
        ctx: &GpuContext,
        which: fn(&Self) -> &wgpu::Buffer,
        count: usize,
    ) -> Result<Vec<T>> {
        let enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("contact.read"),
            });
        let source = which(self).clone();
        submit_and_read(ctx, &mut self.staging, enc, &source, count)
    }

    /// The constraints, in f64.
    pub fn read_constraints(&mut self, ctx: &GpuContext) -> Result<Vec<Constraint>> {
        let c: Vec<types::Constraint> = self.read(ctx, |s| &s.constraints.buffer, self.pairs)?;
        Ok(c.into_iter().map(Constraint::from).collect())
    }

    /// The bucket keys, the bucket starts (faces + 2) and the sorted pairs.
    pub fn read_sort(&mut self, ctx: &GpuContext) -> Result<[Vec<u32>; 3]> {
        let (np, nf) = (self.pairs, self.faces);
        Ok([
            self.read(ctx, |s| &s.keys.buffer, np)?,
            self.read(ctx, |s| &s.starts.buffer, nf + 2)?,
            self.read(ctx, |s| &s.sorted.buffer, np)?,
        ])
    }

    /// The touches of every node (entries of nodes outside the iteration are not written).
    pub fn read_touches(&mut self, ctx: &GpuContext, nodes: usize) -> Result<Vec<f64>> {
        let t: Vec<f32> = self.read(ctx, |s| &s.touches.buffer, nodes)?;
        Ok(t.into_iter().map(f64::from).collect())
    }

    /// The impulse changes of the last sweep (3 per pair).
    pub fn read_dj(&mut self, ctx: &GpuContext) -> Result<Vec<f64>> {
        let d: Vec<f32> = self.read(ctx, |s| &s.dj.buffer, 3 * self.pairs)?;
        Ok(d.into_iter().map(f64::from).collect())
    }

    /// The iteration's state.
    pub fn read_state(&mut self, ctx: &GpuContext) -> Result<SweepState> {
        let w: Vec<u32> = self.read(ctx, |s| &s.state.buffer, 4)?;
        use crate::kernels::sweep_control::word;
        Ok(SweepState {
            violation: f32::from_bits(w[word::VIOLATION]) as f64,
            active: w[word::ACTIVE],
            sweeps: w[word::SWEEPS],
            phase: w[word::PHASE],
        })
    }

    /// The search grid's bounds and the grid (cell, margin) of the last search.
    pub fn read_grid(&mut self, ctx: &GpuContext) -> Result<([f64; 2], [f64; 2])> {
        let b: Vec<f32> = self.read(ctx, |s| &s.bounds.buffer, 2)?;
        let g: Vec<f32> = match &self.search {
            Some(_) => self.read(ctx, |s| s.search.as_ref().unwrap().grid_buffer(), 2)?,
            None => vec![0.0; 2],
        };
        Ok(([b[0] as f64, b[1] as f64], [g[0] as f64, g[1] as f64]))
    }

    /// The contact points of the last search.
    pub fn read_points(&mut self, ctx: &GpuContext, queries: usize) -> Result<Vec<ContactPoint>> {
        let p: Vec<types::ContactPoint> = match &self.search {
            Some(_) => self.read(ctx, |s| s.search.as_ref().unwrap().points_buffer(), queries)?,
            None => Vec::new(),
        };
        Ok(p.into_iter().map(ContactPoint::from).collect())
    }

    /// The contact results, [`SLOT`] per pair.
    pub fn read_results(&mut self, ctx: &GpuContext) -> Result<Vec<f64>> {
        let r: Vec<f32> = self.read(ctx, |s| &s.results.buffer, SLOT * self.pairs)?;
        Ok(r.into_iter().map(f64::from).collect())
    }

    /// Overwrites the constraints (the kernel tests feed each stage the same inputs as its
    /// twin).
    pub fn upload_constraints(&mut self, ctx: &GpuContext, c: &[Constraint]) -> Result<()> {
        let c: Vec<types::Constraint> = c.iter().map(types::Constraint::from).collect();
        self.constraints.upload(ctx, &c)?;
        Ok(())
    }
}
