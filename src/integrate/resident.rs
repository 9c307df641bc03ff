//! [`ResidentSolver`]: the explicit path with every stage of the step on the GPU
//! ([`crate::gpu::ResidentStep`]). The same time discretisation and the same contact
//! iteration as [`super::ExplicitSolver`], its CPU twin (`device = "cpu"`): see
//! `integrate/explicit/`, `kernels/plane_contact.rs` (rigid planes alone) and
//! `gpu/impulse_sweeps.rs` (contact between meshed bodies, and against rigid bodies'
//! analytic surfaces).
//!
//! The host submits many steps at a time and decodes the history rows the device reduced, one
//! submission behind the device. VTU frames end a submission; the state is read back there.

use std::collections::{BTreeMap, VecDeque};
use std::ops::Range;

use rayon::prelude::*;

use super::explicit::lumped_mass;
use super::explicit::Work;
use super::form_trial::FormTrial;
use super::integrator::{ContactForms, Integrator, Pipelined, ENGINE_GPU_RESIDENT};
use super::kept_search::{KeptSearch, FIRST_INTERVAL};
use super::reaction_columns::ReactionColumns;
use super::recorded_sweeps::{RecordedSweeps, FIRST_GUESS};
use super::state::{ContactReport, DamageReport, Energies, FirstDamage, StepReport};
use super::SolverState;
use crate::error::{ImpactError, Result};
use crate::geometry::rigid_shape::RigidShape;
use crate::gpu::resident_step::row_len;
use crate::gpu::{ContactForm, ContactSetup, GpuContext, ResidentSetup, ResidentStep};
use crate::kernels::cohesive_forces::{CohesiveReport, CohesiveState};
use crate::kernels::cohesive_pairs::{CohesiveSetup, PairState};
use crate::kernels::cohesive_reduce::COHESIVE_COLUMNS;
use crate::kernels::contact_gap::NO_FACE;
use crate::kernels::damage_data::DamageData;
use crate::kernels::explicit_correct::FIELDS;
use crate::kernels::plane_contact::{slot, MAX_PLANES, SLOT};
use crate::kernels::{
    ContactNode, ContactPair, LumpedNode, PlaneData, PlaneNode, RigidSurface, SurveySetup,
    FAILURE_FIELDS,
};
use crate::material::damage::Dissipation;
use crate::model::Model;
use crate::model::Primary;
use crate::scene::{ExplicitSettings, Method, RigidMotion};
use crate::search;

/// Whether the model's contacts take the plane kernel (every interface a rigid plane, at
/// most [`MAX_PLANES`]) rather than the device contact iteration.
pub(crate) fn planes_only(model: &Model) -> bool {
    model.interfaces.iter().all(|i| i.is_plane()) && model.interfaces.len() <= MAX_PLANES
}

/// Whether every rigid body's surface has a device form (the analytic shapes, on bodies
/// that do not rotate; a meshed surface's or a rotating body's contact runs on the host,
/// `run` then gives the model the explicit solver with the device's element forces).
pub fn rigid_surfaces_on_device(model: &Model) -> bool {
    (model.rigid.iter()).all(|b| !matches!(b.shape, RigidShape::Mesh(_)) && !b.rotates())
}

/// The device contact iteration's inputs: a pair per (interface, secondary node), the nodes
/// the iteration moves (secondary nodes, primary face corners and rigid bodies' nodes, in
/// node order) with their pairs, face corners and bodies' pair ranges, the search layout and
/// the rigid bodies' surfaces (one per rigid interface).
pub(crate) fn contact_setup(model: &Model) -> Result<ContactSetup> {
    let mut pairs = Vec::new();
    let mut interfaces = Vec::with_capacity(model.interfaces.len());
    let mut rigid = Vec::new();
    // the rigid body ranges (one per rigid interface, as `rigid`) and each body node's
    let mut ranges: Vec<[u32; 2]> = Vec::new();
    let mut bodies: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for itf in &model.interfaces {
        let start = pairs.len();
        let template = match itf.primary {
            Primary::Surface { .. } => ContactPair::default(),
            Primary::Plane { point, normal } => ContactPair {
                point,
                normal,
                ..Default::default()
            },
            Primary::Rigid { body, node, .. } => {
                let b = &model.rigid[body];
                if matches!(b.shape, RigidShape::Mesh(_)) {
                    return Err(ImpactError::Gpu(format!(
                        "rigid body '{}': a meshed surface has no device form",
                        b.name
                    )));
                }
                rigid.push(RigidSurface {
                    node,
                    driven: b.motion == RigidMotion::Prescribed,
                    shape: b.shape.clone(),
                });
                let end = (start + itf.nodes.len()) as u32;
                bodies.entry(node).or_default().push(ranges.len() as u32);
                ranges.push([start as u32, end]);
                ContactPair {
                    body: (rigid.len() - 1) as u32,
                    ..Default::default()
                }
            }
        };
        for (i, &node) in itf.nodes.iter().enumerate() {
            let query = match itf.primary {
                Primary::Surface { ref queries, .. } => (queries.start + i) as u32,
                _ => NO_FACE,
            };
            pairs.push(ContactPair {
                node,
                query,
                law: itf.law,
                ..template
            });
        }
        interfaces.push(start..pairs.len());
    }
    let faces = model.queries.faces.clone();
    let (nodes, links) = contact_nodes(&pairs, &faces, (&ranges, bodies));
    let (face_first, queries) = search::search_layout(model);
    Ok(ContactSetup {
        pairs,
        interfaces,
        nodes,
        links,
        faces,
        face_first,
        queries,
        face_size: search::largest_face_size(model),
        rigid,
    })
}

/// The nodes the iteration moves, in node order, each with its pairs, its face corners and
/// its rigid body's ranges (`bodies`: their numbers in `ranges`), and their links, which
/// start with the number of ranges and each range's first and end pair.
fn contact_nodes(
    pairs: &[ContactPair],
    faces: &[[u32; 4]],
    (ranges, bodies): (&[[u32; 2]], BTreeMap<u32, Vec<u32>>),
) -> (Vec<ContactNode>, Vec<u32>) {
    type Links = (Vec<u32>, Vec<u32>, Vec<u32>);
    let mut own: BTreeMap<u32, Links> = BTreeMap::new();
    for (p, pair) in pairs.iter().enumerate() {
        own.entry(pair.node).or_default().0.push(p as u32);
    }
    for (f, face) in faces.iter().enumerate() {
        for (k, &n) in face.iter().enumerate() {
            own.entry(n).or_default().1.push(4 * f as u32 + k as u32);
        }
    }
    for (n, ranges) in bodies {
        own.entry(n).or_default().2 = ranges;
    }
    let mut nodes = Vec::with_capacity(own.len());
    let mut links = vec![ranges.len() as u32];
    links.extend(ranges.iter().flatten());
    for (node, (p, f, b)) in own {
        let pair_first = links.len() as u32;
        links.extend_from_slice(&p);
        let face_first = links.len() as u32;
        links.extend_from_slice(&f);
        let body_first = links.len() as u32;
        links.extend_from_slice(&b);
        nodes.push(ContactNode {
            node,
            pair_first,
            pair_end: face_first,
            face_first,
            face_end: body_first,
            body_first,
            body_end: links.len() as u32,
        });
    }
    (nodes, links)
}

/// Steps per submission: about 4 million element-steps, from 8 to 1024.
pub fn chunk_steps(elements: usize) -> usize {
    ((1usize << 22) / elements.max(1)).clamp(8, 1024)
}

/// The resident step's inputs for a model (with the plane kernel, the planes are the model's
/// interfaces, in order, and `places` each plane's secondary nodes' places in `plane_nodes`).
pub fn setup(
    model: &Model,
    settings: &ExplicitSettings,
    dt: f64,
    speed_scale: f64,
) -> Result<(ResidentSetup, Vec<Vec<usize>>)> {
    let (mut setup, places) = setup_without_contact(model, settings, dt, speed_scale);
    if !planes_only(model) {
        setup.contact = Some(contact_setup(model)?);
    }
    Ok((setup, places))
}

/// [`setup`] without the contact iteration's inputs where the model has contact between
/// meshed bodies (the ranks of a decomposed run work it on the surface model).
pub fn setup_without_contact(
    model: &Model,
    settings: &ExplicitSettings,
    dt: f64,
    speed_scale: f64,
) -> (ResidentSetup, Vec<Vec<usize>>) {
    let mass = lumped_mass(model);
    let nodes = model.mesh.node_count();
    let lumped: Vec<LumpedNode> = (0..nodes)
        .into_par_iter()
        .map(|n| {
            let free = |a: usize| !model.fixed[3 * n + a];
            LumpedNode {
                mass: mass[n],
                inv_mass: std::array::from_fn(|a| if free(a) { 1.0 / mass[n] } else { 0.0 }),
                ext_acc: std::array::from_fn(|a| if free(a) { model.gravity[a] } else { 0.0 }),
            }
        })
        .collect();
    let mut planes = Vec::new();
    let mut index = vec![usize::MAX; nodes];
    let mut plane_nodes: Vec<PlaneNode> = Vec::new();
    // for each plane interface, each secondary node's place in `plane_nodes`
    let mut places = Vec::new();
    let planes_only = planes_only(model);
    for itf in model.interfaces.iter().filter(|_| planes_only) {
        let Primary::Plane { point, normal } = itf.primary else {
            continue;
        };
        let p = planes.len();
        planes.push(PlaneData {
            point,
            normal,
            law: itf.law,
        });
        let mut place = Vec::with_capacity(itf.nodes.len());
        for &n in &itf.nodes {
            if index[n as usize] == usize::MAX {
                index[n as usize] = plane_nodes.len();
                plane_nodes.push(PlaneNode { node: n, planes: 0 });
            }
            let i = index[n as usize];
            plane_nodes[i].planes |= 1 << p;
            place.push(i);
        }
        places.push(place);
    }
    let mut velocity = model.initial_velocity.clone();
    for (d, v) in velocity.iter_mut().enumerate() {
        if model.fixed[d] {
            *v = 0.0;
        }
    }
    // the prescribed rigid bodies keep their velocities (their inverse mass is zero)
    for (d, w) in model.moving_dofs() {
        velocity[d] = w;
    }
    let acceleration = (0..3 * nodes)
        .into_par_iter()
        .map(|d| lumped[d / 3].ext_acc[d % 3])
        .collect();
    let setup = ResidentSetup {
        dt,
        tolerance: device_tolerance(settings.tolerance) * speed_scale.max(f64::MIN_POSITIVE),
        max_iterations: settings.max_iterations as u32,
        lumped,
        planes,
        plane_nodes,
        reported_plane_nodes: None,
        bodies: corrected_ranges(model),
        probes: model.probes.iter().map(|p| p.node).collect(),
        velocity,
        acceleration,
        contact: None,
        survey: None,
        reactions: ReactionColumns::new(model, &mass).lists,
        damage: None,
        cohesive: None,
    };
    (setup, places)
}

/// Whether a decomposed run on GPUs keeps its step on the hosts (the ranks' element forces
/// on their GPUs) rather than resident: a model whose plies damage, or with named or moving
/// fixes (the resident ranks' rows carry neither the damage nor the reactions), or with
/// loads or fixes moved along a displacement (their forces and velocities change over time
/// on the host).
pub fn needs_host_ranks(model: &Model) -> bool {
    model.damage_laws.iter().any(Option::is_some)
        || !model.reactions.is_empty()
        || !model.fix_motion.is_empty()
        || !model.loads.is_empty()
        || !model.fix_paths.is_empty()
        || !model.cohesive.is_empty()
}

/// The smallest contact tolerance the device iteration takes, relative to the speed scale:
/// its velocities are f32, resolved to 1.2e-7 of their size, and the sweeps' last
/// corrections of a body's velocity (the sum over the many nodes it presses) round away
/// below a few dozen of those. At 1e-6 the coarse drop-weight scene's iteration stalled on
/// lavapipe at its 200 sweeps in 50 of 1,106 steps (its velocities are the tup's 3,303 mm/s,
/// resolved to 2.4e-4); at 1e-5 every step converged in the CPU's sweeps (2,207 in all).
pub const DEVICE_TOLERANCE: f64 = 1e-5;

/// The device iteration's relative tolerance for the scene's `explicit.tolerance`.
pub fn device_tolerance(tolerance: f64) -> f64 {
    tolerance.max(DEVICE_TOLERANCE)
}

/// The node ranges the correctors run over: each meshed body's, then the rigid bodies'
/// nodes (after every meshed body's) as one more.
fn corrected_ranges(model: &Model) -> Vec<Range<usize>> {
    let mut ranges: Vec<Range<usize>> = (model.mesh.bodies.iter())
        .map(|b| b.nodes.clone())
        .collect();
    let nodes = model.mesh.node_count();
    if !model.rigid.is_empty() {
        ranges.push(nodes - model.rigid.len()..nodes);
    }
    ranges
}

/// One decoded history row.
#[derive(Debug, Clone, Default)]
pub(crate) struct Row {
    pub energies: Energies,
    pub bodies: Vec<[f64; 3]>,
    pub reports: Vec<ContactReport>,
    pub probes: Vec<([f64; 3], [f64; 3])>,
    pub report: StepReport,
    /// The ply failure survey's record, where the step surveys.
    pub failure: Option<[f64; FAILURE_FIELDS]>,
    /// The supports' reaction columns ([`ReactionColumns`]).
    pub reactions: Vec<f64>,
    /// The energy damage dissipated over the step, with the fibre modes' share.
    pub dissipated: Dissipation,
    /// Each cohesive interface's separated and damaged areas, and its dissipation and
    /// stored-energy offset over the step ([`crate::kernels::cohesive_reduce`]).
    pub cohesive: Vec<[f64; COHESIVE_COLUMNS]>,
}

/// What decoding a history row needs besides its values: the model, each body's mass, the
/// contact iteration's sweep limit and the step length the row was computed with.
pub(crate) struct RowReader<'a> {
    pub model: &'a Model,
    pub body_mass: &'a [f64],
    pub max_iterations: usize,
    /// The time the row's contact impulses act over
    /// ([`crate::integrate::explicit::impulse_interval`]).
    pub interval: f64,
    /// The reaction columns after the probes' (none on a rank).
    pub reactions: usize,
    /// The cohesive interfaces whose values end the row (none on a rank).
    pub cohesive: usize,
}

impl RowReader<'_> {
    /// The row `r` (of [`row_len`] values) decoded.
    pub fn decode(&self, row: &[f64]) -> Row {
        // the meshed bodies' ranges, then the rigid bodies' (energies only)
        let nb = self.model.mesh.bodies.len() + usize::from(!self.model.rigid.is_empty());
        let np = self.model.interfaces.len();
        let counts = (nb, np, self.model.probes.len(), self.reactions);
        let (r, cohesive) = row.split_at(row.len() - COHESIVE_COLUMNS * self.cohesive);
        let damage = r.len() == row_len(counts, (false, true), 0)
            || r.len() == row_len(counts, (true, true), 0);
        let surveyed = r.len() == row_len(counts, (true, damage), 0);
        debug_assert_eq!(r.len(), row_len(counts, (surveyed, damage), 0));
        let mut e = Energies::default();
        let mut bodies = Vec::with_capacity(nb);
        for b in 0..nb {
            let q = &r[FIELDS * b..FIELDS * (b + 1)];
            e.kinetic += q[0];
            e.strain += q[1];
            e.potential += q[2];
            if let Some(m) = self.body_mass.get(b) {
                bodies.push([q[3], q[4], q[5]].map(|p| p / m));
            }
        }
        let mut report = StepReport {
            iterations: 0,
            converged: true,
        };
        let mut reports = Vec::with_capacity(np);
        for p in 0..np {
            let q = &r[FIELDS * nb + SLOT * p..FIELDS * nb + SLOT * (p + 1)];
            let sweeps = q[8].round() as usize;
            report.iterations = report.iterations.max(sweeps.min(self.max_iterations));
            report.converged &= sweeps <= self.max_iterations;
            let jt = [q[1], q[2], q[3]];
            let j = &q[slot::IMPULSE..slot::IMPULSE + 3];
            reports.push(ContactReport {
                normal_force: q[0] / self.interval,
                tangential_force: crate::geometry::vector::norm(jt) / self.interval,
                active: q[4].round() as usize,
                max_penetration: q[6],
                sliding: q[5].round() as usize,
                friction_work: q[7],
                impact_loss: q[slot::IMPACT_LOSS],
                driver_work: q[slot::DRIVER_WORK],
                // on the primary side: minus the impulses on the secondary nodes
                force: std::array::from_fn(|a| -j[a] / self.interval),
            });
            // the drivers' work is the model's energy input (the host path's balance)
            e.potential -= q[slot::DRIVER_WORK];
        }
        let base = FIELDS * nb + SLOT * np;
        let probes = (0..self.model.probes.len())
            .map(|i| {
                let q = &r[base + 6 * i..base + 6 * (i + 1)];
                ([q[0], q[1], q[2]], [q[3], q[4], q[5]])
            })
            .collect();
        let at = base + 6 * self.model.probes.len();
        let reactions = r[at..at + self.reactions].to_vec();
        let at = at + self.reactions;
        let failure = surveyed.then(|| std::array::from_fn(|k| r[at + k]));
        Row {
            energies: e,
            bodies,
            reports,
            probes,
            report,
            failure,
            reactions,
            dissipated: match damage {
                true => Dissipation {
                    total: r[r.len() - 2],
                    fibre: r[r.len() - 1],
                },
                false => Dissipation::default(),
            },
            cohesive: (cohesive.chunks_exact(COHESIVE_COLUMNS))
                .map(|c| std::array::from_fn(|k| c[k]))
                .collect(),
        }
    }
}

/// Everything a resident run carries from one step to the next: the checkpoint's part
/// (the device's step state as raw words, see [`ResidentStep::read_step_state`]).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ResidentState {
    pub dt: f64,
    pub time: f64,
    pub steps: usize,
    pub buffers: Vec<Vec<u32>>,
    /// The moving fixes' work and the damage's energy so far, and the fixes' power at the
    /// last step (the next step's work).
    #[serde(default)]
    pub work: Work,
    #[serde(default)]
    pub power: f64,
    /// Each cohesive interface's energy dissipated so far.
    #[serde(default)]
    pub cohesive_energy: Vec<f64>,
}

pub struct ResidentSolver<'m> {
    model: &'m Model,
    engine: ResidentStep,
    pub dt: f64,
    pub time: f64,
    pub steps: usize,
    /// Steps the run takes.
    total: usize,
    frame_every: Option<usize>,
    /// Submissions end at multiples of this too (where a checkpoint reads the state).
    checkpoint_every: Option<usize>,
    /// No new submissions: the ones in flight are collected and their rows handed out.
    stopping: bool,
    submitted: usize,
    /// The read-back buffer to collect next.
    slot: usize,
    chunk: usize,
    rows: VecDeque<Row>,
    current: Row,
    mass: Vec<f64>,
    body_mass: Vec<f64>,
    max_iterations: usize,
    places: Vec<Vec<usize>>,
    plane_count: usize,
    /// The pairs of each interface (the device contact iteration).
    pair_ranges: Option<Vec<Range<usize>>>,
    /// The contact sweeps recorded per step and the run's tally.
    sweeps: RecordedSweeps,
    /// The steps between the contact search's sorts and the run's tally.
    search: KeptSearch,
    /// The contact iteration's form, timed on the run's steps, and the run's tally.
    forms: Option<FormTrial>,
    /// The device's seconds over the submissions collected, where it times them.
    device_seconds: Option<f64>,
    /// The shortened last step, if the run has one (see [`Pipelined::schedule`]).
    last_dt: Option<f64>,
    /// The time the contact impulses of the rows being decoded act over
    /// ([`crate::integrate::explicit::impulse_interval`]).
    row_interval: f64,
    /// The energy measure's shift over the shortened last step
    /// ([`Integrator::shorten_step`] of the explicit solver).
    measure_shift: f64,
    /// State at the last frame (or the start): displacement, velocity, contact results (per
    /// plane node and plane, or per contact pair).
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    results: Vec<f64>,
    initial: Energies,
    /// The supports' reaction columns of the rows.
    columns: ReactionColumns,
    /// The moving fixes' work and the damage's energy so far.
    work: Work,
    /// The moving fixes' power at the last step (the next step's work over its length).
    power: f64,
    /// The step the run was set up with (the first damage's time is its step's).
    step_length: f64,
    /// Each cell's damage and the first damaged point, as last read back.
    damage_cells: Option<(
        Vec<[f64; 4]>,
        Option<crate::kernels::damage_data::DamagedPoint>,
    )>,
    /// Each cohesive interface's energy dissipated so far (the rows' sums).
    cohesive_energy: Vec<f64>,
    /// Every cohesive pair's state as last read back (none without cohesive interfaces).
    pairs: Option<Vec<PairState>>,
}

impl<'m> ResidentSolver<'m> {
    /// `total` steps, reading the state back every `frame_every` steps; with `survey`, the
    /// ply failure indices of every step.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: GpuContext,
        model: &'m Model,
        settings: &ExplicitSettings,
        dt: f64,
        speed_scale: f64,
        total: usize,
        frame_every: Option<usize>,
        (survey, damage): (Option<SurveySetup>, Option<DamageData>),
    ) -> Result<Self> {
        let chunk = chunk_steps(model.mesh.element_count());
        let mut s = Self::with_chunk(
            ctx,
            model,
            settings,
            dt,
            speed_scale,
            (total, frame_every, chunk),
            (survey, damage),
        )?;
        s.chunk = chunk;
        Ok(s)
    }

    /// [`Self::new`] with `chunk` steps per submission instead of [`chunk_steps`]:
    /// `(total, frame_every, chunk)`.
    pub fn with_chunk(
        ctx: GpuContext,
        model: &'m Model,
        settings: &ExplicitSettings,
        dt: f64,
        speed_scale: f64,
        (total, frame_every, chunk): (usize, Option<usize>, usize),
        (survey, damage): (Option<SurveySetup>, Option<DamageData>),
    ) -> Result<Self> {
        let (mut setup, places) = setup(model, settings, dt, speed_scale)?;
        setup.survey = survey;
        setup.damage = damage.filter(DamageData::any);
        setup.cohesive = (!model.cohesive.is_empty())
            .then(|| CohesiveSetup::of(crate::model::cohesive::all_pairs(&model.cohesive)));
        let chunk = chunk.max(1);
        let mut engine = ResidentStep::new(ctx, &model.element_data(), &setup, chunk)?;
        engine.set_sweeps(FIRST_GUESS);
        engine.set_search_interval(FIRST_INTERVAL);
        // the setup lumped the mass already (an element loop over the whole mesh)
        let mass: Vec<f64> = setup.lumped.iter().map(|l| l.mass).collect();
        let body_mass = model
            .mesh
            .bodies
            .iter()
            .map(|b| b.nodes.clone().map(|n| mass[n]).sum())
            .collect();
        let kinetic = 0.5
            * setup
                .velocity
                .iter()
                .enumerate()
                .map(|(d, v)| mass[d / 3] * v * v)
                .sum::<f64>();
        let timed = engine.times_submissions();
        let forms = (engine.form()).map(|f| FormTrial::new(engine.forms(), f, timed));
        let device_seconds = timed.then_some(0.0);
        let plane_count = setup.planes.len();
        let pair_ranges = setup.contact.as_ref().map(|c| c.interfaces.clone());
        let columns = ReactionColumns::new(model, &mass);
        let power = columns.power_at_rest();
        let result_len = match &setup.contact {
            Some(c) => SLOT * c.pairs.len(),
            None => SLOT * plane_count * setup.plane_nodes.len(),
        };
        Ok(ResidentSolver {
            model,
            engine,
            dt,
            time: 0.0,
            steps: 0,
            total,
            frame_every: frame_every.filter(|&e| e > 0),
            checkpoint_every: None,
            stopping: false,
            submitted: 0,
            slot: 0,
            chunk,
            rows: VecDeque::new(),
            current: Row {
                bodies: super::body_velocities(model, &mass, &setup.velocity),
                reports: vec![ContactReport::default(); model.interfaces.len()],
                ..Default::default()
            },
            mass,
            body_mass,
            max_iterations: settings.max_iterations,
            places,
            plane_count,
            pair_ranges,
            sweeps: RecordedSweeps::default(),
            search: KeptSearch::default(),
            device_seconds,
            forms,
            last_dt: None,
            row_interval: dt,
            measure_shift: 0.0,
            u: vec![0.0; 3 * model.mesh.node_count()],
            v: setup.velocity.clone(),
            results: vec![0.0; result_len],
            initial: Energies {
                kinetic,
                ..Default::default()
            },
            columns,
            work: Work::default(),
            power,
            step_length: dt,
            damage_cells: None,
            cohesive_energy: vec![0.0; model.cohesive.len()],
            pairs: (setup.cohesive.as_ref()).map(|c| vec![PairState::default(); c.pairs.len()]),
        })
    }

    /// The device step (the benchmarks time its stages).
    pub fn engine_mut(&mut self) -> &mut ResidentStep {
        &mut self.engine
    }

    /// Steps per submission.
    pub fn chunk(&self) -> usize {
        self.chunk
    }

    /// Steps of the next submission from step `from`: a chunk, cut at the end and at the
    /// next frame.
    fn plan(&self, from: usize) -> usize {
        let mut n = self.chunk.min(self.total - from);
        if self.last_dt.is_some() && from + 1 < self.total {
            // the shortened last step is a submission of its own
            n = n.min(self.total - 1 - from);
        }
        for e in [self.frame_every, self.checkpoint_every]
            .into_iter()
            .flatten()
        {
            n = n.min((from / e + 1) * e - from);
        }
        n
    }

    fn at_frame(&self, step: usize) -> bool {
        self.frame_every.is_some_and(|e| step % e == 0)
    }

    /// Where submissions end: frames and checkpoints.
    fn at_cut(&self, step: usize) -> bool {
        self.at_frame(step) || self.checkpoint_every.is_some_and(|e| step % e == 0)
    }

    /// Makes sure the next rows are decoded: collects the oldest submission, keeping the
    /// device one submission ahead (never past a frame, where the state must be read).
    fn fill(&mut self) -> Result<()> {
        if !self.engine.is_pending(self.slot) && !self.stopping {
            if let Some(dt) = self.last_dt.filter(|_| self.submitted + 1 == self.total) {
                // nothing is in flight: the step length changes for this submission alone
                let ama: f64 = self
                    .engine
                    .read_acceleration()?
                    .iter()
                    .enumerate()
                    .map(|(d, a)| self.mass[d / 3] * a * a)
                    .sum();
                self.measure_shift = 0.125 * (self.dt * self.dt - dt * dt) * ama;
                self.engine.set_dt(dt);
                self.row_interval = crate::integrate::explicit::impulse_interval(self.dt, Some(dt));
            }
            let n = self.plan(self.submitted).max(1);
            self.submit(self.slot, n)?;
        }
        let other = 1 - self.slot;
        let last_is_short = self.last_dt.is_some() && self.submitted + 1 == self.total;
        if !self.engine.is_pending(other)
            && self.submitted < self.total
            && !self.at_cut(self.submitted)
            && !last_is_short
            && !self.stopping
        {
            let n = self.plan(self.submitted);
            self.submit(other, n)?;
        }
        let len = self.engine.row_len();
        let rows: Vec<Row> = (self.engine.collect(self.slot)?)
            .chunks_exact(len)
            .map(|r| self.decode(&r.iter().map(|&x| x as f64).collect::<Vec<_>>()))
            .collect();
        let time = self.engine.collected_time();
        if let (Some(total), Some(d)) = (&mut self.device_seconds, time.and_then(|t| t.device)) {
            *total += d;
        }
        if let (Some(forms), Some(time)) = (&mut self.forms, time) {
            forms.collected(self.slot, time);
        }
        if self.pair_ranges.is_some() {
            // the sweeps each step needed (its iterations: the interfaces share one)
            let needs: Vec<u32> = rows.iter().map(|r| r.report.iterations as u32).collect();
            let next = self.sweeps.collected(self.slot, &needs);
            self.engine.set_sweeps(next);
        }
        if let Some(record) = self.engine.search_record() {
            let interval = self.engine.search_interval();
            let next = self.search.collected(self.slot, interval, record);
            self.engine.set_search_interval(next);
        }
        self.slot = other;
        self.rows.extend(rows);
        Ok(())
    }

    /// Submits `n` steps to read-back buffer `slot`.
    fn submit(&mut self, slot: usize, n: usize) -> Result<()> {
        if let Some(forms) = &mut self.forms {
            self.engine.set_form(forms.submitting(slot));
        }
        self.engine.submit(slot, n)?;
        self.sweeps.submitted(slot, self.engine.sweeps());
        self.search.submitted(slot, self.engine.sorts_in(n));
        self.submitted += n;
        Ok(())
    }

    /// Fixes the contact sweeps recorded per step as dispatches of their own (from the next
    /// submission on; by default they follow the last submission's needs, see
    /// [`RecordedSweeps`]). The results do not depend on it.
    pub fn fix_recorded_sweeps(&mut self, sweeps: u32) {
        self.sweeps.fix(sweeps);
        self.engine.set_sweeps(sweeps);
    }

    /// Runs each step's contact iteration in one workgroup (`contact_zone`) or staged, from
    /// the next submission on, where the adapter runs it; returns whether it runs in one
    /// workgroup. By default it does on zones of at most
    /// [`crate::gpu::contact_form::ZONE_PAIRS`] pairs. The results do not depend on it.
    pub fn fix_contact_zone(&mut self, zone: bool) -> bool {
        let zone = self.engine.set_zone(zone);
        self.fix_form();
        zone
    }

    /// Ends the trial of the contact iteration's forms: the run keeps the engine's form.
    fn fix_form(&mut self) {
        if let (Some(forms), Some(form)) = (&mut self.forms, self.engine.form()) {
            forms.fix(form);
        }
    }

    /// Records the contact iteration in `form` from the next submission on, where it runs
    /// here, instead of the form the run's trial chooses ([`FormTrial`]); returns the form
    /// it runs in. The results do not depend on it.
    pub fn fix_contact_form(&mut self, form: ContactForm) -> Option<ContactForm> {
        let form = self.engine.set_form(form);
        self.fix_form();
        form
    }

    /// The trial of the contact iteration's forms and the steps each ran (the device contact
    /// iteration; none without one).
    pub fn form_trial(&self) -> Option<&FormTrial> {
        self.forms.as_ref()
    }

    /// Records the staged contact iteration's sweeps as `contact_relax` dispatches (one a
    /// sweep) or as `contact_sweep` and `contact_apply` (two), from the next submission on;
    /// returns whether `contact_relax` runs. By default it does where no rigid body range
    /// gathers. The results do not depend on it.
    pub fn fix_contact_relax(&mut self, relax: bool) -> bool {
        let relax = self.engine.set_relax(relax);
        self.fix_form();
        relax
    }

    /// Fixes the steps between the contact search's sorts of the faces (from the next
    /// submission on; by default they follow the last submission's grid, see
    /// [`KeptSearch`]). The results do not depend on it.
    pub fn fix_search_interval(&mut self, steps: usize) {
        self.search.fix(steps);
        self.engine.set_search_interval(steps);
    }

    /// The contact search's sorts of the faces and its stale steps over the steps collected
    /// (zero without a device search).
    pub fn search_counts(&self) -> (u64, u64) {
        (self.search.rebuilds, self.search.stale_steps)
    }

    /// The contact sweeps recorded and needed over the steps collected (the device contact
    /// iteration; zero without one).
    pub fn sweep_counts(&self) -> (u64, u64) {
        (self.sweeps.recorded, self.sweeps.needed)
    }

    fn decode(&self, r: &[f64]) -> Row {
        RowReader {
            model: self.model,
            body_mass: &self.body_mass,
            max_iterations: self.max_iterations,
            interval: self.row_interval,
            reactions: self.columns.len(),
            cohesive: self.model.cohesive.len(),
        }
        .decode(r)
    }

    /// A step's work of the moving fixes (their power at the step before, over its
    /// length) and the damage's, and the damage as the device holds it after the step where
    /// the state is read.
    fn count_work(&mut self, read: bool) -> Result<()> {
        self.work.fixes += self.power * self.dt;
        self.power = self.columns.power(&self.current.reactions);
        self.work.count_plies(self.current.dissipated);
        for (e, c) in self.cohesive_energy.iter_mut().zip(&self.current.cohesive) {
            *e += c[2];
        }
        if read {
            self.count_damage_cells()?;
            self.read_pairs()?;
        }
        Ok(())
    }

    /// Reads the cohesive pairs' state back (where the model has cohesive interfaces).
    fn read_pairs(&mut self) -> Result<()> {
        if let Some(p) = self.engine.read_cohesive()? {
            self.pairs = Some(p);
        }
        Ok(())
    }

    /// Reads the damage back: each cell's, and the first damaged point.
    fn count_damage_cells(&mut self) -> Result<()> {
        if let Some(state) = self.engine.read_damage()? {
            let data = self.engine.damage_data().expect("damage");
            let blocks = crate::kernels::damage_data::block_counts(&self.model.mesh.elements);
            self.damage_cells = Some((
                state.cells(data, &blocks),
                state.first_damaged(data, &blocks),
            ));
        }
        Ok(())
    }

    /// Normal impulse and end-of-step gap of secondary node `local` of interface
    /// `interface` at the last state read back (the gap is -inf where the node was out of
    /// reach of a surface).
    fn node_impulse(&self, interface: usize, local: usize) -> (f64, f64) {
        let o = match &self.pair_ranges {
            Some(r) => SLOT * (r[interface].start + local),
            None => SLOT * (self.places[interface][local] * self.plane_count + interface),
        };
        (
            self.results[o + slot::NORMAL_IMPULSE],
            self.results[o + slot::GAP],
        )
    }
}

impl Integrator for ResidentSolver<'_> {
    fn model(&self) -> &Model {
        self.model
    }

    fn method(&self) -> Method {
        Method::Explicit
    }

    fn device_name(&self) -> String {
        self.engine.device_name()
    }

    fn recorded_sweeps(&self) -> Option<(u64, u64)> {
        self.pair_ranges.is_some().then(|| self.sweep_counts())
    }

    fn contact_zone(&self) -> Option<bool> {
        (self.forms.as_ref()).map(|f| f.current().is_zone())
    }

    fn contact_forms(&self) -> Option<ContactForms> {
        self.forms.as_ref().map(FormTrial::summary)
    }

    fn device_seconds(&self) -> Option<f64> {
        self.device_seconds
    }

    fn search_rebuilds(&self) -> Option<(u64, u64)> {
        (self.engine.sorts_in(1) > 0).then(|| self.search_counts())
    }

    fn engine(&self) -> &'static str {
        ENGINE_GPU_RESIDENT
    }

    /// One step (from the rows the device computed); at a frame step the state is read back.
    fn step(&mut self) -> Result<StepReport> {
        if self.rows.is_empty() {
            self.fill()?;
        }
        self.current = self
            .rows
            .pop_front()
            .expect("fill decodes at least one row");
        self.steps += 1;
        self.time = self.steps as f64 * self.dt;
        if let Some(last) = self.last_dt.filter(|_| self.steps == self.total) {
            self.time = (self.total - 1) as f64 * self.dt + last;
            self.dt = last;
            self.current.energies.kinetic -= self.measure_shift;
        }
        let read = self.at_frame(self.steps) || self.steps == self.total;
        if read {
            let (u, v, results) = self.engine.read_state()?;
            self.u = u;
            self.v = v;
            self.results = results;
        }
        self.count_work(read)?;
        Ok(self.current.report)
    }

    fn energies(&mut self) -> Result<Energies> {
        let mut e = if self.steps == 0 {
            self.initial
        } else {
            self.current.energies
        };
        e.potential -= self.work.fixes;
        e.fix_work = self.work.fixes;
        // the pairs' friction springs store less than half their traction's work
        e.strain += self.current.cohesive.iter().map(|c| c[3]).sum::<f64>();
        e.damage = self.work.damage + self.cohesive_energy.iter().sum::<f64>();
        e.plies = self.work.plies();
        Ok(e)
    }

    fn reactions(&self) -> Vec<[f64; 3]> {
        match self.steps {
            0 => self.columns.reactions(&vec![0.0; self.columns.len()]),
            _ => self.columns.reactions(&self.current.reactions),
        }
    }

    fn damage(&self) -> Option<DamageReport> {
        self.engine.damage_data()?;
        let (cells, first) = match &self.damage_cells {
            Some((c, f)) => (c.clone(), *f),
            None => (vec![[0.0; 4]; self.model.mesh.element_count()], None),
        };
        let first = first.map(|p| {
            let time = (f64::from(p.step) * self.step_length).min(self.time);
            FirstDamage::of(self.model, p, time)
        });
        Some(DamageReport {
            energy: self.work.damage,
            fibre: self.work.damage_fibre,
            first,
            cells,
        })
    }

    fn reports(&self) -> Vec<ContactReport> {
        self.current.reports.clone()
    }

    fn cohesive(&self) -> Vec<CohesiveReport> {
        (self.cohesive_energy.iter().enumerate())
            .map(|(k, &energy)| {
                let c = self.current.cohesive.get(k).copied().unwrap_or_default();
                CohesiveReport {
                    delaminated_area: c[0],
                    damaged_area: c[1],
                    energy,
                }
            })
            .collect()
    }

    /// The pairs' damage and slip as last read back (at frames and at the end).
    fn cohesive_state(&self) -> Option<CohesiveState> {
        let pairs = self.pairs.as_ref()?;
        let interfaces = crate::model::cohesive::all_pairs(&self.model.cohesive);
        let mut at = 0;
        let (damage, slip) = interfaces
            .map(|c| {
                let own = &pairs[at..at + c.area.len()];
                at += c.area.len();
                let slip = match c.law.friction > 0.0 {
                    true => own.iter().map(|s| s.slip).collect(),
                    false => Vec::new(),
                };
                (own.iter().map(|s| s.damage).collect(), slip)
            })
            .unzip();
        Some(CohesiveState {
            damage,
            energy: self.cohesive_energy.clone(),
            slip,
            stored_offset: self.current.cohesive.iter().map(|c| c[3]).collect(),
        })
    }

    fn node_contact(&self, interface: usize, point: usize) -> (f64, f64) {
        let (impulse, gap) = self.node_impulse(interface, point);
        let area = self.model.interfaces[interface].area[point];
        // the state is read where the rows are decoded: the interval is theirs
        (impulse / (self.row_interval * area), gap)
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn steps(&self) -> usize {
        self.steps
    }

    fn displacement(&self) -> &[f64] {
        &self.u
    }

    fn velocity(&self) -> &[f64] {
        &self.v
    }

    fn nodal_mass(&self) -> &[f64] {
        &self.mass
    }

    /// The state a checkpoint keeps (at rest only: at a cut, or after stopping).
    fn checkpoint_state(&mut self) -> Result<Option<SolverState>> {
        if !self.at_rest() || self.submitted != self.steps {
            return Err(crate::error::ImpactError::Gpu(format!(
                "the resident state is read at rest only (step {}, {} submitted)",
                self.steps, self.submitted
            )));
        }
        Ok(Some(SolverState::Resident(ResidentState {
            dt: self.dt,
            time: self.time,
            steps: self.steps,
            buffers: self.engine.read_step_state()?,
            work: self.work.clone(),
            power: self.power,
            cohesive_energy: self.cohesive_energy.clone(),
        })))
    }

    /// Continues from a checkpoint's state (of this model).
    fn restore(&mut self, state: SolverState) -> std::result::Result<(), String> {
        let SolverState::Resident(s) = state else {
            return Err(super::integrator::other_integrator());
        };
        if s.steps >= self.total {
            return Err(format!(
                "the checkpoint is at step {}, the run has {}",
                s.steps, self.total
            ));
        }
        self.engine
            .write_step_state(&s.buffers)
            .map_err(|e| e.to_string())?;
        self.dt = s.dt;
        self.row_interval = s.dt;
        self.time = s.time;
        self.steps = s.steps;
        self.submitted = s.steps;
        self.work = s.work;
        self.power = s.power;
        if s.cohesive_energy.len() != self.cohesive_energy.len() {
            return Err("its cohesive interfaces are not this model's".into());
        }
        self.cohesive_energy = s.cohesive_energy;
        if self.engine.damage_data().is_some() {
            self.count_damage_cells().map_err(|e| e.to_string())?;
        }
        self.read_pairs().map_err(|e| e.to_string())?;
        Ok(())
    }

    fn body_velocities(&self) -> Vec<[f64; 3]> {
        self.current.bodies.clone()
    }

    fn failure_record(&self) -> Option<[f64; FAILURE_FIELDS]> {
        self.current.failure
    }

    /// Probe displacement and velocity of the last step.
    fn probes(&self) -> Vec<([f64; 3], [f64; 3])> {
        if self.steps == 0 {
            return self
                .model
                .probes
                .iter()
                .map(|p| {
                    let d = 3 * p.node as usize;
                    ([0.0; 3], [self.v[d], self.v[d + 1], self.v[d + 2]])
                })
                .collect();
        }
        self.current.probes.clone()
    }

    fn pipelined(&mut self) -> Option<&mut dyn Pipelined> {
        Some(self)
    }
}

impl Pipelined for ResidentSolver<'_> {
    /// Makes the run's last step `last_step` long instead of the step (an end time that is
    /// not a whole number of steps), and ends submissions at every multiple of
    /// `checkpoint_every` steps, so that the state can be read there
    /// ([`Integrator::checkpoint_state`]).
    fn schedule(&mut self, last_step: Option<f64>, checkpoint_every: Option<usize>) {
        self.last_dt = last_step;
        self.checkpoint_every = checkpoint_every.map(|e| e.max(1));
    }

    /// Submits nothing more: the steps already submitted are handed out, then the solver is
    /// at rest ([`Pipelined::at_rest`]) and its state can be read.
    fn stop_submitting(&mut self) {
        self.stopping = true;
    }

    /// Nothing in flight and every computed step handed out: the device holds the state of
    /// step [`Integrator::steps`].
    fn at_rest(&self) -> bool {
        self.rows.is_empty() && !self.engine.is_pending(0) && !self.engine.is_pending(1)
    }
}
