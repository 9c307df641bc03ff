//! Explicit central difference with lumped mass and velocity-level contact impulses.
//!
//! **Time discretisation** (central difference in its velocity-Verlet form, one internal
//! force evaluation per step):
//!
//! $v_{n+1/2}^* = v_n + \tfrac{\Delta t}{2} a_n$, contact impulses $J$ correct it to
//! $v_{n+1/2} = v_{n+1/2}^* + M^{-1} G J$, then $u_{n+1} = u_n + \Delta t\, v_{n+1/2}$,
//! $a_{n+1} = M^{-1}(f_{ext} - f_{int}(u_{n+1}))$ and
//! $v_{n+1} = v_{n+1/2} + \tfrac{\Delta t}{2} a_{n+1}$.
//!
//! **Contact** (in the spirit of the paper: a constraint on the gap *rate* of the step,
//! Carpenter, Taylor and Katona's forward increment): each secondary node's mid-step gap rate
//! must close at most its current gap over the step,
//! $g_n + \Delta t\, \dot g_{n+1/2} \le 0$, with $J_N \ge 0$ and complementarity. The normal,
//! the projection and $g_n$ come from the `contact_gap` kernel at $u_n$ (the same kinematics
//! as the implicit path); $\dot g$ is linear in the velocities, so the impulses are found by a
//! projected Jacobi iteration on the host. Its diagonal is the row-sum bound of the coupled
//! compliance, $\tilde C_{ii} = \sum_{node} w_{node} |g_{i,node}| \sum_j |g_{j,node}|$
//! (w the node's largest inverse mass, g the constraint's weight on the node: 1 on the
//! secondary node, $N_k$ on the face nodes), which bounds each row of C in absolute value
//! (Gershgorin), partly prescribed nodes included. So each sweep
//! is a projected-gradient step in a metric that majorises the compliance: the iteration
//! descends monotonically, and a lone constraint is solved in one sweep.
//! Coulomb friction takes the tangential impulse that stops the relative tangential
//! velocity and returns it onto the cone $|J_T| \le \mu J_N$ in the same sweep. The sweeps
//! start from the last step's impulses against a face or a rigid body that does not turn
//! (the warm start, applied to the velocities first), from zero elsewhere.
//!
//! Momentum is exact (every impulse acts with its opposite on the primary face's nodes by
//! the shape functions). The history's contact force is the impulse over the time it acts
//! ([`impulse_interval`]).

mod contact;
pub mod spin;

pub use contact::{
    plane_gap_within_reach, rigid_gap_within_reach, ContactFields, ExplicitContact,
    ExplicitInterface,
};

use crate::backend::Kernels;
use crate::element::ElementBlock;
use crate::error::Result;
use crate::kernels;
use crate::kernels::cohesive_forces::{cohesive_forces, CohesiveReport, CohesiveState};
use crate::material::damage::Dissipation;
use crate::model::cohesive::all_pairs;
use crate::model::Model;
use crate::scene::{ExplicitSettings, Method};
use crate::search;
use rayon::prelude::*;

use super::integrator::{Handover, Integrator};
use super::loads::LoadForces;
use super::state::{ContactReport, DamageReport, Energies, FirstDamage, StepReport};
use super::SolverState;

/// Everything an explicit run carries from one step to the next: the checkpoint's part.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ExplicitState {
    pub dt: f64,
    pub time: f64,
    pub steps: usize,
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
    pub f_int: Vec<f64>,
    pub u_prev: Vec<f64>,
    pub v_half: Vec<f64>,
    pub interfaces: Vec<ExplicitInterface>,
    /// The rigid bodies' rotation (none where no body rotates).
    #[serde(default)]
    pub spins: Vec<spin::BodySpin>,
    /// The plies' damage ([`Kernels::damage_values`]; none where nothing damages).
    #[serde(default)]
    pub damage: Vec<f64>,
    /// The work of the fixes that move, and what damage dissipated, so far.
    #[serde(default)]
    pub work: Work,
    /// The cohesive interfaces' damage and dissipation (none where there are none).
    #[serde(default)]
    pub cohesive: CohesiveState,
    /// What the elements' turns add to $\tfrac12 u_n \cdot f_{int}$ (corotational
    /// kinematics; [`Kernels::turn_energy`]).
    #[serde(default)]
    pub turn_energy: f64,
}

/// What a run's prescribed motion and damage have done so far: the work the moving
/// `[[fix]]`es did on the model, the energy damage dissipated, and the first damage.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Work {
    pub fixes: f64,
    pub damage: f64,
    /// Of `damage`, the fibre modes' share.
    #[serde(default)]
    pub damage_fibre: f64,
    /// The trapezoid sum of the `[[load]]`s' work ([`crate::integrate::loads`]).
    #[serde(default)]
    pub loads: f64,
    /// The energy the steps of another method before this one left in forms this one does
    /// not hold (their stabilisation's, their contact springs'), so that the history's total
    /// goes on where theirs ended ([`Integrator::take_over`]).
    #[serde(default)]
    pub carried: f64,
    pub first_damage: Option<crate::integrate::state::FirstDamage>,
}

impl Work {
    /// What the plies' damage dissipated so far, with the fibre modes' share.
    pub fn plies(&self) -> Dissipation {
        Dissipation {
            total: self.damage,
            fibre: self.damage_fibre,
        }
    }

    /// Counts a step's dissipation by the plies' damage.
    pub fn count_plies(&mut self, d: Dissipation) {
        self.damage += d.total;
        self.damage_fibre += d.fibre;
    }
}

pub struct ExplicitSolver<'m> {
    model: &'m Model,
    pub dt: f64,
    pub time: f64,
    pub steps: usize,
    kernels: Box<dyn Kernels + 'm>,
    /// Lumped nodal mass.
    mass: Vec<f64>,
    /// Inverse mass per dof, zero on prescribed dofs.
    inv_mass: Vec<f64>,
    f_ext: Vec<f64>,
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    /// Acceleration of the elastic and body forces at the current u.
    a: Vec<f64>,
    /// Internal forces at the current u.
    f_int: Vec<f64>,
    /// u_n and v_{n+1/2} of the last step (the time-centred energy).
    u_prev: Vec<f64>,
    v_half: Vec<f64>,
    /// The kernels' turn energy at `f_int` ([`Kernels::turn_energy`]).
    turn_energy: f64,
    /// What the time-centred energy measure shifts by over a shortened step (see
    /// [`Integrator::shorten_step`]); removed from the kinetic energy reported after it.
    measure_shift: f64,
    /// The time the step's contact impulses act over ([`impulse_interval`]).
    interval: f64,
    /// The rigid bodies' rotation.
    spins: spin::Spins,
    contact: ExplicitContact,
    work: Work,
    cohesive: CohesiveState,
    loads: LoadForces,
}

/// The nodal start of an explicit run from the lumped masses: the inverse mass and the
/// body force per dof (zero on prescribed dofs), the initial velocity (zero on prescribed
/// dofs) and the initial acceleration $M^{-1} f_{ext}$.
#[derive(Debug, Clone)]
pub(crate) struct NodalStart {
    pub inv_mass: Vec<f64>,
    pub f_ext: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
}

impl NodalStart {
    /// From each node's mass, the prescribed dofs, gravity and the initial velocity (3 per
    /// node each).
    pub fn new(mass: &[f64], fixed: &[bool], gravity: [f64; 3], v0: &[f64]) -> Self {
        let ndof = 3 * mass.len();
        let free = |d: usize, x: f64| if fixed[d] { 0.0 } else { x };
        let inv_mass: Vec<f64> = (0..ndof).map(|d| free(d, 1.0 / mass[d / 3])).collect();
        let f_ext: Vec<f64> = (0..ndof)
            .map(|d| free(d, mass[d / 3] * gravity[d % 3]))
            .collect();
        let v = (0..ndof).map(|d| free(d, v0[d])).collect();
        let a = (0..ndof).map(|d| f_ext[d] * inv_mass[d]).collect();
        NodalStart {
            inv_mass,
            f_ext,
            v,
            a,
        }
    }
}

impl NodalStart {
    /// With the loads at t = 0 in the external force and the acceleration.
    pub fn loaded(mut self, model: &Model, loads: &LoadForces) -> Self {
        loads.set(model, 0.0, &mut self.f_ext);
        for (d, a) in self.a.iter_mut().enumerate() {
            *a = self.f_ext[d] * self.inv_mass[d];
        }
        self
    }

    /// With the prescribed rigid bodies' dofs at their velocities (they keep them: their
    /// inverse mass is zero).
    pub fn moving(mut self, model: &Model) -> Self {
        for (d, w) in model.moving_dofs() {
            self.v[d] = w;
        }
        self
    }

    /// [`Self::moving`] for a start over the nodes `nodes` (increasing global numbers) only.
    pub fn moving_on(mut self, model: &Model, nodes: &[u32]) -> Self {
        for (d, w) in model.moving_dofs() {
            if let Ok(i) = nodes.binary_search(&((d / 3) as u32)) {
                self.v[3 * i + d % 3] = w;
            }
        }
        self
    }
}

impl<'m> ExplicitSolver<'m> {
    /// Lumps the mass and sets the initial state (u = 0, v = v0, a = M^-1 f_ext).
    pub fn new(
        model: &'m Model,
        settings: ExplicitSettings,
        dt: f64,
        speed_scale: f64,
        kernels: Box<dyn Kernels + 'm>,
    ) -> Result<Self> {
        let ndof = model.dofs();
        let mass = lumped_mass(model);
        let start = NodalStart::new(&mass, &model.fixed, model.gravity, &model.initial_velocity)
            .moving(model);
        let loads = LoadForces::new(model, None, None, &start.f_ext);
        let start = start.loaded(model, &loads);
        let face_size = search::largest_face_size(model);
        let contact = ExplicitContact::new(model, &settings, speed_scale, face_size);
        Ok(ExplicitSolver {
            model,
            dt,
            time: 0.0,
            steps: 0,
            kernels,
            mass,
            inv_mass: start.inv_mass,
            f_ext: start.f_ext,
            u: vec![0.0; ndof],
            // v_{-1/2} := v_0, so that the first step's energy starts from the initial one
            v_half: start.v.clone(),
            v: start.v,
            a: start.a,
            f_int: vec![0.0; ndof],
            u_prev: vec![0.0; ndof],
            turn_energy: 0.0,
            measure_shift: 0.0,
            interval: dt,
            spins: spin::Spins::new(model),
            contact,
            work: Work::default(),
            cohesive: CohesiveState::new(all_pairs(&model.cohesive)),
            loads,
        })
    }

    /// The state a checkpoint keeps.
    pub fn state(&self) -> ExplicitState {
        ExplicitState {
            dt: self.dt,
            time: self.time,
            steps: self.steps,
            u: self.u.clone(),
            v: self.v.clone(),
            a: self.a.clone(),
            f_int: self.f_int.clone(),
            u_prev: self.u_prev.clone(),
            v_half: self.v_half.clone(),
            interfaces: self.contact.interfaces.clone(),
            spins: self.spins.saved(),
            damage: self.kernels.damage_values().unwrap_or_default(),
            work: self.work.clone(),
            cohesive: self.cohesive.clone(),
            turn_energy: self.turn_energy,
        }
    }

    /// Continues from a checkpoint's state (of this model: the lengths must match).
    pub fn restore_state(&mut self, s: ExplicitState) -> std::result::Result<(), String> {
        super::state::check_restore(
            (s.u.len(), self.u.len()),
            (s.interfaces.len(), self.contact.interfaces.len()),
        )?;
        self.dt = s.dt;
        // checkpoints are taken at whole steps
        self.interval = s.dt;
        self.time = s.time;
        self.steps = s.steps;
        self.u = s.u;
        self.v = s.v;
        self.a = s.a;
        self.f_int = s.f_int;
        self.turn_energy = s.turn_energy;
        self.u_prev = s.u_prev;
        self.v_half = s.v_half;
        self.contact.restore(s.interfaces);
        self.spins.restore(s.spins);
        self.kernels.restore_damage(&s.damage)?;
        if !s.cohesive.fits(all_pairs(&self.model.cohesive)) {
            return Err("its cohesive interfaces are not this model's".into());
        }
        self.work = s.work;
        self.cohesive = s.cohesive;
        self.loads.set(self.model, self.time, &mut self.f_ext);
        Ok(())
    }

    /// Adds a step's dissipation, and finds the first damaged point once there is one.
    fn count_damage(&mut self, dissipated: Dissipation) {
        self.work.count_plies(dissipated);
        if self.work.first_damage.is_none() && dissipated.total > 0.0 {
            if let Some((_, Some(p))) = self.kernels.damage_cells() {
                // its step's time (a step of this run's length, or the shortened last one)
                let time = (f64::from(p.step) * self.dt).min(self.time);
                self.work.first_damage = Some(FirstDamage::of(self.model, p, time));
            }
        }
    }

    /// The potential of the external forces in the time-centred form: gravity's
    /// $-f_g \cdot (u_n + u_{n+1})/2$ less the loads' conserved work (see
    /// [`crate::integrate::loads`]).
    fn external_potential(&self) -> f64 {
        use crate::parallel::dot;
        let whole = -0.5 * (dot(&self.f_ext, &self.u_prev) + dot(&self.f_ext, &self.u));
        if self.loads.is_empty() {
            return whole;
        }
        let u = (&self.u_prev[..], &self.u[..]);
        whole + (self.loads).centred_potential(self.model, self.time, self.work.loads, u)
    }

    /// The step's contact impulses on the predicted velocities.
    fn contact(&mut self) -> Result<StepReport> {
        let margin = self
            .contact
            .margin(kernels::search_bounds::fastest_speed(&self.v), self.dt);
        let fields = ContactFields {
            u: &self.u,
            v: &mut self.v,
            v_half: &self.v_half,
            inv_mass: &self.inv_mass,
            interval: self.interval,
            planes: None,
            spins: self.spins.any().then_some(&mut self.spins),
        };
        self.contact
            .step(self.model, self.kernels.as_mut(), fields, self.dt, margin)
    }
}

impl Integrator for ExplicitSolver<'_> {
    fn model(&self) -> &Model {
        self.model
    }

    fn method(&self) -> Method {
        Method::Explicit
    }

    fn device_name(&self) -> String {
        self.kernels.device_name()
    }

    /// One step: predictor, contact impulses, position update, forces, corrector.
    fn step(&mut self) -> Result<StepReport> {
        let dt = self.dt;
        kernels::explicit_predict(dt, &self.a, &mut self.v);
        let state = (
            &self.mass[..],
            &self.f_int[..],
            &self.u[..],
            &self.u_prev[..],
        );
        let times = (self.time, dt);
        let work = drive_paths(self.model, times, state, &mut self.v, (Some, |_| true));
        self.work.fixes += work;
        let report = self.contact()?;
        self.u_prev.copy_from_slice(&self.u);
        self.v_half.copy_from_slice(&self.v);
        kernels::explicit_drift(dt, &self.v, &mut self.u);
        self.spins.drift(dt);
        self.work.fixes += dt * fix_power(self.model, &self.mass, &self.f_int);
        let u = (&self.u_prev[..], &self.u[..]);
        let times = (self.time, dt);
        self.work.loads += (self.loads).explicit_step(self.model, times, u, &mut self.f_ext);
        let uv = (&self.u[..], &self.v[..]);
        let dissipated = self.kernels.step_forces_into(uv, dt, &mut self.f_int)?;
        self.turn_energy = self.kernels.turn_energy();
        let cohesive = all_pairs(&self.model.cohesive);
        cohesive_forces(cohesive, &self.u, &mut self.cohesive, &mut self.f_int);
        let forces = (&self.f_ext[..], &self.f_int[..], &self.inv_mass[..]);
        correct(dt, forces, &mut self.a, &mut self.v);
        self.time += dt;
        self.steps += 1;
        self.count_damage(dissipated);
        Ok(report)
    }

    fn reactions(&self) -> Vec<[f64; 3]> {
        reactions(self.model, &self.mass, &self.f_int)
    }

    fn damage(&self) -> Option<DamageReport> {
        let (cells, _) = self.kernels.damage_cells()?;
        Some(DamageReport {
            energy: self.work.damage,
            fibre: self.work.damage_fibre,
            first: self.work.first_damage,
            cells,
        })
    }

    fn reports(&self) -> Vec<ContactReport> {
        (self.contact.interfaces.iter()).map(|i| i.report).collect()
    }

    fn cohesive(&self) -> Vec<CohesiveReport> {
        self.cohesive.reports(all_pairs(&self.model.cohesive))
    }

    fn cohesive_state(&self) -> Option<CohesiveState> {
        (!self.model.cohesive.is_empty()).then(|| self.cohesive.clone())
    }

    fn body_spins(&self) -> Vec<super::state::ProbeValues> {
        self.spins.columns()
    }

    fn node_contact(&self, interface: usize, point: usize) -> (f64, f64) {
        let st = &self.contact.interfaces[interface];
        let area = self.model.interfaces[interface].area[point];
        (st.impulse[point] / (self.interval * area), st.gap[point])
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

    fn checkpoint_state(&mut self) -> Result<Option<SolverState>> {
        Ok(Some(SolverState::Explicit(Box::new(self.state()))))
    }

    fn restore(&mut self, state: SolverState) -> std::result::Result<(), String> {
        match state {
            SolverState::Explicit(s) => self.restore_state(*s),
            _ => Err(super::integrator::other_integrator()),
        }
    }

    /// Goes on from a static or implicit stage: its displacement, the velocity it hands on
    /// (on the free dofs) or the run's initial one (its kinetic energy counted as the loads'
    /// work), the internal forces and acceleration there, and the total energy it ended at.
    fn take_over(&mut self, h: &Handover) -> Result<()> {
        self.time = h.time;
        self.steps = h.steps;
        self.u.copy_from_slice(&h.u);
        self.u_prev.copy_from_slice(&h.u);
        let given = h.velocity_into(&self.model.fixed, &self.mass, &mut self.v);
        self.v_half.copy_from_slice(&self.v);
        self.work.fixes = h.fix_work;
        self.work.loads = h.load_work + given;
        self.loads.set(self.model, self.time, &mut self.f_ext);
        self.kernels
            .internal_forces_into(&self.u, &mut self.f_int)?;
        self.turn_energy = self.kernels.turn_energy();
        for (d, a) in self.a.iter_mut().enumerate() {
            *a = (self.f_ext[d] - self.f_int[d]) * self.inv_mass[d];
        }
        self.work.carried = 0.0;
        self.work.carried = h.energy - self.energies()?.total();
        Ok(())
    }

    /// Makes the next step `dt` long (the shortened last step of a run that ends between
    /// whole steps).
    ///
    /// Central difference conserves the time-centred energy
    /// $E = \tfrac12 v_{n+1/2} M v_{n+1/2} + \tfrac12 u_n K u_{n+1} - f_{ext} \cdot (u_n + u_{n+1})/2$
    /// exactly for a constant step h. A step of h' instead moves that measure by
    /// $\tfrac18 (h^2 - h'^2)\, a_n \cdot M a_n$ without any change of the motion (with
    /// $M a_n = f_{ext} - K u_n$; `method-notes.md`); the energies reported after the step take
    /// that shift off, so the history's total energy stays the scheme's conserved quantity.
    fn shorten_step(&mut self, dt: f64) {
        let ama: f64 = self
            .a
            .iter()
            .enumerate()
            .map(|(d, a)| self.mass[d / 3] * a * a)
            .sum();
        self.measure_shift = 0.125 * (self.dt * self.dt - dt * dt) * ama;
        shift_half_step(&mut self.v_half, &self.a, (self.dt, dt));
        self.interval = impulse_interval(self.dt, Some(dt));
        self.dt = dt;
    }

    /// Energies of the last step in the time-centred form that central difference conserves
    /// exactly for linear elasticity: kinetic $\tfrac12 v_{n+1/2}^T M v_{n+1/2}$, strain
    /// $\tfrac12 u_n^T K u_{n+1}$, gravity $-f_{ext} \cdot (u_n + u_{n+1})/2$ (proof in
    /// `docs/method-notes.md`). So a rise of the total is a real error (the contact impulses
    /// can only remove energy), not the O(dt^2) wobble of the kinetic energy at whole steps.
    /// Before the first step: the initial state.
    fn energies(&mut self) -> Result<Energies> {
        use crate::parallel::{dot, ordered_sum};
        let mass = &self.mass;
        if self.steps == 0 {
            self.kernels
                .internal_forces_into(&self.u, &mut self.f_int)?;
            self.turn_energy = self.kernels.turn_energy();
            let v = &self.v;
            let kinetic =
                0.5 * ordered_sum(v.len(), |d| mass[d / 3] * v[d] * v[d]) + self.spins.kinetic();
            return Ok(Energies {
                kinetic,
                strain: 0.5 * dot(&self.u, &self.f_int) - self.turn_energy,
                potential: -dot(&self.f_ext, &self.u)
                    + self.loads.in_dot(self.model, self.time, &self.u),
                damage: 0.0,
                plies: Dissipation::default(),
                fix_work: 0.0,
                load_work: 0.0,
            });
        }
        let v = &self.v_half;
        let kinetic =
            0.5 * ordered_sum(v.len(), |d| mass[d / 3] * v[d] * v[d]) + self.spins.kinetic();
        let potential = self.external_potential() - self.contact.driver_work() - self.work.fixes
            + self.work.carried;
        Ok(Energies {
            kinetic: kinetic - self.measure_shift,
            // the pairs' friction springs store less than half their traction's work
            strain: 0.5 * dot(&self.u_prev, &self.f_int) - self.turn_energy
                + self.cohesive.stored_offset(),
            potential,
            damage: self.work.damage + self.cohesive.energy.iter().sum::<f64>(),
            plies: self.work.plies(),
            fix_work: self.work.fixes,
            load_work: self.work.loads,
        })
    }

    fn end_at(&mut self, time: f64) {
        self.time = time;
    }
}

/// The power of the moving `[[fix]]`es at internal forces `f_int`: over their dofs, the
/// reaction $f_{int} - m g$ times the dof's velocity. Central difference's energy identity
/// takes the step's work as this power at the step's start times the step.
pub(crate) fn fix_power(model: &Model, mass: &[f64], f_int: &[f64]) -> f64 {
    (model.fix_motion.iter())
        .map(|&(d, w)| (f_int[d] - mass[d / 3] * model.gravity[d % 3]) * w)
        .sum()
}

/// Sets the velocity in `v` of every dof a `[[fix]]` moves along a displacement, for the step
/// from `t` of `dt` ([`crate::model::FixPath::drive`]), and returns the work the fixes do over
/// it ([`path_work`]) on the dofs `counted`. `state` is the lumped mass, the internal forces
/// at $u_n$, $u_n$ and $u_{n-1}$, 3 per node in the holder's numbering, which `local` gives
/// for a model dof (the whole model's, or a rank's).
pub(crate) fn drive_paths(
    model: &Model,
    (t, dt): (f64, f64),
    (mass, f_int, u, u_prev): (&[f64], &[f64], &[f64], &[f64]),
    v: &mut [f64],
    (local, counted): (impl Fn(usize) -> Option<usize>, impl Fn(usize) -> bool),
) -> f64 {
    let mut work = 0.0;
    for p in &model.fix_paths {
        let each = |l: usize, old: f64, new: f64| {
            if counted(l) {
                let r = f_int[l] - mass[l / 3] * model.gravity[l % 3];
                let steps = (u[l] - u_prev[l], dt * new);
                work += path_work(r, mass[l / 3], (old, new), steps);
            }
        };
        p.drive((t, dt), u, v, &local, each);
    }
    work
}

/// The work a fix that moves a dof of mass `m` along a displacement's path does on the model
/// over a step that takes its velocity from `old` ($v_{n-1/2}$) to `new` ($v_{n+1/2}$), at the
/// reaction $r = f_{int}(u_n) - m g$: central difference's identity takes
/// $r\, (u_{n+1} - u_{n-1})/2$, from the last step's move $u_n - u_{n-1}$ and this one's
/// $u_{n+1} - u_n$ (`steps`; the two differ in length at a shortened last step), and the
/// support gives the dof its change of kinetic energy, $\tfrac12 m (v_{n+1/2}^2 - v_{n-1/2}^2)$.
fn path_work(reaction: f64, m: f64, (old, new): (f64, f64), steps: (f64, f64)) -> f64 {
    0.5 * reaction * (steps.0 + steps.1) + 0.5 * m * (new * new - old * old)
}

/// Each named `[[fix]]`'s reaction at internal forces `f_int`: over its held dofs of each
/// component, $\sum f_{int} - m g$ (the force the support applies to hold them); 0, not -0,
/// along a component it does not hold, as the ranks' sums give it.
pub(crate) fn reactions(model: &Model, mass: &[f64], f_int: &[f64]) -> Vec<[f64; 3]> {
    (model.reactions.iter())
        .map(|r| {
            std::array::from_fn(|a| {
                (r.dofs[a].iter())
                    .map(|&d| f_int[d as usize] - mass[d as usize / 3] * model.gravity[a])
                    .fold(0.0, |s, x| s + x)
            })
        })
        .collect()
}

/// The corrector, on all threads: $a = M^{-1}(f_{ext} - f_{int})$ and $v \mathrel{+}= \tfrac{\Delta t}{2} a$
/// from `(f_ext, f_int, inv_mass)`, per dof.
pub fn correct(
    dt: f64,
    (f_ext, f_int, inv_mass): (&[f64], &[f64], &[f64]),
    a: &mut [f64],
    v: &mut [f64],
) {
    a.par_iter_mut()
        .zip(v.par_iter_mut())
        .enumerate()
        .with_min_len(crate::parallel::CHUNK)
        .for_each(|(d, (a, v))| {
            *a = (f_ext[d] - f_int[d]) * inv_mass[d];
            *v += 0.5 * dt * *a;
        });
}

/// The lumped mass of every node: each element's corner masses on all threads, a block of
/// elements at a time, then summed to the nodes in element order (the same sums, bit for
/// bit, on any number of threads); then the rigid bodies' masses on their nodes.
pub(crate) fn lumped_mass(model: &Model) -> Vec<f64> {
    let mesh = &model.mesh;
    let mut mass = vec![0.0; mesh.node_count()];
    for block in &mesh.elements.blocks {
        scatter_block(block, &mut mass, |nodes, m| {
            let x = mesh.corners(nodes);
            block
                .kind
                .lumped_mass(&x, model.materials[m as usize].density)
        });
    }
    for (node, m) in model.point_masses() {
        mass[node as usize] += m;
    }
    mass
}

/// Adds each element's corner values `f(nodes, material)` to its nodes in `out`: the values
/// of a chunk of elements on all threads, then the sums in element order.
fn scatter_block(
    block: &ElementBlock,
    out: &mut [f64],
    f: impl Fn(&[u32], u32) -> Vec<f64> + Sync,
) {
    use rayon::prelude::*;
    const CHUNK: usize = 1 << 16;
    let n = block.kind.corners();
    let chunks = (block.nodes.chunks(CHUNK * n)).zip(block.material.chunks(CHUNK));
    for (els, mats) in chunks {
        let values: Vec<Vec<f64>> = (els.par_chunks(n).zip(mats))
            .map(|(e, &m)| f(e, m))
            .collect();
        for (e, v) in els.chunks(n).zip(&values) {
            for k in 0..n {
                out[e[k] as usize] += v[k];
            }
        }
    }
}

/// The time a step's contact impulses act over, by which the history divides them to give
/// forces: central difference changes the velocity at $t_n$ by the forces there over
/// $(h_{n-1} + h_n)/2$, so the step's own length `h`, but for a shortened last step (`last`,
/// after steps of `h`) the mean of the two. Divided by the shortened step alone, the last
/// row's force would rise by $(h + h')/(2 h')$: 15% where a run ends 0.77 of a step past
/// its last whole one.
pub fn impulse_interval(h: f64, last: Option<f64>) -> f64 {
    last.map_or(h, |l| 0.5 * (h + l))
}

/// The velocities before the contact's impulses as a step shortened from `h` to h' (`h2`) sees
/// them: $v_n - \tfrac12 h' a_n = v_{n-1/2} + \tfrac12 (h - h') a_n$ (the device's
/// $v^* - h' a_n$), against which the impulses' share of the energy is measured.
pub(crate) fn shift_half_step(v_half: &mut [f64], a: &[f64], (h, h2): (f64, f64)) {
    for (v, a) in v_half.iter_mut().zip(a) {
        *v += 0.5 * (h - h2) * a;
    }
}
