//! The contact of one rank's explicit step.
//!
//! 1. The rank's own surface nodes, as it holds them, go into the surface model
//!    ([`super::surface`]); the rigid bodies' nodes, then the secondary nodes within reach
//!    of a rigid plane or a rigid body, are gathered from their owners.
//! 2. Each rank sends the primary-face nodes it owns to the ranks whose secondary nodes they
//!    may reach this step: those within the search's reach plus the largest face's extent
//!    of the other rank's box of secondary nodes. The ranks learn each other's boxes first,
//!    so both sides of a pair know whether it exchanges.
//! 3. Each rank searches for the secondary nodes it owns, against the faces whose nodes it
//!    has, with the single process's broad phase and closest-point projection: any face
//!    whose grown box holds one of its nodes has all its nodes within that reach.
//! 4. The contacts within reach are gathered on every rank with the state of their nodes,
//!    and every rank works the impulse sweeps on them
//!    ([`ExplicitContact::step_from_points`]), which read no other node.
//!
//! Every value the sweeps read is the single process's, so the impulses and the changed
//! velocities are the same bits.

use super::ranks::Timed;
use super::subdomain::Subdomain;
use super::surface::{surface_model, SurfaceIndex};
use crate::error::Result;
use crate::integrate::explicit::spin::{BodySpin, Spins};
use crate::integrate::explicit::{
    plane_gap_within_reach, rigid_gap_within_reach, ContactFields, ExplicitContact,
    ExplicitInterface, NodalStart,
};
use crate::integrate::StepReport;
use crate::kernels::contact_gap::closest_point;
use crate::kernels::contact_gap::NO_FACE;
use crate::kernels::{as_vec3, ContactPoint, ContactQueries};
use crate::model::{Model, Primary};
use crate::scene::ExplicitSettings;
use crate::search;

/// The contact's share-out in words (`summary.json`).
pub(crate) const DESCRIPTION: &str = "each rank receives from their owners the primary-face nodes its secondary nodes may reach and searches for the secondary nodes it owns; the contacts within reach are gathered on every rank with their nodes' state, and every rank works the impulse sweeps";

/// Values per node state: the surface index, u, v and v_half.
const NODE: usize = 10;
/// Values per contact: the query, the point (face, xi, normal, gap, gap rate), then the
/// state of the secondary node and of the four face nodes.
const RECORD: usize = 1 + 8 + 5 * NODE;

/// The rank's nodes as the step's contact reads them (3 per local node).
pub(crate) struct LocalState<'a> {
    pub u: &'a [f64],
    pub v: &'a mut [f64],
    pub v_half: &'a [f64],
}

/// The contact of a rank: the surface model and what the step keeps and reuses.
pub(crate) struct SurfaceContact {
    model: Model,
    contact: ExplicitContact,
    rank: usize,
    /// (surface index, local node) of every surface node the rank holds.
    held: Vec<(u32, u32)>,
    index: SurfaceIndex,
    /// The surface nodes set from other ranks' values this step.
    foreign: Vec<u32>,
    /// The positions of the surface nodes set this step, for the search.
    x: Vec<[f64; 3]>,
    /// The (interface, place) pairs that may hold a constraint this step: the gathered
    /// contacts' and plane nodes', increasing.
    candidates: Vec<(u32, u32)>,
    /// Whether an interface is a rigid plane or a rigid body's surface.
    analytic: bool,
    /// The rigid bodies' nodes (surface numbers) the rank owns, each once.
    own_bodies: Vec<u32>,
    queries: ContactQueries,
    lists: Vec<Vec<u32>>,
    points: Vec<ContactPoint>,
    /// The queries of the secondary nodes the rank owns, increasing.
    owned_queries: Vec<usize>,
    /// The queries the last step set a point for.
    set_points: Vec<usize>,
    /// The surface nodes' state where the step has it, and the step that last set each.
    u: Vec<f64>,
    v: Vec<f64>,
    v_half: Vec<f64>,
    stamp: Vec<u32>,
    step: u32,
    inv_mass: Vec<f64>,
    /// The rigid bodies' rotation: every rank works the same sweeps on the same contacts,
    /// so every rank holds the same bits.
    spins: Spins,
    /// Primary-face node states received from other ranks, over the run.
    pub received: usize,
}

impl SurfaceContact {
    pub fn new(
        model: &Model,
        sub: &Subdomain,
        mass_all: &[f64],
        (settings, speed_scale): (&ExplicitSettings, f64),
    ) -> SurfaceContact {
        let map = &sub.surface;
        let surface = surface_model(model, &map.nodes);
        let mass: Vec<f64> = map.nodes.iter().map(|&n| mass_all[n as usize]).collect();
        let start = NodalStart::new(
            &mass,
            &surface.fixed,
            model.gravity,
            &surface.initial_velocity,
        );
        let face_size = search::largest_face_size(model);
        let contact = ExplicitContact::new(&surface, settings, speed_scale, face_size);
        let owner = map.owner.clone();
        let mine = |s: &u32| owner[*s as usize] as usize == sub.rank;
        let mut held = vec![false; map.nodes.len()];
        for &(k, _) in &map.held {
            held[k as usize] = true;
        }
        let index = SurfaceIndex::new(&surface, &held, |s| mine(&s));
        let mut own_bodies: Vec<u32> = (surface.interfaces.iter())
            .filter_map(|itf| match itf.primary {
                Primary::Rigid { node, .. } => Some(node),
                _ => None,
            })
            .filter(mine)
            .collect();
        own_bodies.sort_unstable();
        own_bodies.dedup();
        let nq = surface.queries.len();
        let query_owner = |q: usize| owner[surface.queries.secondary[q] as usize] as usize;
        let n = 3 * map.nodes.len();
        SurfaceContact {
            contact,
            rank: sub.rank,
            held: map.held.clone(),
            index,
            foreign: Vec::new(),
            x: vec![[f64::NAN; 3]; map.nodes.len()],
            candidates: Vec::new(),
            analytic: (surface.interfaces.iter()).any(|itf| itf.is_plane() || itf.is_rigid()),
            own_bodies,
            queries: surface.queries.clone(),
            lists: vec![Vec::new(); nq],
            points: vec![ContactPoint::default(); nq],
            owned_queries: (0..nq).filter(|&q| query_owner(q) == sub.rank).collect(),
            set_points: Vec::new(),
            u: vec![0.0; n],
            v: vec![0.0; n],
            v_half: vec![0.0; n],
            stamp: vec![0; map.nodes.len()],
            step: 0,
            inv_mass: start.inv_mass,
            spins: Spins::new(&surface),
            received: 0,
            model: surface,
        }
    }

    /// The contact impulses of the step `dt` on the rank's nodes (`local`, velocities changed
    /// in place), reported as forces over `interval` ([`ContactFields::interval`]); `speed`
    /// is the fastest node's over the whole model.
    pub fn step(
        &mut self,
        talk: &Timed,
        local: LocalState,
        (dt, interval): (f64, f64),
        speed: f64,
    ) -> Result<StepReport> {
        self.step += 1;
        self.foreign.clear();
        self.candidates.clear();
        for i in 0..self.held.len() {
            let (k, n) = self.held[i];
            self.set(k, [local.u, local.v, local.v_half], n as usize);
        }
        self.gather_bodies(talk);
        self.gather_analytic(talk, dt);
        let margin = self.contact.margin(speed, dt);
        self.exchange_faces(talk, margin);
        self.find_own_points(margin);
        self.gather_contacts(talk, margin);
        let (stamp, step) = (&self.stamp, self.step);
        let present = |k: u32| stamp[k as usize] == step;
        let fields = ContactFields {
            u: &self.u,
            v: &mut self.v,
            v_half: &self.v_half,
            inv_mass: &self.inv_mass,
            interval,
            planes: Some(&present),
            spins: self.spins.any().then_some(&mut self.spins),
        };
        let candidates = Some(&self.candidates[..]);
        let report =
            (self.contact).step_from_points(&self.model, fields, dt, margin, candidates)?;
        for &(k, n) in &self.held {
            let (k, n) = (3 * k as usize, 3 * n as usize);
            local.v[n..n + 3].copy_from_slice(&self.v[k..k + 3]);
        }
        Ok(report)
    }

    /// The interfaces' impulses and reports of the last step.
    pub fn contact(&self) -> &ExplicitContact {
        &self.contact
    }

    /// The rigid bodies' rotation.
    pub fn spins(&self) -> &Spins {
        &self.spins
    }

    /// Turns the rotating bodies over the step (after the contact's impulses).
    pub fn drift_spins(&mut self, dt: f64) {
        self.spins.drift(dt);
    }

    /// Continues from a checkpoint's interfaces and rotations (each whole, as every rank
    /// holds them).
    pub fn restore(&mut self, interfaces: Vec<ExplicitInterface>, spins: Vec<BodySpin>) {
        self.contact.restore(interfaces);
        self.spins.restore(spins);
    }

    /// Sets surface node `k`'s state from node `n` of the fields `[u, v, v_half]`.
    fn set(&mut self, k: u32, [u, v, vh]: [&[f64]; 3], n: usize) {
        let (k3, n3) = (3 * k as usize, 3 * n);
        self.u[k3..k3 + 3].copy_from_slice(&u[n3..n3 + 3]);
        self.v[k3..k3 + 3].copy_from_slice(&v[n3..n3 + 3]);
        self.v_half[k3..k3 + 3].copy_from_slice(&vh[n3..n3 + 3]);
        self.stamp[k as usize] = self.step;
    }

    /// Surface node `k`'s state as values: k, u, v, v_half.
    fn state(&self, k: u32) -> [f64; NODE] {
        let k3 = 3 * k as usize;
        let mut out = [0.0; NODE];
        out[0] = f64::from(k);
        out[1..4].copy_from_slice(&self.u[k3..k3 + 3]);
        out[4..7].copy_from_slice(&self.v[k3..k3 + 3]);
        out[7..10].copy_from_slice(&self.v_half[k3..k3 + 3]);
        out
    }

    /// Sets a node's state from another rank's values.
    fn unpack_state(&mut self, x: &[f64]) {
        let k = x[0] as u32;
        let one = [&x[1..4], &x[4..7], &x[7..10]];
        self.set(k, one, 0);
        self.foreign.push(k);
    }

    /// The rigid bodies' nodes, from their owners: every rank's contacts against a body read
    /// its state.
    fn gather_bodies(&mut self, talk: &Timed) {
        if !self.model.interfaces.iter().any(|itf| itf.is_rigid()) {
            return;
        }
        let mine: Vec<f64> = self
            .own_bodies
            .iter()
            .flat_map(|&b| self.state(b))
            .collect();
        for x in gather(talk, &mine).chunks_exact(NODE) {
            self.unpack_state(x);
        }
    }

    /// The secondary nodes of the rigid planes and rigid bodies within reach of them, from
    /// their owners (the sweeps leave out the others, as the single process finds them out
    /// of reach).
    fn gather_analytic(&mut self, talk: &Timed, dt: f64) {
        if !self.analytic {
            return;
        }
        let mut send: Vec<u32> = Vec::new();
        let fields = (&self.u[..], &self.v[..]);
        let spins = self.spins.any().then_some(&self.spins);
        for (k, (itf, owned)) in (self.model.interfaces.iter())
            .zip(&self.index.owned_secondary)
            .enumerate()
        {
            let within = |s: u32| match itf.primary {
                Primary::Plane { point, normal } => {
                    let (s3, x0) = (3 * s as usize, self.model.mesh.nodes[s as usize]);
                    let at = |x: &[f64]| [x[s3], x[s3 + 1], x[s3 + 2]];
                    let state = (at(&self.u), at(&self.v));
                    plane_gap_within_reach(x0, state, (point, normal), dt).1
                }
                Primary::Rigid { node: b, .. } => {
                    let pair = (s as usize, b as usize);
                    rigid_gap_within_reach(&self.model, fields, pair, k, dt, spins).is_some()
                }
                Primary::Surface { .. } => false,
            };
            send.extend(owned.iter().copied().filter(|&s| within(s)));
        }
        send.sort_unstable();
        send.dedup();
        let mine: Vec<f64> = send.iter().flat_map(|&k| self.state(k)).collect();
        for x in gather(talk, &mine).chunks_exact(NODE) {
            self.unpack_state(x);
            let slots = self.index.plane_slots_of(x[0] as u32);
            self.candidates.extend_from_slice(slots);
        }
    }

    /// The current position of surface node `k` (of a node set this step).
    fn position(&self, k: u32) -> [f64; 3] {
        position_of(&self.model.mesh.nodes, &self.u, k)
    }

    /// The box of the positions of `nodes` (empty: +inf to -inf).
    fn bounds(&self, nodes: impl Iterator<Item = u32>) -> [f64; 6] {
        let mut b = [
            f64::INFINITY,
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        for k in nodes {
            let p = self.position(k);
            for a in 0..3 {
                b[a] = b[a].min(p[a]);
                b[3 + a] = b[3 + a].max(p[a]);
            }
        }
        b
    }

    /// Sends the primary-face nodes the rank owns to the ranks whose secondary nodes they
    /// may reach, and sets those the others send.
    fn exchange_faces(&mut self, talk: &Timed, margin: f64) {
        let surfaces: Vec<usize> = (0..self.model.interfaces.len())
            .filter(|&k| !self.model.interfaces[k].is_plane())
            .collect();
        if surfaces.is_empty() || talk.ranks.size() == 1 {
            return;
        }
        // the reach: the search's margin and the largest face's extent (each face is whole
        // on the rank of its element), and a thousandth more for rounding
        let local_extent = self.held_face_extent();
        let reach = (margin + talk.talk(|r| r.max(local_extent))) * 1.001;
        let boxes = Boxes {
            all: talk.talk(|r| r.gather_all(&self.own_boxes(&surfaces))),
            reach,
        };
        let pairs = boxes.pairs(self.rank, surfaces.len());
        let out: Vec<Vec<f64>> = (pairs.iter())
            .map(|&q| self.face_states_for(&surfaces, &boxes, q))
            .collect();
        for x in swap(talk, &pairs, &out)
            .iter()
            .flat_map(|d| d.chunks_exact(NODE))
        {
            self.unpack_state(x);
            self.received += 1;
        }
    }

    /// Per surface interface: the box of the secondary nodes the rank owns, then the box of
    /// the primary-face nodes it owns.
    fn own_boxes(&self, surfaces: &[usize]) -> Vec<f64> {
        (surfaces.iter())
            .flat_map(|&k| {
                let secondary = self.index.owned_secondary[k].iter().copied();
                let faces = self.index.owned_face_nodes[k].iter().copied();
                self.bounds(secondary).into_iter().chain(self.bounds(faces))
            })
            .collect()
    }

    /// The states of the primary-face nodes the rank owns within reach of rank `q`'s
    /// secondary nodes, each once.
    fn face_states_for(&self, surfaces: &[usize], boxes: &Boxes, q: usize) -> Vec<f64> {
        let mut nodes: Vec<u32> = Vec::new();
        for (j, &k) in surfaces.iter().enumerate() {
            let theirs = boxes.secondary(q, j);
            let near = |s: &u32| boxes.holds(theirs, self.position(*s));
            nodes.extend(self.index.owned_face_nodes[k].iter().copied().filter(near));
        }
        nodes.sort_unstable();
        nodes.dedup();
        nodes.into_iter().flat_map(|s| self.state(s)).collect()
    }

    /// The largest box side of the primary faces whose nodes the rank holds. (A face is
    /// whole on the rank of its element, so the largest over the ranks is the largest of
    /// every face.)
    fn held_face_extent(&self) -> f64 {
        let mut extent = 0.0f64;
        for &f in self.index.held_faces.iter().flatten() {
            let b = self.bounds(self.queries.faces[f].iter().copied());
            for a in 0..3 {
                extent = extent.max(b[3 + a] - b[a]);
            }
        }
        extent
    }

    /// The closest points of the rank's own queries against the faces whose nodes it has
    /// this step (the single process's search and [`crate::kernels::contact_gap`]): the
    /// faces it holds and those the nodes it received complete.
    fn find_own_points(&mut self, margin: f64) {
        self.set_positions();
        let completed = self.completed_faces();
        for (k, itf) in self.model.interfaces.iter().enumerate() {
            let Primary::Surface { faces, queries, .. } = &itf.primary else {
                continue;
            };
            let own = &self.owned_queries;
            let ids = &own[own.partition_point(|&q| q < queries.start)
                ..own.partition_point(|&q| q < queries.end)];
            if ids.is_empty() {
                continue;
            }
            let within = &completed[completed.partition_point(|&f| f < faces.start)
                ..completed.partition_point(|&f| f < faces.end)];
            let candidates = sorted_union(&self.index.held_faces[k], within);
            let x = &self.x;
            search::find_candidates_of(&self.queries, x, ids, candidates, margin, &mut self.lists);
        }
        self.own_points();
    }

    /// The faces the nodes received this step complete (every node set this step),
    /// increasing.
    fn completed_faces(&self) -> Vec<usize> {
        let (stamp, step, faces) = (&self.stamp, self.step, &self.queries.faces);
        let mut completed: Vec<usize> = (self.foreign.iter())
            .flat_map(|&k| self.index.faces_of(k))
            .map(|&f| f as usize)
            .filter(|&f| present(stamp, step, &faces[f]))
            .collect();
        completed.sort_unstable();
        completed.dedup();
        completed
    }

    /// The positions of the nodes set this step, for the search. The others keep an earlier
    /// step's position, which the search never reads: it takes only faces whose nodes are
    /// all set this step, and the queries of nodes the rank holds.
    fn set_positions(&mut self) {
        let (reference, u, x) = (&self.model.mesh.nodes, &self.u, &mut self.x);
        let set = (self.held.iter().map(|&(k, _)| k)).chain(self.foreign.iter().copied());
        for k in set {
            x[k as usize] = position_of(reference, u, k);
        }
    }

    /// The closest point of each query the rank owns, from its candidate list.
    fn own_points(&mut self) {
        use rayon::prelude::*;
        let (reference, q) = (&self.model.mesh.nodes, &self.queries);
        let uv = (as_vec3(&self.u), as_vec3(&self.v));
        let lists = &self.lists;
        let points: Vec<ContactPoint> = (self.owned_queries.par_iter())
            .with_min_len(256)
            .map(|&i| closest_point(reference, uv, q, q.secondary[i], &lists[i]))
            .collect();
        for (&i, p) in self.owned_queries.iter().zip(points) {
            self.points[i] = p;
        }
    }

    /// Every rank's contacts within reach, with their nodes' state: the query points of the
    /// step.
    fn gather_contacts(&mut self, talk: &Timed, margin: f64) {
        let reach = -margin.max(f64::MIN_POSITIVE);
        let mut mine = Vec::new();
        for &q in &self.owned_queries {
            let p = self.points[q];
            if p.face == NO_FACE || p.gap < reach {
                continue;
            }
            mine.push(q as f64);
            mine.extend(pack(&p));
            let nodes = std::iter::once(self.queries.secondary[q])
                .chain(self.queries.faces[p.face as usize]);
            for k in nodes {
                mine.extend(self.state(k));
            }
        }
        let all = gather(talk, &mine);
        let points = self.contact.query_points_mut();
        for q in self.set_points.drain(..) {
            points[q] = ContactPoint::default();
        }
        for r in all.chunks_exact(RECORD) {
            let q = r[0] as usize;
            self.contact.query_points_mut()[q] = unpack(&r[1..9]);
            self.set_points.push(q);
            self.candidates.push(self.index.query_slot[q]);
            for x in r[9..].chunks_exact(NODE) {
                self.unpack_state(x);
            }
        }
        self.candidates.sort_unstable();
        self.candidates.dedup();
    }
}

/// The values of two increasing lists, increasing, each once.
fn sorted_union<'a>(a: &'a [usize], b: &'a [usize]) -> impl Iterator<Item = usize> + 'a {
    let (mut a, mut b) = (a.iter().copied().peekable(), b.iter().copied().peekable());
    std::iter::from_fn(move || match (a.peek(), b.peek()) {
        (Some(&x), Some(&y)) if x == y => {
            b.next();
            a.next()
        }
        (Some(&x), Some(&y)) if y < x => b.next(),
        (Some(_), _) => a.next(),
        (None, _) => b.next(),
    })
}

/// The current position of node `k` of `reference` at the displacements `u`.
fn position_of(reference: &[[f64; 3]], u: &[f64], k: u32) -> [f64; 3] {
    let p = reference[k as usize];
    std::array::from_fn(|a| p[a] + u[3 * k as usize + a])
}

/// Whether step `step` has set every node of face `f` (`stamp`: the step that last set
/// each node).
fn present(stamp: &[u32], step: u32, f: &[u32; 4]) -> bool {
    f.iter().all(|&k| stamp[k as usize] == step)
}

/// Every rank's boxes of secondary and primary-face nodes (12 values per surface interface)
/// and the search's reach.
struct Boxes {
    all: Vec<Vec<f64>>,
    reach: f64,
}

impl Boxes {
    /// Rank `q`'s box of secondary nodes of surface interface `j`.
    fn secondary(&self, q: usize, j: usize) -> &[f64] {
        &self.all[q][12 * j..12 * j + 6]
    }

    /// Rank `q`'s box of primary-face nodes of surface interface `j`.
    fn faces(&self, q: usize, j: usize) -> &[f64] {
        &self.all[q][12 * j + 6..12 * j + 12]
    }

    /// Whether `p` lies within reach of box `b`.
    fn holds(&self, b: &[f64], p: [f64; 3]) -> bool {
        (0..3).all(|a| p[a] >= b[a] - self.reach && p[a] <= b[3 + a] + self.reach)
    }

    /// Whether rank `from`'s face nodes may reach rank `to`'s secondary nodes.
    fn sends(&self, from: usize, to: usize, surfaces: usize) -> bool {
        (0..surfaces).any(|j| {
            let (f, s) = (self.faces(from, j), self.secondary(to, j));
            (0..3).all(|a| f[a] <= s[3 + a] + self.reach && f[3 + a] >= s[a] - self.reach)
        })
    }

    /// The ranks `rank` exchanges face nodes with: those it may send to or receive from.
    /// Both sides of a pair find it from the same boxes.
    fn pairs(&self, rank: usize, surfaces: usize) -> Vec<usize> {
        (0..self.all.len())
            .filter(|&q| q != rank)
            .filter(|&q| self.sends(rank, q, surfaces) || self.sends(q, rank, surfaces))
            .collect()
    }
}

/// Every rank's `mine`, of any length, in rank order, on every rank (the lengths first).
fn gather(talk: &Timed, mine: &[f64]) -> Vec<f64> {
    talk.talk(|r| r.gather_varied(mine)).1
}

/// Sends `out[i]` to rank `pairs[i]`, their lengths first, and returns what each sent back.
fn swap(talk: &Timed, pairs: &[usize], out: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let counts: Vec<Vec<f64>> = out.iter().map(|d| vec![d.len() as f64]).collect();
    let mut got = vec![vec![0.0]; pairs.len()];
    exchange(talk, pairs, &counts, &mut got);
    let mut data: Vec<Vec<f64>> = got.iter().map(|c| vec![0.0; c[0] as usize]).collect();
    exchange(talk, pairs, out, &mut data);
    data
}

/// Sends `out[i]` to rank `pairs[i]` and receives its message into `into[i]` (sized).
fn exchange(talk: &Timed, pairs: &[usize], out: &[Vec<f64>], into: &mut [Vec<f64>]) {
    let sends: Vec<(usize, &[f64])> = pairs
        .iter()
        .zip(out)
        .map(|(&q, d)| (q, d.as_slice()))
        .collect();
    let mut recvs: Vec<(usize, &mut [f64])> = pairs
        .iter()
        .zip(into.iter_mut())
        .map(|(&q, d)| (q, d.as_mut_slice()))
        .collect();
    talk.talk(|r| r.exchange(&sends, &mut recvs));
}

/// Values per contact point.
const POINT: usize = 8;

/// A contact point as values (the face number is exact in an f64).
fn pack(p: &ContactPoint) -> [f64; POINT] {
    let (xi, n) = (p.xi, p.normal);
    [
        p.face as f64,
        xi[0],
        xi[1],
        n[0],
        n[1],
        n[2],
        p.gap,
        p.gap_rate,
    ]
}

fn unpack(x: &[f64]) -> ContactPoint {
    ContactPoint {
        face: x[0] as u32,
        xi: [x[1], x[2]],
        normal: [x[3], x[4], x[5]],
        gap: x[6],
        gap_rate: x[7],
    }
}
