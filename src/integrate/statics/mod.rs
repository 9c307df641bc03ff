//! Static steps (`method = "static"`, a deck's `*STATIC`): the model's equilibrium without
//! inertia at a sequence of load levels, the scene's time being the load's pseudo-time.
//!
//! **Increments.** Each step of `time_step` moves the loads, gravity's share of them and the
//! prescribed displacements to their values at the step's end and solves
//! $K u + f_c(u) + S (u - u_n) = f_{ext}$ by Newton's method on the free dofs, the contact
//! rows' stiffness in the matrix ([`contact`]). A step whose iteration does not settle is
//! taken again in halves, down to `minimum_step`; below it the run fails, with the time.
//!
//! **Stabilisation.** A body held only by contact (an impactor resting on a plate, a coupon
//! on its support) has rigid motions K does not resist before the contact closes, and
//! sideways ones no frictionless contact resists. $S = s\, \mathrm{diag}(K)$ holds every dof
//! to where the step started with a spring of `stabilisation` (1e-6 by default) times the
//! dof's own stiffness. Those springs are not small beside a bending load: a slender
//! cantilever's tip load is a small fraction of $\mathrm{diag}(K)\, u$, and the springs of
//! a single increment held 6% of it. So once the iteration settles, the springs are relaxed:
//! their anchors move to the solution and it settles again, until they pull no more than the
//! residual's tolerance ([`StaticSolver::settle_relaxed`]). An increment then ends in the
//! model's own equilibrium wherever it has one; the springs only steady the solves on the
//! way, and hold the modes nothing else holds. Where they cannot be relaxed (a body they
//! alone hold against a force), the energy they hold is counted as dissipated in the energy
//! balance (as Abaqus counts its stabilisation energy).
//!
//! **Energy.** External work (the loads' trapezoid, the prescribed dofs' reactions times
//! their motion) equals the strain energy plus the contact springs' and the stabilisation's
//! share: [`Energies::potential`] holds the last two less the external work.

mod contact;
mod friction;

use super::constraints::Constraints;
use crate::backend::Kernels;
use crate::error::{ImpactError, Result};
use crate::integrate::integrator::{Handover, ImplicitFigures, Integrator};
use crate::integrate::loads::{gravity_force, LoadForces};
use crate::integrate::state::{ContactReport, Energies, InterfaceEnd, StepReport};
use crate::integrate::SolverState;
use crate::linalg::{assemble, Assembled, Csc, FactorStats, SpdSolver};
use crate::model::Model;
use crate::scene::{MassKind, Method, Ordering, StaticSettings};
use contact::{ActiveSet, StaticContact};

/// The hard contact's penalty: this many times the secondary node's own stiffness over its
/// area. Each multiplier update then leaves about 1/(1 + factor) of the penetration.
const PENALTY_FACTOR: f64 = 100.0;
/// Newton iterations at one set of multipliers, and multiplier updates, per increment.
const MAX_NEWTON: usize = 30;
const MAX_UPDATES: usize = 40;
/// The residual's tolerance, relative to the largest nodal force.
const FORCE_TOLERANCE: f64 = 1e-9;
/// The stabilisation's springs are relaxed at most this many times in an increment, and
/// only while each relaxation leaves them pulling less than this fraction of the last.
const MAX_RELAXATIONS: usize = 100;
const RELAXED_SHRINK: f64 = 0.95;
/// A hard contact's penetration tolerance, relative to the largest displacement (and at
/// least this times 1e-6 of the largest face).
const GAP_TOLERANCE: f64 = 1e-6;

/// What a static run carries from one step to the next: the checkpoint's part.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct StaticState {
    pub time: f64,
    pub steps: usize,
    pub u: Vec<f64>,
    pub lambda: Vec<Vec<f64>>,
    pub load_work: f64,
    pub fix_work: f64,
    pub stabilised: f64,
    pub cutbacks: usize,
    /// Each interface's friction tractions at the last accepted increment, and the energy
    /// its friction took from the bodies (held by the stick slopes, or dissipated).
    pub tau: Vec<Vec<[f64; 3]>>,
    pub friction_loss: Vec<f64>,
    /// The energy dynamic steps before this one left in forms it does not hold (their
    /// kinetic energy, dropped where a static step begins; [`Integrator::take_over`]).
    #[serde(default)]
    pub carried: f64,
}

pub struct StaticSolver<'m> {
    model: &'m Model,
    kernels: Box<dyn Kernels + 'm>,
    settings: StaticSettings,
    asm: Assembled,
    dt: f64,
    state: StaticState,
    /// The displacement at the start of the increment being solved.
    u_start: Vec<f64>,
    /// The run's step count and time where this solver's stage starts.
    origin: (usize, f64),
    /// Where the stabilisation's springs are anchored: the increment's start, moved to the
    /// solution each time the springs are relaxed ([`StaticSolver::settle_relaxed`]).
    anchor: Vec<f64>,
    zero: Vec<f64>,
    f_ext: Vec<f64>,
    f_int: Vec<f64>,
    /// The force the prescribed dofs' supports apply (zero on the free dofs).
    support: Vec<f64>,
    loads: LoadForces,
    /// The stabilisation's spring on each free equation.
    spring: Vec<f64>,
    contact: StaticContact,
    /// The `[[equation]]`s on the free equations.
    constraints: Constraints,
    /// The factor of the last active set, and that set.
    factor: Option<(ActiveSet, SpdSolver)>,
    stats: FactorStats,
    clock: f64,
}

impl<'m> StaticSolver<'m> {
    pub fn new(
        model: &'m Model,
        settings: StaticSettings,
        dt: f64,
        kernels: Box<dyn Kernels + 'm>,
    ) -> Result<Self> {
        let asm = assemble(model, MassKind::Lumped, 0.0);
        let ndof = model.dofs();
        let diagonal = diagonal_of(&asm.effective);
        let spring = diagonal
            .iter()
            .map(|d| settings.stabilisation * d)
            .collect();
        let contact = StaticContact::new(model, &node_stiffness(&asm, &diagonal), PENALTY_FACTOR);
        let f_ext = gravity_force(model, &asm.nodal_mass);
        let loads = LoadForces::new(model, None, None, &f_ext);
        let lambda = contact.lambda.clone();
        let constraints = Constraints::new(&model.equations, &asm.equation, asm.dof_of.len());
        let mut solver = StaticSolver {
            model,
            kernels,
            settings,
            asm,
            dt,
            state: StaticState {
                time: 0.0,
                steps: 0,
                u: vec![0.0; ndof],
                lambda,
                load_work: 0.0,
                fix_work: 0.0,
                stabilised: 0.0,
                cutbacks: 0,
                tau: contact.friction.tau.clone(),
                friction_loss: vec![0.0; model.interfaces.len()],
                carried: 0.0,
            },
            u_start: vec![0.0; ndof],
            origin: (0, 0.0),
            anchor: vec![0.0; ndof],
            zero: vec![0.0; ndof],
            f_ext,
            f_int: vec![0.0; ndof],
            support: vec![0.0; ndof],
            loads,
            spring,
            contact,
            constraints,
            factor: None,
            stats: FactorStats::default(),
            clock: 0.0,
        };
        // the rows at t = 0: an overlap there (an interference fit) holds the energy of
        // its penalty springs from the start
        let margin = solver.contact.face_size;
        (solver.contact).broad_phase(model, &solver.u_start, margin);
        (solver.contact).kinematics(model, solver.kernels.as_mut(), &solver.zero, &solver.zero)?;
        Ok(solver)
    }

    /// The prescribed dofs' displacements at time `t1`, from `u_start` at `t0`: the moving
    /// fixes' and prescribed rigid bodies' velocity times t1, the displaced fixes' paths.
    fn prescribe(&mut self, (t0, t1): (f64, f64)) {
        for (d, w) in self.model.moving_dofs() {
            self.state.u[d] = w * t1;
        }
        for p in &self.model.fix_paths {
            for (&d, &value) in p.dofs.iter().zip(&p.value) {
                let d = d as usize;
                self.state.u[d] = p.at(value, (t0, t1), self.u_start[d]);
            }
        }
        self.constraints.apply(&mut self.state.u);
    }

    /// One increment to `t1` from the current state. Returns the Newton iterations, or
    /// `None` where the iteration did not settle (the state is then the caller's to restore).
    fn increment(&mut self, t1: f64) -> Result<Option<usize>> {
        self.loads.set(self.model, t1, &mut self.f_ext);
        self.u_start.clone_from(&self.state.u);
        self.anchor.clone_from(&self.state.u);
        self.prescribe((self.clock, t1));
        let moved = max_abs_difference(&self.state.u, &self.u_start);
        let margin = self.contact.face_size + 2.0 * moved;
        self.contact.broad_phase(self.model, &self.u_start, margin);
        let (model, u0) = (self.model, &self.u_start);
        (self.contact).kinematics(model, self.kernels.as_mut(), u0, &self.zero)?;
        let mut iterations = 0;
        for _ in 0..MAX_UPDATES {
            let Some(n) = self.settle_relaxed()? else {
                return Ok(None);
            };

            iterations += n;
            let size = self.state.u.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let tolerance = GAP_TOLERANCE * size.max(1e-6 * self.contact.face_size);
            if self.contact.hard_violation() <= tolerance {
                return Ok(Some(iterations));
            }
            self.contact.update_multipliers();
        }
        Ok(None)
    }

    /// Newton's iteration at the current multipliers: the number of solves, or `None` where
    /// it did not settle. Once the active set comes back to one it left (a cycle between
    /// sets, where a row's pressure sits near zero), each update is damped: halved until the
    /// residual is no larger than before it.
    fn settle(&mut self) -> Result<Option<usize>> {
        // the pressed rows the last solve had (each row keeps its face over an increment)
        let mut solved_with: Option<ActiveSet> = None;
        let mut seen: Vec<ActiveSet> = Vec::new();
        let mut cycling = false;
        for k in 0..MAX_NEWTON {
            let mut r = self.residual()?;
            let set = self.contact.active_set();
            let scale = self.force_scale();
            let largest = max_abs(&r);
            if solved_with.as_ref() == Some(&set) && largest <= FORCE_TOLERANCE * scale {
                return Ok(Some(k));
            }
            cycling |= solved_with.as_ref() != Some(&set) && seen.contains(&set);
            seen.push(set.clone());
            self.factorise(&set)?;
            let (_, solver) = self.factor.as_ref().expect("factorised just now");
            solver.solve_in_place(&mut r);
            self.stats.solves += 1;
            match cycling {
                true => self.damped_update(&r, largest)?,
                false => self.update(&r, 1.0),
            }
            solved_with = Some(set);
        }
        Ok(None)
    }

    /// `u` moved by `step` times the solved correction `du` (on the free equations), the
    /// dependent dofs set from the others.
    fn update(&mut self, du: &[f64], step: f64) {
        for (e, &d) in self.asm.dof_of.iter().enumerate() {
            self.state.u[d as usize] += step * du[e];
        }
        self.constraints.apply(&mut self.state.u);
    }

    /// The correction `du` taken whole where the residual (largest entry `before`) does not
    /// grow, else halved up to five times.
    fn damped_update(&mut self, du: &[f64], before: f64) -> Result<()> {
        let start = self.state.u.clone();
        let mut step = 1.0;
        for _ in 0..5 {
            self.update(du, step);
            if max_abs(&self.residual()?) <= before {
                return Ok(());
            }
            self.state.u.clone_from(&start);
            step *= 0.5;
        }
        self.update(du, step);
        Ok(())
    }

    /// The residual $f_{ext} - f_{int} - f_c - S(u - u_n)$ on the free equations, with the
    /// rows' gaps at the current state; keeps the supports' forces.
    fn residual(&mut self) -> Result<Vec<f64>> {
        let u = &self.state.u;
        self.kernels.internal_forces_into(u, &mut self.f_int)?;
        self.contact.linear_gaps(u, &self.u_start);
        let mut f = self.f_ext.clone();
        for (fi, x) in f.iter_mut().zip(&self.f_int) {
            *fi -= x;
        }
        self.contact.add_forces(&mut f);
        for (d, s) in self.support.iter_mut().enumerate() {
            *s = if self.model.fixed[d] { -f[d] } else { 0.0 };
        }
        let mut r: Vec<f64> = (self.asm.dof_of.iter().enumerate())
            .map(|(e, &d)| {
                let d = d as usize;
                f[d] - self.spring[e] * (u[d] - self.anchor[d])
            })
            .collect();
        self.constraints.condense_residual(&mut r);
        Ok(r)
    }

    /// The largest nodal force of the state: external, internal or support.
    fn force_scale(&self) -> f64 {
        let big = |x: &[f64]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        big(&self.f_ext)
            .max(big(&self.f_int))
            .max(f64::MIN_POSITIVE)
    }

    /// Factorises $K + S + \sum \epsilon A b b^T$ for the active set `set`, unless the last
    /// factor was of this set (and of the geometry it was made at: the rows' normals and
    /// weights move little within an increment, and the residual corrects them).
    fn factorise(&mut self, set: &[(u32, u32, [u32; 4])]) -> Result<()> {
        let same = self.factor.as_ref().is_some_and(|(s, _)| s == set);
        if same && self.contact.slopes_fixed() {
            return Ok(());
        }
        let k = &self.asm.effective;
        let mut t = Vec::with_capacity(k.nnz() + 81 * set.len());
        for j in 0..k.n {
            for p in k.col_ptr[j]..k.col_ptr[j + 1] {
                t.push((k.row_idx[p] as u32, j as u32, k.values[p]));
            }
            t.push((j as u32, j as u32, self.spring[j]));
        }
        self.contact.triplets(&self.asm.equation, &mut t);
        let a = Csc::from_triplets(k.n, self.constraints.condense(t));
        let start = std::time::Instant::now();
        let solver = SpdSolver::new(&a, Ordering::default()).map_err(|e| {
            ImpactError::Solver(format!(
                "the static stiffness at t = {:.6e} is not positive definite ({e}): a body is free to move where nothing holds it; raise [static] stabilisation or hold it with a [[fix]]",
                self.clock
            ))
        })?;
        self.stats.factorizations += 1;
        self.stats.factorization_seconds += start.elapsed().as_secs_f64();
        if let Some((_, old)) = &self.factor {
            let st = old.stats();
            self.stats.solve_seconds += st.solve_seconds;
            self.stats.analysis_seconds += st.analysis_seconds;
        }
        self.factor = Some((set.to_vec(), solver));
        Ok(())
    }

    /// The increment from `t0` to `t1` just solved, accepted: its work ([`Self::count_work`];
    /// `before`: the supports' forces at its start, `d0` the loads' dot products there), the
    /// friction's tractions committed and their work taken, the clock at `t1`.
    fn accept(&mut self, (t0, t1): (f64, f64), before: &[f64], d0: &[f64]) {
        self.count_work((t0, t1), before, d0);
        let work = self.contact.commit_friction();
        for (loss, w) in self.state.friction_loss.iter_mut().zip(work) {
            *loss -= w;
        }
        self.clock = t1;
    }

    /// The work of the increment just solved: the loads', the supports' and the
    /// stabilisation's (`before`: the supports' forces at its start).
    fn count_work(&mut self, (t0, t1): (f64, f64), before: &[f64], d0: &[f64]) {
        let (u, u0) = (&self.state.u, &self.u_start);
        let d1 = self.loads.dots(self.model, u);
        let stabilised = self.spring_energy();
        self.state.load_work += LoadForces::step_work(self.model, (t0, t1), (d0, &d1));
        let mut fix = 0.0;
        for (d, (&s0, &s1)) in before.iter().zip(&self.support).enumerate() {
            fix += 0.5 * (s0 + s1) * (u[d] - u0[d]);
        }
        self.state.fix_work += fix;
        self.state.stabilised += stabilised;
    }

    /// At a state put in from outside (a checkpoint's, another method's): the loads at its
    /// time, the increment's start and the springs' anchor there, and the contact rows and
    /// residual formed at it.
    fn settle_in(&mut self) -> Result<()> {
        self.loads.set(self.model, self.clock, &mut self.f_ext);
        self.u_start.clone_from(&self.state.u);
        self.anchor.clone_from(&self.state.u);
        let u = self.state.u.clone();
        self.contact
            .broad_phase(self.model, &u, self.contact.face_size);
        (self.contact).kinematics(self.model, self.kernels.as_mut(), &u, &self.zero)?;
        self.residual()?;
        Ok(())
    }

    /// The energy the stabilisation's springs hold: $\tfrac12 s (u - a)^2$ over the free
    /// dofs, `a` their anchor.
    fn spring_energy(&self) -> f64 {
        let (u, a) = (&self.state.u, &self.anchor);
        (self.asm.dof_of.iter().zip(&self.spring))
            .map(|(&d, &s)| 0.5 * s * (u[d as usize] - a[d as usize]).powi(2))
            .sum()
    }

    /// The largest force of a stabilisation spring.
    fn spring_pull(&self) -> f64 {
        let (u, a) = (&self.state.u, &self.anchor);
        (self.asm.dof_of.iter().zip(&self.spring))
            .map(|(&d, &s)| (s * (u[d as usize] - a[d as usize])).abs())
            .fold(0.0, f64::max)
    }

    /// [`Self::settle`], then the stabilisation's springs relaxed. Where the iteration
    /// settles with springs that still pull harder than the residual's tolerance, their
    /// anchors move to the solution and it settles again without their force, until they no
    /// longer pull: the increment ends in the equilibrium of the model alone, where it has
    /// one, and the springs hold no energy. They stop being relaxed where their pull no
    /// longer shrinks (a body they alone hold against a force), or after
    /// [`MAX_RELAXATIONS`]; what they hold then is the stabilisation's energy.
    fn settle_relaxed(&mut self) -> Result<Option<usize>> {
        let Some(mut solves) = self.settle()? else {
            return Ok(None);
        };
        let mut last = f64::INFINITY;
        for _ in 0..MAX_RELAXATIONS {
            let pull = self.spring_pull();
            if pull <= FORCE_TOLERANCE * self.force_scale() || pull > RELAXED_SHRINK * last {
                break;
            }
            last = pull;
            self.anchor.clone_from(&self.state.u);
            let Some(n) = self.settle()? else {
                return Ok(None);
            };
            solves += n;
        }
        Ok(Some(solves))
    }
}

impl Integrator for StaticSolver<'_> {
    fn model(&self) -> &Model {
        self.model
    }

    fn method(&self) -> Method {
        Method::Static
    }

    fn device_name(&self) -> String {
        self.kernels.device_name()
    }

    /// One step of `time_step`, in halves where an increment does not settle.
    fn step(&mut self) -> Result<StepReport> {
        let target = self.origin.1 + (self.state.steps + 1 - self.origin.0) as f64 * self.dt;
        let mut h = self.dt;
        let mut report = StepReport::default();
        while self.clock < target * (1.0 - 1e-12) {
            h = h.min(target - self.clock);
            let saved = (
                self.state.clone(),
                self.support.clone(),
                self.contact.lambda.clone(),
                self.contact.friction.tau.clone(),
            );
            let d0 = self.loads.dots(self.model, &self.state.u);
            let t1 = self.clock + h;
            match self.increment(t1)? {
                Some(n) => {
                    report.iterations += n;
                    self.accept((self.clock, t1), &saved.1, &d0);
                }
                None => {
                    (self.state, self.support, self.contact.lambda) = (saved.0, saved.1, saved.2);
                    self.contact.friction.tau = saved.3;
                    self.state.cutbacks += 1;
                    h *= 0.5;
                    if h < self.settings.minimum_step {
                        return Err(ImpactError::Solver(format!(
                            "the static increment from t = {:.6e} did not converge down to [static] minimum_step = {:.3e}",
                            self.clock, self.settings.minimum_step
                        )));
                    }
                }
            }
        }
        self.clock = target;
        self.state.steps += 1;
        self.state.time = target;
        report.converged = true;
        Ok(report)
    }

    fn energies(&mut self) -> Result<Energies> {
        let u = &self.state.u;
        self.kernels.internal_forces_into(u, &mut self.f_int)?;
        let strain = 0.5 * dot(u, &self.f_int);
        let external = self.state.load_work + self.state.fix_work;
        Ok(Energies {
            kinetic: 0.0,
            strain,
            potential: -dot(&self.f_ext, u)
                + self.loads.in_dot(self.model, self.clock, u)
                + self.contact.stored_energy()
                + self.state.friction_loss.iter().sum::<f64>()
                + self.state.stabilised
                + self.state.carried
                - external,
            damage: 0.0,
            plies: Default::default(),
            fix_work: self.state.fix_work,
            load_work: self.state.load_work,
        })
    }

    fn reports(&self) -> Vec<ContactReport> {
        let mut reports = self.contact.reports(self.model);
        for (k, r) in reports.iter_mut().enumerate() {
            // what the friction took and the stick slopes do not hold
            r.friction_work = self.state.friction_loss[k] - self.contact.stick_energy(k);
            // no inertia, no impacts (scene-format.md)
            r.impact_loss = f64::NAN;
        }
        reports
    }

    fn node_contact(&self, interface: usize, point: usize) -> (f64, f64) {
        self.contact.node_contact(interface, point)
    }

    fn time(&self) -> f64 {
        self.state.time
    }

    fn steps(&self) -> usize {
        self.state.steps
    }

    fn displacement(&self) -> &[f64] {
        &self.state.u
    }

    fn velocity(&self) -> &[f64] {
        &self.zero
    }

    fn nodal_mass(&self) -> &[f64] {
        &self.asm.nodal_mass
    }

    fn checkpoint_state(&mut self) -> Result<Option<SolverState>> {
        let mut s = self.state.clone();
        s.lambda.clone_from(&self.contact.lambda);
        s.tau.clone_from(&self.contact.friction.tau);
        Ok(Some(SolverState::Static(s)))
    }

    fn restore(&mut self, state: SolverState) -> std::result::Result<(), String> {
        let SolverState::Static(s) = state else {
            return Err(super::integrator::other_integrator());
        };
        super::state::check_restore(
            (s.u.len(), self.state.u.len()),
            (s.lambda.len(), self.contact.lambda.len()),
        )?;
        if s.tau.len() != self.contact.friction.tau.len() {
            return Err("the checkpoint's friction is of other interfaces".into());
        }
        self.contact.lambda.clone_from(&s.lambda);
        self.contact.friction.tau.clone_from(&s.tau);
        self.clock = s.time;
        self.state = s;
        self.settle_in().map_err(|e| e.to_string())
    }

    fn start_stage_at(&mut self, steps: usize, time: f64) {
        self.origin = (steps, time);
    }

    /// Goes on from a dynamic stage: its displacement (its velocity dropped: a static step
    /// starts at rest, the kinetic energy kept in the balance as carried), the work its fixes
    /// and loads did, and the total energy it ended at.
    fn take_over(&mut self, h: &Handover) -> Result<()> {
        (self.state.time, self.clock, self.state.steps) = (h.time, h.time, h.steps);
        self.state.u.copy_from_slice(&h.u);
        self.state.load_work = h.load_work;
        self.state.fix_work = h.fix_work;
        self.settle_in()?;
        self.state.carried = 0.0;
        self.state.carried = h.energy - self.energies()?.total();
        Ok(())
    }

    /// A step entered at its start may lower the friction: the tractions start on its cones.
    fn begin_step(&mut self) -> Result<()> {
        self.contact.fit_to_cones();
        Ok(())
    }

    fn reactions(&self) -> Vec<[f64; 3]> {
        (self.model.reactions.iter())
            .map(|r| {
                std::array::from_fn(|a| r.dofs[a].iter().map(|&d| self.support[d as usize]).sum())
            })
            .collect()
    }

    fn interface_ends(&self) -> Vec<InterfaceEnd> {
        vec![InterfaceEnd::default(); self.model.interfaces.len()]
    }

    /// The last factor's ordering and size, with every factorisation's and solve's count
    /// and time over the run; `event_steps` counts the increments cut back.
    fn implicit_figures(&self) -> Option<ImplicitFigures> {
        let mut linear_solver =
            (self.factor.as_ref()).map_or_else(FactorStats::default, |(_, f)| f.stats());
        linear_solver.factorizations = self.stats.factorizations;
        linear_solver.factorization_seconds = self.stats.factorization_seconds;
        linear_solver.solves = self.stats.solves;
        linear_solver.solve_seconds += self.stats.solve_seconds;
        linear_solver.analysis_seconds += self.stats.analysis_seconds;
        Some(ImplicitFigures {
            factorizations: self.stats.factorizations,
            linear_solver,
            mass_factor: None,
            event_steps: self.state.cutbacks,
            newton: None,
        })
    }
}

/// The diagonal of a matrix.
fn diagonal_of(a: &Csc) -> Vec<f64> {
    (0..a.n)
        .map(|j| {
            (a.col_ptr[j]..a.col_ptr[j + 1])
                .find(|&p| a.row_idx[p] == j)
                .map_or(0.0, |p| a.values[p])
        })
        .collect()
}

/// Each node's stiffness: the largest diagonal of its free dofs (the mean over the nodes
/// that have one, for a node held in every direction).
fn node_stiffness(asm: &Assembled, diagonal: &[f64]) -> Vec<f64> {
    let nodes = asm.equation.len() / 3;
    let mut k = vec![0.0f64; nodes];
    for (e, &d) in asm.dof_of.iter().enumerate() {
        let n = d as usize / 3;
        k[n] = k[n].max(diagonal[e]);
    }
    let held: Vec<f64> = k.iter().copied().filter(|&x| x > 0.0).collect();
    let mean = held.iter().sum::<f64>() / held.len().max(1) as f64;
    k.iter().map(|&x| if x > 0.0 { x } else { mean }).collect()
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

fn max_abs_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
