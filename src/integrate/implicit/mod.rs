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
//! negative at impact: the total energy cannot rise.
//!
//! **The classical comparison** (`constraint = "gap"`): the multiplier enforces the gap
//! $g_{n+1} = 0$ and the contact force acts at $t_{n+1}$ in Newmark's equilibrium
//! $M a_{n+1} + K u_{n+1} = f_{ext} + f_{c,n+1}$, as in the classical contact codes the paper
//! compares against; the reported force is then the step's impulse / dt,
//! $(1-\gamma) f_{c,n} + \gamma f_{c,n+1}$.
//!
//! **Iteration.** Each iteration solves with the current pressures (one triangular solve pair;
//! the effective matrix does not depend on the contact, so it is factorised once per run, and
//! once more for the sub-step at the first contact event: see [`ImplicitSolver::step`]),
//! computes the contact kinematics of the new state with the kernels, and updates the
//! pressures with [`augmented_lagrange::update`]. The residual is formed with the kernels'
//! internal forces, so a backend in f32 is corrected iteratively.

use crate::backend::Kernels;
use crate::contact::anderson::Anderson;
use crate::contact::augmented_lagrange::{self, IterationMemory, Penalty};
use crate::contact::friction::{cone_projection, cone_radius, plane_basis, Friction};
use crate::contact::search;
use crate::error::{ImpactError, Result};
use crate::geometry::quad::{self, dot};
use crate::kernels::contact_gap::NO_FACE;
use crate::kernels::{ContactPoint, ContactQueries};
use crate::linalg::{assemble, Assembled, FactorStats, SpdSolver};
use crate::model::Model;
use crate::model::Primary;
use crate::scene::{Acceleration, Constraint, ImplicitSettings};

use super::state::{ContactReport, Energies};

/// Forces below this fraction of an interface's peak normal force so far do not make a
/// contact event (round-off forces of a grazing contact would otherwise refine every step).
pub const EVENT_FORCE_FLOOR: f64 = 1e-3;

/// The contact iteration's tolerance is at least this many times the kernels' unit roundoff
/// (3.6e-6 for f32 kernels; no effect in f64).
pub const KERNEL_NOISE_FACTOR: f64 = 30.0;

/// Contact state of one interface, carried from step to step.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct InterfaceState {
    /// Converged pressure of each secondary node over the last step.
    pub lambda: Vec<f64>,
    /// Kinematics at the end of the last step.
    pub points: Vec<ContactPoint>,
    pub penalty: Penalty,
    /// Coulomb friction, where the interface has mu > 0.
    pub friction: Option<Friction>,
    memory: IterationMemory,
    candidate: Vec<bool>,
    measure: Vec<f64>,
    next: Vec<f64>,
    /// Total normal force at the end of the last step (classical endpoint forces only).
    endpoint_force: f64,
    /// Total friction force vector of the last step (impulse / step).
    tangential: [f64; 3],
    /// Largest normal force reported so far.
    peak_force: f64,
    /// Change of the reported normal force over the last step.
    last_change: f64,
    /// Normal and tangential penalties as the sub-steps of the last contact event left them.
    sub_penalties: Option<(f64, f64)>,
    /// The last step's mean pressure of each node (impulse / (dt A)) when the step was
    /// refined into sub-steps; empty otherwise (then it is `lambda`).
    step_pressure: Vec<f64>,
    pub report: ContactReport,
}

impl InterfaceState {
    /// Node i's contact pressure over the last step: its impulse / (dt A).
    pub fn step_pressure(&self, i: usize) -> f64 {
        if self.step_pressure.is_empty() {
            self.lambda[i]
        } else {
            self.step_pressure[i]
        }
    }

    /// Increases and decreases of the normal and tangential penalties so far.
    fn penalty_counts(&self) -> [usize; 4] {
        let (ti, td) = self
            .friction
            .as_ref()
            .map_or((0, 0), |f| (f.penalty.increases, f.penalty.decreases));
        [self.penalty.increases, self.penalty.decreases, ti, td]
    }

    fn set_penalty_counts(&mut self, c: [usize; 4]) {
        self.penalty.increases = c[0];
        self.penalty.decreases = c[1];
        if let Some(f) = &mut self.friction {
            f.penalty.increases = c[2];
            f.penalty.decreases = c[3];
        }
    }

    /// The normal and tangential penalties (0 for the latter without friction).
    fn penalties(&self) -> (f64, f64) {
        let eps_t = self.friction.as_ref().map_or(0.0, |f| f.penalty.eps);
        (self.penalty.eps, eps_t)
    }

    fn set_penalties(&mut self, (eps_n, eps_t): (f64, f64)) {
        self.penalty.eps = eps_n;
        if let Some(f) = &mut self.friction {
            f.penalty.eps = eps_t;
        }
    }
}

/// The state a step starts from, kept so that a step found to hold a contact event can be
/// taken again in sub-steps.
struct Snapshot {
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    interfaces: Vec<InterfaceState>,
}

/// What one step did.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepReport {
    /// Augmented Lagrange iterations (= linear solves) of the step.
    pub iterations: usize,
    pub converged: bool,
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
    kernels: Box<dyn Kernels + 'm>,
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
    f_ext: Vec<f64>,
    pub interfaces: Vec<InterfaceState>,
    queries: ContactQueries,
    candidate_lists: Vec<Vec<u32>>,
    face_size: f64,
    // scratch
    f_int: Vec<f64>,
    f_c: Vec<f64>,
    w: Vec<f64>,
    rhs: Vec<f64>,
    tmp: Vec<f64>,
    u_tilde: Vec<f64>,
    v_tilde: Vec<f64>,
    /// M (u - u_tilde) and u - u_tilde on the free dofs.
    inertia: Vec<f64>,
    increment: Vec<f64>,
    /// Kinematics of every surface query.
    query_points: Vec<ContactPoint>,
    /// Covariant slip rates of every surface query (only when some surface has friction).
    query_slip: Vec<[f64; 2]>,
    surface_friction: bool,
    anderson: Anderson,
    /// Multipliers of all interfaces in one vector (Anderson acceleration).
    aa_x: Vec<f64>,
    aa_g: Vec<f64>,
    aa_w: Vec<f64>,
    aa_out: Vec<f64>,
    u_new: Vec<f64>,
    v_new: Vec<f64>,
    a_new: Vec<f64>,
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
        let asm = assemble(model, settings.mass, c_m);
        let solver = SpdSolver::new(&asm.effective, settings.ordering)?;
        let mass_solver = match &asm.consistent_mass {
            Some(m) => Some(SpdSolver::new(m, settings.ordering)?),
            None => None,
        };
        let ndof = model.dofs();
        let f_ext = gravity_force(model, &asm);
        let mut v = model.initial_velocity.clone();
        for d in 0..ndof {
            if model.fixed[d] {
                v[d] = 0.0;
            }
        }
        let interfaces = interface_states(model, &settings, &asm, dt, speed_scale);
        let face_size = search::largest_face_diagonal(model);
        let nq = model.queries.len();
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
            kernels,
            u: vec![0.0; ndof],
            v,
            a: vec![0.0; ndof],
            f_ext,
            interfaces,
            queries: model.queries.clone(),
            candidate_lists: vec![Vec::new(); nq],
            face_size,
            f_int: vec![0.0; ndof],
            f_c: vec![0.0; ndof],
            w: vec![0.0; ndof],
            rhs: vec![0.0; asm.dof_of.len()],
            tmp: vec![0.0; asm.dof_of.len()],
            u_tilde: vec![0.0; ndof],
            v_tilde: vec![0.0; ndof],
            inertia: vec![0.0; asm.dof_of.len()],
            increment: vec![0.0; asm.dof_of.len()],
            query_points: vec![ContactPoint::default(); nq],
            query_slip: vec![[0.0; 2]; nq],
            surface_friction: model
                .interfaces
                .iter()
                .any(|i| i.friction > 0.0 && !i.is_plane()),
            anderson: Anderson::default(),
            aa_x: Vec::new(),
            aa_g: Vec::new(),
            aa_w: Vec::new(),
            aa_out: Vec::new(),
            u_new: vec![0.0; ndof],
            v_new: vec![0.0; ndof],
            a_new: vec![0.0; ndof],
            asm,
        };
        // a_0 = M^-1 f_ext (u_0 = 0, no contact force at t = 0)
        let f = s.f_ext.clone();
        let mut a0 = vec![0.0; ndof];
        s.apply_mass_inverse(&f, &mut a0);
        s.a = a0;
        // initial contact kinematics, for the history's first row
        s.broad_phase();
        let (u, v) = (s.u.clone(), s.v.clone());
        s.kinematics(&u, &v)?;
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
            interfaces: self.interfaces.clone(),
        }
    }

    /// Continues from a checkpoint's state (of this model: the lengths must match).
    pub fn restore(&mut self, s: ImplicitState) -> std::result::Result<(), String> {
        super::state::check_restore(
            (s.u.len(), self.u.len()),
            (s.interfaces.len(), self.interfaces.len()),
        )?;
        self.time = s.time;
        self.steps = s.steps;
        self.event_steps = s.event_steps;
        self.u = s.u;
        self.v = s.v;
        self.a = s.a;
        self.interfaces = s.interfaces;
        Ok(())
    }

    pub fn device_name(&self) -> String {
        self.kernels.device_name()
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
        }
        stats
    }

    /// The consistent mass matrix's factor (None with lumped mass).
    pub fn mass_factor(&self) -> Option<FactorStats> {
        self.mass_solver.as_ref().map(SpdSolver::stats)
    }

    pub fn nodal_mass(&self) -> &[f64] {
        &self.asm.nodal_mass
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
                    self.tmp[e] = f[d as usize];
                }
                ms.solve_in_place(&mut self.tmp);
                for (e, &d) in self.asm.dof_of.iter().enumerate() {
                    out[d as usize] = self.tmp[e];
                }
            }
        }
    }

    /// Candidate primary faces of every secondary node, from the current configuration.
    fn broad_phase(&mut self) {
        let margin = search::margin(&self.v, self.dt, self.face_size);
        search::surface_candidates(
            self.model,
            &mut self.queries,
            &mut self.candidate_lists,
            &self.u,
            margin,
        );
    }

    /// Contact kinematics of every interface at (u, v): surfaces through the kernels,
    /// rigid planes analytically.
    fn kinematics(&mut self, u: &[f64], v: &[f64]) -> Result<()> {
        let model = self.model;
        if !self.queries.is_empty() {
            let pts = &mut self.query_points;
            self.kernels.contact_gap_into(u, v, &self.queries, pts)?;
            for (itf, st) in model.interfaces.iter().zip(&mut self.interfaces) {
                if let Primary::Surface { queries, .. } = &itf.primary {
                    st.points.copy_from_slice(&pts[queries.clone()]);
                }
            }
        }
        for (itf, st) in model.interfaces.iter().zip(&mut self.interfaces) {
            if let Primary::Plane { point, normal } = &itf.primary {
                for (i, &n) in itf.nodes.iter().enumerate() {
                    let n = n as usize;
                    let x0 = model.mesh.nodes[n];
                    let x = [x0[0] + u[3 * n], x0[1] + u[3 * n + 1], x0[2] + u[3 * n + 2]];
                    let vel = [v[3 * n], v[3 * n + 1], v[3 * n + 2]];
                    st.points[i] = ContactPoint {
                        face: 0,
                        xi: [0.0; 2],
                        normal: *normal,
                        gap: -dot(quad::sub(x, *point), *normal),
                        gap_rate: -dot(vel, *normal),
                    };
                }
            }
        }
        self.friction_kinematics(u, v)
    }

    /// Slip rates and tangents of the interfaces with friction: surfaces through the
    /// `slip_rate` kernel (tangents from the face at the projected point), planes with a
    /// fixed orthonormal basis.
    fn friction_kinematics(&mut self, u: &[f64], v: &[f64]) -> Result<()> {
        let model = self.model;
        if self.surface_friction {
            self.kernels.slip_rate_into(
                u,
                v,
                &self.queries,
                &self.query_points,
                &mut self.query_slip,
            )?;
        }
        let pos = |n: u32| {
            let n = n as usize;
            let x0 = model.mesh.nodes[n];
            [x0[0] + u[3 * n], x0[1] + u[3 * n + 1], x0[2] + u[3 * n + 2]]
        };
        for (itf, st) in model.interfaces.iter().zip(&mut self.interfaces) {
            let Some(fr) = &mut st.friction else { continue };
            match &itf.primary {
                Primary::Surface { queries, .. } => {
                    fr.slip.copy_from_slice(&self.query_slip[queries.clone()]);
                    for (i, p) in st.points.iter().enumerate() {
                        fr.tangents[i] = if p.face == NO_FACE {
                            [[0.0; 3]; 2]
                        } else {
                            let x = self.queries.faces[p.face as usize].map(pos);
                            let (_, t1, t2, _) = quad::geometry(&x, p.xi);
                            [t1, t2]
                        };
                    }
                }
                Primary::Plane { normal, .. } => {
                    let e = plane_basis(*normal);
                    for (i, &n) in itf.nodes.iter().enumerate() {
                        let n = n as usize;
                        let vel = [v[3 * n], v[3 * n + 1], v[3 * n + 2]];
                        fr.tangents[i] = e;
                        fr.slip[i] = [dot(vel, e[0]), dot(vel, e[1])];
                    }
                }
            }
        }
        Ok(())
    }

    /// Nodal contact forces of the current pressures and geometry into `self.f_c`.
    fn contact_forces(&mut self) {
        self.f_c.fill(0.0);
        for (itf, st) in self.model.interfaces.iter().zip(&self.interfaces) {
            for (i, &node) in itf.nodes.iter().enumerate() {
                let t = st.lambda[i];
                if t == 0.0 {
                    continue;
                }
                let p = st.points[i];
                // traction on the secondary node: T_N n + T_T
                let mut traction = p.normal.map(|x| t * x);
                if let Some(fr) = &st.friction {
                    let tt = fr.traction_of(i);
                    for a in 0..3 {
                        traction[a] += tt[a];
                    }
                }
                let f = traction.map(|x| x * itf.area[i]);
                for a in 0..3 {
                    self.f_c[3 * node as usize + a] += f[a];
                }
                if let Primary::Surface { .. } = itf.primary {
                    let face = self.queries.faces[p.face as usize];
                    let nsh = quad::shape(p.xi);
                    for k in 0..4 {
                        for a in 0..3 {
                            self.f_c[3 * face[k] as usize + a] -= nsh[k] * f[a];
                        }
                    }
                }
            }
        }
        for d in 0..self.f_c.len() {
            if self.model.fixed[d] {
                self.f_c[d] = 0.0;
            }
        }
    }

    /// One time step. Returns the number of iterations and whether the contact converged.
    ///
    /// With the gap-rate constraint and `event_substeps` k > 1, a step that holds a contact
    /// event ([`Self::contact_event`]: an impact, a release, a ramp of the force towards one)
    /// is taken again from its start in k sub-steps of dt / k; its reported forces are then
    /// the impulse of the whole step over dt. Its iterations count both attempts.
    pub fn step(&mut self) -> Result<StepReport> {
        let k = self.settings.event_substeps;
        // a scene without contact has no events: no snapshot to keep
        let refine =
            k > 1 && self.settings.constraint == Constraint::GapRate && !self.interfaces.is_empty();
        for st in &mut self.interfaces {
            st.step_pressure.clear();
        }
        let saved = refine.then(|| Snapshot {
            u: self.u.clone(),
            v: self.v.clone(),
            a: self.a.clone(),
            interfaces: self.interfaces.clone(),
        });
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
            for (st, f0) in self.interfaces.iter_mut().zip(before) {
                st.peak_force = st.peak_force.max(st.report.normal_force);
                st.last_change = st.report.normal_force - f0;
            }
        }
        self.steps += 1;
        self.time = self.steps as f64 * self.dt;
        Ok(report)
    }

    /// Whether the step just taken holds a contact event on some interface (`before`: the
    /// interfaces as the step found them).
    /// With F0, F1 its normal force before and after, m = max(F0, F1) and
    /// r = `event_force_change`, an event is either
    /// - a change of the contact state: the nodes that came into contact or left it carry
    ///   more than r m (an impact, a release), or
    /// - a ramp: |F1 - F0| > r m, in the same direction as the step before (the arrival of
    ///   a loading or unloading wave; a force that alternates from step to step, as in a
    ///   stiff body rattling on its support, is not a ramp).
    ///
    /// Forces below [`EVENT_FORCE_FLOOR`] of the interface's peak make no event.
    fn contact_event(&self, before: &[InterfaceState]) -> bool {
        let r = self.settings.event_force_change;
        let model = self.model;
        model
            .interfaces
            .iter()
            .zip(self.interfaces.iter().zip(before))
            .any(|(itf, (st, old))| {
                let (f0, f1) = (old.report.normal_force, st.report.normal_force);
                let m = f0.max(f1);
                // no node pressed at the step's start or end: a release inside the last
                // step's sub-steps left an average F0 > 0, but nothing happens in this one
                let pressed = old.lambda.iter().chain(&st.lambda).any(|&l| l > 0.0);
                if !pressed || m <= 0.0 || m < EVENT_FORCE_FLOOR * st.peak_force {
                    return false;
                }
                let switched: f64 = itf
                    .area
                    .iter()
                    .zip(old.lambda.iter().zip(&st.lambda))
                    .filter(|(_, (&l0, &l1))| (l0 > 0.0) != (l1 > 0.0))
                    .map(|(a, (&l0, &l1))| a * l0.max(l1))
                    .sum();
                let d = f1 - f0;
                switched > r * m || (d.abs() > r * m && d * old.last_change > 0.0)
            })
    }

    /// Takes the step again from `saved` in k sub-steps of dt / k and reports each interface's
    /// impulse over the whole step / dt (the other report fields are the last sub-step's).
    fn substeps(&mut self, saved: Snapshot, k: usize) -> Result<StepReport> {
        // The penalties adapt to the compliance, which depends on the step: a pressure's
        // effect on the gap rate grows with the step where inertia resists (s ~ h) and
        // shrinks where stiffness does (s ~ 1/h), so no fixed rescaling is right. The
        // sub-steps start from the full step's penalties at the first event and from their
        // own last values after it; eq. 20 adapts them. The steps of dt keep their own.
        let full = self.penalties();
        // the penalty law's counters: the first attempt's changes, then the sub-steps'
        let counts: Vec<[usize; 4]> = self
            .interfaces
            .iter()
            .zip(&saved.interfaces)
            .map(|(st, old)| {
                let (now, before) = (st.penalty_counts(), old.penalty_counts());
                [0, 1, 2, 3].map(|i| now[i] - before[i])
            })
            .collect();
        self.u = saved.u;
        self.v = saved.v;
        self.a = saved.a;
        self.interfaces = saved.interfaces;
        for st in &mut self.interfaces {
            if let Some(p) = st.sub_penalties {
                st.set_penalties(p);
            }
        }
        let h = self.dt / k as f64;
        if self.sub_solver.is_none() {
            let asm = assemble(
                self.model,
                self.settings.mass,
                1.0 / (self.settings.beta * h * h),
            );
            self.sub_solver = Some(self.solver.sibling(&asm.effective)?);
        }
        let kf = k as f64;
        let mut total = StepReport {
            iterations: 0,
            converged: true,
        };
        // impulses of the sub-steps, normal and tangential, and each node's
        let mut sums = vec![(0.0, [0.0; 3]); self.interfaces.len()];
        for st in &mut self.interfaces {
            st.step_pressure = vec![0.0; st.lambda.len()];
        }
        for _ in 0..k {
            let r = self.advance(h, true)?;
            total.iterations += r.iterations;
            total.converged &= r.converged;
            for (sum, st) in sums.iter_mut().zip(&mut self.interfaces) {
                for (p, l) in st.step_pressure.iter_mut().zip(&st.lambda) {
                    *p += l / kf;
                }
                sum.0 += st.report.normal_force;
                for a in 0..3 {
                    sum.1[a] += st.tangential[a];
                }
            }
        }
        for (((sum, st), p), c) in sums.iter().zip(&mut self.interfaces).zip(full).zip(counts) {
            st.sub_penalties = Some(st.penalties());
            st.set_penalties(p);
            let now = st.penalty_counts();
            st.set_penalty_counts([0, 1, 2, 3].map(|i| now[i] + c[i]));
            st.report.normal_force = sum.0 / kf;
            st.tangential = sum.1.map(|x| x / kf);
            st.report.tangential_force = quad::norm(st.tangential);
        }
        self.event_steps += 1;
        Ok(total)
    }

    fn penalties(&self) -> Vec<(f64, f64)> {
        self.interfaces
            .iter()
            .map(InterfaceState::penalties)
            .collect()
    }

    /// One Newmark step of size `h` from the current state, with the run's effective matrix
    /// (`sub` false, h = dt) or the sub-step's (`sub` true, h = dt / event_substeps).
    fn advance(&mut self, h: f64, sub: bool) -> Result<StepReport> {
        let k = self.step_constants(h);
        self.predict(&k);
        self.start_contact()?;
        let mut report = StepReport::default();
        self.anderson.reset();
        for _k in 0..self.settings.max_iterations {
            let (corr, size) = self.equilibrium(&k, sub)?;
            report.iterations += 1;
            self.correct(&k)?;
            let (converged, map_changed) = self.update_multipliers(&k);
            let residual_ok =
                k.exact || corr <= 1e3 * self.kernels.unit_roundoff() * size.max(f64::MIN_POSITIVE);
            if converged && residual_ok {
                report.converged = true;
                break;
            }
            if !converged {
                self.next_multipliers(map_changed);
            }
        }
        self.accept(&k)?;
        Ok(report)
    }

    /// The constants of a step of length `h`.
    fn step_constants(&self, h: f64) -> StepConstants {
        let (dt, beta, gamma) = (h, self.settings.beta, self.settings.gamma);
        // the paper's gap rate holds the contact force constant over the step; the classical
        // gap constraint applies it at t_{n+1} in Newmark's equilibrium (module docs)
        let endpoint = self.settings.constraint == Constraint::Gap;
        StepConstants {
            dt,
            beta,
            gamma,
            c_m: 1.0 / (beta * dt * dt),
            endpoint,
            force_weight: if endpoint { 1.0 } else { 1.0 / (2.0 * beta) },
            exact: self.kernels.unit_roundoff() < 1e-12,
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
            self.u_tilde[d] = self.u[d] + dt * self.v[d] + dt * dt * (0.5 - beta) * self.a[d];
            self.v_tilde[d] = self.v[d] + dt * (1.0 - gamma) * self.a[d];
            self.u_new[d] = self.u_tilde[d] + beta * dt * dt * self.a[d];
        }
    }

    /// The broad phase and the start-of-step kinematics, which decide the candidates (g_n
    /// decides who is a candidate).
    fn start_contact(&mut self) -> Result<()> {
        self.broad_phase();
        let (u0, v0) = (std::mem::take(&mut self.u), std::mem::take(&mut self.v));
        self.kinematics(&u0, &v0)?;
        self.u = u0;
        self.v = v0;
        for st in &mut self.interfaces {
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
        self.contact_forces();
        let f_c = std::mem::take(&mut self.f_c);
        let mut w = std::mem::take(&mut self.w);
        if k.endpoint {
            w.fill(0.0);
        } else {
            self.apply_mass_inverse(&f_c, &mut w);
        }
        // residual of the effective equation at u_new
        let u_new = std::mem::take(&mut self.u_new);
        self.kernels.internal_forces_into(&u_new, &mut self.f_int)?;
        let mut inertia = std::mem::take(&mut self.inertia);
        let mut increment = std::mem::take(&mut self.increment);
        self.inertia_into(&u_new, &mut increment, &mut inertia);
        for (e, &d) in self.asm.dof_of.iter().enumerate() {
            let d = d as usize;
            self.rhs[e] =
                self.f_ext[d] + k.force_weight * f_c[d] - k.c_m * inertia[e] - self.f_int[d];
        }
        self.inertia = inertia;
        self.increment = increment;
        self.u_new = u_new;
        self.f_c = f_c;
        self.w = w;
        let mut delta = std::mem::take(&mut self.rhs);
        match (sub, &self.sub_solver) {
            (true, Some(s)) => s.solve_in_place(&mut delta),
            _ => self.solver.solve_in_place(&mut delta),
        }
        let mut corr = 0.0f64;
        let mut size = 0.0f64;
        for (e, &d) in self.asm.dof_of.iter().enumerate() {
            let d = d as usize;
            self.u_new[d] += delta[e];
            corr = corr.max(delta[e].abs());
            size = size.max((self.u_new[d] - self.u[d]).abs());
        }
        self.rhs = delta;
        Ok((corr, size))
    }

    /// Newmark's correctors from u_new, and the contact kinematics there.
    fn correct(&mut self, k: &StepConstants) -> Result<()> {
        let (dt, beta, gamma, c_m) = (k.dt, k.beta, k.gamma, k.c_m);
        for d in 0..self.u.len() {
            self.a_new[d] = c_m * (self.u_new[d] - self.u_tilde[d]) - self.w[d] / (2.0 * beta);
            self.v_new[d] = self.v_tilde[d] + gamma * dt * self.a_new[d] + dt * self.w[d];
            if self.model.fixed[d] {
                self.a_new[d] = 0.0;
                self.v_new[d] = 0.0;
            }
        }
        let (un, vn) = (
            std::mem::take(&mut self.u_new),
            std::mem::take(&mut self.v_new),
        );
        self.kinematics(&un, &vn)?;
        self.u_new = un;
        self.v_new = vn;
        Ok(())
    }

    /// The augmented Lagrange update of every interface (into `next`). Returns whether every
    /// interface converged, and whether the candidate set or a penalty changed.
    fn update_multipliers(&mut self, k: &StepConstants) -> (bool, bool) {
        let mut converged = true;
        let mut map_changed = false;
        let measure_scale = match self.settings.constraint {
            Constraint::GapRate => 0.0,
            Constraint::Gap => k.gamma / (k.beta * k.dt),
        };
        for (itf, st) in self.model.interfaces.iter().zip(&mut self.interfaces) {
            let mut grew = false;
            for i in 0..st.lambda.len() {
                let p = st.points[i];
                if p.face != NO_FACE && p.gap >= 0.0 && !st.candidate[i] {
                    st.candidate[i] = true;
                    grew = true;
                }
                st.measure[i] = match self.settings.constraint {
                    Constraint::GapRate => p.gap_rate,
                    Constraint::Gap => measure_scale * p.gap,
                };
            }
            let eps_before = (
                st.penalty.eps,
                st.friction.as_ref().map_or(0.0, |f| f.penalty.eps),
            );
            let r = augmented_lagrange::update(
                &mut st.penalty,
                &mut st.memory,
                &st.lambda,
                &st.measure,
                &st.candidate,
                &itf.area,
                &mut st.next,
            );
            if grew || r.relative_change > k.tol {
                converged = false;
            }
            if let Some(fr) = &mut st.friction {
                // tangential change relative to the larger of the normal and tangential
                // force scales: the relative change of the contact force as a whole
                let rt = fr.update(&st.next, &st.candidate, &st.points);
                if rt.change > k.tol * rt.scale.max(r.scale) {
                    converged = false;
                }
            }
            let eps_after = (
                st.penalty.eps,
                st.friction.as_ref().map_or(0.0, |f| f.penalty.eps),
            );
            map_changed |= grew || eps_after != eps_before;
        }
        (converged, map_changed)
    }

    /// The next iteration's multipliers: Anderson's (restarted when the map changed) or the
    /// plain update.
    fn next_multipliers(&mut self, map_changed: bool) {
        if self.settings.acceleration == Acceleration::Anderson {
            if map_changed {
                self.anderson.reset();
            }
            self.accelerate();
        } else {
            for st in &mut self.interfaces {
                std::mem::swap(&mut st.lambda, &mut st.next);
                if let Some(fr) = &mut st.friction {
                    fr.accept_update();
                }
            }
        }
    }

    /// Accepts the step: the new state, and each interface's report.
    fn accept(&mut self, k: &StepConstants) -> Result<()> {
        std::mem::swap(&mut self.u, &mut self.u_new);
        std::mem::swap(&mut self.v, &mut self.v_new);
        std::mem::swap(&mut self.a, &mut self.a_new);
        for (itf, st) in self.model.interfaces.iter().zip(&mut self.interfaces) {
            let mut r = ContactReport::default();
            for i in 0..st.lambda.len() {
                if st.lambda[i] > 0.0 {
                    r.normal_force += st.lambda[i] * itf.area[i];
                    r.active += 1;
                }
                if st.points[i].face != NO_FACE {
                    r.max_penetration = r.max_penetration.max(st.points[i].gap);
                }
            }
            if let Some(fr) = &mut st.friction {
                let (total, sliding) = fr.end_step(k.dt, &itf.area, &st.lambda, &st.points);
                st.tangential = total;
                r.tangential_force = quad::norm(total);
                r.sliding = sliding;
                r.friction_work = fr.work;
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

    /// The next multipliers from the current ones and their update G by Anderson's method,
    /// projected back onto the admissible set: pressures >= 0 on candidates (0 elsewhere),
    /// tractions in the tangent plane and inside the Coulomb cone of the new pressure.
    fn accelerate(&mut self) {
        let (x, g, w) = (&mut self.aa_x, &mut self.aa_g, &mut self.aa_w);
        x.clear();
        g.clear();
        w.clear();
        for (itf, st) in self.model.interfaces.iter().zip(&self.interfaces) {
            x.extend_from_slice(&st.lambda);
            g.extend_from_slice(&st.next);
            w.extend(itf.area.iter().map(|a| a.max(f64::MIN_POSITIVE)));
            if let Some(fr) = &st.friction {
                x.extend_from_slice(&fr.traction);
                g.extend_from_slice(&fr.next);
                w.extend(itf.area.iter().flat_map(|&a| [a.max(f64::MIN_POSITIVE); 3]));
            }
        }
        self.aa_out.resize(x.len(), 0.0);
        self.anderson.step(x, g, w, &mut self.aa_out);
        let mut k = 0;
        for st in &mut self.interfaces {
            let n = st.lambda.len();
            for i in 0..n {
                st.lambda[i] = if st.candidate[i] {
                    self.aa_out[k + i].max(0.0)
                } else {
                    0.0
                };
            }
            k += n;
            if let Some(fr) = &mut st.friction {
                for i in 0..n {
                    let t = [0, 1, 2].map(|a| self.aa_out[k + 3 * i + a]);
                    let r = cone_radius(fr.mu, st.lambda[i], st.candidate[i], &st.points[i]);
                    let t = cone_projection(t, st.points[i].normal, r);
                    fr.traction[3 * i..3 * i + 3].copy_from_slice(&t);
                }
                k += 3 * n;
            }
        }
    }

    /// M (x - u_tilde) on the free dofs (equation order) into `out`; `increment` receives
    /// x - u_tilde.
    fn inertia_into(&self, x: &[f64], increment: &mut [f64], out: &mut [f64]) {
        for (e, &d) in self.asm.dof_of.iter().enumerate() {
            increment[e] = x[d as usize] - self.u_tilde[d as usize];
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

    /// Energies of the current state (one internal force evaluation).
    pub fn energies(&mut self) -> Result<Energies> {
        let u = std::mem::take(&mut self.u);
        self.kernels.internal_forces_into(&u, &mut self.f_int)?;
        self.u = u;
        let strain = 0.5 * dot_slices(&self.u, &self.f_int);
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
        Ok(Energies {
            kinetic,
            strain,
            potential: -dot_slices(&self.f_ext, &self.u),
        })
    }

    /// Centre-of-mass velocity of each body.
    pub fn body_velocities(&self) -> Vec<[f64; 3]> {
        super::body_velocities(self.model, &self.asm.nodal_mass, &self.v)
    }
}

fn dot_slices(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The initial eps_N when the scene gives none: $1/\hat s$ with the mass-only compliance
/// $\hat s = \Delta t\, A (1/m_s + 1/m_p)$ (median over the interface's nodes, m the
/// lumped mass or the consistent mass's diagonal), the gap-rate
/// change per unit pressure if the elastic stiffness did not resist. The true compliance is
/// smaller, so $\epsilon s \le 1$: inside the stable range, near its centre.
fn default_penalty(model: &Model, asm: &Assembled, itf: &crate::model::Interface, dt: f64) -> f64 {
    let inv_mp = match &itf.primary {
        Primary::Plane { .. } => 0.0,
        Primary::Surface { faces, .. } => {
            let nodes = crate::mesh::Mesh::quad_nodes(&model.queries.faces[faces.clone()]);
            let mean: f64 = nodes
                .iter()
                .map(|&n| asm.impulse_mass[n as usize])
                .sum::<f64>()
                / nodes.len() as f64;
            1.0 / mean
        }
    };
    let mut s: Vec<f64> = itf
        .nodes
        .iter()
        .zip(&itf.area)
        .map(|(&n, &a)| dt * a * (1.0 / asm.impulse_mass[n as usize] + inv_mp))
        .collect();
    s.sort_by(f64::total_cmp);
    let med = s.get(s.len() / 2).copied().unwrap_or(1.0);
    1.0 / med
}

/// The body force m g on the free dofs, from the lumped nodal masses.
fn gravity_force(model: &Model, asm: &Assembled) -> Vec<f64> {
    let mut f_ext = vec![0.0; model.dofs()];
    for (n, &m) in asm.nodal_mass.iter().enumerate() {
        for a in 0..3 {
            if !model.fixed[3 * n + a] {
                f_ext[3 * n + a] = m * model.gravity[a];
            }
        }
    }
    f_ext
}

/// Each interface's multipliers, penalties (eps_N from the scene or estimated, eps_T from
/// the scene or eps_N) and friction state at the start of a run.
fn interface_states(
    model: &Model,
    settings: &ImplicitSettings,
    asm: &Assembled,
    dt: f64,
    speed_scale: f64,
) -> Vec<InterfaceState> {
    let mar = settings
        .max_gap_rate
        .unwrap_or(1e-3 * speed_scale.max(f64::MIN_POSITIVE));
    model
        .interfaces
        .iter()
        .map(|itf| {
            let eps = settings
                .penalty_normal
                .unwrap_or_else(|| default_penalty(model, asm, itf, dt));
            let n = itf.nodes.len();
            let friction = (itf.friction > 0.0).then(|| {
                let eps_t = settings.penalty_tangential.unwrap_or(eps);
                let p = Penalty::new(eps_t, settings.penalty, mar, settings.max_force_change);
                Friction::new(itf.friction, p, &itf.area)
            });
            InterfaceState {
                lambda: vec![0.0; n],
                points: vec![ContactPoint::default(); n],
                penalty: Penalty::new(eps, settings.penalty, mar, settings.max_force_change),
                friction,
                memory: IterationMemory::default(),
                candidate: vec![false; n],
                measure: vec![0.0; n],
                next: vec![0.0; n],
                endpoint_force: 0.0,
                tangential: [0.0; 3],
                peak_force: 0.0,
                last_change: 0.0,
                sub_penalties: None,
                step_pressure: Vec::new(),
                report: ContactReport::default(),
            }
        })
        .collect()
}
