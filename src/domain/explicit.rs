//! The explicit step on one rank of a decomposed run: the single-process step
//! ([`crate::integrate::ExplicitSolver`]) on the rank's own elements and nodes, with the
//! shared nodes' forces summed from the neighbours' corners, and the contact of
//! [`super::contact`].
//!
//! Every node a rank holds follows the same operations as in a single process, so the
//! state (displacements, velocities, accelerations, contact impulses) is the same bits on any
//! number of ranks. The history's sums (energies, body velocities) add each rank's owned
//! nodes and then the ranks in order: the same bits as one process on one rank, within
//! rounding (1e-12 relative to the column) on several.

use super::checkpoint;
use super::cohesive::RankCohesive;
use super::contact::{LocalState, SurfaceContact};
use super::forces::RankForces;
use super::partition::Partition;
use super::ranks::{agree, Ranks, Timed};
use super::subdomain::Subdomain;
use crate::error::{ImpactError, Result};
use crate::gpu::GpuContext;
use crate::integrate::explicit::{
    correct, drive_paths, lumped_mass, ExplicitState, NodalStart, Work,
};
use crate::integrate::loads::LoadForces;
use crate::integrate::state::check_restore;
use crate::integrate::{
    ContactReport, Decomposed, Decomposition, Energies, Integrator, Piece, ProbeValues,
    SolverState, StepReport,
};
use crate::kernels::damage_data::{DamageData, DamageState};
use crate::kernels::{self, search_bounds::fastest_speed};
use crate::material::damage::Dissipation;
use crate::model::Model;
use crate::parallel::ordered_sum;
use crate::scene::{ExplicitSettings, Method};

/// What the rank's solver reports of its decomposition.
#[derive(Debug, Clone, Default)]
pub struct RankFigures {
    pub elements: usize,
    pub nodes: usize,
    pub shared_nodes: usize,
    pub neighbours: usize,
    /// Seconds spent in exchanges and collectives (waiting included).
    pub communication: f64,
    /// Seconds spent in the steps' contact, its exchanges included.
    pub contact: f64,
    /// Primary-face node states received from other ranks for the contact search, over the
    /// run.
    pub face_nodes_received: usize,
}

/// Sends each neighbour its corners (`sends`, in the order of `sub.neighbours`) and
/// receives theirs into `received` (3 per corner, each neighbour's at its
/// [`super::subdomain::Neighbour::receive`] range).
pub(super) fn exchange_corners(
    talk: &Timed,
    sub: &Subdomain,
    sends: &[Vec<f64>],
    received: &mut [f64],
) {
    let send_list: Vec<(usize, &[f64])> = (sub.neighbours.iter())
        .zip(sends)
        .map(|(nb, s)| (nb.rank, s.as_slice()))
        .collect();
    let mut recv_list = Vec::with_capacity(sub.neighbours.len());
    let mut rest = received;
    for nb in &sub.neighbours {
        let (mine, after) = rest.split_at_mut(3 * nb.receive.len());
        recv_list.push((nb.rank, mine));
        rest = after;
    }
    talk.talk(|r| r.exchange(&send_list, &mut recv_list));
}

/// One rank's explicit solver.
pub struct DomainSolver<'m> {
    model: &'m Model,
    ranks: &'m dyn Ranks,
    sub: Subdomain,
    kernels: RankForces,
    dt: f64,
    time: f64,
    steps: usize,
    /// Every node's lumped mass (the whole model's, as the setup has it).
    mass_all: Vec<f64>,
    mass: Vec<f64>,
    inv_mass: Vec<f64>,
    f_ext: Vec<f64>,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    f_int: Vec<f64>,
    u_prev: Vec<f64>,
    v_half: Vec<f64>,
    measure_shift: f64,
    /// The time the step's contact impulses act over
    /// ([`crate::integrate::explicit::impulse_interval`]).
    interval: f64,
    surface: SurfaceContact,
    received: Vec<f64>,
    /// The rank's part of the model, for its pieces of the frames.
    piece: Model,
    communication: std::cell::Cell<f64>,
    contact_seconds: f64,
    /// The moving `[[fix]]` dofs the rank owns (local dof, velocity), and the work they did
    /// so far (this rank's part).
    moving_fixes: Vec<(usize, f64)>,
    fix_work: f64,
    /// The damage of the whole model and the rank's elements' numbers in it, where any
    /// element damages, and the energy the rank's elements dissipated so far.
    damage: Option<RankDamage>,
    damage_energy: Dissipation,
    /// The `[[load]]`s on the rank's nodes, and the work of those on its owned nodes so far.
    loads: LoadForces,
    load_work: f64,
    /// The cohesive pairs at the rank's nodes, where the model has any.
    cohesive: Option<RankCohesive>,
    /// The rank's elements' turn energy at `f_int` (corotational kinematics; on every rank
    /// but the first 0 until the first forces after a restore, which counts it once).
    turn_energy: f64,
}

/// The whole model's damage inputs, the rank's, and the rank's damageable elements'
/// numbers among the whole model's (per block).
struct RankDamage {
    global: DamageData,
    mine: DamageData,
    picked: Vec<Vec<u32>>,
}

impl<'m> DomainSolver<'m> {
    /// Rank `ranks.rank()`'s part of `model` under `partition`, its element forces on `ctx`
    /// (the rank's GPU) or on the CPU, turned with the elements where `corotational`.
    pub fn new(
        model: &'m Model,
        ranks: &'m dyn Ranks,
        partition: &Partition,
        (settings, dt, speed_scale): (&ExplicitSettings, f64, f64),
        (ctx, damage, corotational): (Option<GpuContext>, Option<&DamageData>, bool),
    ) -> Result<Self> {
        let mut sub = Subdomain::new(model, partition, ranks.rank());
        let damage = damage.map(|global| {
            let counts = crate::kernels::damage_data::block_counts(&model.mesh.elements);
            let (mine, picked) = global.select(&counts, &sub.elements);
            RankDamage {
                global: global.clone(),
                mine,
                picked,
            }
        });
        let own = damage.as_ref().map(|d| d.mine.clone());
        // a rank whose kernels fail stops every rank (none waits for it)
        let kernels = agree(ranks, RankForces::new(&mut sub, ctx, (own, corotational)))
            .map_err(|why| ImpactError::Gpu(format!("building the kernels: {why}")))?;
        let mass_all = lumped_mass(model);
        let mass: Vec<f64> = sub.nodes.iter().map(|&n| mass_all[n as usize]).collect();
        let fixed = sub.restrict(&model.fixed);
        let start = NodalStart::new(
            &mass,
            &fixed,
            model.gravity,
            &sub.restrict(&model.initial_velocity),
        )
        .moving_on(model, &sub.nodes);
        let loads = LoadForces::new(model, Some(&sub.nodes), Some(&sub.owned), &start.f_ext);
        let start = start.loaded(model, &loads);
        let surface = SurfaceContact::new(model, &sub, &mass_all, (settings, speed_scale));
        let ndof = 3 * sub.nodes.len();
        let piece = sub.piece_model(model);
        let cohesive = RankCohesive::new(model, &sub);
        let moving_fixes = (model.fix_motion.iter())
            .filter_map(|&(d, w)| {
                let i = sub.nodes.binary_search(&((d / 3) as u32)).ok()?;
                sub.owned[i].then_some((3 * i + d % 3, w))
            })
            .collect();
        Ok(DomainSolver {
            model,
            ranks,
            kernels,
            received: vec![0.0; 3 * sub.received],
            sub,
            dt,
            interval: dt,
            time: 0.0,
            steps: 0,
            mass,
            inv_mass: start.inv_mass,
            f_ext: start.f_ext,
            u: vec![0.0; ndof],
            v_half: start.v.clone(),
            v: start.v,
            a: start.a,
            f_int: vec![0.0; ndof],
            u_prev: vec![0.0; ndof],
            measure_shift: 0.0,
            surface,
            piece,
            mass_all,
            communication: std::cell::Cell::new(0.0),
            contact_seconds: 0.0,
            moving_fixes,
            fix_work: 0.0,
            damage,
            damage_energy: Dissipation::default(),
            loads,
            load_work: 0.0,
            turn_energy: 0.0,
            cohesive,
        })
    }

    /// The power of the moving fixes the rank owns at its internal forces (see
    /// [`crate::integrate::explicit::fix_power`]).
    fn fix_power(&self) -> f64 {
        let g = self.model.gravity;
        (self.moving_fixes.iter())
            .map(|&(d, w)| (self.f_int[d] - self.mass[d / 3] * g[d % 3]) * w)
            .sum()
    }

    /// The rank's dof of model dof `d`, where the rank holds its node.
    fn local_dof(&self, d: usize) -> Option<usize> {
        let i = self.sub.nodes.binary_search(&((d / 3) as u32)).ok()?;
        Some(3 * i + d % 3)
    }

    /// The rank's share and its time in communication so far.
    pub fn figures(&self) -> RankFigures {
        RankFigures {
            elements: self.sub.data.elements.count(),
            nodes: self.sub.nodes.len(),
            shared_nodes: self.sub.shared.len(),
            neighbours: self.sub.neighbours.len(),
            communication: self.communication.get(),
            contact: self.contact_seconds,
            face_nodes_received: self.surface.received,
        }
    }

    /// `f` on the ranks, its time counted as communication.
    fn talk<T>(&self, f: impl FnOnce(&dyn Ranks) -> T) -> T {
        self.timed().talk(f)
    }

    /// The ranks with the rank's communication clock.
    fn timed(&self) -> Timed<'_> {
        Timed {
            ranks: self.ranks,
            seconds: &self.communication,
        }
    }

    /// The rank's internal forces: its elements', then the shared nodes' sums with the
    /// corners the neighbours send.
    fn internal_forces(&mut self) -> Result<()> {
        self.kernels.internal_forces(&self.u, &mut self.f_int)?;
        self.turn_energy = self.kernels.turn_energy();
        self.sum_shared();
        Ok(())
    }

    /// [`Self::internal_forces`] of an explicit step: the damage stepped over it first, the
    /// cohesive pairs after the shared nodes' sums (as the single process adds them after
    /// its gather).
    fn step_forces(&mut self) -> Result<()> {
        let uv = (&self.u[..], &self.v[..]);
        self.damage_energy += self.kernels.step_forces(uv, self.dt, &mut self.f_int)?;
        self.turn_energy = self.kernels.turn_energy();
        self.sum_shared();
        if let Some(c) = &mut self.cohesive {
            c.forces(&self.u, &mut self.f_int);
        }
        Ok(())
    }

    /// The shared nodes' forces: the rank's corners and those the neighbours send.
    fn sum_shared(&mut self) {
        if self.sub.neighbours.is_empty() {
            return;
        }
        let sends = self.kernels.sends(&self.sub);
        let talk = Timed {
            ranks: self.ranks,
            seconds: &self.communication,
        };
        exchange_corners(&talk, &self.sub, &sends, &mut self.received);
        (self.kernels).sum_shared(&self.sub, &self.received, &mut self.f_int);
    }

    /// The step's contact ([`SurfaceContact`]), its impulses on the rank's velocities.
    fn contact(&mut self) -> Result<StepReport> {
        if self.model.interfaces.is_empty() {
            return Ok(StepReport {
                iterations: 0,
                converged: true,
            });
        }
        let local_speed = fastest_speed(&self.v);
        let speed = self.talk(|r| r.max(local_speed));
        // from the fields, not `self.timed()`: the surface and the velocities change below
        let talk = Timed {
            ranks: self.ranks,
            seconds: &self.communication,
        };
        let local = LocalState {
            u: &self.u,
            v: &mut self.v,
            v_half: &self.v_half,
        };
        self.surface
            .step(&talk, local, (self.dt, self.interval), speed)
    }

    /// Sums over the rank's owned dofs of `f(d)` for each column, then over the ranks.
    fn owned_sums<const K: usize>(&self, f: [&(dyn Fn(usize) -> f64 + Sync); K]) -> [f64; K] {
        let owned = &self.sub.owned;
        let n = 3 * self.sub.nodes.len();
        let local: [f64; K] =
            std::array::from_fn(|k| ordered_sum(n, |d| if owned[d / 3] { f[k](d) } else { 0.0 }));
        let total = self.talk(|r| r.sum(&local));
        std::array::from_fn(|k| total[k])
    }
}

impl DomainSolver<'_> {
    /// The whole model's damage state on rank 0 (empty elsewhere, and without damage): each
    /// rank's damageable elements' records gathered (a collective).
    fn gather_damage(&mut self) -> Result<Vec<f64>> {
        let Some(d) = &self.damage else {
            return Ok(Vec::new());
        };
        let (mine_data, picked) = (d.mine.clone(), d.picked.clone());
        let values = self.kernels.kernels().damage_values()?;
        let mut mine = DamageState::new(&mine_data);
        mine.restore(&mine_data, &values)
            .map_err(ImpactError::Ranks)?;
        let (ids, records) = mine.records(&mine_data, &picked);
        let ids = self.talk(|r| r.gather_varied_to_first(&ids));
        let records = self.talk(|r| r.gather_varied_to_first(&records));
        let (Some(ids), Some(records)) = (ids, records) else {
            return Ok(Vec::new());
        };
        let d = self.damage.as_ref().expect("damage");
        let mut global = DamageState::new(&d.global);
        global.steps = mine.steps;
        global.put_records(&d.global, &ids, &records);
        Ok(global.flat())
    }

    /// The rank's part of the whole model's damage state (`values`, a checkpoint's).
    fn restore_damage(&mut self, values: &[f64]) -> std::result::Result<(), String> {
        let Some(d) = &self.damage else {
            return match values.is_empty() {
                true => Ok(()),
                false => Err("the checkpoint holds ply damage and this model has none".into()),
            };
        };
        let mut global = DamageState::new(&d.global);
        global.restore(&d.global, values)?;
        let mine = global.pick(&d.global, &d.mine, &d.picked);
        self.kernels.kernels().restore_damage(&mine.flat())
    }

    /// [`Self::first_damage_now`] (the checkpoint's).
    fn first_damage(&mut self) -> Option<crate::integrate::state::FirstDamage> {
        self.first_damage_now()
    }

    /// The first damaged point over every rank (a collective; none without damage): the
    /// earliest step's, then the lowest element's.
    fn first_damage_now(&self) -> Option<crate::integrate::state::FirstDamage> {
        self.damage.as_ref()?;
        let mine = (self.kernels.damage_cells())
            .and_then(|(_, p)| p)
            .map(|p| {
                let global = f64::from(self.sub.elements[p.element]);
                [f64::from(p.step), global, f64::from(p.entry), p.mode as f64]
            })
            .unwrap_or([f64::INFINITY; 4]);
        let all = self.talk(|r| r.gather_all(&mine));
        let best = (all.iter())
            .filter(|r| r[0].is_finite())
            .min_by(|a, b| (a[0], a[1]).partial_cmp(&(b[0], b[1])).expect("finite"))?;
        let p = crate::kernels::damage_data::DamagedPoint {
            step: best[0] as u32,
            element: best[1] as usize,
            entry: best[2] as u32,
            mode: best[3] as usize,
        };
        let time = (best[0] * self.dt).min(self.time);
        Some(crate::integrate::state::FirstDamage::of(
            self.model, p, time,
        ))
    }
}

impl Integrator for DomainSolver<'_> {
    fn model(&self) -> &Model {
        self.model
    }

    fn method(&self) -> Method {
        Method::Explicit
    }

    fn device_name(&self) -> String {
        self.kernels.device_name()
    }

    fn engine(&self) -> &'static str {
        use crate::integrate::integrator::{ENGINE_RANKS, ENGINE_RANKS_GPU};
        match self.kernels {
            RankForces::Cpu(_) => ENGINE_RANKS,
            RankForces::Gpu { .. } => ENGINE_RANKS_GPU,
        }
    }

    /// The single-process step (see [`crate::integrate::ExplicitSolver`]) on the rank's
    /// nodes; the state is gathered for a frame on the steps the run writes one.
    fn step(&mut self) -> Result<StepReport> {
        let dt = self.dt;
        kernels::explicit_predict(dt, &self.a, &mut self.v);
        // the work of the fixes along displacements, on the rank's owned nodes
        let mut v = std::mem::take(&mut self.v);
        let state = (
            &self.mass[..],
            &self.f_int[..],
            &self.u[..],
            &self.u_prev[..],
        );
        let owned = |l: usize| self.sub.owned[l / 3];
        let dofs = (|d| self.local_dof(d), owned);
        let work = drive_paths(self.model, (self.time, dt), state, &mut v, dofs);
        self.v = v;
        self.fix_work += work;
        let clock = std::time::Instant::now();
        let report = self.contact()?;
        self.contact_seconds += clock.elapsed().as_secs_f64();
        self.u_prev.copy_from_slice(&self.u);
        self.v_half.copy_from_slice(&self.v);
        kernels::explicit_drift(dt, &self.v, &mut self.u);
        self.surface.drift_spins(dt);
        self.fix_work += dt * self.fix_power();
        let u = (&self.u_prev[..], &self.u[..]);
        let times = (self.time, dt);
        self.load_work += (self.loads).explicit_step(self.model, times, u, &mut self.f_ext);
        self.step_forces()?;
        let forces = (&self.f_ext[..], &self.f_int[..], &self.inv_mass[..]);
        correct(dt, forces, &mut self.a, &mut self.v);
        self.time += dt;
        self.steps += 1;
        Ok(report)
    }

    fn reports(&self) -> Vec<ContactReport> {
        (self.surface.contact().interfaces.iter())
            .map(|i| i.report)
            .collect()
    }

    fn node_contact(&self, interface: usize, point: usize) -> (f64, f64) {
        let st = &self.surface.contact().interfaces[interface];
        let area = self.model.interfaces[interface].area[point];
        (st.impulse[point] / (self.interval * area), st.gap[point])
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn steps(&self) -> usize {
        self.steps
    }

    /// The displacements of the rank's nodes.
    fn displacement(&self) -> &[f64] {
        &self.u
    }

    /// The velocities of the rank's nodes.
    fn velocity(&self) -> &[f64] {
        &self.v
    }

    fn decomposed(&self) -> Option<&dyn Decomposed> {
        Some(self)
    }

    fn decomposed_mut(&mut self) -> Option<&mut dyn Decomposed> {
        Some(self)
    }

    fn nodal_mass(&self) -> &[f64] {
        &self.mass_all
    }

    /// The probed nodes' values as their owners have them: each rank marks the probes it
    /// owns and gives their values; every rank takes each probe from its owner.
    fn probes(&self) -> Vec<ProbeValues> {
        let mut mine = vec![0.0; 7 * self.model.probes.len()];
        for (p, probe) in self.model.probes.iter().enumerate() {
            let Ok(i) = self.sub.nodes.binary_search(&probe.node) else {
                continue;
            };
            if self.sub.owned[i] {
                mine[7 * p] = 1.0;
                mine[7 * p + 1..7 * p + 4].copy_from_slice(&self.u[3 * i..3 * i + 3]);
                mine[7 * p + 4..7 * p + 7].copy_from_slice(&self.v[3 * i..3 * i + 3]);
            }
        }
        let all = self.talk(|r| r.gather_all(&mine));
        (0..self.model.probes.len())
            .map(|p| {
                let owner = all.iter().find(|r| r[7 * p] == 1.0).unwrap_or(&all[0]);
                let c = &owner[7 * p + 1..7 * p + 7];
                ([c[0], c[1], c[2]], [c[3], c[4], c[5]])
            })
            .collect()
    }

    /// Each body's mass and momentum over the rank's owned nodes, summed over the ranks.
    fn body_spins(&self) -> Vec<ProbeValues> {
        self.surface.spins().columns()
    }

    fn body_velocities(&self) -> Vec<[f64; 3]> {
        // each body's nodes on this rank: its range of the rank's part
        let bodies = &self.piece.mesh.bodies;
        let mut mine = vec![0.0; 4 * bodies.len()];
        for (b, body) in bodies.iter().enumerate() {
            let m = &mut mine[4 * b..4 * b + 4];
            for i in body.nodes.clone().filter(|&i| self.sub.owned[i]) {
                m[0] += self.mass[i];
                for a in 0..3 {
                    m[1 + a] += self.mass[i] * self.v[3 * i + a];
                }
            }
        }
        let all = self.talk(|r| r.sum(&mine));
        (all.chunks_exact(4))
            .map(|c| [c[1] / c[0], c[2] / c[0], c[3] / c[0]])
            .collect()
    }

    /// The single process's state at this step ([`super::checkpoint`]), on rank 0.
    fn checkpoint_state(&mut self) -> Result<Option<SolverState>> {
        let damage = self.gather_damage()?;
        let first_damage = self.first_damage();
        let cohesive = (self.cohesive.as_ref())
            .map(|c| c.gather(self.model, &self.timed()))
            .unwrap_or_default();
        let fields = [
            &self.u[..],
            &self.v,
            &self.a,
            &self.f_int,
            &self.u_prev,
            &self.v_half,
        ];
        let count = self.model.mesh.node_count();
        let d = self.damage_energy;
        let sums = self.talk(|r| {
            r.sum(&[
                self.fix_work,
                d.total,
                d.fibre,
                self.load_work,
                self.turn_energy,
            ])
        });
        let gathered = checkpoint::gather_fields(&self.timed(), &self.sub, fields, count)
            .map_err(ImpactError::Ranks)?;
        let Some([u, v, a, f_int, u_prev, v_half]) = gathered else {
            return Ok(None);
        };
        Ok(Some(SolverState::Explicit(Box::new(ExplicitState {
            dt: self.dt,
            time: self.time,
            steps: self.steps,
            u,
            v,
            a,
            f_int,
            u_prev,
            v_half,
            interfaces: self.surface.contact().interfaces.clone(),
            spins: self.surface.spins().saved(),
            damage,
            work: Work {
                fixes: sums[0],
                damage: sums[1],
                damage_fibre: sums[2],
                loads: sums[3],
                first_damage,
                // ranks run one method throughout
                carried: 0.0,
            },
            cohesive,
            turn_energy: sums[4],
        }))))
    }

    /// Continues from a single process's state (written on any number of ranks).
    fn restore(&mut self, state: SolverState) -> std::result::Result<(), String> {
        let SolverState::Explicit(s) = state else {
            return Err(crate::integrate::integrator::other_integrator());
        };
        let interfaces = self.surface.contact().interfaces.len();
        check_restore(
            (s.u.len(), 3 * self.model.mesh.node_count()),
            (s.interfaces.len(), interfaces),
        )?;
        let global = [&s.u[..], &s.v, &s.a, &s.f_int, &s.u_prev, &s.v_half];
        [self.u, self.v, self.a, self.f_int, self.u_prev, self.v_half] =
            checkpoint::restrict_fields(&self.sub, global);
        (self.dt, self.time, self.steps) = (s.dt, s.time, s.steps);
        // checkpoints are taken at whole steps
        self.interval = s.dt;
        self.surface.restore(s.interfaces, s.spins);
        // the work so far counted once, on the first rank
        let first = self.ranks.rank() == 0;
        self.fix_work = if first { s.work.fixes } else { 0.0 };
        self.damage_energy = match first {
            true => s.work.plies(),
            false => Dissipation::default(),
        };
        self.load_work = if first { s.work.loads } else { 0.0 };
        self.turn_energy = if first { s.turn_energy } else { 0.0 };
        self.loads.set(self.model, self.time, &mut self.f_ext);
        if let Some(c) = &mut self.cohesive {
            let pairs = crate::model::cohesive::all_pairs(&self.model.cohesive);
            if !s.cohesive.fits(pairs) {
                return Err("its cohesive interfaces are not this model's".into());
            }
            c.restore(&s.cohesive, first);
        }
        self.restore_damage(&s.damage)
    }

    /// See [`crate::integrate::ExplicitSolver`]'s: $a \cdot M a$ summed over the ranks.
    fn shorten_step(&mut self, dt: f64) {
        let (mass, a) = (&self.mass, &self.a);
        // summed in dof order, as the single process sums it
        let owned = &self.sub.owned;
        let mine: f64 = (a.iter().enumerate())
            .filter(|(d, _)| owned[d / 3])
            .map(|(d, a)| mass[d / 3] * a * a)
            .sum();
        let ama = self.talk(|r| r.sum(&[mine]))[0];
        self.measure_shift = 0.125 * (self.dt * self.dt - dt * dt) * ama;
        crate::integrate::explicit::shift_half_step(&mut self.v_half, &self.a, (self.dt, dt));
        self.interval = crate::integrate::explicit::impulse_interval(self.dt, Some(dt));
        self.dt = dt;
    }

    /// The time-centred energies of [`crate::integrate::ExplicitSolver`], each rank's owned
    /// dofs summed, then the ranks in order.
    fn energies(&mut self) -> Result<Energies> {
        // the rank's turn energy, on the first dof of its first owned node
        let first = self.sub.owned.iter().position(|&o| o).map(|i| 3 * i);
        if self.steps == 0 {
            self.internal_forces()?;
            let (m, v, u, f, fe) = (&self.mass, &self.v, &self.u, &self.f_int, &self.f_ext);
            let turn = self.turn_energy;
            let [k, s, p] = self.owned_sums([
                &|d| m[d / 3] * v[d] * v[d],
                &|d| u[d] * f[d] - if Some(d) == first { 2.0 * turn } else { 0.0 },
                &|d| fe[d] * u[d],
            ]);
            return Ok(Energies {
                kinetic: 0.5 * k + self.surface.spins().kinetic(),
                strain: 0.5 * s,
                // u = 0: the loads have no part in it yet
                potential: -p,
                damage: 0.0,
                plies: Dissipation::default(),
                fix_work: 0.0,
                load_work: 0.0,
            });
        }
        let (m, v, u0, u1, f, fe) = (
            &self.mass,
            &self.v_half,
            &self.u_prev,
            &self.u,
            &self.f_int,
            &self.f_ext,
        );
        // the fixes' work and the damage's energy there too
        let bonded = self.cohesive.as_ref().map_or(0.0, RankCohesive::energy);
        // the strain energy's terms beside 1/2 u f: the pairs' and the elements' turn
        let offset = self
            .cohesive
            .as_ref()
            .map_or(0.0, RankCohesive::stored_offset)
            - self.turn_energy;
        let plies = self.damage_energy;
        let (work, damage) = (self.fix_work, plies.total + bonded);
        let u = (&self.u_prev[..], &self.u[..]);
        let loads = (self.loads).centred_potential(self.model, self.time, self.load_work, u);
        let load_work = self.load_work;
        let [k, s, p0, p1, w, dmg, pt, pf, lp, lw] = self.owned_sums([
            &|d| m[d / 3] * v[d] * v[d],
            &|d| u0[d] * f[d] + if Some(d) == first { 2.0 * offset } else { 0.0 },
            &|d| fe[d] * u0[d],
            &|d| fe[d] * u1[d],
            &|d| if Some(d) == first { work } else { 0.0 },
            &|d| if Some(d) == first { damage } else { 0.0 },
            &|d| if Some(d) == first { plies.total } else { 0.0 },
            &|d| if Some(d) == first { plies.fibre } else { 0.0 },
            &|d| if Some(d) == first { loads } else { 0.0 },
            &|d| if Some(d) == first { load_work } else { 0.0 },
        ]);
        Ok(Energies {
            // the bodies' rotation as every rank has it, once
            kinetic: 0.5 * k - self.measure_shift + self.surface.spins().kinetic(),
            strain: 0.5 * s,
            // the prescribed rigid bodies' drivers work on the model (every rank has it whole)
            potential: -0.5 * (p0 + p1) + lp - self.surface.contact().driver_work() - w,
            damage: dmg,
            plies: Dissipation {
                total: pt,
                fibre: pf,
            },
            fix_work: w,
            load_work: lw,
        })
    }

    /// Each named fix's reaction: the rank's owned held dofs, summed over the ranks.
    fn reactions(&self) -> Vec<[f64; 3]> {
        if self.model.reactions.is_empty() {
            return Vec::new();
        }
        let g = self.model.gravity;
        let mut mine = Vec::with_capacity(3 * self.model.reactions.len());
        for r in &self.model.reactions {
            for (a, dofs) in r.dofs.iter().enumerate() {
                let sum: f64 = (dofs.iter())
                    .filter_map(|&d| {
                        let i = self.sub.nodes.binary_search(&(d / 3)).ok()?;
                        let l = 3 * i + a;
                        self.sub.owned[i].then(|| self.f_int[l] - self.mass[i] * g[a])
                    })
                    .sum();
                mine.push(sum);
            }
        }
        let all = self.talk(|r| r.sum(&mine));
        all.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
    }

    fn end_at(&mut self, time: f64) {
        self.time = time;
    }

    /// Each cohesive interface over every rank (a collective).
    fn cohesive(&self) -> Vec<crate::kernels::cohesive_forces::CohesiveReport> {
        (self.cohesive.as_ref()).map_or_else(Vec::new, |c| c.reports(&self.timed()))
    }

    /// The whole model's cohesive state, on every rank (a collective).
    fn cohesive_state(&self) -> Option<crate::kernels::cohesive_forces::CohesiveState> {
        (self.cohesive.as_ref()).map(|c| c.gather(self.model, &self.timed()))
    }

    /// The damage over every rank (a collective): the energy, the first damaged point and
    /// every element's damage.
    fn damage(&self) -> Option<crate::integrate::state::DamageReport> {
        self.damage.as_ref()?;
        let d = self.damage_energy;
        let sums = self.talk(|r| r.sum(&[d.total, d.fibre]));
        let first = self.first_damage_now();
        let mut mine = Vec::new();
        if let Some((cells, _)) = self.kernels.damage_cells() {
            for (&e, c) in self.sub.elements.iter().zip(&cells) {
                mine.push(f64::from(e));
                mine.extend_from_slice(c);
            }
        }
        let all = self.talk(|r| r.gather_all(&mine));
        let mut cells = vec![[0.0; 4]; self.model.mesh.element_count()];
        for r in &all {
            for c in r.chunks_exact(5) {
                cells[c[0] as usize] = [c[1], c[2], c[3], c[4]];
            }
        }
        Some(crate::integrate::state::DamageReport {
            energy: sums[0],
            fibre: sums[1],
            first,
            cells,
        })
    }
}

impl Decomposed for DomainSolver<'_> {
    fn piece(&self) -> Piece<'_> {
        Piece {
            model: &self.piece,
            u: &self.u,
            v: &self.v,
            nodes: &self.sub.nodes,
            elements: &self.sub.elements,
            damage: self.kernels.damage_cells().map(|(c, _)| c),
        }
    }

    fn gather_all(&self, mine: &[f64]) -> Vec<Vec<f64>> {
        self.talk(|r| r.gather_all(mine))
    }

    fn decomposition(&mut self) -> Decomposition {
        decomposition_of(self.ranks, &self.figures(), super::contact::DESCRIPTION)
    }
}

/// The decomposition of a run whose ranks each report `f` and share out the contact as
/// `contact` says (gathered: every rank calls it).
pub(super) fn decomposition_of(ranks: &dyn Ranks, f: &RankFigures, contact: &str) -> Decomposition {
    let mine = [
        f.elements as f64,
        f.nodes as f64,
        f.shared_nodes as f64,
        f.neighbours as f64,
        f.communication,
        f.face_nodes_received as f64,
        f.contact,
    ];
    let all = ranks.gather_all(&mine);
    let column = |k: usize| all.iter().map(|r| r[k] as usize).collect();
    Decomposition {
        ranks: ranks.size(),
        partition: super::partition::DESCRIPTION.into(),
        contact: contact.into(),
        elements: column(0),
        nodes: column(1),
        shared_nodes: column(2),
        neighbours: column(3),
        communication_seconds: all.iter().map(|r| r[4]).collect(),
        contact_seconds: all.iter().map(|r| r[6]).collect(),
        face_nodes_received: column(5),
    }
}
