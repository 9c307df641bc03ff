//! The implicit path's contact iteration: the broad phase, the kinematics of every secondary
//! node through the kernels, the nodal contact forces of the multipliers, and the augmented
//! Lagrange update (plain, or accelerated by Anderson's method).

use crate::backend::Kernels;
use crate::contact::anderson::Anderson;
use crate::contact::augmented_lagrange;
use crate::contact::friction::{plane_basis, returned_traction};
use crate::error::Result;
use crate::geometry::{
    face::{self, FaceKind},
    vector::{self, dot},
};
use crate::kernels::contact_gap::{closest_on_face, face_point, NO_FACE};
use crate::kernels::{as_vec3, ContactPoint, ContactQueries};
use crate::model::{Model, Primary};
use crate::scene::{Acceleration, ConstraintMeasure};
use crate::search;

use super::super::explicit::spin::Spins;
use super::interface::InterfaceState;
use super::StepConstants;

/// Node `n`'s three values of the per-dof field `x`.
fn at(x: &[f64], n: usize) -> [f64; 3] {
    [x[3 * n], x[3 * n + 1], x[3 * n + 2]]
}

/// How much farther (in face sizes) than the closest face the face a node held in the
/// iteration before may be and still be kept ([`MultiplierIteration::keep_held_faces`]).
const FACE_HYSTERESIS: f64 = 1e-6;

/// The step's contact multipliers, found by the adaptive-penalty augmented Lagrange
/// iteration on the gap rate: the interfaces' states and the queries they are built from.
pub(super) struct MultiplierIteration {
    pub(super) interfaces: Vec<InterfaceState>,
    queries: ContactQueries,
    candidate_lists: Vec<Vec<u32>>,
    face_size: f64,
    /// The face each query held in the iteration before ([`NO_FACE`] at a step's start).
    held: Vec<u32>,
    /// Kinematics of every surface query.
    query_points: Vec<ContactPoint>,
    /// Covariant slip rates of every surface query (only when some surface has friction).
    query_slip: Vec<[f64; 2]>,
    surface_friction: bool,
    pub(super) anderson: Anderson,
    /// Multipliers of all interfaces in one vector, their update and weights, and
    /// Anderson's next multipliers.
    aa_x: Vec<f64>,
    aa_g: Vec<f64>,
    aa_w: Vec<f64>,
    aa_out: Vec<f64>,
    /// Each secondary node's arm from its rotating rigid body's reference point, as the
    /// last kinematics found it (empty for the other interfaces).
    arms: Vec<Vec<[f64; 3]>>,
}

impl MultiplierIteration {
    pub(super) fn new(model: &Model, interfaces: Vec<InterfaceState>) -> Self {
        let nq = model.queries.len();
        MultiplierIteration {
            interfaces,
            queries: model.queries.clone(),
            candidate_lists: vec![Vec::new(); nq],
            face_size: search::largest_face_size(model),
            held: vec![NO_FACE; nq],
            query_points: vec![ContactPoint::default(); nq],
            query_slip: vec![[0.0; 2]; nq],
            surface_friction: (model.interfaces.iter())
                .any(|i| i.law.is_frictional() && !i.is_plane()),
            anderson: Anderson::default(),
            aa_x: Vec::new(),
            aa_g: Vec::new(),
            aa_w: Vec::new(),
            aa_out: Vec::new(),
            arms: (model.interfaces.iter())
                .map(|itf| match itf.primary {
                    Primary::Rigid { body, .. } if model.rigid[body].rotates() => {
                        vec![[0.0; 3]; itf.nodes.len()]
                    }
                    _ => Vec::new(),
                })
                .collect(),
        }
    }

    /// Candidate primary faces of every secondary node, from the configuration u (the
    /// margin from the velocity v over a step dt).
    pub(super) fn broad_phase(&mut self, model: &Model, u: &[f64], v: &[f64], dt: f64) {
        let margin = search::margin(v, dt, self.face_size);
        search::surface_candidates(
            model,
            &mut self.queries,
            &mut self.candidate_lists,
            u,
            margin,
        );
        self.held.fill(NO_FACE);
    }

    /// Contact kinematics of every interface at (u, v) with the rigid bodies turned as
    /// `spins` has them: surfaces through the kernels, rigid planes and rigid bodies'
    /// surfaces analytically.
    pub(super) fn kinematics(
        &mut self,
        model: &Model,
        kernels: &mut dyn Kernels,
        (u, v): (&[f64], &[f64]),
        spins: &Spins,
    ) -> Result<()> {
        if !self.queries.is_empty() {
            let pts = &mut self.query_points;
            kernels.contact_gap_into(u, v, &self.queries, pts)?;
            self.keep_held_faces(model, u, v);
            let pts = &self.query_points;
            for (itf, st) in model.interfaces.iter().zip(&mut self.interfaces) {
                if let Primary::Surface { queries, .. } = &itf.primary {
                    st.points.copy_from_slice(&pts[queries.clone()]);
                }
            }
        }
        for (k, (itf, st)) in model
            .interfaces
            .iter()
            .zip(&mut self.interfaces)
            .enumerate()
        {
            if let Primary::Rigid { body, node: b, .. } = itf.primary {
                let turned = spins.rotates(body).then_some(spins);
                for (i, &n) in itf.nodes.iter().enumerate() {
                    let (point, arm) =
                        rigid_point(model, (u, v), (n as usize, b as usize), body, turned);
                    st.points[i] = point;
                    if let Some(arm) = arm {
                        self.arms[k][i] = arm;
                    }
                }
            }
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
                        gap: -dot(vector::sub(x, *point), *normal),
                        gap_rate: -dot(vel, *normal),
                    };
                }
            }
        }
        self.friction_kinematics(model, kernels, (u, v), spins)
    }

    /// Within a step, a query whose closest face changed keeps the face it held in the
    /// iteration before while that face is at most [`FACE_HYSTERESIS`] face sizes farther.
    ///
    /// A node at a vertex or edge where the primary surface is not flat is about equally
    /// close to faces with different normals; without the hysteresis the closest one can
    /// change from one iteration to the next with the last bits of u, and the iteration then
    /// flips the force's direction between them and never converges.
    fn keep_held_faces(&mut self, model: &Model, u: &[f64], v: &[f64]) {
        let (u3, v3) = (as_vec3(u), as_vec3(v));
        let x0 = &model.mesh.nodes;
        let reach = FACE_HYSTERESIS * self.face_size;
        let q = &self.queries;
        for (i, p) in self.query_points.iter_mut().enumerate() {
            let held = self.held[i];
            if held != NO_FACE && p.face != NO_FACE && held != p.face {
                let s = q.secondary[i];
                let (_, now) = closest_on_face(x0, u3, q, s, p.face);
                let (xi, before) = closest_on_face(x0, u3, q, s, held);
                if before <= now + reach {
                    *p = face_point(x0, u3, v3, q, s, held, xi);
                }
            }
            self.held[i] = p.face;
        }
    }

    /// Slip rates and tangents of the interfaces with friction: surfaces through the
    /// `slip_rate` kernel (tangents from the face at the projected point), planes with a
    /// fixed orthonormal basis.
    fn friction_kinematics(
        &mut self,
        model: &Model,
        kernels: &mut dyn Kernels,
        (u, v): (&[f64], &[f64]),
        spins: &Spins,
    ) -> Result<()> {
        if self.surface_friction {
            kernels.slip_rate_into(
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
        for (k, (itf, st)) in model
            .interfaces
            .iter()
            .zip(&mut self.interfaces)
            .enumerate()
        {
            let Some(fr) = &mut st.friction else { continue };
            match &itf.primary {
                Primary::Surface { queries, .. } => {
                    fr.slip.copy_from_slice(&self.query_slip[queries.clone()]);
                    for (i, p) in st.points.iter().enumerate() {
                        fr.tangents[i] = if p.face == NO_FACE {
                            [[0.0; 3]; 2]
                        } else {
                            let nodes = self.queries.faces[p.face as usize];
                            let x = nodes.map(pos);
                            let (_, t1, t2, _) = FaceKind::of(&nodes).geometry(&x, p.xi);
                            [t1, t2]
                        };
                    }
                }
                Primary::Plane { normal, .. } => {
                    let e = plane_basis(*normal);
                    for (i, &n) in itf.nodes.iter().enumerate() {
                        let vel = at(v, n as usize);
                        fr.tangents[i] = e;
                        fr.slip[i] = [dot(vel, e[0]), dot(vel, e[1])];
                    }
                }
                Primary::Rigid { node: b, body, .. } => {
                    let vb = at(v, *b as usize);
                    let arms = &self.arms[k];
                    for (i, &n) in itf.nodes.iter().enumerate() {
                        let e = plane_basis(st.points[i].normal);
                        let surface = match arms.is_empty() {
                            true => vb,
                            false => vector::add(vb, vector::cross(spins.omega(*body), arms[i])),
                        };
                        let rel = vector::sub(at(v, n as usize), surface);
                        fr.tangents[i] = e;
                        fr.slip[i] = [dot(rel, e[0]), dot(rel, e[1])];
                    }
                }
            }
        }
        Ok(())
    }

    /// The contact force on secondary node `i` of an interface (`itf`, `st`): the traction
    /// $T_N n + T_T$ times its area.
    fn node_force(itf: &crate::model::Interface, st: &InterfaceState, i: usize) -> [f64; 3] {
        let t = st.lambda[i];
        let mut traction = st.points[i].normal.map(|x| t * x);
        if let Some(fr) = &st.friction {
            traction = vector::add(traction, fr.traction_of(i));
        }
        traction.map(|x| x * itf.area[i])
    }

    /// The moment of interface `k`'s contact forces on its secondary nodes about its
    /// rotating rigid body's reference point, $\sum_i r_i \times f_i$ (zero for the other
    /// interfaces). The body takes its negative.
    pub(super) fn moment(&self, model: &Model, k: usize) -> [f64; 3] {
        let (itf, st) = (&model.interfaces[k], &self.interfaces[k]);
        let mut m = [0.0; 3];
        for (i, arm) in self.arms[k].iter().enumerate() {
            if st.lambda[i] != 0.0 {
                m = vector::add(m, vector::cross(*arm, Self::node_force(itf, st, i)));
            }
        }
        m
    }

    /// Nodal contact forces of the current pressures and geometry into `f_c`.
    pub(super) fn forces_into(&self, model: &Model, f_c: &mut [f64]) {
        f_c.fill(0.0);
        for (itf, st) in model.interfaces.iter().zip(&self.interfaces) {
            for (i, &node) in itf.nodes.iter().enumerate() {
                if st.lambda[i] == 0.0 {
                    continue;
                }
                let p = st.points[i];
                let f = Self::node_force(itf, st, i);
                for a in 0..3 {
                    f_c[3 * node as usize + a] += f[a];
                }
                if let Primary::Rigid { node: b, .. } = itf.primary {
                    for a in 0..3 {
                        f_c[3 * b as usize + a] -= f[a];
                    }
                }
                if let Primary::Surface { .. } = itf.primary {
                    let face = self.queries.faces[p.face as usize];
                    let nsh = face::shape(&face, p.xi);
                    for k in 0..4 {
                        for a in 0..3 {
                            f_c[3 * face[k] as usize + a] -= nsh[k] * f[a];
                        }
                    }
                }
            }
        }
        for (f, &fixed) in f_c.iter_mut().zip(&model.fixed) {
            if fixed {
                *f = 0.0;
            }
        }
    }

    /// Makes a candidate of every node whose gap at the current iterate is >= 0; returns
    /// whether any was. Called only at an iterate where the candidates' pressures have
    /// converged: a transient iterate, before the other nodes' pressures have settled, shows
    /// nodes at the surface that the converged state does not press; admitted there, they
    /// would stay candidates for the step and be stopped short of the surface, and which of
    /// them were admitted would follow the iteration's path down to the last bits of the
    /// kernels' arithmetic (`docs/method-notes.md`, "H(g), the candidate set").
    fn admit_penetrating(&mut self) -> bool {
        let mut grew = false;
        for st in &mut self.interfaces {
            for (p, c) in st.points.iter().zip(&mut st.candidate) {
                if p.face != NO_FACE && p.gap >= 0.0 && !*c {
                    *c = true;
                    grew = true;
                }
            }
        }
        grew
    }

    /// The augmented Lagrange update of every interface (into `next`). Returns whether every
    /// interface converged, and whether the candidate set or a penalty changed; the set
    /// grows only where the pressures have converged ([`Self::admit_penetrating`]).
    pub(super) fn update_multipliers(
        &mut self,
        model: &Model,
        constraint: ConstraintMeasure,
        k: &StepConstants,
    ) -> (bool, bool) {
        let mut converged = true;
        let mut pressures_settled = true;
        let mut map_changed = false;
        let measure_scale = match constraint {
            ConstraintMeasure::GapRate => 0.0,
            ConstraintMeasure::Gap => k.gamma / (k.beta * k.dt),
        };
        for (itf, st) in model.interfaces.iter().zip(&mut self.interfaces) {
            for i in 0..st.lambda.len() {
                let p = st.points[i];
                st.measure[i] = match constraint {
                    ConstraintMeasure::GapRate => p.gap_rate,
                    ConstraintMeasure::Gap => measure_scale * p.gap,
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
                k.tol,
                &mut st.next,
            );
            if r.relative_change > k.tol {
                converged = false;
                pressures_settled = false;
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
            map_changed |= eps_after != eps_before;
        }
        if pressures_settled && self.admit_penetrating() {
            return (false, true);
        }
        (converged, map_changed)
    }

    /// The next iteration's multipliers: Anderson's (restarted when the map changed) or the
    /// plain update.
    pub(super) fn next_multipliers(
        &mut self,
        model: &Model,
        acceleration: Acceleration,
        map_changed: bool,
    ) {
        if acceleration == Acceleration::Anderson {
            if map_changed {
                self.anderson.reset();
            }
            self.accelerate(model);
        } else {
            for st in &mut self.interfaces {
                std::mem::swap(&mut st.lambda, &mut st.next);
                if let Some(fr) = &mut st.friction {
                    fr.accept_update();
                }
            }
        }
    }

    /// The next multipliers from the current ones and their update G by Anderson's method,
    /// projected back onto the admissible set: pressures >= 0 on candidates (0 elsewhere),
    /// tractions in the tangent plane and inside the Coulomb cone of the new pressure.
    fn accelerate(&mut self, model: &Model) {
        let (x, g, w) = (&mut self.aa_x, &mut self.aa_g, &mut self.aa_w);
        x.clear();
        g.clear();
        w.clear();
        for (itf, st) in model.interfaces.iter().zip(&self.interfaces) {
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
                    let (p, c) = (st.lambda[i], st.candidate[i]);
                    let t = returned_traction(&fr.law, t, p, c, &st.points[i]);
                    fr.traction[3 * i..3 * i + 3].copy_from_slice(&t);
                }
                k += 3 * n;
            }
        }
    }

    /// The area-weighted size of the last update's change of the pressures,
    /// $\sqrt{\sum_i (A_i (\lambda^{next}_i - \lambda_i))^2}$.
    pub(super) fn residual(&self, model: &Model) -> f64 {
        let mut sum = 0.0;
        for (itf, st) in model.interfaces.iter().zip(&self.interfaces) {
            for ((&next, &now), &a) in st.next.iter().zip(&st.lambda).zip(&itf.area) {
                sum += (a * (next - now)).powi(2);
            }
        }
        sum.sqrt()
    }

    /// Whether some interface has friction (the Newton step leaves those to Anderson).
    pub(super) fn frictional(&self) -> bool {
        self.interfaces.iter().any(|st| st.friction.is_some())
    }

    /// The interfaces' states and the surface faces, for the Newton step.
    pub(super) fn newton_parts(&mut self) -> (&mut [InterfaceState], &[[u32; 4]]) {
        (&mut self.interfaces, &self.queries.faces)
    }

    pub(super) fn penalties(&self) -> Vec<(f64, f64)> {
        self.interfaces
            .iter()
            .map(InterfaceState::penalties)
            .collect()
    }
}

/// The kinematics of secondary node `n` against the surface of rigid body `body` on node
/// `b`: its gap, normal and gap rate, the surface as `turned` has it where the body rotates
/// (its points moving with the body's angular velocity too; the node's arm comes back).
fn rigid_point(
    model: &Model,
    (u, v): (&[f64], &[f64]),
    (n, b): (usize, usize),
    body: usize,
    turned: Option<&Spins>,
) -> (ContactPoint, Option<[f64; 3]>) {
    let (xb0, ub, vb) = (model.mesh.nodes[b], at(u, b), at(v, b));
    let x = vector::add(model.mesh.nodes[n], at(u, n));
    let rb = &model.rigid[body];
    let (distance, normal, surface, arm) = match turned {
        None => {
            let (distance, normal) = rb.distance(xb0, ub, x);
            (distance, normal, vb, None)
        }
        Some(s) => {
            let (distance, normal) = rb.distance_turned((xb0, ub), s.rotation(body), x);
            let arm = vector::sub(x, vector::add(xb0, ub));
            let surface = vector::add(vb, vector::cross(s.omega(body), arm));
            (distance, normal, surface, Some(arm))
        }
    };
    let point = ContactPoint {
        face: 0,
        xi: [0.0; 2],
        normal,
        gap: -distance,
        gap_rate: -dot(vector::sub(at(v, n), surface), normal),
    };
    (point, arm)
}
