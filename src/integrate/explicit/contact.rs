//! The contact impulses of an explicit step (see the module above for the constraint on the
//! step's gap rate, the split compliance and the projected Jacobi sweeps).
//!
//! [`ExplicitContact`] holds everything the contact of a step keeps and reuses, and works on
//! whatever model and velocity field it is handed: the whole model in a single process, or
//! the contact surfaces alone that every rank of a decomposed run holds
//! ([`crate::domain`]). Given the same positions, velocities and reach it takes the same
//! operations in the same order, so the impulses are the same bits.

use crate::backend::Kernels;
use crate::contact::law::ContactLaw;
use crate::error::Result;
use crate::geometry::{
    face,
    vector::{self, dot},
};
use crate::kernels::contact_gap::NO_FACE;
use crate::kernels::impulse::{self, impulse_update, ImpulseUpdate};
use crate::kernels::{ContactPoint, ContactQueries};
use crate::model::{Model, Primary};
use crate::scene::{ExplicitSettings, RigidMotion};
use rayon::prelude::*;

use super::super::state::ContactReport;
use super::super::state::StepReport;
use super::spin::Spins;

/// One contact constraint of a step: a secondary node against a face point, a plane or a
/// rigid body's surface (a face of one node, the body's).
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
    law: ContactLaw,
    /// Split compliance: gap-rate change per unit normal impulse, bounded from above.
    compliance: f64,
    /// Against a rotating rigid body: the body and the node's arm from its reference point
    /// (the surface point's velocity is the body's plus omega x arm).
    spin: Option<(u32, [f64; 3])>,
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

/// The contact of the explicit steps: the queries and their candidates, the step's
/// constraints and the interfaces' impulses and reports.
pub struct ExplicitContact {
    pub interfaces: Vec<ExplicitInterface>,
    queries: ContactQueries,
    candidate_lists: Vec<Vec<u32>>,
    query_points: Vec<ContactPoint>,
    /// The largest primary face (the search's reach beyond the motion of the step).
    pub face_size: f64,
    /// Absolute tolerance of the contact iteration (a gap rate).
    tolerance: f64,
    max_iterations: usize,
    // scratch
    constraints: Vec<NodeConstraint>,
    /// Sum of the weights of the step's constraints on each node.
    touches: Vec<f64>,
    delta: Vec<[f64; 3]>,
    /// Each constraint's relative velocity at v_{n-1/2} (before the impulses): with it the
    /// friction work and the impact loss are the tangential and normal impulses' shares of
    /// the change of the time-centred energy (docs/method-notes.md).
    before: Vec<[f64; 3]>,
    /// Whether the interfaces' entries came from a checkpoint, not from this contact's last
    /// constraints: the next step clears them all.
    restored: bool,
}

/// The velocity field a step's contact works on: the nodes' velocities (changed by the
/// impulses), those of the step before (`v_half`, for the friction work) and the inverse
/// mass per dof (zero on prescribed dofs).
pub struct ContactFields<'a> {
    pub u: &'a [f64],
    pub v: &'a mut [f64],
    pub v_half: &'a [f64],
    pub inv_mass: &'a [f64],
    /// The time the step's impulses act over, by which its reports divide them to give
    /// forces: the step, but for a run's shortened last step
    /// ([`impulse_interval`](crate::integrate::explicit::impulse_interval)).
    pub interval: f64,
    /// The rigid planes' secondary nodes whose state the fields hold, where not all: a node
    /// left out is out of every plane's reach ([`plane_gap_within_reach`]).
    pub planes: Option<&'a dyn Fn(u32) -> bool>,
    /// The rigid bodies' rotation, where a body rotates (a single process's explicit
    /// solver; a body that rotates is refused elsewhere).
    pub spins: Option<&'a mut Spins>,
}

/// Whether a node at `x0 + u` moving at `v` is within the reach of the plane through
/// `point` with unit `normal` over a step `dt`: its gap is no more negative than four steps
/// of its own motion (the device step's rule, `kernels/plane_contact.rs`). Returns the gap.
pub fn plane_gap_within_reach(
    x0: [f64; 3],
    (u, v): ([f64; 3], [f64; 3]),
    (point, normal): ([f64; 3], [f64; 3]),
    dt: f64,
) -> (f64, bool) {
    let x = std::array::from_fn(|a| x0[a] + u[a]);
    let gap = -dot(vector::sub(x, point), normal);
    (gap, within_reach(gap, v, dt))
}

/// Whether a gap is within four steps of the relative velocity `rel`'s motion,
/// $g \ge -4 \Delta t |rel|$ (a NaN gap stays in, and its NaN impulse ends the run as
/// diverged).
fn within_reach(gap: f64, rel: [f64; 3], dt: f64) -> bool {
    let reach = -4.0 * dt * vector::norm(rel);
    gap.partial_cmp(&reach) != Some(std::cmp::Ordering::Less)
}

/// A rotating body's contact: the body and the secondary node's arm from its reference point.
pub type BodyArm = Option<(u32, [f64; 3])>;

/// The gap and normal of secondary node `n` against the surface of the rigid body on node
/// `b` (interface `k`), where the node is within four steps of their relative motion of it
/// (the rigid planes' rule). Against a body that rotates (`spins`) the surface is turned,
/// its points move with the body's angular velocity too, and the body and arm come back.
pub fn rigid_gap_within_reach(
    model: &Model,
    (u, v): (&[f64], &[f64]),
    (n, b): (usize, usize),
    k: usize,
    dt: f64,
    spins: Option<&Spins>,
) -> Option<(f64, [f64; 3], BodyArm)> {
    let at = |x: &[f64], n: usize| [x[3 * n], x[3 * n + 1], x[3 * n + 2]];
    let Primary::Rigid { body, .. } = model.interfaces[k].primary else {
        return None;
    };
    if let Some(s) = spins.filter(|s| s.rotates(body)) {
        let (gap, normal, arm) = turned_gap_within_reach(model, (u, v), (n, b), body, s, dt)?;
        return Some((gap, normal, Some((body as u32, arm))));
    }
    let x0 = model.mesh.nodes[n];
    let x = std::array::from_fn(|a| x0[a] + u[3 * n + a]);
    let (distance, normal) = model.rigid[body].distance(model.mesh.nodes[b], at(u, b), x);
    let rel = vector::sub(at(v, n), at(v, b));
    within_reach(-distance, rel, dt).then_some((-distance, normal, None))
}

impl ExplicitContact {
    /// The contact of `model`'s interfaces, with the iteration's tolerance scaled by
    /// `speed_scale`; `face_size` is the largest primary face of the whole model.
    pub fn new(
        model: &Model,
        settings: &ExplicitSettings,
        speed_scale: f64,
        face_size: f64,
    ) -> Self {
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
        ExplicitContact {
            interfaces,
            queries: model.queries.clone(),
            candidate_lists: vec![Vec::new(); nq],
            query_points: vec![ContactPoint::default(); nq],
            face_size,
            tolerance: settings.tolerance * speed_scale.max(f64::MIN_POSITIVE),
            max_iterations: settings.max_iterations,
            constraints: Vec::new(),
            touches: vec![0.0; model.mesh.node_count()],
            delta: vec![[0.0; 3]; model.mesh.node_count()],
            before: Vec::new(),
            restored: false,
        }
    }

    /// The work of the prescribed rigid bodies' drivers since the start of the run.
    pub fn driver_work(&self) -> f64 {
        self.interfaces.iter().map(|i| i.report.driver_work).sum()
    }

    /// Continues from a checkpoint's interfaces.
    pub fn restore(&mut self, interfaces: Vec<ExplicitInterface>) {
        self.interfaces = interfaces;
        self.restored = true;
    }

    /// The broad phase's margin, which is also the reach of the step: the largest face plus
    /// four steps of the fastest node's motion (`speed`, over the whole model).
    pub fn margin(&self, speed: f64, dt: f64) -> f64 {
        self.face_size + 4.0 * dt * speed
    }

    /// Contact impulses of the step: the closest points of every query, then
    /// [`ExplicitContact::step_from_points`]. `margin` is [`ExplicitContact::margin`].
    pub fn step(
        &mut self,
        model: &Model,
        kernels: &mut dyn Kernels,
        f: ContactFields,
        dt: f64,
        margin: f64,
    ) -> Result<StepReport> {
        // the broad phase's margin is also the reach of the step: nodes farther from their
        // surface cannot touch it within the step, even with their neighbours' impulses
        if !self.queries.is_empty() {
            kernels.contact_search_into(
                model,
                f.u,
                f.v,
                margin,
                &mut self.queries,
                &mut self.candidate_lists,
                &mut self.query_points,
            )?;
        }
        self.step_from_points(model, f, dt, margin, None)
    }

    /// The closest point of every query, for a caller that finds them itself (the ranks of
    /// a decomposed run each find their own and gather the rest).
    pub fn query_points_mut(&mut self) -> &mut [ContactPoint] {
        &mut self.query_points
    }

    /// Contact impulses of the step from the query points found: projected Jacobi sweeps
    /// until no constraint is violated by more than the tolerance. `candidates`, where
    /// given, are the (interface, secondary node) pairs that may hold a constraint, in
    /// increasing order (the others have no query point and are no plane node within
    /// reach); without them every pair is looked at.
    pub fn step_from_points(
        &mut self,
        model: &Model,
        f: ContactFields,
        dt: f64,
        margin: f64,
        candidates: Option<&[(u32, u32)]>,
    ) -> Result<StepReport> {
        // the last step's constraints, whose entries the candidates' path clears
        let last = std::mem::take(&mut self.constraints);
        let mut f = f;
        let mut spins = f.spins.take();
        self.gather_constraints(model, &f, dt, margin, candidates, spins.as_deref());
        let count = self.constraints.len();
        let (mut jn, mut jt) = self.warm_impulses();
        match candidates {
            // only the entries the last step's constraints set
            Some(_) if !self.restored => self.clear_reported(&last),
            _ => {
                for st in &mut self.interfaces {
                    st.impulse.fill(0.0);
                    st.tangential.fill([0.0; 3]);
                    st.gap.fill(f64::NAN);
                }
                self.restored = false;
            }
        }
        // the relative velocities at v_{n-1/2}, for the friction work and the impact loss
        self.before.clear();
        let omega = omegas(spins.as_deref());
        for c in &self.constraints {
            self.before.push(relative_velocity(c, f.v_half, &omega));
        }
        let mut report = StepReport {
            iterations: 0,
            converged: true,
        };
        if count > 0 {
            report.converged = false;
            let touched = touched_nodes(&self.constraints);
            self.apply_warm((f.v, f.inv_mass), (&jn, &jt), &touched);
            for sweep in 0..self.max_iterations {
                report.iterations = sweep + 1;
                let violation = self.sweep(
                    (f.v, f.inv_mass, spins.as_deref_mut()),
                    dt,
                    (&mut jn, &mut jt),
                    &touched,
                );
                if violation <= self.tolerance {
                    report.converged = true;
                    break;
                }
            }
        }
        let omega = omegas(spins.as_deref());
        self.contact_reports(f.v, &omega, (dt, f.interval), &jn, &jt);
        self.add_driver_work(model, (f.v, &omega), &jn, &jt);
        Ok(report)
    }

    /// Adds the step's work of the prescribed rigid bodies' drivers: each constraint's
    /// impulse on its secondary node dotted with the body's (constant) velocity.
    fn add_driver_work(
        &mut self,
        model: &Model,
        (v, omega): (&[f64], &[[f64; 3]]),
        jn: &[f64],
        jt: &[[f64; 3]],
    ) {
        for (i, c) in self.constraints.iter().enumerate() {
            let k = c.interface as usize;
            let Primary::Rigid { body, node, .. } = model.interfaces[k].primary else {
                continue;
            };
            if model.rigid[body].motion == RigidMotion::Prescribed {
                let b = 3 * node as usize;
                let j: [f64; 3] = std::array::from_fn(|a| jn[i] * c.normal[a] + jt[i][a]);
                let mut work = dot(j, [v[b], v[b + 1], v[b + 2]]);
                // a spinning driver's work through the contact point's turning
                if let Some((body, arm)) = c.spin {
                    work += dot(omega[body as usize], vector::cross(arm, j));
                }
                self.interfaces[k].report.driver_work += work;
            }
        }
    }

    /// The constraints of the step at (u_n, v*) with their split compliances: surfaces from
    /// the query points, planes analytically; only nodes within one face size plus four
    /// steps of the fastest node's motion of their primary surface, or within four steps of
    /// their own motion of a plane.
    fn gather_constraints(
        &mut self,
        model: &Model,
        f: &ContactFields,
        dt: f64,
        margin: f64,
        candidates: Option<&[(u32, u32)]>,
        spins: Option<&Spins>,
    ) {
        let (u, v): (&[f64], &[f64]) = (f.u, &*f.v);
        let pairs: Vec<(usize, usize)> = match candidates {
            None => (model.interfaces.iter().enumerate())
                .flat_map(|(k, itf)| (0..itf.nodes.len()).map(move |i| (k, i)))
                .collect(),
            Some(list) => {
                debug_assert!(list.is_sorted(), "the candidates in constraint order");
                list.iter()
                    .map(|&(k, i)| (k as usize, i as usize))
                    .collect()
            }
        };
        // a plane's node whose state the fields do not hold is out of every plane's reach
        let held = |&(k, i): &(usize, usize)| {
            let itf = &model.interfaces[k];
            !f.planes.is_some_and(|p| itf.is_plane() && !p(itf.nodes[i]))
        };
        let pairs: Vec<(usize, usize)> = pairs.into_iter().filter(held).collect();
        // each pair's kinematics on all threads, collected in pair order
        let this = &*self;
        let constraints: Vec<NodeConstraint> = (pairs.par_iter())
            .with_min_len(256)
            .filter_map(|&(k, i)| this.constraint_of(model, (u, v, spins), dt, (k, i), margin))
            .collect();
        self.constraints = constraints;
        self.split_compliances(f.inv_mass, spins);
    }

    /// Zeroes the interfaces' impulses and gaps the last step's constraints `last` set.
    fn clear_reported(&mut self, last: &[NodeConstraint]) {
        for c in last {
            let st = &mut self.interfaces[c.interface as usize];
            let i = c.local as usize;
            (st.impulse[i], st.tangential[i], st.gap[i]) = (0.0, [0.0; 3], f64::NAN);
        }
    }

    /// The impulses the step's sweeps start from (the warm start): a constraint against a
    /// face or a body that does not turn, and that can be enforced, starts from its
    /// secondary node's impulses of the last step, the tangential one without its part along
    /// the new normal and returned onto the law's set; planes and new contacts start from
    /// zero.
    fn warm_impulses(&self) -> (Vec<f64>, Vec<[f64; 3]>) {
        let count = self.constraints.len();
        let (mut jn, mut jt) = (vec![0.0f64; count], vec![[0.0f64; 3]; count]);
        for (i, c) in self.constraints.iter().enumerate() {
            if c.face.is_none() || c.spin.is_some() || c.compliance <= 0.0 {
                continue;
            }
            let st = &self.interfaces[c.interface as usize];
            let l = c.local as usize;
            jn[i] = st.impulse[l].max(0.0);
            jt[i] = c.law.projected(st.tangential[l], c.normal, jn[i]);
        }
        (jn, jt)
    }

    /// The constraint of secondary node `i` of interface `k`, if it is within reach of its
    /// primary surface (`margin`) or plane.
    fn constraint_of(
        &self,
        model: &Model,
        (u, v, spins): (&[f64], &[f64], Option<&Spins>),
        dt: f64,
        (k, i): (usize, usize),
        margin: f64,
    ) -> Option<NodeConstraint> {
        let itf = &model.interfaces[k];
        let node = itf.nodes[i];
        let n = node as usize;
        let mut spin = None;
        let (face, weights, normal, gap) = match &itf.primary {
            Primary::Surface { queries, .. } => {
                let p = self.query_points[queries.start + i];
                // out of the step's reach: the broad phase's margin
                if p.face == NO_FACE || p.gap < -margin.max(f64::MIN_POSITIVE) {
                    return None;
                }
                let face = self.queries.faces[p.face as usize];
                (Some(face), face::shape(&face, p.xi), p.normal, p.gap)
            }
            Primary::Plane { point, normal } => {
                let at = |x: &[f64]| [x[3 * n], x[3 * n + 1], x[3 * n + 2]];
                let (state, plane) = ((at(u), at(v)), (*point, *normal));
                let (gap, within) = plane_gap_within_reach(model.mesh.nodes[n], state, plane, dt);
                if !within {
                    return None;
                }
                (None, [0.0; 4], *normal, gap)
            }
            Primary::Rigid { node: b, .. } => {
                let (gap, normal, arm) =
                    rigid_gap_within_reach(model, (u, v), (n, *b as usize), k, dt, spins)?;
                spin = arm;
                // a face of one node: the body's, with weight 1
                (Some([*b; 4]), [1.0, 0.0, 0.0, 0.0], normal, gap)
            }
        };
        Some(NodeConstraint {
            interface: k as u32,
            local: i as u32,
            node,
            face,
            weights,
            normal,
            gap,
            law: itf.law,
            compliance: 0.0,
            spin,
        })
    }

    /// The split compliance of every constraint of the step.
    fn split_compliances(&mut self, inv_mass: &[f64], spins: Option<&Spins>) {
        // the row-sum bound of the coupled compliance: each node's inverse mass times the sum
        // of the weights with which the step's constraints act on it (zero outside this call)
        for c in &self.constraints {
            self.touches[c.node as usize] += 1.0;
            if let Some(f) = c.face {
                for (&n, w) in f.iter().zip(&c.weights) {
                    self.touches[n as usize] += w.abs();
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
            let mut along = inv(c.node, c.normal, inv_mass);
            let mut s = self.touches[c.node as usize] * inv_max(c.node, inv_mass);
            if let Some(f) = c.face {
                for (&n, w) in f.iter().zip(&c.weights) {
                    along += w.abs() * inv(n, c.normal, inv_mass);
                    s += w.abs() * self.touches[n as usize] * inv_max(n, inv_mass);
                }
            }
            c.compliance = if along > 0.0 { s } else { 0.0 };
        }
        if let Some(spins) = spins {
            self.add_rotational_compliance(spins);
        }
        for c in &self.constraints {
            self.touches[c.node as usize] = 0.0;
            for n in c.face.into_iter().flatten() {
                self.touches[n as usize] = 0.0;
            }
        }
    }

    /// Adds the rotation of free bodies to the row-sum bound: each constraint on such a body
    /// couples with the others on it through $r_i \times n_i \cdot I_w^{-1} (r_j \times n_j)$,
    /// bounded by the body's constraint count times its largest arm squared times the
    /// largest eigenvalue of its inverse inertia.
    fn add_rotational_compliance(&mut self, spins: &Spins) {
        let nb = spins.bodies.len();
        let (mut count, mut arm) = (vec![0.0f64; nb], vec![0.0f64; nb]);
        for c in &self.constraints {
            if let Some((b, r)) = c.spin.filter(|(b, _)| spins.is_free(*b as usize)) {
                count[b as usize] += 1.0;
                arm[b as usize] = arm[b as usize].max(dot(r, r));
            }
        }
        for c in &mut self.constraints {
            if let Some((b, _)) = c.spin.filter(|(b, _)| spins.is_free(*b as usize)) {
                let b = b as usize;
                // (a normal that meets only held translations is enforced by the turning)
                c.compliance += count[b] * arm[b] * spins.inv_max[b];
            }
        }
    }

    /// One Jacobi sweep: every constraint's update from the sweep's starting velocities, on
    /// all threads; then the impulses are scattered to the nodes (and the free rotating
    /// bodies' angular impulses summed) in constraint order, so the sums do not depend on the
    /// thread count. Returns the sweep's largest violation.
    fn sweep(
        &mut self,
        (v, inv_mass, spins): (&mut [f64], &[f64], Option<&mut Spins>),
        dt: f64,
        (jn, jt): (&mut [f64], &mut [[f64; 3]]),
        touched: &[u32],
    ) -> f64 {
        let omega = omegas(spins.as_deref());
        let vs: &[f64] = v;
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
                        relative_velocity(c, vs, &omega),
                        c.normal,
                        c.compliance,
                        &c.law,
                        jn[i],
                        jt[i],
                    )
                })
            })
            .collect();
        let mut violation = 0.0f64;
        let mut angular = vec![[0.0f64; 3]; omega.len()];
        for (i, up) in updates.into_iter().enumerate() {
            let Some(up) = up else { continue };
            violation = violation.max(up.violation);
            (jn[i], jt[i]) = (up.jn, up.jt);
            self.scatter(i, up.dj, &mut angular);
        }
        if let Some(spins) = spins {
            for (b, l) in angular.iter().enumerate() {
                if spins.is_free(b) && *l != [0.0; 3] {
                    spins.add_angular_impulse(b, *l);
                }
            }
        }
        self.move_touched(v, inv_mass, touched);
        violation
    }

    /// Applies the warm start's impulses `jn`, `jt` ([`Self::warm_impulses`]; none on a
    /// turning body) to the velocities, in constraint order as a sweep applies its changes.
    fn apply_warm(
        &mut self,
        (v, inv_mass): (&mut [f64], &[f64]),
        (jn, jt): (&[f64], &[[f64; 3]]),
        touched: &[u32],
    ) {
        let mut warm = false;
        for i in 0..self.constraints.len() {
            if jn[i] > 0.0 {
                let n = self.constraints[i].normal;
                let dj = std::array::from_fn(|a| jn[i] * n[a] + jt[i][a]);
                self.scatter(i, dj, &mut []);
                warm = true;
            }
        }
        if warm {
            self.move_touched(v, inv_mass, touched);
        }
    }

    /// Adds constraint i's impulse change `dj` to its nodes' sums (and, against a turning
    /// body, the body's angular impulse to `angular`).
    fn scatter(&mut self, i: usize, dj: [f64; 3], angular: &mut [[f64; 3]]) {
        let c = &self.constraints[i];
        let n = c.node as usize;
        for (d, j) in self.delta[n].iter_mut().zip(dj) {
            *d += j;
        }
        if let Some(f) = c.face {
            for (&m, w) in f.iter().zip(&c.weights) {
                for (d, j) in self.delta[m as usize].iter_mut().zip(dj) {
                    *d -= w * j;
                }
            }
        }
        // the body takes -dj at the node: the angular impulse arm x (-dj)
        if let Some((b, arm)) = c.spin {
            let t = vector::cross(arm, dj);
            for (l, t) in angular[b as usize].iter_mut().zip(t) {
                *l -= t;
            }
        }
    }

    /// Moves the velocities of the constrained nodes and their faces' nodes (`touched`) by
    /// their sums over the inverse mass, and clears the sums.
    fn move_touched(&mut self, v: &mut [f64], inv_mass: &[f64], touched: &[u32]) {
        for &n in touched {
            let n = n as usize;
            let d = std::mem::take(&mut self.delta[n]);
            for a in 0..3 {
                v[3 * n + a] += d[a] * inv_mass[3 * n + a];
            }
        }
    }

    /// Each interface's report of the step `dt` from the final impulses `jn`, `jt`, its
    /// forces the impulses over `interval`.
    fn contact_reports(
        &mut self,
        v: &[f64],
        omega: &[[f64; 3]],
        (dt, interval): (f64, f64),
        jn: &[f64],
        jt: &[[f64; 3]],
    ) {
        let mut force = vec![[0.0f64; 3]; self.interfaces.len()];
        for st in &mut self.interfaces {
            st.report = ContactReport {
                friction_work: st.report.friction_work,
                impact_loss: st.report.impact_loss,
                driver_work: st.report.driver_work,
                ..Default::default()
            };
        }
        for i in 0..self.constraints.len() {
            let c = self.constraints[i];
            let rel = relative_velocity(&c, v, omega);
            let rn = dot(rel, c.normal);
            let st = &mut self.interfaces[c.interface as usize];
            st.impulse[c.local as usize] = jn[i];
            st.tangential[c.local as usize] = jt[i];
            st.gap[c.local as usize] = c.gap - dt * rn;
            let r = &mut st.report;
            if jn[i] > 0.0 {
                r.active += 1;
                r.normal_force += jn[i] / interval;
                if c.law.is_sliding(jt[i], jn[i], 1e-9) {
                    r.sliding += 1;
                }
            }
            for a in 0..3 {
                force[c.interface as usize][a] += jt[i][a] / interval;
                r.force[a] -= (jn[i] * c.normal[a] + jt[i][a]) / interval;
            }
            // the linearised end-of-step gap
            r.max_penetration = r.max_penetration.max(c.gap - dt * rn);
            let (impact, friction) =
                impulse::impulse_energy((jn[i], jt[i]), c.normal, (self.before[i], rel));
            r.impact_loss -= impact;
            if c.law.is_frictional() {
                r.friction_work -= friction;
            }
        }
        for (st, f) in self.interfaces.iter_mut().zip(&force) {
            st.report.tangential_force = vector::norm(*f);
        }
    }
}

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

/// Relative velocity of a constraint's secondary node against its primary point in the
/// velocity field `v`, with the rigid bodies' angular velocities `omega`.
fn relative_velocity(c: &NodeConstraint, v: &[f64], omega: &[[f64; 3]]) -> [f64; 3] {
    let rel = impulse::relative_velocity(v, c.node, c.face.as_ref().map(|f| (f, &c.weights)));
    match c.spin {
        Some((b, arm)) => vector::sub(rel, vector::cross(omega[b as usize], arm)),
        None => rel,
    }
}

/// Each rigid body's angular velocity now (none without rotating bodies).
fn omegas(spins: Option<&Spins>) -> Vec<[f64; 3]> {
    spins.map_or_else(Vec::new, |s| {
        (0..s.bodies.len()).map(|b| s.omega(b)).collect()
    })
}

/// The gap, normal and arm of secondary node `n` against the surface of the rotating rigid
/// body `body` on node `b`, where the node is within four steps of their relative motion of
/// it (the surface point moving with the body's angular velocity too).
fn turned_gap_within_reach(
    model: &Model,
    (u, v): (&[f64], &[f64]),
    (n, b): (usize, usize),
    body: usize,
    spins: &Spins,
    dt: f64,
) -> Option<(f64, [f64; 3], [f64; 3])> {
    let at = |x: &[f64], n: usize| [x[3 * n], x[3 * n + 1], x[3 * n + 2]];
    let xb = vector::add(model.mesh.nodes[b], at(u, b));
    let x = vector::add(model.mesh.nodes[n], at(u, n));
    let rb = &model.rigid[body];
    let rotation = spins.rotation(body);
    let (distance, normal) = rb.distance_turned((model.mesh.nodes[b], at(u, b)), rotation, x);
    let arm = vector::sub(x, xb);
    let surface = vector::add(at(v, b), vector::cross(spins.omega(body), arm));
    let rel = vector::sub(at(v, n), surface);
    within_reach(-distance, rel, dt).then_some((-distance, normal, arm))
}
