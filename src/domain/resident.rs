//! [`RankResident`]: a rank of a decomposed explicit run with its whole step on its GPU
//! ([`crate::gpu::ResidentStep`]), for models whose rigid bodies' surfaces have a device
//! form (analytic shapes that do not rotate). Where plies have strengths, each rank's
//! device surveys its own cells and the ranks merge their records (the worst point
//! numbered as in the model's survey, the lowest on a tie): the single GPU's record.
//!
//! Where rigid planes are the only contacts (each node's contact is its own, so none
//! crosses the cut), a step is two submissions. The first runs the predictor, the planes,
//! the drift and the rank's element forces, and reads back the corners the exchange needs;
//! the host sends the neighbours theirs and sums each shared node's corners, its own and
//! the received, in the global corner order in f32 (as the single GPU's gather adds them).
//! The second writes those sums over the gathered forces, runs the correctors and reduces
//! the history row, which comes back to be added over the ranks. With contact between
//! meshed bodies, the predictor is a submission of its own, after which every rank works the
//! contact iteration on the whole contact surfaces ([`super::resident_contact`]) and takes
//! back its surface nodes' velocities before the drift.
//!
//! So every node a rank holds takes the same f32 operations as on one GPU of the same
//! kind: the state (displacements, velocities, contact results) and the history's state
//! columns (probes, maxima, and the contact on the surfaces, which every rank has whole)
//! are the single GPU's bits on any number of ranks. The history's sums over the nodes
//! (energies, momenta, the planes' contact forces) add each rank's owned nodes on its device
//! and then the ranks in order: the single GPU's values to the rounding of a different
//! order of the same f32 sums.
//!
//! The rank's nodes are renumbered on the device, each body's owned nodes first and then
//! the nodes it holds for its neighbours, so that the correctors' sums of the owned nodes
//! are ranges of their own; likewise the plane nodes, owned first. The rigid bodies' nodes
//! (in no element) are rank 0's, one more range of the correctors, as on one GPU.

use std::ops::Range;

use super::checkpoint::gather_records;
use super::explicit::{decomposition_of, exchange_corners, RankFigures};
use super::partition::Partition;
use super::ranks::{agree, Ranks, Timed};
use super::resident_contact::SurfaceContact;
use super::subdomain::Subdomain;
use crate::error::{ImpactError, Result};
use crate::gpu::buffer::padded_bytes;
use crate::gpu::rank_surface::SurfaceState;
use crate::gpu::{GpuContext, ResidentSetup, ResidentStep};
use crate::integrate::integrator::ENGINE_GPU_RESIDENT;
use crate::integrate::resident::{self, planes_only, ResidentState, Row, RowReader};
use crate::integrate::{
    ContactForms, ContactReport, Decomposed, Decomposition, Energies, Integrator, Piece, Pipelined,
    ProbeValues, SolverState, StepReport,
};
use crate::kernels::explicit_correct::FIELDS;
use crate::kernels::failure_reduce::{empty, merge};
use crate::kernels::plane_contact::{slot, SLOT};
use crate::kernels::{ElementData, PlaneNode, SurveySetup, FAILURE_FIELDS};
use crate::model::Model;
use crate::scene::{ExplicitSettings, Method};

/// The contact's share-out in words (`summary.json`), on the surfaces and on rigid planes
/// alone.
const SURFACES: &str = "every rank reads back the state of the surface nodes it owns after the predictor; one gather gives every rank every surface node's state, and every rank works the contact iteration on the whole contact surfaces on its GPU and takes back the velocities of the surface nodes it holds";
const PLANES: &str = "each node's contact with the rigid planes on every rank that holds it, the history's sums over the plane nodes each rank owns";

/// The rank's part of the device's ply failure survey: the points of its cells, on its
/// device's node numbers, and each one's number in the model's survey (`cells`: the model's
/// cell of each of `global`'s points).
fn rank_survey(
    global: &SurveySetup,
    cells: &[u32],
    sub: &Subdomain,
    order: &DeviceOrder,
) -> (SurveySetup, Vec<u32>) {
    let (mut points, mut numbers) = (Vec::new(), Vec::new());
    for (i, (p, &c)) in global.points.iter().zip(cells).enumerate() {
        if sub.elements.binary_search(&c).is_err() {
            continue;
        }
        let mut q = *p;
        for n in &mut q.nodes[..p.corners as usize] {
            // an element's nodes are its rank's
            let l = sub.nodes.binary_search(n).unwrap_or(0);
            *n = order.device_of[l];
        }
        points.push(q);
        numbers.push(i as u32);
    }
    let setup = SurveySetup {
        points,
        operators: global.operators.clone(),
        strengths: global.strengths.clone(),
    };
    (setup, numbers)
}

/// The rank's nodes on its device: each body's owned nodes, then the nodes it holds for
/// its neighbours.
struct DeviceOrder {
    /// The device number of each local node.
    device_of: Vec<u32>,
    /// The local node of each device number.
    local_of: Vec<u32>,
    /// Each body's owned nodes, then each body's other nodes (device numbers).
    ranges: Vec<Range<usize>>,
    /// Whether the rank owns each device node.
    owned: Vec<bool>,
}

impl DeviceOrder {
    /// The rank's nodes in the device's order; `rigid`: the model's rigid bodies' nodes
    /// (in no element: rank 0 holds and owns them) are one more range of owned nodes, after
    /// the bodies' owned nodes, on every rank (empty on the others), as the single GPU's
    /// correctors take them after the bodies.
    fn new(sub: &Subdomain, piece: &Model, rigid: bool) -> Result<Self> {
        let n = sub.nodes.len();
        let mut local_of = Vec::with_capacity(n);
        let (mut mine, mut others) = (Vec::new(), Vec::new());
        let mut in_body = vec![false; n];
        for body in &piece.mesh.bodies {
            body.nodes.clone().for_each(|l| in_body[l] = true);
            let start = local_of.len();
            let own = body.nodes.clone().filter(|&l| sub.owned[l]);
            local_of.extend(own.map(|l| l as u32));
            mine.push(start..local_of.len());
            let held = body.nodes.clone().filter(|&l| !sub.owned[l]);
            let start = local_of.len();
            local_of.extend(held.map(|l| l as u32));
            others.push(start..local_of.len());
        }
        if rigid {
            let start = local_of.len();
            let free = (0..n).filter(|&l| !in_body[l] && sub.owned[l]);
            local_of.extend(free.map(|l| l as u32));
            mine.push(start..local_of.len());
        }
        if local_of.len() != n {
            return Err(ImpactError::Gpu(format!(
                "rank {}: {} of its {n} nodes lie in no body",
                sub.rank,
                n - local_of.len()
            )));
        }
        let mut device_of = vec![0u32; n];
        for (d, &l) in local_of.iter().enumerate() {
            device_of[l as usize] = d as u32;
        }
        let owned = local_of.iter().map(|&l| sub.owned[l as usize]).collect();
        mine.extend(others);
        Ok(DeviceOrder {
            device_of,
            local_of,
            ranges: mine,
            owned,
        })
    }

    /// Per-node values (`width` per node) of the local order in the device's.
    fn to_device<T: Copy>(&self, x: &[T], width: usize) -> Vec<T> {
        (self.local_of.iter())
            .flat_map(|&l| {
                x[width * l as usize..width * (l as usize + 1)]
                    .iter()
                    .copied()
            })
            .collect()
    }

    /// Per-node values (`width` per node) of the device's order in the local one.
    fn to_local<T: Copy>(&self, x: &[T], width: usize) -> Vec<T> {
        (self.device_of.iter())
            .flat_map(|&d| {
                x[width * d as usize..width * (d as usize + 1)]
                    .iter()
                    .copied()
            })
            .collect()
    }

    /// The rank's elements on device node numbers.
    fn element_data(&self, data: &ElementData) -> ElementData {
        let mut d = data.clone();
        d.reference = self.to_device(&data.reference, 1);
        for block in &mut d.elements.blocks {
            for n in &mut block.nodes {
                *n = self.device_of[*n as usize];
            }
        }
        d
    }
}

/// The rank's plane nodes: which of the model's (by their place in the single GPU's list)
/// it holds, at which of its own places.
struct PlacedPlanes {
    nodes: Vec<PlaneNode>,
    /// The owned ones, listed first.
    owned: usize,
    /// The rank's place of each of the model's plane nodes, where it holds it.
    place: Vec<Option<usize>>,
    /// The model's place of each of the rank's plane nodes.
    model_place: Vec<usize>,
}

impl PlacedPlanes {
    fn new(global: &[PlaneNode], sub: &Subdomain, order: &DeviceOrder) -> Self {
        let held: Vec<(usize, u32, bool)> = (global.iter().enumerate())
            .filter_map(|(g, p)| {
                let l = sub.nodes.binary_search(&p.node).ok()?;
                Some((g, order.device_of[l], sub.owned[l]))
            })
            .collect();
        let mut place = vec![None; global.len()];
        let mut nodes = Vec::with_capacity(held.len());
        let mut model_place = Vec::with_capacity(held.len());
        for owned in [true, false] {
            for &(g, d, o) in held.iter().filter(|h| h.2 == owned) {
                place[g] = Some(nodes.len());
                model_place.push(g);
                nodes.push(PlaneNode {
                    node: d,
                    planes: global[g].planes,
                });
                debug_assert_eq!(o, owned);
            }
        }
        let owned = held.iter().filter(|h| h.2).count();
        PlacedPlanes {
            nodes,
            owned,
            place,
            model_place,
        }
    }
}

/// The records of one of the resident state's buffers a rank has: each one's place among
/// the model's (`count` of them) and on the rank's device, `width` words each.
struct StateRecords {
    places: Vec<(usize, usize)>,
    width: usize,
    count: usize,
}

/// One rank's explicit solver, resident on its GPU.
pub struct RankResident<'m> {
    model: &'m Model,
    ranks: &'m dyn Ranks,
    sub: Subdomain,
    order: DeviceOrder,
    engine: ResidentStep,
    dt: f64,
    /// The shortened last step, once the run asked for it.
    last_dt: Option<f64>,
    time: f64,
    steps: usize,
    total: usize,
    frame_every: Option<usize>,
    /// Every node's lumped mass (the whole model's).
    mass_all: Vec<f64>,
    body_mass: Vec<f64>,
    max_iterations: usize,
    /// Each interface's secondary nodes' places in the rank's plane nodes, where it holds
    /// them.
    places: Vec<Vec<Option<usize>>>,
    plane_count: usize,
    /// The model's place (in the single GPU's list) of each of the rank's plane nodes, the
    /// owned ones (listed first) and the model's plane nodes.
    plane_places: Vec<usize>,
    owned_planes: usize,
    model_plane_nodes: usize,
    /// Whether the rank owns each probe's node, and its device number where it holds it.
    probes: Vec<(bool, u32)>,
    /// The contact between meshed bodies, on the surfaces (none where rigid planes are the
    /// only contacts), and its history columns of the step.
    surface: Option<SurfaceContact>,
    contact_row: Vec<f32>,
    /// Seconds in the contact on the surfaces: the surface state's read-back (where not run
    /// ahead), its gather, and the submission that runs the iteration with the rank's
    /// element forces.
    contact_seconds: f64,
    /// Where plies have strengths: the model's survey number of each point the rank's
    /// device surveys (its row ends with their record).
    survey_points: Option<Vec<u32>>,
    current: Row,
    initial: Energies,
    measure_shift: f64,
    /// The state at the last frame (or the start), on the rank's local nodes, and the
    /// rank's plane results (as [`Self::places`] points into them).
    u: Vec<f64>,
    v: Vec<f64>,
    results: Vec<f64>,
    received: Vec<f64>,
    piece: Model,
    communication: std::cell::Cell<f64>,
    /// The next step's first part, where the last step's submission ran it.
    ahead: Option<Ahead>,
    checkpoint_every: Option<usize>,
    /// The run stops: no step runs ahead any more.
    stopping: bool,
}

/// The first part of a rank's next step, run in the submission of the step before (its
/// correctors and history row) where the run reads no state between the two.
enum Ahead {
    /// The next step's chosen corners (rigid planes as the only contacts).
    Corners(Vec<[f32; 3]>),
    /// The state of the surface nodes after the next step's predictor (contact on the
    /// surfaces).
    Front(SurfaceState),
}

impl<'m> RankResident<'m> {
    /// Rank `ranks.rank()`'s part of `model` under `partition` on `ctx`, for `total` steps
    /// with a frame every `frame_every`; `survey`: the model's device failure survey and the
    /// cell of each of its points, where plies have strengths.
    pub fn new(
        model: &'m Model,
        ranks: &'m dyn Ranks,
        partition: &Partition,
        (settings, dt, speed_scale): (&ExplicitSettings, f64, f64),
        (ctx, total, frame_every): (GpuContext, usize, Option<usize>),
        survey: Option<(SurveySetup, Vec<u32>)>,
    ) -> Result<Self> {
        let mut sub = Subdomain::new(model, partition, ranks.rank());
        let piece = sub.piece_model(model);
        // the contact between meshed bodies is the surface model's (`SurfaceContact`)
        let (global, places) = resident::setup_without_contact(model, settings, dt, speed_scale);
        let rigid = !model.rigid.is_empty();
        let built = Self::device_step(
            &mut sub,
            (&piece, rigid),
            (&global, survey.as_ref()),
            ctx.clone(),
        );
        // a rank whose device step fails stops every rank (none waits for it)
        let (order, planes, mut engine, survey_points) = agree(ranks, built)
            .map_err(|why| ImpactError::Gpu(format!("building the resident step: {why}")))?;
        // the setup's collectives, on a clock of their own
        let setup_clock = std::cell::Cell::new(0.0);
        let talk = Timed {
            ranks,
            seconds: &setup_clock,
        };
        let surface = match planes_only(model) {
            true => None,
            false => {
                let built = SurfaceContact::new(model, &sub, &global, ctx, &talk);
                let built = built.and_then(|(c, owned, held)| {
                    let device = |l: &[u32]| -> Vec<u32> {
                        l.iter().map(|&l| order.device_of[l as usize]).collect()
                    };
                    let nodes = (device(&owned), device(&held));
                    engine.surface_with((&nodes.0, &nodes.1), &c.step, &c.held_places())?;
                    Ok(c)
                });
                Some(agree(ranks, built).map_err(|why| {
                    ImpactError::Gpu(format!("building the contact on the surfaces: {why}"))
                })?)
            }
        };
        let mass_all: Vec<f64> = global.lumped.iter().map(|l| l.mass).collect();
        let body_mass = (model.mesh.bodies.iter())
            .map(|b| b.nodes.clone().map(|n| mass_all[n]).sum())
            .collect();
        let v = sub.restrict(&global.velocity);
        let mine: f64 = (0..sub.nodes.len())
            .filter(|&l| sub.owned[l])
            .flat_map(|l| (0..3).map(move |a| (l, a)))
            .map(|(l, a)| mass_all[sub.nodes[l] as usize] * v[3 * l + a] * v[3 * l + a])
            .sum();
        let kinetic = 0.5 * talk.talk(|r| r.sum(&[mine]))[0];
        let probes = (model.probes.iter())
            .map(|p| match sub.nodes.binary_search(&p.node) {
                Ok(l) => (sub.owned[l], order.device_of[l]),
                Err(_) => (false, 0),
            })
            .collect();
        let places = (places.iter())
            .map(|list| list.iter().map(|&g| planes.place[g]).collect())
            .collect();
        let plane_count = global.planes.len();
        let results = match &surface {
            Some(c) => vec![0.0; SLOT * c.pairs.last().map_or(0, |r| r.end)],
            None => vec![0.0; SLOT * plane_count * planes.nodes.len()],
        };
        Ok(RankResident {
            model,
            ranks,
            current: Row {
                bodies: crate::integrate::body_velocities(model, &mass_all, &global.velocity),
                reports: vec![ContactReport::default(); model.interfaces.len()],
                ..Default::default()
            },
            received: vec![0.0; 3 * sub.received],
            u: vec![0.0; 3 * sub.nodes.len()],
            v,
            sub,
            order,
            engine,
            dt,
            last_dt: None,
            time: 0.0,
            steps: 0,
            total,
            frame_every: frame_every.filter(|&e| e > 0),
            mass_all,
            body_mass,
            max_iterations: settings.max_iterations,
            places,
            plane_count,
            plane_places: planes.model_place,
            owned_planes: planes.owned,
            model_plane_nodes: global.plane_nodes.len(),
            surface,
            contact_row: Vec::new(),
            contact_seconds: 0.0,
            survey_points,
            probes,
            initial: Energies {
                kinetic,
                ..Default::default()
            },
            measure_shift: 0.0,
            results,
            piece,
            communication: std::cell::Cell::new(0.0),
            ahead: None,
            checkpoint_every: None,
            stopping: false,
        })
    }

    /// The rank's device order, plane nodes and resident step, with its exchange.
    /// (`rigid`: the model has rigid bodies.)
    fn device_step(
        sub: &mut Subdomain,
        (piece, rigid): (&Model, bool),
        (global, survey): (&ResidentSetup, Option<&(SurveySetup, Vec<u32>)>),
        ctx: GpuContext,
    ) -> Result<(DeviceOrder, PlacedPlanes, ResidentStep, Option<Vec<u32>>)> {
        let order = DeviceOrder::new(sub, piece, rigid)?;
        let (survey, numbers) = match survey {
            Some((setup, cells)) => {
                let (setup, numbers) = rank_survey(setup, cells, sub, &order);
                (Some(setup), Some(numbers))
            }
            None => (None, None),
        };
        let planes = PlacedPlanes::new(&global.plane_nodes, sub, &order);
        let lumped: Vec<_> = sub
            .nodes
            .iter()
            .map(|&n| global.lumped[n as usize])
            .collect();
        // a probe's node where the rank holds it (its owner's row is the one taken)
        let probes = (global.probes.iter())
            .map(|&n| {
                sub.nodes
                    .binary_search(&n)
                    .map_or(0, |l| order.device_of[l])
            })
            .collect();
        let setup = ResidentSetup {
            dt: global.dt,
            tolerance: global.tolerance,
            max_iterations: global.max_iterations,
            lumped: order.to_device(&lumped, 1),
            planes: global.planes.clone(),
            plane_nodes: planes.nodes.clone(),
            reported_plane_nodes: Some(planes.owned),
            bodies: order.ranges.clone(),
            probes,
            velocity: order.to_device(&sub.restrict(&global.velocity), 3),
            acceleration: order.to_device(&sub.restrict(&global.acceleration), 3),
            contact: None,
            survey,
            reactions: Vec::new(),
            damage: None,
            cohesive: None,
        };
        let data = order.element_data(&sub.data);
        let mut engine = ResidentStep::new(ctx, &data, &setup, 1)?;
        let chosen = sub.exchanged_corners();
        let shared: Vec<u32> = (sub.shared.iter())
            .map(|&l| order.device_of[l as usize])
            .collect();
        engine.exchange_with(&chosen, &shared)?;
        sub.pack_corners(&chosen);
        Ok((order, planes, engine, numbers))
    }

    /// The ranks with the rank's communication clock.
    fn timed(&self) -> Timed<'_> {
        Timed {
            ranks: self.ranks,
            seconds: &self.communication,
        }
    }

    /// The whole model's history row from the rank's (its bodies' owned and other nodes'
    /// sums, its interfaces' results over its owned plane nodes, no probes): each value
    /// added over the ranks in order, the maxima taken, each probe its owner's.
    fn model_row(&self, row: &[f32]) -> Vec<f64> {
        // the bodies' owned nodes and the rigid bodies' (as one more body, where there are
        // any), then the bodies' other nodes
        let nb = self.model.mesh.bodies.len();
        let nr = nb + usize::from(!self.model.rigid.is_empty());
        let np = self.model.interfaces.len();
        let mut mine: Vec<f64> = row[..FIELDS * nr].iter().map(|&x| f64::from(x)).collect();
        // the contact on the surfaces is every rank's: rank 0 gives it (the others add
        // zeros, exactly)
        let (contact, in_row) = match &self.surface {
            Some(_) => (&self.contact_row[..], 0),
            None => (
                &row[FIELDS * (nr + nb)..FIELDS * (nr + nb) + SLOT * np],
                SLOT * np,
            ),
        };
        let first = self.surface.is_none() || self.ranks.rank() == 0;
        mine.extend(
            contact
                .iter()
                .map(|&x| if first { f64::from(x) } else { 0.0 }),
        );
        let base = FIELDS * (nr + nb) + in_row;
        for (p, &(owned, _)) in self.probes.iter().enumerate() {
            let values = &row[base + 6 * p..base + 6 * (p + 1)];
            mine.extend(
                values
                    .iter()
                    .map(|&x| if owned { f64::from(x) } else { 0.0 }),
            );
        }
        // the failure survey's record, its worst point numbered as the model's survey
        let columns = mine.len();
        if let Some(numbers) = &self.survey_points {
            let tail = &row[row.len() - FAILURE_FIELDS..];
            let mut record: Vec<f64> = tail.iter().map(|&x| f64::from(x)).collect();
            if record[6] >= 0.0 {
                record[6] = f64::from(numbers[record[6] as usize]);
            }
            mine.extend(record);
        }
        let all = self.timed().talk(|r| r.gather_all(&mine));
        let by_max = |c: usize| {
            c >= FIELDS * nr
                && c < FIELDS * nr + SLOT * np
                && slot::reduced_by_max((c - FIELDS * nr) % SLOT)
        };
        let mut out: Vec<f64> = (0..columns)
            .map(|c| match by_max(c) {
                true => all.iter().map(|r| r[c]).fold(0.0, f64::max),
                false => all.iter().map(|r| r[c]).fold(0.0, |s, x| s + x),
            })
            .collect();
        if self.survey_points.is_some() {
            // the ranks' records merged (in any order: the lowest point wins a tie)
            let mut record = empty();
            for r in &all {
                merge(&mut record, &r[columns..]);
            }
            out.extend(record);
        }
        out
    }

    /// Reads the device's state into the rank's local arrays (a frame).
    fn read_state(&mut self) -> Result<()> {
        let (u, v, results) = self.engine.read_state()?;
        self.u = self.order.to_local(&u, 3);
        self.v = self.order.to_local(&v, 3);
        self.results = match &mut self.surface {
            Some(c) => (c.step.read_results()?.into_iter())
                .map(|w| f64::from(f32::from_bits(w)))
                .collect(),
            None => results,
        };
        Ok(())
    }

    /// Each state buffer's records the rank owns (`owned_only`) or holds: u (a split pair
    /// per node), v, a, and the plane results (per plane node, in the single GPU's order).
    fn state_layout(&self, owned_only: bool) -> [StateRecords; 4] {
        let (order, sub) = (&self.order, &self.sub);
        let nodes: Vec<(usize, usize)> = (0..order.local_of.len())
            .filter(|&d| !owned_only || order.owned[d])
            .map(|d| (sub.nodes[order.local_of[d] as usize] as usize, d))
            .collect();
        let planes = (self.plane_places.iter().enumerate())
            .take(if owned_only {
                self.owned_planes
            } else {
                usize::MAX
            })
            .map(|(at, &g)| (g, at))
            .collect();
        let n = self.model.mesh.node_count();
        let records = |places, width, count| StateRecords {
            places,
            width,
            count,
        };
        [
            records(nodes.clone(), 6, n),
            records(nodes.clone(), 3, n),
            records(nodes, 3, n),
            records(planes, SLOT * self.plane_count, self.model_plane_nodes),
        ]
    }

    fn at_frame(&self, step: usize) -> bool {
        self.frame_every.is_some_and(|e| step % e == 0)
    }

    /// Whether the submission that ends step `s` also runs step `s + 1`'s first part: not
    /// into the run's last step (it may be shortened, and the state is read after it), not
    /// at a frame or a checkpoint (the state is read there), and not once the run stops.
    fn runs_ahead(&self, s: usize) -> bool {
        !self.stopping
            && s + 1 < self.total
            && !self.at_frame(s)
            && self.checkpoint_every.is_none_or(|e| s % e != 0)
    }

    /// The correctors and history row of the step that `sums` complete, and where
    /// [`Self::runs_ahead`] the next step's first part in the same submission (one wait for
    /// the device, where there were two; the same operations on the same values).
    fn correct(&mut self, sums: &[[f32; 3]]) -> Result<Vec<f32>> {
        if !self.runs_ahead(self.steps + 1) {
            return self.engine.step_correct(sums);
        }
        let (row, ahead) = match self.surface {
            None => {
                let (row, corners) = self.engine.step_correct_then_forces(sums)?;
                (row, Ahead::Corners(corners))
            }
            Some(_) => {
                let (row, state) = self.engine.step_correct_then_front(sums)?;
                (row, Ahead::Front(state))
            }
        };
        self.ahead = Some(ahead);
        Ok(row)
    }
}

impl Integrator for RankResident<'_> {
    fn model(&self) -> &Model {
        self.model
    }

    fn method(&self) -> Method {
        Method::Explicit
    }

    fn device_name(&self) -> String {
        self.engine.device_name()
    }

    fn engine(&self) -> &'static str {
        ENGINE_GPU_RESIDENT
    }

    /// The contact iteration on the surfaces: each step records the last step's sweeps and
    /// two more as dispatches of their own.
    fn recorded_sweeps(&self) -> Option<(u64, u64)> {
        (self.surface.as_ref()).map(|c| (c.step.recorded, c.step.needed))
    }

    fn contact_zone(&self) -> Option<bool> {
        (self.surface.as_ref()).map(|c| c.step.runs_zone())
    }

    /// The rank's trial of the surface iteration's forms (each rank's own: every form gives
    /// the same bits).
    fn contact_forms(&self) -> Option<ContactForms> {
        (self.surface.as_ref()).map(|c| c.forms.summary())
    }

    /// The search on the surfaces sorts the faces every step (a step is a submission).
    fn search_rebuilds(&self) -> Option<(u64, u64)> {
        (self.surface.as_ref())
            .filter(|c| c.step.has_search())
            .map(|c| (c.step.sorts, 0))
    }

    /// One step: the rank's forces, the exchange of the shared nodes' corners, the
    /// correctors and the history row added over the ranks; at a frame step the state is
    /// read back.
    fn step(&mut self) -> Result<StepReport> {
        let ahead = self.ahead.take();
        let chosen = match &mut self.surface {
            None => match ahead {
                Some(Ahead::Corners(chosen)) => chosen,
                _ => self.engine.step_forces()?,
            },
            Some(surface) => {
                let clock = std::time::Instant::now();
                let mine = match ahead {
                    Some(Ahead::Front(state)) => state,
                    _ => self.engine.step_front()?,
                };
                let talk = Timed {
                    ranks: self.ranks,
                    seconds: &self.communication,
                };
                surface.gather(&talk, &mine)?;
                surface.submitting();
                let forces = self.engine.step_surface_forces(&mut surface.step)?;
                surface.collected(forces.device, forces.host);
                self.contact_row = forces.row;
                self.contact_seconds += clock.elapsed().as_secs_f64();
                forces.corners
            }
        };
        let sends = self.sub.sends(&chosen);
        let talk = Timed {
            ranks: self.ranks,
            seconds: &self.communication,
        };
        exchange_corners(&talk, &self.sub, &sends, &mut self.received);
        let sums = self.sub.shared_sums(&chosen, &self.received);
        let row = self.correct(&sums)?;
        let row = self.model_row(&row);
        self.steps += 1;
        let reader = RowReader {
            reactions: 0,
            cohesive: 0,
            model: self.model,
            body_mass: &self.body_mass,
            max_iterations: self.max_iterations,
            interval: crate::integrate::explicit::impulse_interval(self.dt, self.last_dt),
        };
        self.current = reader.decode(&row);
        self.current.energies.kinetic -= self.measure_shift;
        self.time = match self.last_dt {
            Some(last) => (self.steps - 1) as f64 * self.dt + last,
            None => self.steps as f64 * self.dt,
        };
        if self.at_frame(self.steps) || self.steps == self.total {
            self.read_state()?;
        }
        Ok(self.current.report)
    }

    fn energies(&mut self) -> Result<Energies> {
        Ok(if self.steps == 0 {
            self.initial
        } else {
            self.current.energies
        })
    }

    fn reports(&self) -> Vec<ContactReport> {
        self.current.reports.clone()
    }

    /// The pressure and gap of a secondary node the rank holds, at the last state read
    /// (zero and no gap for another rank's: a frame takes the rank's own nodes).
    fn node_contact(&self, interface: usize, point: usize) -> (f64, f64) {
        let o = match &self.surface {
            // every rank has every pair's results
            Some(c) => SLOT * (c.pairs[interface].start + point),
            None => match self.places[interface][point] {
                Some(place) => SLOT * (place * self.plane_count + interface),
                None => return (0.0, f64::NAN),
            },
        };
        let area = self.model.interfaces[interface].area[point];
        let interval = crate::integrate::explicit::impulse_interval(self.dt, self.last_dt);
        (
            self.results[o + slot::NORMAL_IMPULSE] / (interval * area),
            self.results[o + slot::GAP],
        )
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn steps(&self) -> usize {
        self.steps
    }

    /// The displacements of the rank's nodes at the last frame.
    fn displacement(&self) -> &[f64] {
        &self.u
    }

    /// The velocities of the rank's nodes at the last frame.
    fn velocity(&self) -> &[f64] {
        &self.v
    }

    fn nodal_mass(&self) -> &[f64] {
        &self.mass_all
    }

    fn body_velocities(&self) -> Vec<[f64; 3]> {
        self.current.bodies.clone()
    }

    /// The merged record of the ranks' device surveys (at the start, with no displacement,
    /// every index is zero).
    fn failure_record(&self) -> Option<[f64; FAILURE_FIELDS]> {
        match self.steps {
            0 => self.survey_points.as_ref().map(|_| empty()),
            _ => self.current.failure,
        }
    }

    fn probes(&self) -> Vec<ProbeValues> {
        if self.steps > 0 {
            return self.current.probes.clone();
        }
        // the start: no displacement, the initial velocity (every rank holds the model's)
        let mine: Vec<f64> = (self.model.probes.iter().zip(&self.probes))
            .flat_map(|(p, &(owned, _))| {
                let l = self.sub.nodes.binary_search(&p.node).unwrap_or(0);
                (0..3).map(move |a| (owned, 3 * l + a))
            })
            .map(|(owned, d)| if owned { self.v[d] } else { 0.0 })
            .collect();
        let all = self.timed().talk(|r| r.sum(&mine));
        all.chunks_exact(3)
            .map(|c| ([0.0; 3], [c[0], c[1], c[2]]))
            .collect()
    }

    /// The single GPU's resident state at this step (its device buffers' words), gathered
    /// on rank 0 from the nodes and plane nodes each rank owns.
    fn checkpoint_state(&mut self) -> Result<Option<SolverState>> {
        if self.ahead.is_some() {
            return Err(ImpactError::Gpu(format!(
                "the resident state is read at rest only (step {}, the next one begun)",
                self.steps
            )));
        }
        let words = self.engine.read_step_state()?;
        let layout = self.state_layout(true);
        let mut buffers = Vec::with_capacity(words.len());
        // the contact on the surfaces: every rank has its results whole
        let surface_results = match &mut self.surface {
            Some(c) => Some(c.step.read_results()?),
            None => None,
        };
        let talk = self.timed();
        for (k, (w, r)) in words.iter().zip(&layout).enumerate() {
            if let (3, Some(results)) = (k, &surface_results) {
                if self.ranks.rank() == 0 {
                    buffers.push(results.clone());
                }
                continue;
            }
            let width = r.width;
            let mine: Vec<f64> = (r.places.iter())
                .flat_map(|&(_, at)| w[width * at..width * (at + 1)].iter())
                .map(|&x| f64::from(x))
                .collect();
            let global: Vec<usize> = r.places.iter().map(|&(g, _)| g).collect();
            if let Some(all) = gather_records(&talk, &global, &mine, (width, r.count)) {
                let padded = (padded_bytes(4 * all.len() as u64) / 4) as usize;
                let mut b: Vec<u32> = all.into_iter().map(|x| x as u32).collect();
                b.resize(padded, 0);
                buffers.push(b);
            }
        }
        // rank 0 gathered every buffer, the others none
        if buffers.len() != words.len() {
            return Ok(None);
        }
        Ok(Some(SolverState::Resident(ResidentState {
            work: Default::default(),
            power: 0.0,
            cohesive_energy: Vec::new(),
            dt: self.dt,
            time: self.time,
            steps: self.steps,
            buffers,
        })))
    }

    /// Continues from the single GPU's resident state (written on one process or on any
    /// number of ranks): each device node and plane node takes its words.
    fn restore(&mut self, state: SolverState) -> std::result::Result<(), String> {
        let SolverState::Resident(s) = state else {
            return Err(crate::integrate::integrator::other_integrator());
        };
        if s.steps >= self.total {
            return Err(format!(
                "the checkpoint is at step {}, the run has {}",
                s.steps, self.total
            ));
        }
        let layout = self.state_layout(false);
        let sizes = self.engine.step_state_words();
        let other = || "the checkpoint's state is of another model".to_string();
        if s.buffers.len() != layout.len() {
            return Err(other());
        }
        if let Some(c) = &self.surface {
            c.step
                .write_results(&s.buffers[3])
                .map_err(|e| e.to_string())?;
        }
        let mut mine = Vec::with_capacity(layout.len());
        for (k, ((global, r), size)) in s.buffers.iter().zip(&layout).zip(sizes).enumerate() {
            if k == 3 && self.surface.is_some() {
                // the rank's own plane results (none): as they are
                mine.push(vec![0; size]);
                continue;
            }
            let width = r.width;
            if global.len() < width * r.count {
                return Err(other());
            }
            let mut w = vec![0u32; size];
            for &(g, at) in &r.places {
                w[width * at..width * (at + 1)]
                    .copy_from_slice(&global[width * g..width * (g + 1)]);
            }
            mine.push(w);
        }
        (self.engine)
            .write_step_state(&mine)
            .map_err(|e| e.to_string())?;
        (self.dt, self.time, self.steps) = (s.dt, s.time, s.steps);
        self.read_state().map_err(|e| e.to_string())
    }

    /// Makes the last step `dt` long; the energy measure shifts by $\frac{1}{8}(\Delta t^2 -
    /// dt^2)\, a \cdot M a$, summed over the ranks' owned nodes.
    fn shorten_step(&mut self, dt: f64) {
        let ama = match self.engine.read_acceleration() {
            Ok(a) => {
                let (order, lumped_mass) = (&self.order, &self.mass_all);
                let sub = &self.sub;
                (a.iter().enumerate())
                    .filter(|(d, _)| order.owned[d / 3])
                    .map(|(d, a)| {
                        let l = order.local_of[d / 3] as usize;
                        lumped_mass[sub.nodes[l] as usize] * a * a
                    })
                    .sum()
            }
            Err(_) => f64::NAN,
        };
        let ama = self.timed().talk(|r| r.sum(&[ama]))[0];
        self.measure_shift = 0.125 * (self.dt * self.dt - dt * dt) * ama;
        self.engine.set_dt(dt);
        if let Some(c) = &mut self.surface {
            c.step.set_dt(dt);
        }
        self.last_dt = Some(dt);
    }

    fn end_at(&mut self, time: f64) {
        self.time = time;
    }

    fn decomposed(&self) -> Option<&dyn Decomposed> {
        Some(self)
    }

    fn decomposed_mut(&mut self) -> Option<&mut dyn Decomposed> {
        Some(self)
    }

    fn pipelined(&mut self) -> Option<&mut dyn Pipelined> {
        Some(self)
    }
}

impl Pipelined for RankResident<'_> {
    /// The checkpoint interval: the state is read there, so no step runs ahead into the
    /// next (the shortened last step never has a step run ahead into it).
    fn schedule(&mut self, _last_step: Option<f64>, checkpoint_every: Option<usize>) {
        self.checkpoint_every = checkpoint_every.map(|e| e.max(1));
    }

    /// No step runs ahead any more: the one begun, if any, is the last handed out.
    fn stop_submitting(&mut self) {
        self.stopping = true;
    }

    fn at_rest(&self) -> bool {
        self.ahead.is_none()
    }
}

impl Decomposed for RankResident<'_> {
    fn piece(&self) -> Piece<'_> {
        Piece {
            model: &self.piece,
            u: &self.u,
            v: &self.v,
            nodes: &self.sub.nodes,
            elements: &self.sub.elements,
            damage: None,
        }
    }

    fn gather_all(&self, mine: &[f64]) -> Vec<Vec<f64>> {
        self.timed().talk(|r| r.gather_all(mine))
    }

    fn decomposition(&mut self) -> Decomposition {
        let figures = RankFigures {
            elements: self.sub.data.elements.count(),
            nodes: self.sub.nodes.len(),
            shared_nodes: self.sub.shared.len(),
            neighbours: self.sub.neighbours.len(),
            communication: self.communication.get(),
            contact: self.contact_seconds,
            face_nodes_received: 0,
        };
        let contact = match self.surface {
            Some(_) => SURFACES,
            None => PLANES,
        };
        decomposition_of(self.ranks, &figures, contact)
    }
}
