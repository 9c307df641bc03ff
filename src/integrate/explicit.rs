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
//! velocity and returns it onto the cone $|J_T| \le \mu J_N$ in the same sweep.
//!
//! Momentum is exact (every impulse acts with its opposite on the primary face's nodes by
//! the shape functions). The history's contact force is the impulse / dt.

use crate::backend::Kernels;
use crate::contact::search;
use crate::element;
use crate::error::Result;
use crate::geometry::{
    face,
    vector::{self, dot},
};
use crate::kernels::contact_gap::NO_FACE;
use crate::kernels::impulse::{self, impulse_update, ImpulseUpdate};
use crate::kernels::{self, ContactPoint, ContactQueries};
use crate::model::Model;
use crate::model::Primary;
use crate::scene::{ExplicitSettings, Method};
use rayon::prelude::*;

use super::implicit::StepReport;
use super::integrator::Integrator;
use super::state::{ContactReport, Energies, SolverState};

/// One contact constraint of a step: a secondary node against a face point or a plane.
#[derive(Debug, Clone, Copy)]
struct NodeConstraint {
    interface: u32,
    /// Index of the secondary node within its interface.
    local: u32,
    node: u32,
    /// Primary face nodes and their shape function values (none for a plane).
    face: Option<[u32; 4]>,
    weights: [f64; 4],
    normal: [f64; 3],
    gap: f64,
    mu: f64,
    /// Split compliance: gap-rate change per unit normal impulse, bounded from above.
    compliance: f64,
}

/// Contact state of one interface over the last step.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct ExplicitInterface {
    /// Normal impulse of each secondary node over the last step.
    pub impulse: Vec<f64>,
    /// Tangential (friction) impulse of each secondary node over the last step.
    pub tangential: Vec<[f64; 3]>,
    /// Linearised end-of-step gap of each secondary node (NaN where no surface is in reach).
    pub gap: Vec<f64>,
    pub report: ContactReport,
}

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
}

pub struct ExplicitSolver<'m> {
    model: &'m Model,
    settings: ExplicitSettings,
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
    pub interfaces: Vec<ExplicitInterface>,
    /// What the time-centred energy measure shifts by over a shortened step (see
    /// [`Integrator::shorten_step`]); removed from the kinetic energy reported after it.
    measure_shift: f64,
    queries: ContactQueries,
    candidate_lists: Vec<Vec<u32>>,
    face_size: f64,
    query_points: Vec<ContactPoint>,
    /// Absolute tolerance of the contact iteration (a gap rate).
    tolerance: f64,
    // scratch
    constraints: Vec<NodeConstraint>,
    /// Sum of the weights of the step's constraints on each node.
    touches: Vec<f64>,
    delta: Vec<[f64; 3]>,
    slip_before: Vec<[f64; 3]>,
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
        let nodes = model.mesh.node_count();
        let ndof = 3 * nodes;
        let mass = lumped_mass(model);
        let inv_mass: Vec<f64> = (0..ndof)
            .map(|d| {
                if model.fixed[d] {
                    0.0
                } else {
                    1.0 / mass[d / 3]
                }
            })
            .collect();
        let f_ext: Vec<f64> = (0..ndof)
            .map(|d| {
                if model.fixed[d] {
                    0.0
                } else {
                    mass[d / 3] * model.gravity[d % 3]
                }
            })
            .collect();
        let mut v = model.initial_velocity.clone();
        for d in 0..ndof {
            if model.fixed[d] {
                v[d] = 0.0;
            }
        }
        let a: Vec<f64> = (0..ndof).map(|d| f_ext[d] * inv_mass[d]).collect();
        let face_size = search::largest_face_size(model);
        let interfaces = model
            .interfaces
            .iter()
            .map(|itf| ExplicitInterface {
                impulse: vec![0.0; itf.nodes.len()],
                tangential: vec![[0.0; 3]; itf.nodes.len()],
                gap: vec![f64::NAN; itf.nodes.len()],
                report: ContactReport::default(),
            })
            .collect();
        let nq = model.queries.len();
        // v_{-1/2} := v_0, so that the first step's energy starts from the initial one
        let v_half = v.clone();
        Ok(ExplicitSolver {
            model,
            dt,
            time: 0.0,
            steps: 0,
            kernels,
            mass,
            inv_mass,
            f_ext,
            u: vec![0.0; ndof],
            v,
            a,
            f_int: vec![0.0; ndof],
            u_prev: vec![0.0; ndof],
            v_half,
            interfaces,
            measure_shift: 0.0,
            queries: model.queries.clone(),
            candidate_lists: vec![Vec::new(); nq],
            face_size,
            query_points: vec![ContactPoint::default(); nq],
            tolerance: settings.tolerance * speed_scale.max(f64::MIN_POSITIVE),
            settings,
            constraints: Vec::new(),
            touches: vec![0.0; nodes],
            delta: vec![[0.0; 3]; nodes],
            slip_before: Vec::new(),
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
            interfaces: self.interfaces.clone(),
        }
    }

    /// Continues from a checkpoint's state (of this model: the lengths must match).
    pub fn restore_state(&mut self, s: ExplicitState) -> std::result::Result<(), String> {
        super::state::check_restore(
            (s.u.len(), self.u.len()),
            (s.interfaces.len(), self.interfaces.len()),
        )?;
        self.dt = s.dt;
        self.time = s.time;
        self.steps = s.steps;
        self.u = s.u;
        self.v = s.v;
        self.a = s.a;
        self.f_int = s.f_int;
        self.u_prev = s.u_prev;
        self.v_half = s.v_half;
        self.interfaces = s.interfaces;
        Ok(())
    }

    /// The constraints of the step at (u_n, v*): surfaces through the kernels, planes
    /// analytically; only nodes within one face size plus four steps of the fastest node's
    /// motion of their primary surface, or within four steps of their own motion of a plane.
    fn gather_constraints(&mut self) -> Result<()> {
        // the broad phase's margin is also the reach of the step: nodes farther from their
        // surface cannot touch it within the step, even with their neighbours' impulses
        let margin = search::margin(&self.v, self.dt, self.face_size);
        if !self.queries.is_empty() {
            self.kernels.contact_search_into(
                self.model,
                &self.u,
                &self.v,
                margin,
                &mut self.queries,
                &mut self.candidate_lists,
                &mut self.query_points,
            )?;
        }
        self.constraints.clear();
        for (k, itf) in self.model.interfaces.iter().enumerate() {
            for i in 0..itf.nodes.len() {
                if let Some(c) = self.constraint_of(k, i, margin) {
                    self.constraints.push(c);
                }
            }
        }
        self.split_compliances();
        Ok(())
    }

    /// The constraint of secondary node `i` of interface `k`, if it is within reach of its
    /// primary surface (`margin`) or plane.
    fn constraint_of(&self, k: usize, i: usize, margin: f64) -> Option<NodeConstraint> {
        let itf = &self.model.interfaces[k];
        let node = itf.nodes[i];
        let n = node as usize;
        let (face, weights, normal, gap) = match &itf.primary {
            Primary::Surface { queries, .. } => {
                let p = self.query_points[queries.start + i];
                if p.face == NO_FACE {
                    return None;
                }
                let face = self.queries.faces[p.face as usize];
                (Some(face), face::shape(&face, p.xi), p.normal, p.gap)
            }
            Primary::Plane { point, normal } => {
                let x0 = self.model.mesh.nodes[n];
                let x = std::array::from_fn(|a| x0[a] + self.u[3 * n + a]);
                (
                    None,
                    [0.0; 4],
                    *normal,
                    -dot(vector::sub(x, *point), *normal),
                )
            }
        };
        // a plane constrains a node alone: its reach is four steps of the node's own
        // motion (the device step's rule, kernels/plane_contact.rs)
        let reach = if face.is_none() {
            let v = &self.v[3 * n..3 * n + 3];
            -4.0 * self.dt * vector::norm([v[0], v[1], v[2]])
        } else {
            -margin.max(f64::MIN_POSITIVE)
        };
        if gap < reach {
            return None;
        }
        Some(NodeConstraint {
            interface: k as u32,
            local: i as u32,
            node,
            face,
            weights,
            normal,
            gap,
            mu: itf.friction,
            compliance: 0.0,
        })
    }

    /// The split compliance of every constraint of the step.
    fn split_compliances(&mut self) {
        // the row-sum bound of the coupled compliance: each node's inverse mass times the sum
        // of the weights with which the step's constraints act on it
        self.touches.fill(0.0);
        for c in &self.constraints {
            self.touches[c.node as usize] += 1.0;
            if let Some(f) = c.face {
                for k in 0..4 {
                    self.touches[f[k] as usize] += c.weights[k].abs();
                }
            }
        }
        let inv = |n: u32, nrm: [f64; 3], inv_mass: &[f64]| -> f64 {
            (0..3)
                .map(|a| nrm[a] * nrm[a] * inv_mass[3 * n as usize + a])
                .sum::<f64>()
        };
        // the largest inverse mass of a node bounds |n_i . M^-1 n_j| for any two unit normals,
        // also where some of its dofs are prescribed (the inverse mass along one normal does
        // not: the iteration could diverge there)
        let inv_max = |n: u32, inv_mass: &[f64]| -> f64 {
            (0..3)
                .map(|a| inv_mass[3 * n as usize + a])
                .fold(0.0, f64::max)
        };
        for c in &mut self.constraints {
            // a constraint whose normal meets only prescribed dofs cannot be enforced
            let mut along = inv(c.node, c.normal, &self.inv_mass);
            let mut s = self.touches[c.node as usize] * inv_max(c.node, &self.inv_mass);
            if let Some(f) = c.face {
                for k in 0..4 {
                    along += c.weights[k].abs() * inv(f[k], c.normal, &self.inv_mass);
                    s += c.weights[k].abs()
                        * self.touches[f[k] as usize]
                        * inv_max(f[k], &self.inv_mass);
                }
            }
            c.compliance = if along > 0.0 { s } else { 0.0 };
        }
    }

    /// Contact impulses of the step: projected Jacobi sweeps until no constraint is violated
    /// by more than the tolerance.
    fn contact(&mut self) -> Result<StepReport> {
        self.gather_constraints()?;
        for st in &mut self.interfaces {
            st.impulse.fill(0.0);
            st.tangential.fill([0.0; 3]);
            st.gap.fill(f64::NAN);
        }
        let count = self.constraints.len();
        let mut jn = vec![0.0f64; count];
        let mut jt = vec![[0.0f64; 3]; count];
        // the slip at v_{n-1/2}: with it the friction work is the tangential share of the
        // impulses' change of the time-centred energy (docs/method-notes.md)
        self.slip_before.clear();
        for i in 0..count {
            let c = self.constraints[i];
            let rel = relative_velocity(&c, &self.v_half);
            let rn = dot(rel, c.normal);
            self.slip_before
                .push(std::array::from_fn(|a| rel[a] - rn * c.normal[a]));
        }
        let mut report = StepReport {
            iterations: 0,
            converged: true,
        };
        if count > 0 {
            report.converged = false;
            let touched = touched_nodes(&self.constraints);
            for sweep in 0..self.settings.max_iterations {
                report.iterations = sweep + 1;
                if self.sweep(&mut jn, &mut jt, &touched) <= self.tolerance {
                    report.converged = true;
                    break;
                }
            }
        }
        self.contact_reports(&jn, &jt);
        Ok(report)
    }

    /// One Jacobi sweep: every constraint's update from the sweep's starting velocities, on
    /// all threads; then the impulses are scattered to the nodes in constraint order, so the
    /// sums do not depend on the thread count. Returns the sweep's largest violation.
    fn sweep(&mut self, jn: &mut [f64], jt: &mut [[f64; 3]], touched: &[u32]) -> f64 {
        let (v, dt) = (&self.v, self.dt);
        let updates: Vec<Option<ImpulseUpdate>> = self
            .constraints
            .par_iter()
            .with_min_len(256)
            .enumerate()
            .map(|(i, c)| {
                (c.compliance > 0.0).then(|| {
                    impulse_update(
                        c.gap,
                        dt,
                        relative_velocity(c, v),
                        c.normal,
                        c.compliance,
                        c.mu,
                        jn[i],
                        jt[i],
                    )
                })
            })
            .collect();
        let mut violation = 0.0f64;
        for (i, up) in updates.into_iter().enumerate() {
            let Some(up) = up else { continue };
            let c = &self.constraints[i];
            violation = violation.max(up.violation);
            (jn[i], jt[i]) = (up.jn, up.jt);
            let dj = up.dj;
            let n = c.node as usize;
            for a in 0..3 {
                self.delta[n][a] += dj[a];
            }
            if let Some(f) = c.face {
                for k in 0..4 {
                    for a in 0..3 {
                        self.delta[f[k] as usize][a] -= c.weights[k] * dj[a];
                    }
                }
            }
        }
        // only the constrained nodes and their faces' nodes moved
        for &n in touched {
            let n = n as usize;
            let d = std::mem::take(&mut self.delta[n]);
            for a in 0..3 {
                self.v[3 * n + a] += d[a] * self.inv_mass[3 * n + a];
            }
        }
        violation
    }

    /// Each interface's report of the step from the final impulses `jn`, `jt`.
    fn contact_reports(&mut self, jn: &[f64], jt: &[[f64; 3]]) {
        let dt = self.dt;
        let mut force = vec![[0.0f64; 3]; self.interfaces.len()];
        for st in &mut self.interfaces {
            let work = st.report.friction_work;
            st.report = ContactReport {
                friction_work: work,
                ..Default::default()
            };
        }
        for i in 0..self.constraints.len() {
            let c = self.constraints[i];
            let rel = relative_velocity(&c, &self.v);
            let rn = dot(rel, c.normal);
            let st = &mut self.interfaces[c.interface as usize];
            st.impulse[c.local as usize] = jn[i];
            st.tangential[c.local as usize] = jt[i];
            st.gap[c.local as usize] = c.gap - dt * rn;
            let r = &mut st.report;
            if jn[i] > 0.0 {
                r.active += 1;
                r.normal_force += jn[i] / dt;
                if c.mu > 0.0 && vector::norm(jt[i]) >= c.mu * jn[i] * (1.0 - 1e-9) {
                    r.sliding += 1;
                }
            }
            for a in 0..3 {
                force[c.interface as usize][a] += jt[i][a] / dt;
            }
            // the linearised end-of-step gap
            r.max_penetration = r.max_penetration.max(c.gap - dt * rn);
            if c.mu > 0.0 {
                let slip: [f64; 3] = std::array::from_fn(|a| rel[a] - rn * c.normal[a]);
                let before = self.slip_before[i];
                r.friction_work -= (0..3)
                    .map(|a| jt[i][a] * 0.5 * (before[a] + slip[a]))
                    .sum::<f64>();
            }
        }
        for (st, f) in self.interfaces.iter_mut().zip(&force) {
            st.report.tangential_force = vector::norm(*f);
        }
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
        let report = self.contact()?;
        self.u_prev.copy_from_slice(&self.u);
        self.v_half.copy_from_slice(&self.v);
        kernels::explicit_drift(dt, &self.v, &mut self.u);
        self.kernels
            .internal_forces_into(&self.u, &mut self.f_int)?;
        let (f_ext, f_int, inv_mass) = (&self.f_ext, &self.f_int, &self.inv_mass);
        self.a
            .par_iter_mut()
            .zip(self.v.par_iter_mut())
            .enumerate()
            .with_min_len(crate::parallel::CHUNK)
            .for_each(|(d, (a, v))| {
                *a = (f_ext[d] - f_int[d]) * inv_mass[d];
                *v += 0.5 * dt * *a;
            });
        self.time += dt;
        self.steps += 1;
        Ok(report)
    }

    fn reports(&self) -> Vec<ContactReport> {
        self.interfaces.iter().map(|i| i.report).collect()
    }

    fn node_contact(&self, interface: usize, point: usize) -> (f64, f64) {
        let st = &self.interfaces[interface];
        let area = self.model.interfaces[interface].area[point];
        (st.impulse[point] / (self.dt * area), st.gap[point])
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

    fn checkpoint_state(&mut self) -> Result<SolverState> {
        Ok(SolverState::Explicit(self.state()))
    }

    fn restore(&mut self, state: SolverState) -> std::result::Result<(), String> {
        match state {
            SolverState::Explicit(s) => self.restore_state(s),
            _ => Err(super::integrator::other_integrator()),
        }
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
            let v = &self.v;
            let kinetic = 0.5 * ordered_sum(v.len(), |d| mass[d / 3] * v[d] * v[d]);
            return Ok(Energies {
                kinetic,
                strain: 0.5 * dot(&self.u, &self.f_int),
                potential: -dot(&self.f_ext, &self.u),
            });
        }
        let v = &self.v_half;
        let kinetic = 0.5 * ordered_sum(v.len(), |d| mass[d / 3] * v[d] * v[d]);
        let potential = -0.5 * (dot(&self.f_ext, &self.u_prev) + dot(&self.f_ext, &self.u));
        Ok(Energies {
            kinetic: kinetic - self.measure_shift,
            strain: 0.5 * dot(&self.u_prev, &self.f_int),
            potential,
        })
    }

    fn end_at(&mut self, time: f64) {
        self.time = time;
    }
}

/// The lumped mass of every node: each element's corner masses on all threads, a block of
/// elements at a time, then summed to the nodes in element order (the same sums, bit for
/// bit, on any number of threads).
pub fn lumped_mass(model: &Model) -> Vec<f64> {
    let mesh = &model.mesh;
    let rho = |m: u32| model.materials[m as usize].density;
    let mut mass = vec![0.0; mesh.node_count()];
    scatter_blocks(&mesh.hexes, &mesh.hex_material, &mut mass, |h, m| {
        element::hex8::lumped_mass(&h.map(|n| mesh.nodes[n as usize]), rho(m))
    });
    scatter_blocks(&mesh.tets, &mesh.tet_material, &mut mass, |t, m| {
        element::tet4::lumped_mass(&t.map(|n| mesh.nodes[n as usize]), rho(m))
    });
    mass
}

/// Adds each element's corner values `f(element, material)` to its nodes in `out`: the values
/// of a block of elements on all threads, then the sums in element order.
fn scatter_blocks<const N: usize>(
    elements: &[[u32; N]],
    material: &[u32],
    out: &mut [f64],
    f: impl Fn(&[u32; N], u32) -> [f64; N] + Sync,
) {
    use rayon::prelude::*;
    const BLOCK: usize = 1 << 16;
    for (els, mats) in elements.chunks(BLOCK).zip(material.chunks(BLOCK)) {
        let values: Vec<[f64; N]> = (els.par_iter().zip(mats)).map(|(e, &m)| f(e, m)).collect();
        for (e, v) in els.iter().zip(&values) {
            for k in 0..N {
                out[e[k] as usize] += v[k];
            }
        }
    }
}

/// Relative velocity of a constraint's secondary node against its primary point in the
/// velocity field `v`.
/// The nodes a step's constraints act on (their own and their faces'), sorted, once each.
fn touched_nodes(constraints: &[NodeConstraint]) -> Vec<u32> {
    let mut nodes: Vec<u32> = constraints
        .iter()
        .flat_map(|c| std::iter::once(c.node).chain(c.face.into_iter().flatten()))
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

fn relative_velocity(c: &NodeConstraint, v: &[f64]) -> [f64; 3] {
    impulse::relative_velocity(v, c.node, c.face.as_ref().map(|f| (f, &c.weights)))
}
