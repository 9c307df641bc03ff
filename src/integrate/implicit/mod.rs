//! Implicit Newmark with the paper's adaptive augmented Lagrange contact iteration.
//!
//! **Time discretisation.** With $\tilde u = u_n + \Delta t\, v_n + \Delta t^2(\tfrac12 - \beta) a_n$
//! and $\tilde v = v_n + \Delta t (1-\gamma) a_n$, the step solves
//!
//! $(K + M/(\beta\Delta t^2))\, u_{n+1} = f_{ext} + M\tilde u/(\beta\Delta t^2) + \bar f_c / (2\beta)$
//!
//! where $\bar f_c$ is the contact force of the step, held constant over it (the impulse of the
//! step divided by $\Delta t$). Then $w = M^{-1}\bar f_c$,
//! $a_{n+1} = (u_{n+1} - \tilde u)/(\beta\Delta t^2) - w/(2\beta)$ (the acceleration of the
//! elastic and body forces) and $v_{n+1} = \tilde v + \gamma\Delta t\, a_{n+1} + \Delta t\, w$.
//! So the contact impulse is exactly $\Delta t\,\bar f_c$, and for the trapezoidal rule
//! $u_{n+1} - u_n = \tfrac{\Delta t}{2}(v_n + v_{n+1})$: the work of the contact force over a
//! step is $-\tfrac{\Delta t}{2}\sum_i T_i A_i (\dot g_{i,n} + \dot g_{i,n+1})$, which the gap-rate
//! constraint ($\dot g_{n+1} = 0$ wherever $T > 0$) makes zero in persistent contact and
//! negative at impact. It is positive only for a node that separates at the step's start
//! ($\dot g_n < 0$) and carries pressure in it, because the other body catches it up
//! (`docs/method-notes.md`, "Time discretisation of the contact force").
//!
//! **The classical comparison** (`constraint = "gap"`): the multiplier enforces the gap
//! $g_{n+1} = 0$ and the contact force acts at $t_{n+1}$ in Newmark's equilibrium
//! $M a_{n+1} + K u_{n+1} = f_{ext} + f_{c,n+1}$, as in the classical contact codes the paper
//! compares against; the reported force is then the step's impulse / dt,
//! $(1-\gamma) f_{c,n} + \gamma f_{c,n+1}$.
//!
//! **Rotating rigid bodies.** A rigid body that rotates keeps its orientation and angular
//! momentum beside the system (its translation is a node of it). Its angular impulse over
//! the step is $\Delta t$ times the moment of the step's contact forces, held constant as
//! the forces are: each iteration updates $L_{n+1} = L_n - \Delta t \sum_i r_i \times f_i$,
//! turns the body as the explicit path does ([`super::explicit::spin`]), and takes the
//! kinematics on the turned surface, whose points move at $v_b + \omega_{n+1} \times r$.
//!
//! **Iteration.** Each iteration solves with the current pressures (one triangular solve pair;
//! the effective matrix does not depend on the contact, so it is factorised once per run, and
//! once more for the sub-step at the first contact event: see [`ImplicitSolver::step`]),
//! computes the contact kinematics of the new state with the kernels, and updates the
//! pressures with [`augmented_lagrange::update`]. The residual is formed with the kernels'
//! internal forces, so a backend in f32 is corrected iteratively.

mod contact;
mod contact_space;
mod factors;
mod flexibility;
mod interface;
mod newton;
mod substeps;
mod workspace;

pub use interface::InterfaceState;

use crate::backend::Kernels;
use crate::error::{ImpactError, Result};
use crate::geometry::vector;
use crate::kernels::contact_gap::NO_FACE;
use crate::linalg::{assemble, Assembled, Csc, FactorStats, SpdSolver};
use crate::model::{Model, Primary};
use crate::scene::{Acceleration, ConstraintMeasure, ContactSpace, ImplicitSettings, Method};

use super::constraints::Constraints;
use super::explicit::spin::{BodySpin, Spins};
use super::integrator::{Handover, ImplicitFigures, Integrator, NewtonFigures};
use super::loads::{gravity_force, LoadForces};
use super::state::{ContactReport, Energies, InterfaceEnd, StepReport};
use super::SolverState;
use contact::MultiplierIteration;
pub(crate) use factors::FactorPlan;
use flexibility::Flexibility;
use interface::interface_states;
use workspace::Workspace;

/// Forces below this fraction of an interface's peak normal force so far do not make a
/// contact event (round-off forces of a grazing contact would otherwise refine every step).
pub(crate) const EVENT_FORCE_FLOOR: f64 = 1e-3;

/// The contact iteration's tolerance is at least this many times the kernels' unit roundoff
/// (3.6e-6 for f32 kernels; no effect in f64).
pub(crate) const KERNEL_NOISE_FACTOR: f64 = 30.0;

/// The state a step starts from, kept so that a step found to hold a contact event can be
/// taken again in sub-steps.
struct Snapshot {
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    interfaces: Vec<InterfaceState>,
    spins: Spins,
    load_work: f64,
}

/// Everything an implicit run carries from one step to the next: the checkpoint's part.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ImplicitState {
    pub time: f64,
    pub steps: usize,
    pub event_steps: usize,
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
    pub interfaces: Vec<InterfaceState>,
    /// The rotating rigid bodies' orientations and momenta (none without them).
    pub spins: Vec<BodySpin>,
    /// The nodes of the Newton step's flexibilities, of the step and of the sub-step, in the
    /// order they joined (`acceleration = "newton"`).
    #[serde(default)]
    pub flexibility_nodes: [Vec<u32>; 2],
    /// The `[[load]]`s' work so far.
    #[serde(default)]
    pub load_work: f64,
    /// The energy steps of another method before this one left in forms it does not hold
    /// ([`Integrator::take_over`]).
    #[serde(default)]
    pub carried: f64,
}

pub struct ImplicitSolver<'m> {
    model: &'m Model,
    settings: ImplicitSettings,
    pub dt: f64,
    pub time: f64,
    pub steps: usize,
    asm: Assembled,
    solver: SpdSolver,
    /// The effective matrix of the sub-step dt / event_substeps, factorised at the first
    /// contact event (same pattern, so the symbolic analysis is shared).
    sub_solver: Option<SpdSolver>,
    /// Steps taken again in sub-steps because they held a contact event.
    pub event_steps: usize,
    mass_solver: Option<SpdSolver>,
    /// The contact equations (all false without a contact space), and a vector on them.
    in_space: Vec<bool>,
    contact_rhs: Vec<f64>,
    /// The free equations of every contact node, where a flexibility may keep its columns
    /// (without a contact space: [`Self::flexibility_equilibrium`]).
    response_equations: Vec<u32>,
    kernels: Box<dyn Kernels + 'm>,
    /// The state at the end of the last step.
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
    f_ext: Vec<f64>,
    /// The `[[load]]`s in `f_ext`, their work so far, and the time the (sub-)step being
    /// taken starts at.
    loads: LoadForces,
    load_work: f64,
    /// [`ImplicitState::carried`].
    carried: f64,
    /// The run's step count and time where this solver's stage starts.
    origin: (usize, f64),
    clock: f64,
    contact: MultiplierIteration,
    /// The rigid bodies' rotation at the end of the last step, and at the iterate's.
    spins: Spins,
    spins_new: Spins,
    work: Workspace,
    /// $K_{eff}^{-1}$ on the contact nodes, of the step's factor and of the sub-step's
    /// (`acceleration = "newton"`), and the Newton steps' counts.
    flexibility: [Flexibility; 2],
    newton: NewtonFigures,
    /// The `[[equation]]`s: the effective matrix is condensed by them, each solve's
    /// residual too, and the dependent dofs follow the others.
    constraints: Constraints,
}

/// What one step of length `dt` holds fixed: Newmark's parameters, the effective mass
/// factor c_m = 1/(beta dt^2), whether the contact force acts at the step's end (the classical
/// gap constraint) and its weight in the equilibrium, and the convergence tolerance.
struct StepConstants {
    dt: f64,
    beta: f64,
    gamma: f64,
    c_m: f64,
    endpoint: bool,
    force_weight: f64,
    /// The kernels compute in f64 (the residual test is then not needed).
    exact: bool,
    tol: f64,
    /// Whether w = $M^{-1} f_c$ is formed at every iteration: the iterate's velocity depends
    /// on it through $\Delta t (1 - \gamma/(2\beta))$, except for the trapezoidal rule, whose
    /// w is then formed once, at the step's end, for the acceleration (where no interface
    /// has friction; the classical gap has no w).
    mass_term: bool,
}

impl<'m> ImplicitSolver<'m> {
    /// Assembles, factorises once, and sets the initial state (u = 0, v = v0, a = M^-1 f_ext).
    pub fn new(
        model: &'m Model,
        settings: ImplicitSettings,
        dt: f64,
        speed_scale: f64,
        kernels: Box<dyn Kernels + 'm>,
    ) -> Result<Self> {
        let c_m = 1.0 / (settings.beta * dt * dt);
        let mut asm = assemble(model, settings.mass, c_m);
        let constraints = Constraints::new(&model.equations, &asm.equation, asm.dof_of.len());
        if !constraints.is_empty() {
            asm.effective = constraints.condense_matrix(&asm.effective);
        }
        let exact = kernels.unit_roundoff() < 1e-12;
        let plan = FactorPlan::new(model, &settings, &asm, exact)?;
        plan.check()?;
        let FactorPlan {
            effective,
            mass,
            in_space,
            ..
        } = plan;
        let count = effective.contact_equations();
        let solver = effective.factorise(&asm.effective)?;
        let mass_solver = match (mass, &asm.consistent_mass) {
            (Some(plan), Some(m)) => Some(plan.factorise(m)?),
            _ => None,
        };
        let ndof = model.dofs();
        let mut f_ext = gravity_force(model, &asm.nodal_mass);
        let loads = LoadForces::new(model, None, None, &f_ext);
        loads.set(model, 0.0, &mut f_ext);
        let mut v = model.initial_velocity.clone();
        for (vd, &fixed) in v.iter_mut().zip(&model.fixed) {
            if fixed {
                *vd = 0.0;
            }
        }
        for (d, w) in model.moving_dofs() {
            v[d] = w;
        }
        let interfaces = interface_states(model, &settings, &asm, dt, speed_scale);
        let mut s = ImplicitSolver {
            model,
            settings,
            dt,
            time: 0.0,
            steps: 0,
            solver,
            sub_solver: None,
            event_steps: 0,
            mass_solver,
            contact_rhs: vec![0.0; count],
            in_space,
            response_equations: contact_space::contact_node_equations(model, &asm),
            kernels,
            u: vec![0.0; ndof],
            v,
            a: vec![0.0; ndof],
            f_ext,
            loads,
            load_work: 0.0,
            carried: 0.0,
            origin: (0, 0.0),
            clock: 0.0,
            contact: MultiplierIteration::new(model, interfaces),
            spins: Spins::new(model),
            spins_new: Spins::new(model),
            work: Workspace::new(ndof, asm.dof_of.len()),
            asm,
            flexibility: Default::default(),
            newton: NewtonFigures::default(),
            constraints,
        };
        // a_0 = M^-1 f_ext (u_0 = 0, no contact force at t = 0)
        let f = s.f_ext.clone();
        let mut a0 = vec![0.0; ndof];
        s.acceleration_into(&f, &mut a0)?;
        s.a = a0;
        // initial contact kinematics, for the history's first row
        s.contact.broad_phase(s.model, &s.u, &s.v, s.dt);
        let (u, v) = (s.u.clone(), s.v.clone());
        (s.contact).kinematics(s.model, s.kernels.as_mut(), (&u, &v), &s.spins)?;
        Ok(s)
    }

    /// The state a checkpoint keeps.
    pub fn state(&self) -> ImplicitState {
        ImplicitState {
            time: self.time,
            steps: self.steps,
            event_steps: self.event_steps,
            u: self.u.clone(),
            v: self.v.clone(),
            a: self.a.clone(),
            interfaces: self.contact.interfaces.clone(),
            spins: self.spins.saved(),
            flexibility_nodes: self.flexibility.each_ref().map(Flexibility::nodes),
            load_work: self.load_work,
            carried: self.carried,
        }
    }

    /// Continues from a checkpoint's state (of this model: the lengths must match).
    pub fn restore_state(&mut self, s: ImplicitState) -> std::result::Result<(), String> {
        super::state::check_restore(
            (s.u.len(), self.u.len()),
            (s.interfaces.len(), self.contact.interfaces.len()),
        )?;
        self.time = s.time;
        self.steps = s.steps;
        self.event_steps = s.event_steps;
        self.u = s.u;
        self.v = s.v;
        self.a = s.a;
        self.contact.interfaces = s.interfaces;
        self.spins.restore(s.spins);
        self.flexibility = s.flexibility_nodes.map(Flexibility::resume);
        self.load_work = s.load_work;
        self.carried = s.carried;
        self.clock = s.time;
        self.loads.set(self.model, s.time, &mut self.f_ext);
        Ok(())
    }

    pub fn factorizations(&self) -> usize {
        self.solver.factorizations()
            + self.sub_solver.as_ref().map_or(0, |s| s.factorizations())
            + self.mass_solver.as_ref().map_or(0, |m| m.factorizations())
    }

    /// The effective matrix's factor: ordering, size, and the cost of every factorisation and
    /// solve over all step sizes.
    pub fn linear_solver(&self) -> FactorStats {
        let mut stats = self.solver.stats();
        if let Some(sub) = &self.sub_solver {
            let s = sub.stats();
            stats.factorizations += s.factorizations;
            stats.factorization_seconds += s.factorization_seconds;
            stats.solves += s.solves;
            stats.solve_seconds += s.solve_seconds;
            stats.contact_solves += s.contact_solves;
            stats.contact_solve_seconds += s.contact_solve_seconds;
        }
        stats
    }

    /// The consistent mass matrix's factor (None with lumped mass).
    pub fn mass_factor(&self) -> Option<FactorStats> {
        self.mass_solver.as_ref().map(SpdSolver::stats)
    }

    /// out = M^-1 f (on the free dofs; zero on fixed ones).
    fn apply_mass_inverse(&mut self, f: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        match &self.mass_solver {
            None => {
                for &d in &self.asm.dof_of {
                    out[d as usize] = f[d as usize] / self.asm.nodal_mass[d as usize / 3];
                }
            }
            Some(ms) => {
                for (e, &d) in self.asm.dof_of.iter().enumerate() {
                    self.work.tmp[e] = f[d as usize];
                }
                ms.solve_in_place(&mut self.work.tmp);
                for (e, &d) in self.asm.dof_of.iter().enumerate() {
                    out[d as usize] = self.work.tmp[e];
                }
            }
        }
    }

    /// out = M^-1 f, the acceleration of the forces `f`, within the `[[equation]]`s where
    /// there are any.
    fn acceleration_into(&mut self, f: &[f64], out: &mut [f64]) -> Result<()> {
        match self.constraints.is_empty() {
            true => self.apply_mass_inverse(f, out),
            false => self.constrained_acceleration(f, out)?,
        }
        Ok(())
    }

    /// out = T (T^T M T)^-1 T^T f: the acceleration the `[[equation]]`s allow (the lumped
    /// or consistent mass condensed and factorised for this one solve).
    fn constrained_acceleration(&mut self, f: &[f64], out: &mut [f64]) -> Result<()> {
        let n = self.asm.dof_of.len();
        let m = match &self.asm.consistent_mass {
            Some(m) => self.constraints.condense_matrix(m),
            None => {
                let diagonal = (self.asm.dof_of.iter().enumerate())
                    .map(|(e, &d)| (e as u32, e as u32, self.asm.nodal_mass[d as usize / 3]))
                    .collect();
                Csc::from_triplets(n, self.constraints.condense(diagonal))
            }
        };
        let solver = SpdSolver::new(&m, self.settings.ordering)?;
        let mut rhs: Vec<f64> = (self.asm.dof_of.iter()).map(|&d| f[d as usize]).collect();
        self.constraints.condense_residual(&mut rhs);
        solver.solve_in_place(&mut rhs);
        out.fill(0.0);
        for (&x, &d) in rhs.iter().zip(&self.asm.dof_of) {
            out[d as usize] = x;
        }
        self.constraints.apply(out);
        Ok(())
    }

    /// One Newmark step of size `h` from the current state, with the run's effective matrix
    /// (`sub` false, h = dt) or the sub-step's (`sub` true, h = dt / event_substeps).
    fn advance(&mut self, h: f64, sub: bool) -> Result<StepReport> {
        let times = (self.clock, self.clock + h);
        self.loads.set(self.model, times.1, &mut self.f_ext);
        let d0 = self.loads.dots(self.model, &self.u);
        let k = self.step_constants(h);
        self.predict(&k);
        self.start_contact()?;
        let mut report = StepReport::default();
        self.contact.anderson.reset();
        let space = self.contact_space_ready(&k, sub);
        // without one, later iterations solve for the forces' change alone (f64 kernels, no
        // friction: on the sliding block of tests/friction.rs, whose Anderson iteration
        // takes up to 144 iterations in a step, the last bits the re-formed residual removes
        // left two steps at the iteration limit)
        let incremental = k.exact
            && self.settings.contact_space == ContactSpace::Auto
            && !self.contact.frictional();
        // whether the iterate's contact equations ran ahead of the rest of the model
        let mut ahead = false;
        let mut newton = newton::NewtonGuard::new(
            self.settings.acceleration == Acceleration::Newton && !self.contact.frictional(),
        );
        for _k in 0..self.settings.max_iterations {
            let later = report.iterations > 0;
            let on_space = match space && later {
                true => self.contact_equilibrium(&k, sub)?,
                false => None,
            };
            ahead |= on_space.is_some();
            let off_space = incremental && !space && later;
            let moved = match off_space {
                true => self.flexibility_equilibrium(&k, sub),
                false => None,
            };
            ahead |= moved.is_some();
            self.newton.flexibility_moves += usize::from(moved.is_some());
            let (corr, size) = match on_space.or(moved) {
                Some(c) => c,
                None if off_space => self.incremental_equilibrium(&k, sub)?,
                None => {
                    ahead = false;
                    self.equilibrium(&k, sub)?
                }
            };
            self.turn_bodies(k.dt);
            report.iterations += 1;
            self.correct(&k)?;
            let (mut converged, map_changed) =
                self.contact
                    .update_multipliers(self.model, self.settings.constraint, &k);
            let residual_ok =
                k.exact || corr <= 1e3 * self.kernels.unit_roundoff() * size.max(f64::MIN_POSITIVE);
            let residual = self.contact.residual(self.model);
            let mut stepped = false;
            if converged && residual_ok && newton.allows(residual, map_changed) {
                // the update's change is eps m: small for a small eps however far m is from
                // zero. The Newton step measures how far the pressures are
                let size = self.newton_step(&k, sub, Some(k.tol));
                stepped = size.is_some_and(|s| s > k.tol);
                converged = !stepped;
                self.newton.steps += usize::from(stepped);
            }
            if converged && residual_ok {
                report.converged = true;
                break;
            }
            if !converged && !stepped {
                let stepped = newton.allows(residual, map_changed)
                    && self.newton_step(&k, sub, None).is_some();
                self.newton.steps += usize::from(stepped);
                if !stepped {
                    newton.give_up();
                    let acceleration = match self.settings.acceleration {
                        Acceleration::Newton => Acceleration::Anderson,
                        a => a,
                    };
                    let restart = map_changed || newton.left();
                    (self.contact).next_multipliers(self.model, acceleration, restart);
                }
            }
        }
        self.newton.steps_left += usize::from(newton.was_left());
        if ahead {
            // the rest of the model under the final multipliers
            self.recover(&k, sub)?;
            self.turn_bodies(k.dt);
        }
        let deferred = !k.endpoint && !k.mass_term;
        if deferred {
            // the trapezoidal rule's w, for the acceleration, under the last solve's forces
            self.form_w(true);
        }
        if ahead || deferred {
            self.correct(&k)?;
        }
        self.accept(&k)?;
        if !self.loads.is_empty() {
            let d1 = self.loads.dots(self.model, &self.u);
            self.load_work += LoadForces::step_work(self.model, times, (&d0, &d1));
        }
        self.clock = times.1;
        Ok(report)
    }

    /// The Newton step of the pressures ([`newton`]) with the step's (or sub-step's)
    /// flexibility, grown to the nodes the candidates touch: its relative size, or `None`
    /// where it cannot be taken (more nodes than a flexibility holds, or a singular matrix).
    /// With `keep_below`, a step no larger is not taken ([`newton::newton_update`]).
    fn newton_step(
        &mut self,
        k: &StepConstants,
        sub: bool,
        keep_below: Option<f64>,
    ) -> Option<f64> {
        if self.respond(k, sub) {
            self.flexibility[usize::from(sub)].respond_at(&self.response_equations);
        }
        let solver = step_factor(&self.solver, &self.sub_solver, sub);
        let flex = &mut self.flexibility[usize::from(sub)];
        // the forces of the current pressures on the current geometry, less the last solve's
        self.contact.forces_into(self.model, &mut self.work.f_c);
        let (f_c, f_last) = (&self.work.f_c, &self.work.f_last);
        let lag: Vec<(u32, [f64; 3])> = (0..f_c.len() / 3)
            .filter_map(|n| {
                let d = [0, 1, 2].map(|a| f_c[3 * n + a] - f_last[3 * n + a]);
                (d != [0.0; 3]).then_some((n as u32, d))
            })
            .collect();
        let (interfaces, faces) = self.contact.newton_parts();
        let rows = newton::rows(self.model, interfaces, faces);
        let mut nodes = newton::touched_nodes(&rows);
        nodes.extend(lag.iter().map(|l| l.0));
        let ahead = || newton::nodes_ahead(self.model, interfaces, faces);
        if !flex.ensure(&nodes, ahead, &self.asm, solver) {
            return None;
        }
        let alpha_k = k.gamma * k.c_m * k.dt * k.force_weight;
        let alpha_m = match k.endpoint {
            true => 0.0,
            false => k.dt * (1.0 - k.gamma / (2.0 * k.beta)),
        };
        let alpha = (alpha_k, alpha_m);
        let parts = (interfaces, rows.as_slice());
        newton::newton_update(
            self.model,
            parts,
            &lag,
            flex,
            (alpha, &self.asm),
            keep_below,
        )
    }

    /// The effective matrix's factor of the step (`sub`: the sub-step's, where it was made).
    fn effective(&self, sub: bool) -> &SpdSolver {
        step_factor(&self.solver, &self.sub_solver, sub)
    }

    /// The constants of a step of length `h`.
    fn step_constants(&self, h: f64) -> StepConstants {
        let (dt, beta, gamma) = (h, self.settings.beta, self.settings.gamma);
        // the paper's gap rate holds the contact force constant over the step; the classical
        // gap constraint applies it at t_{n+1} in Newmark's equilibrium (module docs)
        let endpoint = self.settings.constraint == ConstraintMeasure::Gap;
        StepConstants {
            dt,
            beta,
            gamma,
            c_m: 1.0 / (beta * dt * dt),
            endpoint,
            force_weight: if endpoint { 1.0 } else { 1.0 / (2.0 * beta) },
            exact: self.kernels.unit_roundoff() < 1e-12,
            // friction keeps w at every iteration: its last bits decided two steps of the
            // sliding block of tests/friction.rs at the iteration limit
            mass_term: !endpoint
                && (dt * (1.0 - gamma / (2.0 * beta)) != 0.0 || self.contact.frictional()),
            // the multipliers cannot settle below the noise of the kernels' arithmetic
            tol: self
                .settings
                .tolerance
                .max(KERNEL_NOISE_FACTOR * self.kernels.unit_roundoff()),
        }
    }

    /// Newmark's predictors, and u_new = the predicted displacement.
    fn predict(&mut self, k: &StepConstants) {
        let (dt, beta, gamma) = (k.dt, k.beta, k.gamma);
        for d in 0..self.u.len() {
            self.work.u_tilde[d] = self.u[d] + dt * self.v[d] + dt * dt * (0.5 - beta) * self.a[d];
            self.work.v_tilde[d] = self.v[d] + dt * (1.0 - gamma) * self.a[d];
            self.work.u_new[d] = self.work.u_tilde[d] + beta * dt * dt * self.a[d];
        }
    }

    /// The broad phase and the start-of-step kinematics, which decide the candidates (g_n
    /// decides who is a candidate).
    fn start_contact(&mut self) -> Result<()> {
        self.contact
            .broad_phase(self.model, &self.u, &self.v, self.dt);
        let (u0, v0) = (std::mem::take(&mut self.u), std::mem::take(&mut self.v));
        let spins = &self.spins;
        (self.contact).kinematics(self.model, self.kernels.as_mut(), (&u0, &v0), spins)?;
        self.u = u0;
        self.v = v0;
        for st in &mut self.contact.interfaces {
            st.memory.reset();
            st.penalty.new_step();
            for i in 0..st.lambda.len() {
                st.candidate[i] =
                    st.points[i].face != NO_FACE && (st.lambda[i] > 0.0 || st.points[i].gap >= 0.0);
                if !st.candidate[i] {
                    st.lambda[i] = 0.0;
                }
            }
            if let Some(fr) = &mut st.friction {
                fr.start_step(&st.points, &st.candidate);
            }
        }
        Ok(())
    }

    /// One solve of the effective equation at u_new with the current contact forces:
    /// u_new moves by the solution. Returns the largest correction and the largest
    /// displacement increment of the step.
    fn equilibrium(&mut self, k: &StepConstants, sub: bool) -> Result<(f64, f64)> {
        self.contact.forces_into(self.model, &mut self.work.f_c);
        let f_c = std::mem::take(&mut self.work.f_c);
        // residual of the effective equation at u_new
        let u_new = std::mem::take(&mut self.work.u_new);
        self.kernels
            .internal_forces_into(&u_new, &mut self.work.f_int)?;
        let mut inertia = std::mem::take(&mut self.work.inertia);
        let mut increment = std::mem::take(&mut self.work.increment);
        self.inertia_into(&u_new, &mut increment, &mut inertia);
        for (e, &d) in self.asm.dof_of.iter().enumerate() {
            let d = d as usize;
            self.work.rhs[e] =
                self.f_ext[d] + k.force_weight * f_c[d] - k.c_m * inertia[e] - self.work.f_int[d];
        }
        self.work.inertia = inertia;
        self.work.increment = increment;
        self.work.u_new = u_new;
        self.work.f_c = f_c;
        let mut delta = std::mem::take(&mut self.work.rhs);
        self.constraints.condense_residual(&mut delta);
        self.effective(sub).solve_in_place(&mut delta);
        let moved = self.move_iterate(&delta);
        self.constraints.apply(&mut self.work.u_new);
        self.work.rhs = delta;
        self.accept_forces(k);
        self.work.u_base.copy_from_slice(&self.work.u_new);
        self.work.f_base.copy_from_slice(&self.work.f_last);
        Ok(moved)
    }

    /// u_new moves by `delta` (free dofs, equation order). Returns the largest correction
    /// and the largest displacement increment of the step.
    fn move_iterate(&mut self, delta: &[f64]) -> (f64, f64) {
        let moves = delta.iter().zip(&self.asm.dof_of);
        move_dofs(
            &mut self.work.u_new,
            &self.u,
            moves.map(|(&x, &d)| (d as usize, x)),
        )
    }

    /// One solve of the effective equation for the change of the contact forces since the
    /// last solve: the element forces are linear in u and the iterate balances the last
    /// solve's forces, so u_new moves by $K_{eff}^{-1} w_f (f_c - f_{c,last})$, a load on the
    /// contact nodes alone, whose forward pass skips the supernodes it does not reach; no
    /// element forces. w takes $M^{-1} f_c$. Returns as [`Self::equilibrium`].
    fn incremental_equilibrium(&mut self, k: &StepConstants, sub: bool) -> Result<(f64, f64)> {
        self.contact.forces_into(self.model, &mut self.work.f_c);
        let delta = self.force_change_response(k, sub, false);
        let moved = self.move_iterate(&delta);
        self.work.rhs = delta;
        self.accept_forces(k);
        Ok(moved)
    }

    /// $K_{eff}^{-1} w_f (f_c - f_{ref})$ on the free dofs (the workspace's right-hand side,
    /// taken out), $f_{ref}$ the last solve's forces or, `from_base`, the last full solve's.
    fn force_change_response(&mut self, k: &StepConstants, sub: bool, from_base: bool) -> Vec<f64> {
        let mut delta = std::mem::take(&mut self.work.rhs);
        let f_c = &self.work.f_c;
        let f_ref = match from_base {
            true => &self.work.f_base,
            false => &self.work.f_last,
        };
        for (r, &d) in delta.iter_mut().zip(&self.asm.dof_of) {
            *r = k.force_weight * (f_c[d as usize] - f_ref[d as usize]);
        }
        self.effective(sub).solve_in_place(&mut delta);
        delta
    }

    /// The current contact forces become the last solve's: w takes $M^{-1} f_c$ (zero under
    /// the classical gap constraint).
    fn accept_forces(&mut self, k: &StepConstants) {
        // without the mass term w waits for the step's end (it does not move the velocity)
        match k.mass_term {
            true => self.form_w(false),
            false => self.work.w.fill(0.0),
        }
        self.work.f_last.copy_from_slice(&self.work.f_c);
    }

    /// w = $M^{-1} f$, f the current contact forces or (`last`) the last solve's.
    fn form_w(&mut self, last: bool) {
        let forces = match last {
            true => &mut self.work.f_last,
            false => &mut self.work.f_c,
        };
        let f = std::mem::take(forces);
        let mut w = std::mem::take(&mut self.work.w);
        self.apply_mass_inverse(&f, &mut w);
        match last {
            true => self.work.f_last = f,
            false => self.work.f_c = f,
        }
        self.work.w = w;
    }

    /// The whole model under the current contact forces after iterations on the contact
    /// space: the effective equation is linear in them, so the iterate is the last full
    /// solve's plus $K_{eff}^{-1} w_f (f_c - f_{base})$, a load on the contact equations
    /// alone (with them numbered last, the forward solve touches only the factor's top), and
    /// w takes $M^{-1} f_c$ everywhere. Where the forces changed outside the contact
    /// equations of a contact space, a full [`Self::equilibrium`] instead (without one, the
    /// iterations moved the contact nodes by the flexibility's columns, from f64 kernels).
    fn recover(&mut self, k: &StepConstants, sub: bool) -> Result<()> {
        self.contact.forces_into(self.model, &mut self.work.f_c);
        let (f_c, f_base) = (&self.work.f_c, &self.work.f_base);
        let space = self.contact_space_ready(k, sub);
        let outside = space
            && (self.asm.dof_of.iter().zip(&self.in_space))
                .any(|(&d, &inside)| !inside && f_c[d as usize] != f_base[d as usize]);
        if outside {
            return self.equilibrium(k, sub).map(|_| ());
        }
        let delta = self.force_change_response(k, sub, true);
        self.work.u_new.copy_from_slice(&self.work.u_base);
        for (&x, &d) in delta.iter().zip(&self.asm.dof_of) {
            self.work.u_new[d as usize] += x;
        }
        self.work.rhs = delta;
        self.accept_forces(k);
        Ok(())
    }

    /// Newmark's correctors from u_new, and the contact kinematics there.
    fn correct(&mut self, k: &StepConstants) -> Result<()> {
        let (dt, beta, gamma, c_m) = (k.dt, k.beta, k.gamma, k.c_m);
        for d in 0..self.u.len() {
            self.work.a_new[d] =
                c_m * (self.work.u_new[d] - self.work.u_tilde[d]) - self.work.w[d] / (2.0 * beta);
            self.work.v_new[d] =
                self.work.v_tilde[d] + gamma * dt * self.work.a_new[d] + dt * self.work.w[d];
            if self.model.fixed[d] {
                // held (v = 0) or moved at a prescribed rigid body's velocity
                self.work.a_new[d] = 0.0;
                self.work.v_new[d] = self.v[d];
            }
        }
        let (un, vn) = (
            std::mem::take(&mut self.work.u_new),
            std::mem::take(&mut self.work.v_new),
        );
        let spins = &self.spins_new;
        (self.contact).kinematics(self.model, self.kernels.as_mut(), (&un, &vn), spins)?;
        self.work.u_new = un;
        self.work.v_new = vn;
        Ok(())
    }

    /// The rotating rigid bodies at the step's end under the current contact forces: a free
    /// body's angular momentum takes the moment of the step's impulses, then each body turns
    /// over the step ([`Spins::drift`]).
    fn turn_bodies(&mut self, dt: f64) {
        if !self.spins.any() {
            return;
        }
        self.spins_new.clone_from(&self.spins);
        for (k, itf) in self.model.interfaces.iter().enumerate() {
            if let Primary::Rigid { body, .. } = itf.primary {
                let m = self.contact.moment(self.model, k);
                if self.spins.is_free(body) && m != [0.0; 3] {
                    self.spins_new.add_angular_impulse(body, m.map(|x| -dt * x));
                }
            }
        }
        self.spins_new.drift(dt);
    }

    /// Accepts the step: the new state, and each interface's report.
    fn accept(&mut self, k: &StepConstants) -> Result<()> {
        std::mem::swap(&mut self.u, &mut self.work.u_new);
        std::mem::swap(&mut self.v, &mut self.work.v_new);
        std::mem::swap(&mut self.a, &mut self.work.a_new);
        if self.spins.any() {
            self.spins.clone_from(&self.spins_new);
        }
        let moments: Vec<[f64; 3]> = match self.spins.any() {
            true => (0..self.model.interfaces.len())
                .map(|j| self.contact.moment(self.model, j))
                .collect(),
            false => Vec::new(),
        };
        for (j, (itf, st)) in (self.model.interfaces.iter())
            .zip(&mut self.contact.interfaces)
            .enumerate()
        {
            let mut r = ContactReport {
                driver_work: st.report.driver_work,
                ..Default::default()
            };
            // the force on the model, for a prescribed rigid body's driver work
            let mut force = [0.0; 3];
            for i in 0..st.lambda.len() {
                if st.lambda[i] > 0.0 {
                    r.normal_force += st.lambda[i] * itf.area[i];
                    r.active += 1;
                    for (f, n) in force.iter_mut().zip(st.points[i].normal) {
                        *f += st.lambda[i] * itf.area[i] * n;
                    }
                }
                if st.points[i].face != NO_FACE {
                    r.max_penetration = r.max_penetration.max(st.points[i].gap);
                }
            }
            if let Some(fr) = &mut st.friction {
                let (total, sliding) = fr.end_step(k.dt, &itf.area, &st.lambda, &st.points);
                st.tangential = total;
                force = std::array::from_fn(|a| force[a] + total[a]);
                r.tangential_force = vector::norm(total);
                r.sliding = sliding;
                r.friction_work = fr.work;
            }
            r.force = force.map(|f| -f);
            if let Some(vb) = driven_velocity(self.model, itf, &self.v) {
                r.driver_work += k.dt * dot_slices(&force, &vb);
                // through the turning surface points too: omega . sum r x f
                if let (Primary::Rigid { body, .. }, Some(m)) = (&itf.primary, moments.get(j)) {
                    r.driver_work += k.dt * vector::dot(self.spins.omega(*body), *m);
                }
            }
            if k.endpoint {
                // impulse of the step / dt with forces at both ends
                let f_end = r.normal_force;
                r.normal_force = (1.0 - k.gamma) * st.endpoint_force + k.gamma * f_end;
                st.endpoint_force = f_end;
            }
            st.report = r;
        }
        if !self.u.iter().chain(&self.v).all(|x| x.is_finite()) {
            return Err(ImpactError::Solver(
                "non-finite displacement or velocity".into(),
            ));
        }
        Ok(())
    }

    /// M (x - u_tilde) on the free dofs (equation order) into `out`; `increment` receives
    /// x - u_tilde.
    fn inertia_into(&self, x: &[f64], increment: &mut [f64], out: &mut [f64]) {
        for (e, &d) in self.asm.dof_of.iter().enumerate() {
            increment[e] = x[d as usize] - self.work.u_tilde[d as usize];
        }
        match &self.asm.consistent_mass {
            None => {
                for (e, &d) in self.asm.dof_of.iter().enumerate() {
                    out[e] = self.asm.nodal_mass[d as usize / 3] * increment[e];
                }
            }
            Some(m) => m.mul_into(increment, out),
        }
    }
}

impl Integrator for ImplicitSolver<'_> {
    fn model(&self) -> &Model {
        self.model
    }

    fn method(&self) -> Method {
        Method::Implicit
    }

    fn device_name(&self) -> String {
        self.kernels.device_name()
    }

    /// One time step. Returns the number of iterations and whether the contact converged.
    ///
    /// With the gap-rate constraint and `event_substeps` k > 1, a step that holds a contact
    /// event ([`Self::contact_event`]: an impact, a release, a ramp of the force towards one)
    /// is taken again from its start in k sub-steps of dt / k; its reported forces are then
    /// the impulse of the whole step over dt. Its iterations count both attempts.
    fn step(&mut self) -> Result<StepReport> {
        let k = self.settings.event_substeps;
        // a scene without contact has no events: no snapshot to keep
        let refine = k > 1
            && self.settings.constraint == ConstraintMeasure::GapRate
            && !self.contact.interfaces.is_empty();
        for st in &mut self.contact.interfaces {
            st.step_pressure.clear();
        }
        let saved = refine.then(|| Snapshot {
            u: self.u.clone(),
            v: self.v.clone(),
            a: self.a.clone(),
            interfaces: self.contact.interfaces.clone(),
            spins: self.spins.clone(),
            load_work: self.load_work,
        });
        self.clock = self.time;
        let mut report = self.advance(self.dt, false)?;
        if let Some(saved) = saved {
            // what the event test needs of the next step: this step's change and the peak
            let before: Vec<f64> = saved
                .interfaces
                .iter()
                .map(|st| st.report.normal_force)
                .collect();
            if self.contact_event(&saved.interfaces) {
                let r = self.substeps(saved, k)?;
                report.iterations += r.iterations;
                report.converged = r.converged;
            }
            for (st, f0) in self.contact.interfaces.iter_mut().zip(before) {
                st.peak_force = st.peak_force.max(st.report.normal_force);
                st.last_change = st.report.normal_force - f0;
            }
        }
        self.steps += 1;
        self.time = self.origin.1 + (self.steps - self.origin.0) as f64 * self.dt;
        Ok(report)
    }

    /// Energies of the current state (one internal force evaluation).
    fn energies(&mut self) -> Result<Energies> {
        let u = std::mem::take(&mut self.u);
        self.kernels
            .internal_forces_into(&u, &mut self.work.f_int)?;
        self.u = u;
        let strain = 0.5 * dot_slices(&self.u, &self.work.f_int);
        let kinetic = match &self.asm.consistent_mass {
            None => {
                0.5 * self
                    .v
                    .iter()
                    .enumerate()
                    .map(|(d, v)| self.asm.nodal_mass[d / 3] * v * v)
                    .sum::<f64>()
            }
            Some(m) => {
                let ve: Vec<f64> = self
                    .asm
                    .dof_of
                    .iter()
                    .map(|&d| self.v[d as usize])
                    .collect();
                let mut mv = vec![0.0; ve.len()];
                m.mul_into(&ve, &mut mv);
                0.5 * dot_slices(&ve, &mv)
            }
        };
        let driver_work: f64 = (self.contact.interfaces.iter())
            .map(|i| i.report.driver_work)
            .sum();
        Ok(Energies {
            kinetic: kinetic + self.spins.kinetic(),
            strain,
            potential: -dot_slices(&self.f_ext, &self.u)
                + self.loads.in_dot(self.model, self.clock, &self.u)
                - self.load_work
                - driver_work
                + self.carried,
            damage: 0.0,
            plies: Default::default(),
            fix_work: 0.0,
            load_work: self.load_work,
        })
    }

    fn reports(&self) -> Vec<ContactReport> {
        (self.contact.interfaces.iter())
            .map(|i| ContactReport {
                // not measured by the implicit steps (scene-format.md)
                impact_loss: f64::NAN,
                ..i.report
            })
            .collect()
    }

    fn body_spins(&self) -> Vec<super::state::ProbeValues> {
        self.spins.columns()
    }

    fn node_contact(&self, interface: usize, point: usize) -> (f64, f64) {
        let st = &self.contact.interfaces[interface];
        let p = st.points[point];
        let gap = if p.face == NO_FACE { f64::NAN } else { p.gap };
        (st.step_pressure(point), gap)
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
        &self.asm.nodal_mass
    }

    fn begin_step(&mut self) -> Result<()> {
        // M a = f_ext + f_c - f_int at the state the last step left
        self.kernels
            .internal_forces_into(&self.u, &mut self.work.f_int)?;
        self.contact.forces_into(self.model, &mut self.work.f_c);
        let f: Vec<f64> = (self.f_ext.iter().zip(&self.work.f_c).zip(&self.work.f_int))
            .map(|((e, c), i)| e + c - i)
            .collect();
        let mut a = vec![0.0; f.len()];
        self.acceleration_into(&f, &mut a)?;
        self.a = a;
        Ok(())
    }

    fn checkpoint_state(&mut self) -> Result<Option<SolverState>> {
        Ok(Some(SolverState::Implicit(self.state())))
    }

    fn start_stage_at(&mut self, steps: usize, time: f64) {
        self.origin = (steps, time);
    }

    /// Goes on from a static or explicit stage: its displacement, the velocity it hands on
    /// (on the free dofs) or the run's initial one (its kinetic energy counted as the loads'
    /// work), the acceleration the model gives there, and the total energy it ended at.
    fn take_over(&mut self, h: &Handover) -> Result<()> {
        (self.time, self.clock, self.steps) = (h.time, h.time, h.steps);
        self.u.copy_from_slice(&h.u);
        let given = h.velocity_into(&self.model.fixed, &self.asm.nodal_mass, &mut self.v);
        self.load_work = h.load_work + given;
        self.loads.set(self.model, self.time, &mut self.f_ext);
        self.begin_step()?;
        self.carried = 0.0;
        self.carried = h.energy - self.energies()?.total();
        Ok(())
    }

    fn restore(&mut self, state: SolverState) -> std::result::Result<(), String> {
        match state {
            SolverState::Implicit(s) => self.restore_state(s),
            _ => Err(super::integrator::other_integrator()),
        }
    }

    fn interface_ends(&self) -> Vec<InterfaceEnd> {
        (self.contact.interfaces.iter())
            .map(|st| InterfaceEnd {
                penalty_normal: Some(st.penalty.eps),
                penalty_tangential: st.friction.as_ref().map(|f| f.penalty.eps),
                friction_work: st.friction.as_ref().map_or(0.0, |f| f.work),
                impact_loss: None,
                penalty_increases: st.penalty.increases,
                penalty_decreases: st.penalty.decreases,
            })
            .collect()
    }

    fn implicit_figures(&self) -> Option<ImplicitFigures> {
        Some(ImplicitFigures {
            factorizations: self.factorizations(),
            linear_solver: self.linear_solver(),
            mass_factor: self.mass_factor(),
            event_steps: self.event_steps,
            newton: (self.settings.acceleration == Acceleration::Newton).then(|| NewtonFigures {
                flexibility_nodes: self.flexibility.iter().map(|f| f.nodes().len()).sum(),
                friction_keeps_anderson: self.contact.frictional(),
                ..self.newton
            }),
        })
    }
}

/// The velocity of the interface's rigid body where it is prescribed (its driver works).
/// [`ImplicitSolver::effective`] from the two factors alone (for a caller that borrows the
/// solver's other fields mutably meanwhile).
fn step_factor<'a>(
    solver: &'a SpdSolver,
    sub_solver: &'a Option<SpdSolver>,
    sub: bool,
) -> &'a SpdSolver {
    match (sub, sub_solver) {
        (true, Some(s)) => s,
        _ => solver,
    }
}

fn driven_velocity(model: &Model, itf: &crate::model::Interface, v: &[f64]) -> Option<[f64; 3]> {
    let Primary::Rigid { body, node, .. } = itf.primary else {
        return None;
    };
    let b = 3 * node as usize;
    (model.rigid[body].motion == crate::scene::RigidMotion::Prescribed)
        .then(|| [v[b], v[b + 1], v[b + 2]])
}

/// `u_new` moves by x at each (dof, x) of `moves`. Returns the largest move and the largest
/// displacement increment from `u` among the dofs moved.
fn move_dofs(
    u_new: &mut [f64],
    u: &[f64],
    moves: impl Iterator<Item = (usize, f64)>,
) -> (f64, f64) {
    let (mut corr, mut size) = (0.0f64, 0.0f64);
    for (d, x) in moves {
        u_new[d] += x;
        corr = corr.max(x.abs());
        size = size.max((u_new[d] - u[d]).abs());
    }
    (corr, size)
}

fn dot_slices(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
