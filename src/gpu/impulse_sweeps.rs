//! [`ImpulseSweeps`]: the contact impulses of the explicit step on the device, for scenes
//! with contact between meshed bodies or against rigid bodies' analytic surfaces (and any
//! number of rigid planes). The same constraints
//! and the same projected Jacobi sweeps as the host path (`integrate::explicit`), staged so
//! that every value has one writer (the bounds and the state words aside, which are
//! atomics) and every sum is gathered in a fixed order:
//!
//! 1. the search grid from the step's bounds (`search_bounds`, `search_grid`) and the device
//!    search ([`GpuSearch`]), if any interface has a primary surface: the faces' sort into
//!    the grid on the steps the caller says ([`SearchMode`]), the narrow phase on every step
//!    (over every face of an interface on a step whose kept grid no longer holds; a step
//!    that keeps the sort dispatches no `search_grid`, its narrow phase doing the same
//!    arithmetic);
//! 2. `contact_constraints`, one per pair (secondary node of an interface), then the pairs
//!    in reach bucket-sorted by their primary face (`bucket_count`, `prefix_sum`,
//!    `bucket_fill`, as the search sorts faces by cell) and each bucket put in pair order
//!    (`bucket_order`: the atomics rank them in a different order every run; it also clears
//!    the bucket sizes for the next step's count, the state words and the search bounds);
//! 3. the row-sum compliance: `contact_touches` per contact node (it gathers the pairs of
//!    its faces from the buckets) and `contact_compliance` per pair, whose first
//!    invocation starts the sweeps (or stops the iteration with no pair in reach); then the
//!    warm start, the last step's impulses (`contact_constraints` takes them from the
//!    results) applied to the velocities (`body_gather`, `contact_warm`);
//! 4. the sweeps: with no rigid body range, `contact_relax`, one dispatch a sweep (the
//!    apply of the sweep before it and the sweep itself, the contact nodes' velocities
//!    carried between two slots), and its settle after the last recorded one; otherwise
//!    `contact_sweep` per pair (impulse changes), `body_gather` per rigid body range (one
//!    workgroup each sums its pairs' impulse changes), then `contact_apply` per contact node
//!    (it gathers them into its velocity; its first invocation applies the stopping rule).
//!    The caller says how many sweeps to record; once the iteration has stopped, those
//!    recorded after it exit at once (direct dispatches: on an H100 an indirect dispatch
//!    cost several times a direct one). `contact_finish`, one workgroup, runs any sweeps the
//!    iteration needs after them, the same arithmetic in the same order, so that the
//!    results do not depend on how many were recorded, nor on the kernels that ran them;
//! 5. `contact_report`, one per pair: the results `history_reduce` sums per interface (and,
//!    where the step's predictor ran in the search's bounds, the contact nodes' drift).

use std::ops::Range;

use super::bucket_sort::BucketSort;
use super::buffer::Storage;
use super::contact_form::{ContactForm, ZONE_PAIRS, ZONE_TRIAL_PAIRS};
use super::context::{GpuContext, ZONE_BINDINGS};
use super::engine::at_least_one;
use super::kernel::{Kernel, Launch};
use super::kernels::{
    BodyGather, BucketCount, BucketFill, BucketOrder, ContactApply, ContactCompliance,
    ContactConstraints, ContactFinish, ContactRelax, ContactReportKernel, ContactSweep,
    ContactTouches, ContactWarm, ContactZone, FillWords, PredictBounds, SearchBounds,
    SearchGridKernel,
};
use super::one_group;
use super::scan::Scan;
use super::search::{GpuSearch, KeptBuffers};
use super::shaders;
use super::types::{self, to_device, WORKGROUP};
use crate::error::Result;
use crate::kernels::plane_contact::SLOT;
use crate::kernels::sweep_control::word;
use crate::kernels::{ContactNode, ContactPair, RigidSurface};
use crate::kernels::{Relax, SearchMode};

/// Sweeps a step records at most as `contact_relax` dispatches (its launches, one per sweep
/// number, are built once); `contact_finish` runs any after them.
pub const RELAX_SWEEPS: usize = 64;

/// Pairs per workgroup of `contact_relax` (five lanes each; `PAIRS_PER_GROUP` in the
/// shader).
const RELAX_PAIRS_PER_GROUP: u32 = 12;

/// `Params.aux2`'s flag of `contact_relax`'s settle launch.
const SETTLE: u32 = 1 << 31;

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
    /// The largest face size (the search margin's base).
    pub face_size: f64,
    /// The rigid bodies' analytic surfaces the pairs name (`ContactPair::body`).
    pub rigid: Vec<RigidSurface>,
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

/// The contact iteration's kernels, built once.
struct IterationKernels {
    gather: BodyGather,
    zero: FillWords,
    bounds: SearchBounds,
    predict_bounds: PredictBounds,
    grid: SearchGridKernel,
    constraints: ContactConstraints,
    count: BucketCount,
    fill: BucketFill,
    order: BucketOrder,
    touches: ContactTouches,
    compliance: ContactCompliance,
    warm: ContactWarm,
    sweep: ContactSweep,
    apply: ContactApply,
    relax: ContactRelax,
    finish: ContactFinish,
    report: ContactReportKernel,
    /// The whole iteration in one workgroup, where the adapter binds [`ZONE_BINDINGS`]
    /// storage buffers per stage: at `lanes` lanes, then at each further width the run's
    /// trial times ([`GpuContext::zone_trial`]), with its width.
    zones: Vec<(u32, ContactZone)>,
    /// The lanes of `contact_finish` and `contact_zone` ([`GpuContext::zone_lanes`], within
    /// the adapter's limits).
    lanes: u32,
}

impl IterationKernels {
    /// Builds the pipelines of every kernel of the iteration, once; the one-workgroup
    /// kernels with [`GpuContext::zone_lanes`] lanes (within the adapter's limits), and
    /// `contact_zone` at the context's further widths where `trial` (the run's trial can
    /// time them).
    fn new(ctx: &GpuContext, trial: bool) -> Self {
        let lanes = one_group::within(&ctx.limits, ctx.zone_lanes);
        let wide = |name: &'static str, lanes: u32| {
            Kernel::new(
                ctx,
                name,
                &one_group::with_lanes(shaders::source(name), lanes),
            )
        };
        let mut widths = vec![lanes];
        for &w in ctx.zone_trial.iter().filter(|_| trial) {
            let w = one_group::within(&ctx.limits, w);
            if !widths.contains(&w) {
                widths.push(w);
            }
        }
        let zone = ctx.limits.max_storage_buffers_per_shader_stage >= ZONE_BINDINGS;
        IterationKernels {
            gather: BodyGather::new(ctx),
            zero: FillWords::new(ctx),
            bounds: SearchBounds::new(ctx),
            predict_bounds: PredictBounds::new(ctx),
            grid: SearchGridKernel::new(ctx),
            constraints: ContactConstraints::new(ctx),
            count: BucketCount::new(ctx),
            fill: BucketFill::new(ctx),
            order: BucketOrder::new(ctx),
            touches: ContactTouches::new(ctx),
            compliance: ContactCompliance::new(ctx),
            warm: ContactWarm::new(ctx),
            sweep: ContactSweep::new(ctx),
            apply: ContactApply::new(ctx),
            relax: ContactRelax::new(ctx),
            finish: ContactFinish(wide(ContactFinish::NAME, lanes)),
            report: ContactReportKernel::new(ctx),
            zones: (widths.into_iter())
                .filter(|_| zone)
                .map(|w| (w, ContactZone(wide(ContactZone::NAME, w))))
                .collect(),
            lanes,
        }
    }
}

/// (`bucket_order` clears the pair buckets' sizes, the state words and the search bounds
/// for the next step.)
struct Launches {
    /// `search_bounds`, then `predict_bounds` (the step's predictor with the bounds).
    bounds: Option<[Launch; 2]>,
    /// `search_grid` on the steps that sort the faces: [`SearchMode::Build`] and
    /// [`SearchMode::First`] (a step that keeps the sort dispatches none).
    grid: Option<[Launch; 2]>,
    constraints: Launch,
    count: Launch,
    fill: Launch,
    order: Launch,
    touches: Launch,
    compliance: Launch,
    warm: Launch,
    sweep: Launch,
    gather: Launch,
    apply: Launch,
    /// `contact_relax` for sweeps 1, 2, ... and its settles after 1, 2, ... recorded sweeps
    /// (none where the iteration gathers rigid body ranges).
    relax: Vec<Launch>,
    settle: Vec<Launch>,
    finish: Launch,
    /// `contact_report`, [`Drift::None`] and [`Drift::Late`] (indexed by its value).
    report: [Launch; 2],
    /// `contact_zone`, as `report`, at each of the kernels' widths.
    zone: Vec<[Launch; 2]>,
}

/// Whether the iteration's last kernel drifts the contact nodes: where the step's predictor
/// ran in the search's bounds (`predict_bounds`, which drifts the other nodes), so that the
/// step dispatches no `explicit_drift`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Drift {
    None = 0,
    Late = 1,
}

/// The model's contact data on the device: its pairs, contact nodes and their links, and the
/// rigid bodies' surfaces.
struct ModelBuffers {
    pairs: Storage,
    nodes: Storage,
    links: Storage,
    rigid: Storage,
    /// Each model node's contact node (`u32::MAX` for the others).
    contact_of: Storage,
}

impl ModelBuffers {
    /// Uploads the setup's pairs, contact nodes, links and rigid surfaces (in f32 where they
    /// are f64), and each of the model's `nodes` nodes' contact node.
    fn upload(ctx: &GpuContext, setup: &ContactSetup, nodes: usize) -> Result<Self> {
        let mut contact_of = vec![u32::MAX; nodes.max(1)];
        for (i, c) in setup.nodes.iter().enumerate() {
            contact_of[c.node as usize] = i as u32;
        }
        let pairs: Vec<types::GpuContactPair> = to_device(&setup.pairs);
        let nodes: Vec<types::GpuContactNode> = to_device(&setup.nodes);
        let rigid = (setup.rigid.iter())
            .map(|s| {
                types::GpuRigidSurface::of(s).ok_or_else(|| {
                    crate::error::ImpactError::Gpu(
                        "a meshed rigid surface has no device form: the host's contact takes it"
                            .into(),
                    )
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(ModelBuffers {
            pairs: Storage::with_data(ctx, "contact.pairs", &pairs)?,
            nodes: Storage::with_data(ctx, "contact.nodes", &nodes)?,
            links: Storage::with_data(ctx, "contact.links", &at_least_one(setup.links.clone()))?,
            rigid: Storage::with_data(ctx, "contact.rigid", &at_least_one(rigid))?,
            contact_of: Storage::with_data(ctx, "contact.contact_of", &contact_of)?,
        })
    }
}

/// The iteration's working buffers (what its stages write).
pub(super) struct WorkBuffers {
    pub(super) bounds: Storage,
    pub(super) constraints: Storage,
    /// The pairs sorted by primary face: buckets 0..faces hold the pairs on each face,
    /// bucket `faces` the others.
    pub(super) sort: BucketSort,
    pub(super) touches: Storage,
    /// The impulse changes of a sweep, 3 per pair and then per rigid body range, in two
    /// halves (`contact_relax` keeps two sweeps'; the other kernels use the first).
    pub(super) dj: Storage,
    /// The contact nodes' velocities `contact_relax` carries from sweep to sweep: two slots
    /// of 3 per contact node.
    pub(super) carried: Storage,
    pub(super) state: Storage,
    pub(super) results: Storage,
    /// Bitsets of the model's nodes (bit n % 32 of word n / 32): no node, and the contact
    /// nodes (the late nodes of [`Drift::Late`]), indexed by [`Drift`].
    late: [Storage; 2],
}

impl WorkBuffers {
    /// Allocates the working buffers for `np` pairs, `nf` primary faces, `nodes` nodes and
    /// `ranges` rigid body ranges (whose impulse changes follow the pairs' in `dj`), and the
    /// late nodes' bitsets of the setup's contact nodes.
    fn new(
        ctx: &GpuContext,
        (np, nf, nodes): (usize, usize, usize),
        ranges: usize,
        contact_nodes: &[ContactNode],
    ) -> Result<Self> {
        let words = |n: usize| (4 * n) as u64;
        // the step's bounds, then their copy the search leaves
        let bounds = Storage::new(ctx, "contact.bounds", 24)?;
        let constraints = Storage::new(
            ctx,
            "contact.constraints",
            (np * std::mem::size_of::<types::GpuConstraint>()) as u64,
        )?;
        let labels = [
            "contact.keys",
            "contact.ranks",
            "contact.counts",
            "contact.starts",
            "contact.sorted",
        ];
        let sort = BucketSort::new(ctx, labels, np, nf + 1)?;
        let touches = Storage::new(ctx, "contact.touches", words(nodes))?;
        let dj = Storage::new(ctx, "contact.dj", words(2 * 3 * (np + ranges)))?;
        let carried = Storage::new(
            ctx,
            "contact.carried",
            words(6 * contact_nodes.len().max(1)),
        )?;
        let state = Storage::new(ctx, "contact.state", 4 * word::WORDS as u64)?;
        let results = Storage::with_data(ctx, "contact.results", &vec![0.0f32; SLOT * np])?;
        let mut bits = vec![0u32; nodes.div_ceil(32).max(1)];
        let none = Storage::with_data(ctx, "contact.early", &bits)?;
        for c in contact_nodes {
            bits[c.node as usize / 32] |= 1 << (c.node % 32);
        }
        let late = [none, Storage::with_data(ctx, "contact.late", &bits)?];
        Ok(WorkBuffers {
            bounds,
            constraints,
            sort,
            touches,
            dj,
            carried,
            state,
            results,
            late,
        })
    }
}

/// What the launches bind: the kernels, the step's, the model's and the working buffers,
/// the search's (or placeholders) and the sizes.
struct Bindings<'a> {
    ctx: &'a GpuContext,
    k: &'a IterationKernels,
    b: &'a StepBuffers<'a>,
    m: &'a ModelBuffers,
    w: &'a WorkBuffers,
    /// The search's grid, points and faces (placeholders where there is no search).
    grid: &'a wgpu::Buffer,
    points: &'a wgpu::Buffer,
    faces: &'a wgpu::Buffer,
    np: u32,
    nf: u32,
    nc: u32,
    /// The rigid body ranges.
    nr: u32,
    /// The sweeps a step can record as `contact_relax` dispatches (0 with rigid body
    /// ranges).
    relaxed: u32,
}

impl Bindings<'_> {
    /// The search's launches, `search_bounds`, `predict_bounds` and `search_grid` on the
    /// steps that sort the faces (none without a search).
    fn search(
        &self,
        search: Option<&GpuSearch>,
        nodes: usize,
    ) -> (Option<[Launch; 2]>, Option<[Launch; 2]>) {
        let (ctx, k, b, w) = (self.ctx, self.k, self.b, self.w);
        let item_count = nodes.max(self.nf as usize) as u32;
        let bounds = search.map(|s| {
            let bounds = k.bounds.launch(
                ctx,
                item_count,
                nodes as u32,
                self.nf,
                b.reference,
                b.displacement,
                b.velocity,
                s.faces_buffer(),
                s.centres_buffer(),
                &w.bounds.buffer,
                s.boxes_buffer(),
            );
            let predict = k.predict_bounds.launch(
                ctx,
                item_count,
                nodes as u32,
                self.nf,
                b.step,
                b.reference,
                b.displacement,
                b.velocity,
                b.acceleration,
                s.faces_buffer(),
                s.centres_buffer(),
                &w.bounds.buffer,
                s.boxes_buffer(),
                &w.late[Drift::Late as usize].buffer,
            );
            [bounds, predict]
        });
        let grid = search.map(|s| {
            [SearchMode::Build, SearchMode::First].map(|mode| {
                k.grid.launch(
                    ctx,
                    1,
                    s.mask(),
                    mode as u32,
                    b.step,
                    &w.bounds.buffer,
                    s.grid_buffer(),
                )
            })
        });
        (bounds, grid)
    }

    /// The constraints' and the bucket sort's launches: `contact_constraints`,
    /// `bucket_count`, `bucket_fill` and `bucket_order` (the bucket starts come from the
    /// iteration's [`Scan`] between the first two).
    fn sort(&self) -> [Launch; 4] {
        let (ctx, k, b, m, w) = (self.ctx, self.k, self.b, self.m, self.w);
        let (np, nf) = (self.np, self.nf);
        let constraints = k.constraints.launch(
            ctx,
            np,
            nf,
            0,
            b.step,
            self.grid,
            b.reference,
            b.displacement,
            b.velocity,
            b.acceleration,
            &m.pairs.buffer,
            self.points,
            self.faces,
            &w.constraints.buffer,
            &w.sort.keys.buffer,
            &m.rigid.buffer,
            &w.results.buffer,
        );
        let count = k.count.launch(
            ctx,
            np,
            0,
            0,
            &w.sort.keys.buffer,
            &w.sort.counts.buffer,
            &w.sort.ranks.buffer,
        );
        let fill = k.fill.launch(
            ctx,
            np,
            0,
            0,
            &w.sort.keys.buffer,
            &w.sort.ranks.buffer,
            &w.sort.starts.buffer,
            &w.sort.sorted.buffer,
        );
        // the face buckets only (the sentinel bucket is never gathered); it clears every
        // bucket's size and the state words too
        let order = k.order.launch(
            ctx,
            nf,
            0,
            0,
            &w.sort.starts.buffer,
            &w.sort.sorted.buffer,
            &w.sort.counts.buffer,
            &w.state.buffer,
            &w.bounds.buffer,
        );
        [constraints, count, fill, order]
    }

    /// The row-sum compliance's launches, `contact_touches` and `contact_compliance`, and
    /// the warm start's `contact_warm`.
    fn compliance(&self) -> [Launch; 3] {
        let (ctx, k, b, m, w) = (self.ctx, self.k, self.b, self.m, self.w);
        let touches = k.touches.launch(
            ctx,
            self.nc,
            0,
            0,
            &m.nodes.buffer,
            &m.links.buffer,
            &w.constraints.buffer,
            &w.sort.starts.buffer,
            &w.sort.sorted.buffer,
            &w.touches.buffer,
            &w.state.buffer,
        );
        let compliance = k.compliance.launch(
            ctx,
            self.np,
            0,
            0,
            &w.constraints.buffer,
            &w.touches.buffer,
            b.lumped,
            &m.pairs.buffer,
            &w.state.buffer,
            &w.dj.buffer,
        );
        let warm = k.warm.launch(
            ctx,
            self.nc,
            self.np,
            0,
            &m.nodes.buffer,
            &m.links.buffer,
            &w.constraints.buffer,
            &w.sort.starts.buffer,
            &w.sort.sorted.buffer,
            &w.dj.buffer,
            b.lumped,
            b.velocity,
            &w.state.buffer,
            &w.carried.buffer,
        );
        [touches, compliance, warm]
    }

    /// The sweeps' launches: `contact_sweep`, `contact_apply` and `contact_finish`.
    fn sweeps(&self) -> (Launch, Launch, Launch) {
        let (ctx, k, b, m, w) = (self.ctx, self.k, self.b, self.m, self.w);
        let sweep = k.sweep.launch(
            ctx,
            self.np,
            0,
            0,
            b.step,
            &w.constraints.buffer,
            &m.pairs.buffer,
            b.velocity,
            &w.dj.buffer,
            &w.state.buffer,
        );
        let apply = k.apply.launch(
            ctx,
            self.nc,
            self.np,
            0,
            b.step,
            &m.nodes.buffer,
            &m.links.buffer,
            &w.constraints.buffer,
            &w.sort.starts.buffer,
            &w.sort.sorted.buffer,
            &w.dj.buffer,
            b.lumped,
            b.velocity,
            &w.state.buffer,
        );
        let finish = k.finish.launch(
            ctx,
            self.np,
            self.nc,
            0,
            b.step,
            &w.constraints.buffer,
            &m.pairs.buffer,
            b.velocity,
            &w.dj.buffer,
            &w.state.buffer,
            &m.nodes.buffer,
            &m.links.buffer,
            &w.sort.starts.buffer,
            &w.sort.sorted.buffer,
            b.lumped,
        );
        (sweep, apply, finish)
    }

    /// `contact_relax`'s launches for sweeps 1..=relaxed, and its settles after as many:
    /// five invocations per pair (Params.aux), [`RELAX_PAIRS_PER_GROUP`] pairs a
    /// workgroup, then one per contact node.
    fn relax(&self) -> (Vec<Launch>, Vec<Launch>) {
        let (ctx, k, b, m, w) = (self.ctx, self.k, self.b, self.m, self.w);
        let launch = |aux2: u32| {
            k.relax.launch(
                ctx,
                64 * self.np.div_ceil(RELAX_PAIRS_PER_GROUP) + self.nc,
                self.np,
                aux2,
                b.step,
                &w.constraints.buffer,
                &m.pairs.buffer,
                &m.nodes.buffer,
                &m.links.buffer,
                &w.sort.starts.buffer,
                &w.sort.sorted.buffer,
                b.lumped,
                &w.dj.buffer,
                &w.carried.buffer,
                &m.contact_of.buffer,
                b.velocity,
                &w.state.buffer,
            )
        };
        let sweeps = 1..=self.relaxed;
        (
            sweeps.clone().map(launch).collect(),
            sweeps.map(|r| launch((r + 1) | SETTLE)).collect(),
        )
    }

    /// The whole iteration's launches, `contact_zone` at each width (where the adapter runs
    /// it), each [`Drift`]: one workgroup, Params.aux the contact nodes and aux2 the primary
    /// faces.
    fn zone(&self) -> Vec<[Launch; 2]> {
        (self.k.zones.iter())
            .map(|(_, k)| self.zone_launches(k))
            .collect()
    }

    /// [`Self::zone`] of kernel `k`.
    fn zone_launches(&self, k: &ContactZone) -> [Launch; 2] {
        let (ctx, b, m, w) = (self.ctx, self.b, self.m, self.w);
        let sort = &w.sort;
        [Drift::None, Drift::Late].map(|drift| {
            k.launch(
                ctx,
                self.np,
                self.nc,
                self.nf,
                b.step,
                self.grid,
                b.reference,
                b.displacement,
                b.velocity,
                b.acceleration,
                &m.pairs.buffer,
                self.points,
                self.faces,
                &w.constraints.buffer,
                &sort.keys.buffer,
                &m.rigid.buffer,
                &sort.counts.buffer,
                &sort.ranks.buffer,
                &sort.starts.buffer,
                &sort.sorted.buffer,
                &w.state.buffer,
                &m.nodes.buffer,
                &m.links.buffer,
                &w.touches.buffer,
                b.lumped,
                &w.dj.buffer,
                &w.results.buffer,
                &w.late[drift as usize].buffer,
                &w.bounds.buffer,
            )
        })
    }

    /// The report's launches, `contact_report`, each [`Drift`]: an invocation per pair
    /// (Params.aux) and per contact node (aux2).
    fn report(&self) -> [Launch; 2] {
        let (b, w) = (self.b, self.w);
        [Drift::None, Drift::Late].map(|drift| {
            self.k.report.launch(
                self.ctx,
                self.np.max(self.nc),
                self.np,
                self.nc,
                b.step,
                &w.constraints.buffer,
                &self.m.pairs.buffer,
                b.velocity,
                &w.state.buffer,
                &w.results.buffer,
                &self.m.rigid.buffer,
                &self.m.nodes.buffer,
                b.displacement,
                &w.late[drift as usize].buffer,
            )
        })
    }

    /// Every launch of the iteration, stage after stage.
    fn launches(&self, search: Option<&GpuSearch>, nodes: usize) -> Launches {
        let (bounds, grid) = self.search(search, nodes);
        let [constraints, count, fill, order] = self.sort();
        let [touches, compliance, warm] = self.compliance();
        let (sweep, apply, finish) = self.sweeps();
        let (relax, settle) = self.relax();
        // one workgroup per rigid body range: Params.aux the pairs
        let gather = self.k.gather.launch(
            self.ctx,
            self.nr * WORKGROUP,
            self.np,
            0,
            &self.m.links.buffer,
            &self.w.constraints.buffer,
            &self.w.dj.buffer,
            &self.w.state.buffer,
        );
        Launches {
            bounds,
            grid,
            constraints,
            count,
            fill,
            order,
            touches,
            compliance,
            warm,
            sweep,
            gather,
            apply,
            relax,
            settle,
            finish,
            report: self.report(),
            zone: self.zone(),
        }
    }
}

/// The explicit step's contact impulses on the device: the search, the constraint kernels
/// and the projected Jacobi sweeps, their buffers and launches built once.
pub struct ImpulseSweeps {
    pub(super) search: Option<GpuSearch>,
    kernels: IterationKernels,
    launches: Launches,
    pub(super) work: WorkBuffers,
    /// The pairs' bucket starts from the bucket sizes (faces + 1 buckets).
    scan: Scan,
    pub(super) staging: Storage,
    // kept alive for the bind groups
    _buffers: Vec<Storage>,
    pub(super) pairs: usize,
    pub(super) faces: usize,
    /// The rigid body ranges, whose impulse changes follow the pairs' in `dj`.
    pub(super) ranges: usize,
    pub(super) contact_nodes: usize,
    max_iterations: u32,
    /// Where set, the search bounds' speed starts from this one (f32 bits) instead of zero:
    /// the fastest node of a model of which these nodes are a part ([`Self::set_speed_floor`]).
    speed_floor: Option<Launch>,
    /// Which width of `contact_zone` runs a step's iteration in one workgroup after the
    /// search (an index into the kernels' widths), if it does rather than staged
    /// ([`Self::set_zone`], [`Self::set_form`]).
    zone: Option<usize>,
    /// Whether the staged iteration's recorded sweeps are `contact_relax` dispatches where
    /// it can run ([`Self::set_relax`]).
    relax: bool,
}

impl ImpulseSweeps {
    /// The iteration on `setup`; with `trial`, where the caller's run times the forms
    /// ([`Self::forms`]), `contact_zone` at the context's further widths too.
    pub fn new(
        ctx: &GpuContext,
        b: &StepBuffers,
        setup: &ContactSetup,
        (nodes, max_iterations): (usize, u32),
        trial: bool,
    ) -> Result<Self> {
        // the further widths where the run's trial times the zone (timestamps, a zone of
        // at most ZONE_TRIAL_PAIRS pairs)
        let trial = trial && ctx.has_timestamps() && setup.pairs.len() <= ZONE_TRIAL_PAIRS;
        let kernels = IterationKernels::new(ctx, trial);
        let (np, nf) = (setup.pairs.len(), setup.faces.len());
        let model = ModelBuffers::upload(ctx, setup, nodes)?;
        let work = WorkBuffers::new(ctx, (np, nf, nodes), setup.rigid.len(), &setup.nodes)?;
        let search = Self::search(ctx, b, setup, &work.bounds.buffer)?;
        // placeholders where no interface has a primary surface
        let none = Storage::new(ctx, "contact.none", 64)?;
        let (grid, points, faces) = match &search {
            Some(s) => (s.grid_buffer(), s.points_buffer(), s.faces_buffer()),
            None => (&none.buffer, &none.buffer, &none.buffer),
        };
        let launches = Bindings {
            ctx,
            k: &kernels,
            b,
            m: &model,
            w: &work,
            grid,
            points,
            faces,
            np: np as u32,
            nf: nf as u32,
            nc: setup.nodes.len() as u32,
            nr: setup.rigid.len() as u32,
            relaxed: match setup.rigid.is_empty() {
                true => max_iterations.min(RELAX_SWEEPS as u32),
                false => 0,
            },
        }
        .launches(search.as_ref(), nodes);
        let zone = (!launches.zone.is_empty() && np <= ZONE_PAIRS).then_some(0);
        let ModelBuffers {
            pairs,
            nodes: cnodes,
            links,
            rigid,
            contact_of,
        } = model;
        let scan = Scan::new(
            ctx,
            &work.sort.counts.buffer,
            &work.sort.starts.buffer,
            nf + 1,
        )?;
        Ok(ImpulseSweeps {
            search,
            kernels,
            launches,
            work,
            scan,
            staging: super::buffer::staging(ctx)?,
            _buffers: vec![pairs, cnodes, links, rigid, contact_of, none],
            pairs: np,
            faces: nf,
            ranges: setup.rigid.len(),
            contact_nodes: setup.nodes.len(),
            max_iterations,
            speed_floor: None,
            zone,
            relax: true,
        })
    }

    /// The device search, if any interface has a primary surface, with the step's buffers
    /// (the step uniform and the search `bounds`).
    fn search(
        ctx: &GpuContext,
        b: &StepBuffers,
        setup: &ContactSetup,
        bounds: &wgpu::Buffer,
    ) -> Result<Option<GpuSearch>> {
        if setup.queries.is_empty() {
            return Ok(None);
        }
        Ok(Some(GpuSearch::new(
            ctx,
            (b.reference, b.displacement, b.velocity),
            &setup.faces,
            &setup.face_first,
            &setup.queries,
            setup.face_size,
            Some(KeptBuffers {
                step: b.step,
                bounds,
            }),
        )?))
    }

    /// The contact results, [`SLOT`] floats per pair (see `contact_report.wgsl`).
    pub fn results_buffer(&self) -> &wgpu::Buffer {
        &self.work.results.buffer
    }

    /// Makes the search's bounds start from `speed` (f32 bits) as their fastest node's speed,
    /// from the next dispatch on: the iteration on a part of a model (a decomposed run's
    /// surfaces) then takes the whole model's search reach, as the single GPU does.
    pub fn set_speed_floor(&mut self, ctx: &GpuContext, speed: u32) {
        match &mut self.speed_floor {
            Some(l) => l.set_count(ctx, 1, speed),
            None => {
                let l = self
                    .kernels
                    .zero
                    .launch(ctx, 1, speed, 0, &self.work.bounds.buffer);
                self.speed_floor = Some(l);
            }
        }
    }

    pub fn pair_count(&self) -> usize {
        self.pairs
    }

    /// Runs each step's iteration in one workgroup (`contact_zone`) or staged, from the next
    /// recording on, where the adapter runs `contact_zone`; returns whether it runs. The
    /// results do not depend on it. By default it runs on zones of at most [`ZONE_PAIRS`]
    /// pairs.
    pub fn set_zone(&mut self, zone: bool) -> bool {
        self.zone = (zone && self.zone_available()).then_some(0);
        self.zone.is_some()
    }

    /// Records the staged iteration's sweeps as `contact_relax` dispatches (one a sweep and
    /// the settle) or as `contact_sweep` and `contact_apply` (two a sweep), from the next
    /// recording on, where `contact_relax` can run (no rigid body range); returns whether it
    /// runs. The results do not depend on it. By default it runs.
    pub fn set_relax(&mut self, relax: bool) -> bool {
        self.relax = relax && !self.launches.relax.is_empty();
        self.relax
    }

    /// Whether the staged iteration's recorded sweeps are `contact_relax` dispatches.
    pub fn runs_relax(&self) -> bool {
        self.relax && !self.launches.relax.is_empty()
    }

    /// The form the iteration is recorded in, from the next recording on.
    pub fn form(&self) -> ContactForm {
        match (self.zone, self.runs_relax()) {
            (Some(i), _) => ContactForm::Zone(self.kernels.zones[i].0),
            (None, true) => ContactForm::Relax,
            (None, false) => ContactForm::Staged,
        }
    }

    /// Records the iteration in `form` from the next recording on, where it runs here
    /// (otherwise the staged form); returns the form it is recorded in. The results do not
    /// depend on it.
    pub fn set_form(&mut self, form: ContactForm) -> ContactForm {
        self.zone = match form {
            ContactForm::Zone(lanes) => (self.kernels.zones.iter())
                .position(|(w, _)| *w == lanes)
                .or((self.zone_available()).then_some(0)),
            _ => None,
        };
        // staged after the zone, the sweeps take `contact_relax` unless the form says not
        self.set_relax(form != ContactForm::Staged);
        self.form()
    }

    /// The forms worth timing against each other on this adapter: `contact_zone` at each
    /// width built where it runs and the zone has at most [`ZONE_TRIAL_PAIRS`] pairs,
    /// `contact_relax` where no rigid body range gathers, and the two-dispatch sweeps.
    pub fn forms(&self) -> Vec<ContactForm> {
        let mut forms: Vec<ContactForm> = (self.kernels.zones.iter())
            .filter(|_| self.pairs <= ZONE_TRIAL_PAIRS)
            .map(|(w, _)| ContactForm::Zone(*w))
            .collect();
        if !self.launches.relax.is_empty() {
            forms.push(ContactForm::Relax);
        }
        forms.push(ContactForm::Staged);
        forms
    }

    /// Whether the adapter runs `contact_zone` (it binds [`ZONE_BINDINGS`] storage buffers
    /// per stage).
    pub fn zone_available(&self) -> bool {
        !self.launches.zone.is_empty()
    }

    /// Whether a step's iteration runs in one workgroup (no sweeps recorded).
    pub fn runs_zone(&self) -> bool {
        self.zone.is_some()
    }

    /// The lanes of the one-workgroup kernels, `contact_zone` and `contact_finish`.
    pub fn zone_lanes(&self) -> u32 {
        self.kernels.lanes
    }

    /// Bytes held on the device.
    pub fn device_bytes(&self) -> u64 {
        let w = &self.work;
        [
            &w.bounds,
            &w.constraints,
            &w.sort.keys,
            &w.sort.ranks,
            &w.sort.counts,
            &w.sort.starts,
            &w.sort.sorted,
            &w.touches,
            &w.dj,
            &w.carried,
            &w.state,
            &w.results,
        ]
        .iter()
        .map(|s| s.capacity)
        .chain(self._buffers.iter().map(|s| s.capacity))
        .sum()
    }

    /// Dispatches the search (if any; the faces sorted into its grid again unless `mode`
    /// keeps the last sort), the constraints up to their compliance (which starts the
    /// sweeps) and the warm start, inside an open compute pass. The results do not depend
    /// on `mode`.
    pub fn dispatch_setup(&self, pass: &mut wgpu::ComputePass, mode: SearchMode) {
        self.dispatch_search(pass, mode, false);
        self.dispatch_constraints(pass);
    }

    /// Dispatches the constraints up to their compliance (which starts the sweeps) and the
    /// warm start.
    fn dispatch_constraints(&self, pass: &mut wgpu::ComputePass) {
        let (k, l) = (&self.kernels, &self.launches);
        k.constraints.0.dispatch(pass, &l.constraints);
        k.count.0.dispatch(pass, &l.count);
        self.scan.dispatch(pass);
        k.fill.0.dispatch(pass, &l.fill);
        k.order.0.dispatch(pass, &l.order);
        k.touches.0.dispatch(pass, &l.touches);
        // its first invocation starts the sweeps, or stops with no pair in reach
        k.compliance.0.dispatch(pass, &l.compliance);
        if self.ranges > 0 {
            k.gather.0.dispatch(pass, &l.gather);
        }
        k.warm.0.dispatch(pass, &l.warm);
    }

    /// Dispatches the search, if any (the faces sorted into its grid again unless `mode`
    /// keeps the last sort); with `predict`, the step's predictor runs in its bounds
    /// ([`Self::dispatch_predicting`]).
    pub fn dispatch_search(&self, pass: &mut wgpu::ComputePass, mode: SearchMode, predict: bool) {
        let (k, l) = (&self.kernels, &self.launches);
        if let (Some(search), Some(bounds), Some(grid)) = (&self.search, &l.bounds, &l.grid) {
            if let Some(floor) = &self.speed_floor {
                k.zero.0.dispatch(pass, floor);
            }
            match predict {
                true => k.predict_bounds.0.dispatch(pass, &bounds[1]),
                false => k.bounds.0.dispatch(pass, &bounds[0]),
            }
            // a step that keeps the sort runs `search_grid`'s arithmetic in its narrow phase
            if mode == SearchMode::Keep {
                search.dispatch_narrow_keeping(pass);
            } else {
                k.grid
                    .0
                    .dispatch(pass, &grid[usize::from(mode == SearchMode::First)]);
                search.dispatch_sort(pass);
                search.dispatch_narrow(pass);
            }
        }
    }

    /// The sweeps [`Self::dispatch_sweeps`] records of `sweeps` asked for.
    pub fn recorded(&self, sweeps: u32) -> u32 {
        match self.runs_relax() {
            false => sweeps.min(self.max_iterations),
            true => sweeps.min(self.launches.relax.len() as u32),
        }
    }

    /// Dispatches `sweeps` sweeps (at most `max_iterations`) after the setup: with no rigid
    /// body range (and unless [`Self::set_relax`] says otherwise), up to [`RELAX_SWEEPS`]
    /// `contact_relax` dispatches and the settle after them, otherwise
    /// [`Self::dispatch_staged_sweeps`]. The same arithmetic either way.
    pub fn dispatch_sweeps(&self, pass: &mut wgpu::ComputePass, sweeps: u32) {
        let l = &self.launches;
        if !self.runs_relax() {
            self.dispatch_staged_sweeps(pass, sweeps);
            return;
        }
        let n = (sweeps as usize).min(l.relax.len());
        let relax = &self.kernels.relax.0;
        for launch in &l.relax[..n] {
            relax.dispatch(pass, launch);
        }
        if n > 0 {
            relax.dispatch(pass, &l.settle[n - 1]);
        }
    }

    /// Dispatches one launch of `contact_relax` alone (none where the iteration gathers rigid
    /// body ranges, or past [`RELAX_SWEEPS`]): the stages' tests run them one at a time.
    pub fn dispatch_relax(&self, pass: &mut wgpu::ComputePass, launch: Relax) {
        let l = &self.launches;
        let (launches, n) = match launch {
            Relax::Sweep(d) => (&l.relax, d),
            Relax::Settle(r) => (&l.settle, r),
        };
        if let Some(launch) = (n as usize).checked_sub(1).and_then(|i| launches.get(i)) {
            self.kernels.relax.0.dispatch(pass, launch);
        }
    }

    /// Dispatches `sweeps` sweeps (at most `max_iterations`), each a `contact_sweep`, the
    /// rigid bodies' `body_gather` and a `contact_apply` (which applies the stopping rule
    /// after the sweep): each can follow the last in a submission of its own.
    pub fn dispatch_staged_sweeps(&self, pass: &mut wgpu::ComputePass, sweeps: u32) {
        let (k, l) = (&self.kernels, &self.launches);
        for _ in 0..sweeps.min(self.max_iterations) {
            k.sweep.0.dispatch(pass, &l.sweep);
            if self.ranges > 0 {
                k.gather.0.dispatch(pass, &l.gather);
            }
            k.apply.0.dispatch(pass, &l.apply);
        }
    }

    /// Dispatches `contact_finish`: the sweeps the iteration still needs, in one workgroup.
    pub fn dispatch_finish(&self, pass: &mut wgpu::ComputePass) {
        let l = &self.launches.finish;
        self.kernels.finish.0.dispatch_with(pass, &l.bind, [1, 1]);
    }

    /// Dispatches the report of the step's results.
    pub fn dispatch_report(&self, pass: &mut wgpu::ComputePass) {
        self.dispatch_report_drifting(pass, Drift::None);
    }

    /// Dispatches the report, with the late nodes' drift as `drift` says.
    fn dispatch_report_drifting(&self, pass: &mut wgpu::ComputePass, drift: Drift) {
        let (k, l) = (&self.kernels, &self.launches);
        k.report.0.dispatch(pass, &l.report[drift as usize]);
    }

    /// Dispatches `contact_zone`: the whole iteration after the search in one workgroup
    /// (where the adapter runs it; nothing otherwise), at the width the step runs it with
    /// (the run's first otherwise).
    pub fn dispatch_zone(&self, pass: &mut wgpu::ComputePass) {
        self.dispatch_zone_drifting(pass, self.zone.unwrap_or(0), Drift::None);
    }

    /// Dispatches `contact_zone` at its `width`-th width, with the late nodes' drift as
    /// `drift` says.
    fn dispatch_zone_drifting(&self, pass: &mut wgpu::ComputePass, width: usize, drift: Drift) {
        if let (Some((_, k)), Some(l)) =
            (self.kernels.zones.get(width), self.launches.zone.get(width))
        {
            k.0.dispatch_with(pass, &l[drift as usize].bind, [1, 1]);
        }
    }

    /// Dispatches the whole iteration of a step, the search as `mode` says, inside an open
    /// compute pass (wgpu orders each dispatch after the writes of the ones before): after
    /// the search, `contact_zone` where it runs ([`Self::set_zone`]), otherwise the staged
    /// iteration with `sweeps` of its sweeps as dispatches of their own and the rest in
    /// `contact_finish`.
    pub fn dispatch(&self, pass: &mut wgpu::ComputePass, sweeps: u32, mode: SearchMode) {
        self.dispatch_step(pass, (sweeps, mode), false);
    }

    /// Whether the iteration can run the step's predictor in its search's bounds
    /// ([`Self::dispatch_predicting`]): it has a device search.
    pub fn predicts(&self) -> bool {
        self.launches.bounds.is_some()
    }

    /// [`Self::dispatch`] with the step's predictor, v* = v_n + dt/2 a_n, in the search's
    /// bounds and the step's drift, u_{n+1} = u_n + dt v* (`predict_bounds`, one dispatch in
    /// place of `explicit_predict` and `search_bounds`, drifts every node but the contact
    /// nodes, and the iteration's last kernel drifts those after the sweeps): the velocity
    /// is v_n on entry, and the iteration's nodes are every node of the model (a single
    /// device's step). The caller dispatches no `explicit_drift`. Only where the iteration
    /// [`Self::predicts`] (it has a device search); elsewhere the caller runs the predictor,
    /// [`Self::dispatch`] and the drift.
    pub fn dispatch_predicting(&self, pass: &mut wgpu::ComputePass, sweeps: u32, mode: SearchMode) {
        self.dispatch_step(pass, (sweeps, mode), true);
    }

    /// The step's iteration, `predict` as [`Self::dispatch_search`] takes it.
    fn dispatch_step(
        &self,
        pass: &mut wgpu::ComputePass,
        (sweeps, mode): (u32, SearchMode),
        predict: bool,
    ) {
        self.dispatch_search(pass, mode, predict);
        let drift = if predict { Drift::Late } else { Drift::None };
        if let Some(width) = self.zone {
            self.dispatch_zone_drifting(pass, width, drift);
            return;
        }
        self.dispatch_constraints(pass);
        self.dispatch_sweeps(pass, sweeps);
        self.dispatch_finish(pass);
        self.dispatch_report_drifting(pass, drift);
    }

    /// Records `part` of the iteration (one of the `dispatch_*` above) in a compute pass of
    /// its own.
    pub fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        part: impl FnOnce(&Self, &mut wgpu::ComputePass),
    ) {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("contact_iteration"),
            timestamp_writes: None,
        });
        part(self, &mut pass);
    }
}
