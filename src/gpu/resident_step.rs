//! [`ResidentStep`]: the whole explicit central-difference step on the device, many steps
//! per submission, with the history values reduced on the device and read back
//! asynchronously once per submission.
//!
//! A step records: `explicit_predict` (v* = v + dt/2 a; with a device contact search,
//! `predict_bounds` runs it with the search's bounds in one dispatch), the contact impulses
//! (`plane_contact` where all contacts are rigid planes, at most 8; otherwise the contact
//! iteration, [`super::ImpulseSweeps`], which takes rigid bodies' surfaces too),
//! `explicit_drift` (u += dt v; where `predict_bounds` runs, it drifts the nodes the
//! iteration does not move and the iteration drifts the rest), the element kernels (corner forces; after them the plies' damage and the cohesive pairs, [`CohesiveStage`], whose forces join the corners'), `gather_correct` over
//! every body's nodes and the rigid bodies' nodes in one dispatch (the nodal forces gathered
//! as `node_gather` sums them, a, v and the energy and momentum sums per workgroup, each
//! body's apart; a rank runs `node_gather` and `explicit_correct` apart, its shared nodes'
//! exchange between them) and
//! `history_reduce` (one row of history values, written at the step's place in the
//! submission's rows). A whole submission is
//! one compute pass. The contact search sorts the faces into its grid at the submission's
//! first step and every [`ResidentStep::set_search_interval`] steps after it, and keeps the
//! sort in between (its grid says when it no longer holds, and such a step tests every
//! face: the results do not depend on the interval). The rows, after the search grid's
//! record, are copied into a mapped read-back buffer at the end of the submission; two
//! read-back buffers alternate: the host decodes one submission's rows while the device runs
//! the next.
//!
//! The state stays on the device; [`ResidentStep::read_state`] fetches it (VTU frames).

use std::ops::Range;

use rayon::prelude::*;

use super::buffer::{map_read, read_back, read_floats, take_mapped, Mapping, Storage};
use super::cohesive_stage::{CohesiveStage, CohesiveTarget};
use super::contact_form::ContactForm;
use super::context::GpuContext;
use super::engine::{at_least_one, GpuKernels};
use super::failure_stage::{FailureStage, StageTarget};
use super::impulse_sweeps::{ContactSetup, ImpulseSweeps, StepBuffers};
use super::kernel::Launch;
use super::rank_exchange::RankExchange;
use super::rank_surface::RankSurface;
use super::submission_clock::{SubmissionClock, STAMP_BYTES};
use super::types::WORKGROUP;
use super::types::{self, to_device, Split3};
use super::{
    ExplicitCorrect, ExplicitDrift, ExplicitPredict, GatherCorrect, HistoryReduce, PlaneContact,
};
use crate::error::{ImpactError, Result};
use crate::kernels::cohesive_pairs::{CohesiveSetup, PairState};
use crate::kernels::cohesive_reduce::COHESIVE_COLUMNS;
use crate::kernels::cohesive_scatter::BondedNodes;
use crate::kernels::explicit_correct::FIELDS;
use crate::kernels::history_reduce::{
    OP_CORNERS, OP_DISPLACEMENT, OP_MAX, OP_PARTIALS, OP_SUM, OP_VELOCITY,
};
use crate::kernels::plane_contact::{slot, MAX_PLANES, SLOT};
use crate::kernels::{
    ElementData, LumpedNode, PlaneData, PlaneNode, ReduceColumn, SearchMode, SurveySetup,
    FAILURE_FIELDS,
};

/// Bytes of the search grid's record at the start of each read-back buffer.
const GRID_BYTES: u64 = std::mem::size_of::<types::GpuSearchGrid>() as u64;

/// Where the history rows start in a read-back buffer: after the search grid's record and
/// the submission's timestamps ([`SubmissionClock`]).
const ROWS_AT: u64 = GRID_BYTES + STAMP_BYTES;

/// What a collected submission took: its steps, the device's time for its compute pass
/// (where the adapter has timestamps) and the host's time to record and submit it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubmissionTime {
    pub steps: usize,
    pub device: Option<f64>,
    pub host: f64,
}

impl SubmissionTime {
    /// Seconds per step of the slower of the two (the host records a submission while the
    /// device runs the one before), or `None` without the device's time.
    pub fn per_step(&self) -> Option<f64> {
        (self.device).map(|d| d.max(self.host) / self.steps.max(1) as f64)
    }
}

/// What the steps of the last collected submission made of the contact search's kept grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchRecord {
    /// The largest share of a grid cell the steps that kept the grid needed (at most 1 while
    /// it holds; about 1 / (1 + skin) just after a sort).
    pub fill: f64,
    /// The steps of the run so far whose kept grid no longer held (they tested every face).
    pub stale_steps: u64,
}

/// What the resident step needs besides the elements, in f64 (the CPU twins take the same).
#[derive(Debug, Clone)]
pub struct ResidentSetup {
    pub dt: f64,
    /// The contact iteration's tolerance (a gap rate) and sweep limit.
    pub tolerance: f64,
    pub max_iterations: u32,
    pub lumped: Vec<LumpedNode>,
    pub planes: Vec<PlaneData>,
    pub plane_nodes: Vec<PlaneNode>,
    /// The first plane nodes whose contact results the history rows sum (all of them where
    /// `None`): a rank of a decomposed run reports the nodes it owns, listed first.
    pub reported_plane_nodes: Option<usize>,
    /// Node range of each body, then that of the rigid bodies' nodes where there are any
    /// (the correctors' ranges).
    pub bodies: Vec<Range<usize>>,
    /// Probe nodes.
    pub probes: Vec<u32>,
    /// Initial velocity and acceleration, 3 per node.
    pub velocity: Vec<f64>,
    pub acceleration: Vec<f64>,
    /// Contact between meshed bodies: the device contact iteration, which then takes the
    /// rigid planes too (as pairs); `planes` and `plane_nodes` are left empty.
    pub contact: Option<ContactSetup>,
    /// The ply failure survey of every step (materials with strengths): its record follows
    /// the columns in each history row.
    pub survey: Option<SurveySetup>,
    /// The supports' reactions: per column, the corner-force indices it sums (component-major,
    /// `a C + s`), after the probes' columns.
    pub reactions: Vec<Vec<u32>>,
    /// The plies' damage, where any element damages: the step's dissipation and its fibre
    /// share follow the failure record in each row.
    pub damage: Option<crate::kernels::damage_data::DamageData>,
    /// The cohesive interfaces, where the model has any: each interface's
    /// [`COHESIVE_COLUMNS`] values end each row.
    pub cohesive: Option<CohesiveSetup>,
}

/// Values of a history row, in order: per body [`FIELDS`] (kinetic, strain, gravity,
/// momentum x y z), per contact interface [`SLOT`] (its contact results, summed; the gap and
/// the sweeps as maxima), per probe 6 (displacement, velocity), the supports' reaction
/// columns, then the failure survey's record where there is one ([`FAILURE_FIELDS`]) and
/// the step's damage dissipation and its fibre share where there is damage, then each
/// cohesive interface's [`COHESIVE_COLUMNS`] values (none where `cohesive` is 0).
pub(crate) fn row_len(
    (bodies, interfaces, probes, reactions): (usize, usize, usize, usize),
    (survey, damage): (bool, bool),
    cohesive: usize,
) -> usize {
    let record = if survey { FAILURE_FIELDS } else { 0 };
    FIELDS * bodies
        + SLOT * interfaces
        + 6 * probes
        + reactions
        + record
        + 2 * usize::from(damage)
        + COHESIVE_COLUMNS * cohesive
}

/// The contact results' place of each interface in the plane kernel's layout: `plane_nodes`
/// nodes, each with [`SLOT`] floats per plane.
pub fn plane_slots(planes: usize, plane_nodes: usize) -> Vec<(u32, u32, u32)> {
    (0..planes as u32)
        .map(|p| (p * SLOT as u32, plane_nodes as u32, (SLOT * planes) as u32))
        .collect()
}

/// The contact results' place of each interface in the contact iteration's layout:
/// [`SLOT`] floats per pair, interface after interface.
pub(crate) fn pair_slots(interfaces: &[Range<usize>]) -> Vec<(u32, u32, u32)> {
    interfaces
        .iter()
        .map(|r| ((SLOT * r.start) as u32, r.len() as u32, SLOT as u32))
        .collect()
}

/// The row's columns given each body's first workgroup slot and workgroup count in the
/// correctors' partials, and each interface's (first, count, stride) in the contact results.
pub fn row_columns(
    groups: &[(u32, u32)],
    slots: &[(u32, u32, u32)],
    probes: &[u32],
) -> Vec<ReduceColumn> {
    let mut cols = Vec::new();
    for &(base, count) in groups {
        for q in 0..FIELDS as u32 {
            cols.push(ReduceColumn {
                first: base * FIELDS as u32 + q,
                count,
                stride: FIELDS as u32,
                op: OP_PARTIALS,
            });
        }
    }
    for &(first, count, stride) in slots {
        for f in 0..SLOT as u32 {
            cols.push(ReduceColumn {
                first: first + f,
                count,
                stride,
                op: if slot::reduced_by_max(f as usize) {
                    OP_MAX
                } else {
                    OP_SUM
                },
            });
        }
    }
    for &n in probes {
        for (op, a) in [OP_DISPLACEMENT, OP_VELOCITY]
            .into_iter()
            .flat_map(|op| (0..3).map(move |a| (op, a)))
        {
            cols.push(ReduceColumn {
                first: 3 * n + a,
                count: 1,
                stride: 1,
                op,
            });
        }
    }
    cols
}

/// The step's kernels' pipelines, built once.
pub(super) struct StepKernels {
    pub(super) predict: ExplicitPredict,
    pub(super) plane: PlaneContact,
    pub(super) drift: ExplicitDrift,
    pub(super) correct: ExplicitCorrect,
    pub(super) gather_correct: GatherCorrect,
    pub(super) reduce: HistoryReduce,
}

impl StepKernels {
    /// Builds the pipelines of the step's kernels (the element kernels are [`GpuKernels`]').
    fn new(ctx: &GpuContext) -> Self {
        StepKernels {
            predict: ExplicitPredict::new(ctx),
            plane: PlaneContact::new(ctx),
            drift: ExplicitDrift::new(ctx),
            correct: ExplicitCorrect::new(ctx),
            gather_correct: GatherCorrect::new(ctx),
            reduce: HistoryReduce::new(ctx),
        }
    }
}

/// The model's buffers of the step besides the elements': the acceleration, the lumped
/// masses, the rigid planes, their nodes and their contact results.
pub(super) struct ModelBuffers {
    pub(super) a: Storage,
    lumped: Storage,
    planes: Storage,
    plane_nodes: Storage,
    pub(super) results: Storage,
    plane_count: usize,
    plane_node_count: usize,
}

impl ModelBuffers {
    /// Uploads the setup's acceleration, lumped masses and rigid planes (in f32).
    fn upload(ctx: &GpuContext, setup: &ResidentSetup) -> Result<Self> {
        let a = Storage::with_data(ctx, "acceleration", &to_f32(&setup.acceleration))?;
        let lumped: Vec<types::Lumped> = to_device(&setup.lumped);
        let lumped = Storage::with_data(ctx, "lumped", &lumped)?;
        let planes: Vec<types::Plane> = to_device(&setup.planes);
        let planes = Storage::with_data(ctx, "planes", &at_least_one(planes))?;
        let pn: Vec<types::GpuPlaneNode> = to_device(&setup.plane_nodes);
        let plane_nodes = Storage::with_data(ctx, "plane_nodes", &at_least_one(pn))?;
        let (plane_count, plane_node_count) = (setup.planes.len(), setup.plane_nodes.len());
        let results = Storage::with_data(
            ctx,
            "plane_results",
            &vec![0.0f32; SLOT * plane_count * plane_node_count],
        )?;
        Ok(ModelBuffers {
            a,
            lumped,
            planes,
            plane_nodes,
            results,
            plane_count,
            plane_node_count,
        })
    }
}

/// The history row's columns, on the host and on the device, and the rows buffer.
pub(super) struct HistoryRows {
    /// The columns `history_reduce` writes (the failure record and the damage follow them).
    pub(super) column_list: Vec<ReduceColumn>,
    columns: Storage,
    /// The reaction columns' corner-force indices.
    lists: Storage,
    /// The history rows of one submission, `chunk_capacity` rows of `row_len` floats.
    pub(super) rows: Storage,
    pub(super) row_len: usize,
    /// Where the damage's two columns and the cohesive interfaces' start in a row.
    pub(super) damage_at: usize,
    pub(super) cohesive_at: usize,
}

impl HistoryRows {
    /// The columns of the bodies' partials (`groups`), of each interface's contact results
    /// and of the probes, and a rows buffer of `chunk_capacity` rows.
    fn new(
        ctx: &GpuContext,
        setup: &ResidentSetup,
        groups: &[(u32, u32)],
        m: &ModelBuffers,
        chunk_capacity: usize,
    ) -> Result<Self> {
        let slots = match &setup.contact {
            Some(c) => pair_slots(&c.interfaces),
            None => plane_slots(
                m.plane_count,
                (setup.reported_plane_nodes)
                    .map_or(m.plane_node_count, |r| r.min(m.plane_node_count)),
            ),
        };
        let mut column_list = row_columns(groups, &slots, &setup.probes);
        let mut lists = Vec::new();
        for r in &setup.reactions {
            column_list.push(ReduceColumn {
                first: lists.len() as u32,
                count: r.len() as u32,
                stride: 1,
                op: OP_CORNERS,
            });
            lists.extend_from_slice(r);
        }
        let survey = if setup.survey.is_some() {
            FAILURE_FIELDS
        } else {
            0
        };
        let damage_at = column_list.len() + survey;
        let cohesive_at = damage_at + 2 * usize::from(setup.damage.is_some());
        let row_len = cohesive_at
            + COHESIVE_COLUMNS * setup.cohesive.as_ref().map_or(0, |c| c.interfaces.len());
        let cols: Vec<types::GpuReduceColumn> = to_device(&column_list);
        let columns = Storage::with_data(ctx, "history.columns", &cols)?;
        let lists = Storage::with_data(ctx, "history.corner_lists", &at_least_one(lists))?;
        let rows = Storage::new(ctx, "history.rows", (chunk_capacity * row_len * 4) as u64)?;
        Ok(HistoryRows {
            column_list,
            columns,
            lists,
            rows,
            row_len,
            damage_at,
            cohesive_at,
        })
    }
}

/// The buffers the step's launches bind.
struct LaunchBuffers<'a> {
    k: &'a GpuKernels,
    step: &'a wgpu::Buffer,
    m: &'a ModelBuffers,
    partials: &'a Storage,
    /// The corrector's table of bodies, and the bodies in it.
    correct_bodies: &'a Storage,
    bodies: u32,
    history: &'a HistoryRows,
    /// The contact results the history reads: the contact iteration's or the planes'.
    results: &'a wgpu::Buffer,
}

pub(super) struct Launches {
    pub(super) predict: Launch,
    pub(super) plane: Option<Launch>,
    pub(super) drift: Launch,
    /// Every body's nodes in one dispatch.
    pub(super) correct: Launch,
    /// The gather and the corrector in one dispatch (a single device's step).
    pub(super) gather_correct: Launch,
    /// One per row of a submission: launch j writes the row of the submission's step j.
    pub(super) reduce: Vec<Launch>,
}

impl Launches {
    /// Every launch of the step, stage after stage; `groups` are the workgroups in all of
    /// the bodies' partials.
    fn new(ks: &StepKernels, b: &LaunchBuffers, groups: u32, chunk_capacity: usize) -> Self {
        let (k, ctx) = (b.k, &b.k.ctx);
        let nodes = k.nodes;
        Launches {
            predict: ks.predict.launch(
                ctx,
                3 * nodes as u32,
                0,
                0,
                b.step,
                &b.m.a.buffer,
                &k.v.buffer,
            ),
            plane: Self::plane(&ks.plane, b),
            drift: ks
                .drift
                .launch(ctx, nodes as u32, 0, 0, b.step, &k.v.buffer, &k.u.buffer),
            correct: Self::correct(&ks.correct, b, groups),
            gather_correct: Self::gather_correct(&ks.gather_correct, b, groups),
            reduce: Self::reduce(&ks.reduce, b, chunk_capacity),
        }
    }

    /// The rigid planes' launch, where there are plane nodes.
    fn plane(plane: &PlaneContact, b: &LaunchBuffers) -> Option<Launch> {
        let (k, m) = (b.k, b.m);
        // Params.aux: the number of planes
        (m.plane_node_count > 0).then(|| {
            plane.launch(
                &k.ctx,
                m.plane_node_count as u32,
                m.plane_count as u32,
                0,
                b.step,
                &k.mesh.reference.buffer,
                &k.u.buffer,
                &m.a.buffer,
                &m.lumped.buffer,
                &m.planes.buffer,
                &m.plane_nodes.buffer,
                &k.v.buffer,
                &m.results.buffer,
            )
        })
    }

    /// The corrector's launch over every body's `groups` workgroups (Params.aux the
    /// bodies).
    fn correct(correct: &ExplicitCorrect, b: &LaunchBuffers, groups: u32) -> Launch {
        let k = b.k;
        correct.launch(
            &k.ctx,
            groups * WORKGROUP,
            b.bodies,
            0,
            b.step,
            &k.u.buffer,
            &k.forces.buffer,
            &b.m.lumped.buffer,
            &k.v.buffer,
            &b.m.a.buffer,
            &b.partials.buffer,
            &b.correct_bodies.buffer,
        )
    }

    /// The gather and corrector's launch over every body's `groups` workgroups (Params.aux
    /// the bodies, aux2 the corner slots).
    fn gather_correct(kernel: &GatherCorrect, b: &LaunchBuffers, groups: u32) -> Launch {
        let k = b.k;
        kernel.launch(
            &k.ctx,
            groups * WORKGROUP,
            b.bodies,
            k.layout.count() as u32,
            b.step,
            &k.u.buffer,
            &b.m.lumped.buffer,
            &k.v.buffer,
            &b.m.a.buffer,
            &b.partials.buffer,
            &b.correct_bodies.buffer,
            &k.mesh.offsets.buffer,
            &k.mesh.incidence.buffer,
            &k.corners.buffer,
        )
    }

    /// The history reductions' launches, one per row of a submission.
    fn reduce(reduce: &HistoryReduce, b: &LaunchBuffers, chunk_capacity: usize) -> Vec<Launch> {
        let (k, ctx, h) = (b.k, &b.k.ctx, b.history);
        (0..chunk_capacity)
            .map(|j| {
                // one workgroup per column, writing row j at rows[first..]: the grid
                // counts invocations, Params.count the columns
                let (columns_n, first) = (h.column_list.len() as u32, (j * h.row_len) as u32);
                let mut l = reduce.launch(
                    ctx,
                    columns_n * WORKGROUP,
                    first,
                    0,
                    &h.columns.buffer,
                    &b.partials.buffer,
                    b.results,
                    &k.u.buffer,
                    &k.v.buffer,
                    &k.corners.buffer,
                    &h.lists.buffer,
                    &h.rows.buffer,
                );
                l.set_count(ctx, columns_n, first);
                l
            })
            .collect()
    }
}

/// A submission whose rows are being read back.
struct Pending {
    steps: usize,
    index: wgpu::SubmissionIndex,
    mapped: Mapping,
    /// The host's seconds to record and submit it.
    host: f64,
}

pub struct ResidentStep {
    pub(super) k: GpuKernels,
    pub(super) kernels: StepKernels,
    /// The step's constants (`dt` changes for a shortened last step).
    step: wgpu::Buffer,
    step_consts: types::Step,
    /// The accelerations, lumped masses, planes and plane results.
    pub(super) m: ModelBuffers,
    /// The correctors' workgroup sums, [`FIELDS`] per workgroup, body after body.
    pub(super) partials: Storage,
    /// Each body's first workgroup, first node and nodes for the corrector, and the
    /// workgroups in all.
    correct_bodies: Storage,
    /// The history row's columns and the rows buffer.
    pub(super) history: HistoryRows,
    pub(super) launches: Launches,
    pub(super) contact: Option<ImpulseSweeps>,
    /// The ply failure survey of every step, where materials have strengths.
    failure: Option<FailureStage>,
    /// The cohesive interfaces, where the model has any.
    cohesive: Option<CohesiveStage>,
    /// A rank's exchange of the forces of the nodes it shares (a decomposed run).
    pub(super) exchange: Option<RankExchange>,
    /// A rank's part in the contact iteration on the surfaces (a decomposed run).
    pub(super) surface: Option<RankSurface>,
    /// Sweeps of the contact iteration recorded per step as dispatches of their own (at most
    /// `max_iterations`); `contact_finish` runs the rest.
    sweeps: u32,
    max_iterations: u32,
    /// Steps between the contact search's sorts of the faces (1: every step).
    search_interval: usize,
    /// The search grid's record of the last collected submission.
    search_record: Option<SearchRecord>,
    readback: [Storage; 2],
    pending: [Option<Pending>; 2],
    /// The submissions' timestamps, where the adapter has them.
    pub(super) clock: Option<SubmissionClock>,
    /// The time of the last collected submission.
    collected: Option<SubmissionTime>,
    /// Steps one submission can hold (the read-back buffers' size).
    pub chunk_capacity: usize,
}

impl ResidentStep {
    pub fn new(
        ctx: GpuContext,
        data: &ElementData,
        setup: &ResidentSetup,
        chunk_capacity: usize,
    ) -> Result<Self> {
        if setup.planes.len() > MAX_PLANES {
            return Err(ImpactError::Gpu(format!(
                "{} rigid planes: the device step takes at most {MAX_PLANES}",
                setup.planes.len()
            )));
        }
        let mut k = GpuKernels::new(ctx, data)?.with_damage(setup.damage.clone())?;
        // the displacement starts at zero, as a new buffer is
        k.upload_velocity(&setup.velocity)?;
        let ctx = &k.ctx;
        let m = ModelBuffers::upload(ctx, setup)?;
        let (step, step_consts) = Self::step_uniform(ctx, setup);
        let kernels = StepKernels::new(ctx);
        // the correctors' partials: one slot of FIELDS per workgroup, body after body
        let (groups, total_groups) = Self::partial_groups(&setup.bodies);
        let partials = Storage::new(ctx, "partials", (total_groups as usize * FIELDS * 4) as u64)?;
        let correct_bodies = Self::correct_bodies(ctx, &setup.bodies, &groups, total_groups)?;
        let contact = Self::new_impulse_sweeps(&k, &step, &m, setup)?;
        let chunk_capacity = chunk_capacity.max(1);
        let history = HistoryRows::new(ctx, setup, &groups, &m, chunk_capacity)?;
        let buffers = LaunchBuffers {
            k: &k,
            step: &step,
            m: &m,
            partials: &partials,
            correct_bodies: &correct_bodies,
            bodies: setup.bodies.len() as u32,
            history: &history,
            results: contact
                .as_ref()
                .map_or(&m.results.buffer, |c| c.results_buffer()),
        };
        let launches = Launches::new(&kernels, &buffers, total_groups, chunk_capacity);
        let failure = (setup.survey.as_ref())
            .map(|s| {
                let target = StageTarget {
                    displacement: &k.u.buffer,
                    rows: &history.rows.buffer,
                    row_len: history.row_len,
                    column: history.column_list.len(),
                    chunk_capacity,
                };
                FailureStage::new(ctx, s, &target)
            })
            .transpose()?;
        if let Some((d, _)) = &mut k.damage {
            // the step's dissipation and its fibre share close each row; the state advances
            // every step
            let at = (history.row_len, history.damage_at, chunk_capacity);
            d.reduce_into_rows(ctx, &history.rows.buffer, at);
            d.set_step(ctx, setup.dt, true);
        }
        let cohesive = (setup.cohesive.as_ref())
            .map(|c| Self::cohesive_stage(&k, data, c, (&history, chunk_capacity)))
            .transpose()?;
        let readback = Self::readback_buffers(ctx, chunk_capacity * history.row_len)?;
        let clock = SubmissionClock::new(ctx)?;
        Ok(ResidentStep {
            kernels,
            step,
            step_consts,
            m,
            partials,
            correct_bodies,
            history,
            launches,
            contact,
            failure,
            cohesive,
            exchange: None,
            surface: None,
            sweeps: setup.max_iterations,
            max_iterations: setup.max_iterations,
            search_interval: 1,
            search_record: None,
            readback,
            pending: [None, None],
            clock,
            collected: None,
            chunk_capacity,
            k,
        })
    }

    /// The cohesive interfaces' stage on the engine's buffers, its reduces writing into the
    /// rows of `history`.
    fn cohesive_stage(
        k: &GpuKernels,
        data: &ElementData,
        setup: &CohesiveSetup,
        (history, chunk_capacity): (&HistoryRows, usize),
    ) -> Result<CohesiveStage> {
        let layout = data.layout();
        let incidence = crate::kernels::node_gather::Incidence::new(&data.elements, k.nodes);
        let mut bonded = BondedNodes::new(setup, &incidence);
        for b in &mut bonded.nodes {
            b.corner = layout.to_device(b.corner as usize) as u32;
        }
        let target = CohesiveTarget {
            displacement: &k.u.buffer,
            corner_forces: &k.corners.buffer,
            slots: layout.count() as u32,
        };
        let mut stage = CohesiveStage::new(&k.ctx, setup, &bonded, &target)?;
        let at = (history.row_len, history.cohesive_at, chunk_capacity);
        stage.reduce_into_rows(&k.ctx, &history.rows.buffer, at);
        Ok(stage)
    }

    /// The step's constants and their uniform buffer, written.
    fn step_uniform(ctx: &GpuContext, setup: &ResidentSetup) -> (wgpu::Buffer, types::Step) {
        let step_consts = types::Step {
            dt: setup.dt as f32,
            tolerance: setup.tolerance as f32,
            max_iterations: setup.max_iterations,
            pad: 0,
        };
        let step = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("explicit_step"),
            size: std::mem::size_of::<types::Step>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        ctx.queue
            .write_buffer(&step, 0, bytemuck::bytes_of(&step_consts));
        (step, step_consts)
    }

    /// Each body's (first workgroup slot, workgroups) in the correctors' partials (at least
    /// one each), and the workgroups in all.
    fn partial_groups(bodies: &[Range<usize>]) -> (Vec<(u32, u32)>, u32) {
        let mut groups = Vec::new();
        let mut total_groups = 0u32;
        for b in bodies {
            let g = b.len().div_ceil(WORKGROUP as usize).max(1) as u32;
            groups.push((total_groups, g));
            total_groups += g;
        }
        (groups, total_groups)
    }

    /// The corrector's table of bodies: each body's first workgroup, first node and nodes,
    /// then the workgroups in all.
    fn correct_bodies(
        ctx: &GpuContext,
        bodies: &[Range<usize>],
        groups: &[(u32, u32)],
        total_groups: u32,
    ) -> Result<Storage> {
        let table: Vec<[u32; 4]> = (bodies.iter().zip(groups))
            .map(|(b, &(first, _))| [first, b.start as u32, b.len() as u32, 0])
            .chain([[total_groups, 0, 0, 0]])
            .collect();
        Storage::with_data(ctx, "correct_bodies", &table)
    }

    /// The device contact iteration, where the model has contact between meshed bodies.
    fn new_impulse_sweeps(
        k: &GpuKernels,
        step: &wgpu::Buffer,
        m: &ModelBuffers,
        setup: &ResidentSetup,
    ) -> Result<Option<ImpulseSweeps>> {
        let Some(c) = &setup.contact else {
            return Ok(None);
        };
        let buffers = StepBuffers {
            step,
            reference: &k.mesh.reference.buffer,
            displacement: &k.u.buffer,
            velocity: &k.v.buffer,
            acceleration: &m.a.buffer,
            lumped: &m.lumped.buffer,
        };
        // the resident solver's trial times the forms
        Ok(Some(ImpulseSweeps::new(
            &k.ctx,
            &buffers,
            c,
            (k.nodes, setup.max_iterations),
            true,
        )?))
    }

    /// The two read-back buffers of the search grid's record, the timestamps and `floats` of
    /// history rows.
    fn readback_buffers(ctx: &GpuContext, floats: usize) -> Result<[Storage; 2]> {
        let make_readback = || {
            Storage::with_usage(
                ctx,
                "history.readback",
                ROWS_AT + (floats * 4) as u64,
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            )
        };
        Ok([make_readback()?, make_readback()?])
    }

    pub fn device_name(&self) -> String {
        self.k.ctx.adapter.name.clone()
    }

    pub fn context(&self) -> &GpuContext {
        &self.k.ctx
    }

    /// Floats per history row (see [`row_len`]).
    pub fn row_len(&self) -> usize {
        self.history.row_len
    }

    /// Bytes held on the device.
    pub fn device_bytes(&self) -> u64 {
        self.k.device_bytes()
            + [
                &self.m.a,
                &self.m.lumped,
                &self.m.planes,
                &self.m.plane_nodes,
                &self.m.results,
                &self.partials,
                &self.correct_bodies,
                &self.history.columns,
                &self.history.rows,
                &self.readback[0],
                &self.readback[1],
            ]
            .iter()
            .map(|s| s.capacity)
            .sum::<u64>()
            + self.contact.as_ref().map_or(0, |c| c.device_bytes())
            + self.failure.as_ref().map_or(0, |f| f.device_bytes())
            + self.cohesive.as_ref().map_or(0, |c| c.device_bytes())
    }

    /// The acceleration (3 per node).
    pub fn read_acceleration(&mut self) -> Result<Vec<f64>> {
        let k = &mut self.k;
        read_floats(
            &k.ctx,
            &mut k.staging,
            "read_back",
            &self.m.a.buffer,
            3 * k.nodes,
        )
    }

    /// Whether the step runs its predictor in the contact search's bounds and its contact
    /// iteration drifts every node (no `explicit_predict` or `explicit_drift`): where the
    /// iteration has a device search and no rigid planes' kernel runs between the
    /// predictor and the iteration.
    pub fn predicts(&self) -> bool {
        self.launches.plane.is_none() && self.contact.as_ref().is_some_and(|c| c.predicts())
    }

    /// Dispatches the step's stages before the contact iteration (the predictor, and the
    /// rigid planes' impulses when they are the only contacts).
    pub(super) fn dispatch_front(&self, pass: &mut wgpu::ComputePass) {
        let l = &self.launches;
        self.kernels.predict.0.dispatch(pass, &l.predict);
        if let Some(p) = &l.plane {
            self.kernels.plane.0.dispatch(pass, p);
        }
    }

    /// Dispatches the step's stages after the contact iteration: the drift (unless the
    /// step `drifted` already), the element kernels, the gather with the correctors in one
    /// dispatch, the failure survey and the history row of the submission's step `j`.
    fn dispatch_back(&self, pass: &mut wgpu::ComputePass, j: usize, drifted: bool) {
        let l = &self.launches;
        if !drifted {
            self.kernels.drift.0.dispatch(pass, &l.drift);
        }
        self.k.dispatch_element_kernels(pass);
        if let Some(c) = &self.cohesive {
            c.dispatch(pass);
        }
        self.kernels
            .gather_correct
            .0
            .dispatch(pass, &l.gather_correct);
        self.dispatch_survey_row(pass, j);
    }

    /// Dispatches the drift and the internal forces.
    pub(super) fn dispatch_forces(&self, pass: &mut wgpu::ComputePass) {
        self.kernels.drift.0.dispatch(pass, &self.launches.drift);
        self.k.dispatch_internal_forces(pass);
    }

    /// Dispatches the correctors, the failure survey and the history row of the
    /// submission's step `j`.
    pub(super) fn dispatch_row(&self, pass: &mut wgpu::ComputePass, j: usize) {
        self.kernels
            .correct
            .0
            .dispatch(pass, &self.launches.correct);
        self.dispatch_survey_row(pass, j);
    }

    /// Dispatches the failure survey, the damage's dissipation and the history row of the
    /// submission's step `j`.
    fn dispatch_survey_row(&self, pass: &mut wgpu::ComputePass, j: usize) {
        let l = &self.launches;
        if let Some(f) = &self.failure {
            f.dispatch(pass, j);
        }
        if let Some((d, _)) = &self.k.damage {
            d.dispatch_row(pass, j);
        }
        if let Some(c) = &self.cohesive {
            c.dispatch_row(pass, j);
        }
        self.kernels.reduce.0.dispatch(pass, &l.reduce[j]);
    }

    /// Records `steps` whole steps, writing their history rows into the rows buffer, in one
    /// compute pass (wgpu orders each dispatch after the writes of the ones before; the
    /// search zeroes its counters with `fill_words` and `bucket_order` clears the
    /// iteration's, not buffer clears, which would end the pass), with `stamps` at its start
    /// and end if given.
    pub(super) fn record_steps(
        &self,
        enc: &mut wgpu::CommandEncoder,
        steps: usize,
        stamps: Option<wgpu::ComputePassTimestampWrites>,
    ) {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("explicit_step"),
            timestamp_writes: stamps,
        });
        for j in 0..steps {
            let mode = self.search_mode(j);
            let drifted = match &self.contact {
                Some(c) if self.predicts() => {
                    c.dispatch_predicting(&mut pass, self.sweeps, mode);
                    true
                }
                contact => {
                    self.dispatch_front(&mut pass);
                    if let Some(c) = contact {
                        c.dispatch(&mut pass, self.sweeps, mode);
                    }
                    false
                }
            };
            self.dispatch_back(&mut pass, j, drifted);
        }
    }

    /// What the submission's step `j` does with the search grid: its first step sorts the
    /// faces and starts the grid's fill anew, every `search_interval`-th sorts them, the
    /// others keep the sort.
    fn search_mode(&self, j: usize) -> SearchMode {
        if j == 0 {
            SearchMode::First
        } else if j % self.search_interval == 0 {
            SearchMode::Build
        } else {
            SearchMode::Keep
        }
    }

    /// Steps between the contact search's sorts of the faces, from the next submission on
    /// (at least 1). The results do not depend on it.
    pub fn set_search_interval(&mut self, steps: usize) {
        self.search_interval = steps.max(1);
    }

    pub fn search_interval(&self) -> usize {
        self.search_interval
    }

    /// The sorts of the faces a submission of `steps` steps records (none without a device
    /// search).
    pub fn sorts_in(&self, steps: usize) -> usize {
        match self.contact.as_ref().and_then(|c| c.search.as_ref()) {
            Some(_) => steps.div_ceil(self.search_interval),
            None => 0,
        }
    }

    /// The search grid's record of the last collected submission (none without a device
    /// search, or before the first collection).
    pub fn search_record(&self) -> Option<SearchRecord> {
        self.search_record
    }

    /// Records and submits `steps` steps whose history rows go to read-back buffer `slot`,
    /// and starts mapping it; [`Self::collect`] waits for them. Does not wait.
    pub fn submit(&mut self, slot: usize, steps: usize) -> Result<()> {
        if self.pending[slot].is_some() {
            return Err(ImpactError::Gpu(format!(
                "read-back buffer {slot} is still in use"
            )));
        }
        let start = std::time::Instant::now();
        let steps = steps.min(self.chunk_capacity);
        let bytes = ROWS_AT + (steps * self.history.row_len * 4) as u64;
        let ctx = &self.k.ctx;
        let mut enc = ctx.encoder("explicit_steps");
        let clock = self.clock.as_ref();
        self.record_steps(&mut enc, steps, clock.map(|c| c.writes(slot)));
        let readback = &self.readback[slot].buffer;
        if let Some(s) = self.contact.as_ref().and_then(|c| c.search.as_ref()) {
            enc.copy_buffer_to_buffer(s.grid_buffer(), 0, readback, 0, GRID_BYTES);
        }
        if let Some(c) = clock {
            c.copy(&mut enc, slot, readback, GRID_BYTES);
        }
        enc.copy_buffer_to_buffer(
            &self.history.rows.buffer,
            0,
            readback,
            ROWS_AT,
            bytes - ROWS_AT,
        );
        let index = ctx.queue.submit([enc.finish()]);
        self.pending[slot] = Some(Pending {
            steps,
            index,
            mapped: map_read(&self.readback[slot].buffer, bytes),
            host: start.elapsed().as_secs_f64(),
        });
        Ok(())
    }

    /// Every buffer a step starts from: u, v, a and the contact results (of the contact
    /// iteration, or of the rigid planes), and the damage's records and points' states.
    /// With them and the constants, the next step is determined.
    fn state_buffers(&self) -> Vec<&wgpu::Buffer> {
        let results = match &self.contact {
            Some(c) => c.results_buffer(),
            None => &self.m.results.buffer,
        };
        let damage = self.k.damage.iter().flat_map(|(d, _)| d.state_buffers());
        let cohesive = self.cohesive.iter().map(CohesiveStage::state_buffer);
        [
            &self.k.u.buffer,
            &self.k.v.buffer,
            &self.m.a.buffer,
            results,
        ]
        .into_iter()
        .chain(damage)
        .chain(cohesive)
        .collect()
    }

    /// The bytes of every buffer a step starts from (`state_buffers`: u, v, a and the contact
    /// results); nothing may be in flight.
    pub fn read_step_state(&mut self) -> Result<Vec<Vec<u32>>> {
        if self.pending.iter().any(Option::is_some) {
            return Err(ImpactError::Gpu(
                "read_step_state: a submission is still in flight".into(),
            ));
        }
        let sizes: Vec<(usize, wgpu::Buffer)> = self
            .state_buffers()
            .iter()
            .map(|b| ((b.size() / 4) as usize, (*b).clone()))
            .collect();
        let k = &mut self.k;
        sizes
            .iter()
            .map(|(words, buffer)| {
                read_back(&k.ctx, &mut k.staging, "read_step_state", buffer, *words)
            })
            .collect()
    }

    /// The words of each buffer [`Self::read_step_state`] reads (their padding included).
    pub fn step_state_words(&self) -> Vec<usize> {
        (self.state_buffers().iter())
            .map(|b| (b.size() / 4) as usize)
            .collect()
    }

    /// Writes back what [`Self::read_step_state`] read (of an engine of the same model).
    pub fn write_step_state(&self, state: &[Vec<u32>]) -> Result<()> {
        let buffers = self.state_buffers();
        if state.len() != buffers.len()
            || state
                .iter()
                .zip(&buffers)
                .any(|(s, b)| (s.len() * 4) as u64 != b.size())
        {
            return Err(ImpactError::Gpu(
                "write_step_state: the state is of another model".into(),
            ));
        }
        for (s, b) in state.iter().zip(buffers) {
            self.k.ctx.queue.write_buffer(b, 0, bytemuck::cast_slice(s));
        }
        Ok(())
    }

    /// Sweeps of the contact iteration recorded per step as dispatches of their own, from
    /// the next submission on (at most `max_iterations`). The results do not depend on it:
    /// `contact_finish` runs the sweeps a step needs after them.
    pub fn set_sweeps(&mut self, sweeps: u32) {
        self.sweeps = sweeps.min(self.max_iterations);
    }

    /// Sweeps recorded per step as dispatches of their own: none where the iteration runs in
    /// one workgroup ([`ImpulseSweeps::set_zone`]).
    pub fn sweeps(&self) -> u32 {
        match &self.contact {
            Some(c) if c.runs_zone() => 0,
            Some(c) => c.recorded(self.sweeps),
            _ => self.sweeps,
        }
    }

    /// The device contact iteration, where the model has contact between meshed bodies.
    pub fn impulse_sweeps_ref(&self) -> Option<&ImpulseSweeps> {
        self.contact.as_ref()
    }

    /// Runs each step's contact iteration in one workgroup or staged, from the next
    /// submission on ([`ImpulseSweeps::set_zone`]); returns whether it runs in one
    /// workgroup. The results do not depend on it.
    pub fn set_zone(&mut self, zone: bool) -> bool {
        self.contact.as_mut().is_some_and(|c| c.set_zone(zone))
    }

    /// Records the staged iteration's sweeps as `contact_relax` dispatches or as
    /// `contact_sweep` and `contact_apply`, from the next submission on
    /// ([`ImpulseSweeps::set_relax`]); returns whether `contact_relax` runs. The results do
    /// not depend on it.
    pub fn set_relax(&mut self, relax: bool) -> bool {
        self.contact.as_mut().is_some_and(|c| c.set_relax(relax))
    }

    /// Waits for submission `slot` and returns its rows (steps x [`Self::row_len`]).
    pub fn collect(&mut self, slot: usize) -> Result<Vec<f32>> {
        let Some(p) = self.pending[slot].take() else {
            return Err(ImpactError::Gpu(format!(
                "nothing submitted to read-back buffer {slot}"
            )));
        };
        let ctx = &self.k.ctx;
        ctx.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(p.index),
                timeout: None,
            })
            .map_err(|e| {
                ImpactError::Gpu(format!(
                    "{}: waiting for the explicit steps: {e}",
                    ctx.adapter.name
                ))
            })?;
        let bytes = ROWS_AT + (p.steps * self.history.row_len * 4) as u64;
        let buffer = &self.readback[slot].buffer;
        let mut words: Vec<u32> = take_mapped(ctx, buffer, bytes, &p.mapped, "the history rows")?;
        let rows = (words.split_off(ROWS_AT as usize / 4).into_iter())
            .map(f32::from_bits)
            .collect();
        let (grid_words, stamps) = words.split_at(GRID_BYTES as usize / 4);
        self.collected = Some(SubmissionTime {
            steps: p.steps,
            device: self.clock.as_ref().and_then(|c| c.seconds(stamps)),
            host: p.host,
        });
        if self.sorts_in(1) > 0 {
            let grid: types::GpuSearchGrid =
                bytemuck::pod_read_unaligned(bytemuck::cast_slice(grid_words));
            self.search_record = Some(SearchRecord {
                fill: grid.fill as f64,
                stale_steps: grid.stale_steps as u64,
            });
        }
        Ok(rows)
    }

    /// What the last collected submission took ([`Self::collect`]).
    pub fn collected_time(&self) -> Option<SubmissionTime> {
        self.collected
    }

    /// Whether the device times its submissions (the adapter has timestamp queries).
    pub fn times_submissions(&self) -> bool {
        self.clock.is_some()
    }

    /// The form the contact iteration is recorded in from the next submission on (`None`
    /// without the device contact iteration).
    pub fn form(&self) -> Option<ContactForm> {
        self.contact.as_ref().map(|c| c.form())
    }

    /// Records the contact iteration in `form` from the next submission on, where it runs
    /// here ([`ImpulseSweeps::set_form`]). The results do not depend on it.
    pub fn set_form(&mut self, form: ContactForm) -> Option<ContactForm> {
        self.contact.as_mut().map(|c| c.set_form(form))
    }

    /// The forms of the contact iteration worth timing here ([`ImpulseSweeps::forms`]).
    pub fn forms(&self) -> Vec<ContactForm> {
        self.contact.as_ref().map_or(Vec::new(), |c| c.forms())
    }

    /// Sets the step length of the submissions from the next on (a shortened last step).
    pub fn set_dt(&mut self, dt: f64) {
        self.step_consts.dt = dt as f32;
        self.k
            .ctx
            .queue
            .write_buffer(&self.step, 0, bytemuck::bytes_of(&self.step_consts));
        if let Some((d, _)) = &mut self.k.damage {
            d.set_step(&self.k.ctx, dt, true);
        }
    }

    /// The damage's inputs, where any element damages.
    pub fn damage_data(&self) -> Option<&crate::kernels::damage_data::DamageData> {
        self.k.damage.as_ref().map(|(_, d)| d)
    }

    /// The damage state on the device (where any element damages); nothing may be in
    /// flight.
    pub fn read_damage(&mut self) -> Result<Option<crate::kernels::damage_data::DamageState>> {
        self.k.read_damage()
    }

    /// Every cohesive pair's state on the device (where the model has cohesive interfaces);
    /// nothing may be in flight.
    pub fn read_cohesive(&mut self) -> Result<Option<Vec<PairState>>> {
        let k = &mut self.k;
        (self.cohesive.as_ref())
            .map(|c| c.read_state(&k.ctx, &mut k.staging))
            .transpose()
    }

    /// Whether read-back buffer `slot` holds a submission not yet collected.
    pub fn is_pending(&self, slot: usize) -> bool {
        self.pending[slot].is_some()
    }

    /// The device's state after everything submitted: displacement and velocity (3 per
    /// node) and the contact results ([`SLOT`] per (plane node, plane), or per pair of the
    /// contact iteration).
    pub fn read_state(&mut self) -> Result<(Vec<f64>, Vec<f64>, Vec<f64>)> {
        let k = &mut self.k;
        let (ctx, staging, label) = (&k.ctx, &mut k.staging, "read_state");
        let u: Vec<Split3> = read_back(ctx, staging, label, &k.u.buffer, k.nodes)?;
        let v = read_floats(ctx, staging, label, &k.v.buffer, 3 * k.nodes)?;
        let (results, count) = match &self.contact {
            Some(c) => (c.results_buffer(), SLOT * c.pair_count()),
            None => (
                &self.m.results.buffer,
                SLOT * self.m.plane_count * self.m.plane_node_count,
            ),
        };
        let r = read_floats(ctx, staging, label, results, count)?;
        let u = u
            .iter()
            .flat_map(|s| (0..3).map(|a| s.hi[a] as f64 + s.lo[a] as f64))
            .collect();
        Ok((u, v, r))
    }
}

/// f64 values as the device's f32.
pub(super) fn to_f32(x: &[f64]) -> Vec<f32> {
    x.par_iter().map(|&a| a as f32).collect()
}
