//! A static step's contact: every secondary node's gap at a configuration, linearised as a
//! row $b = \partial g / \partial x$ over the node and what it presses on, and the forces
//! and stiffness of its pressure.
//!
//! A node's pressure is $T = \langle \lambda + \epsilon g \rangle$ (g > 0 a penetration):
//! - with a soft law on the contact ([`PressureLaw`]: `stiffness`, CalculiX's linear
//!   pressure-overclosure, or `exponential`), T is the law's p(g), and $\epsilon$ its slope
//!   at the iterate: the bodies overlap by $T / \epsilon$ under a linear law;
//! - without one (hard contact), $\epsilon$ is a penalty made from the node's stiffness and
//!   $\lambda$ the augmented Lagrange multiplier, updated as $\lambda \leftarrow T$ until the
//!   penetration is below the tolerance: the paper's iteration on the gap increment (the gap
//!   rate times the increment, summed over the increments).
//!
//! The force on the secondary node is $T A n$ and its opposite goes to the primary face's
//! corners by their shape functions (or to a rigid body's node); the stiffness is
//! $\epsilon A\, b\, b^T$ on the nodes the row touches. Within an increment each row keeps
//! the face, point and normal found at its start, its gap linear in the displacement
//! ([`StaticContact::linear_gaps`]), so that Newton's iteration on a fixed active set is exact.

use crate::backend::Kernels;
use crate::error::Result;
use crate::geometry::{face, vector};
use crate::integrate::state::ContactReport;
use crate::kernels::contact_gap::NO_FACE;
use crate::kernels::{ContactPoint, ContactQueries};
use crate::model::{Model, Primary};
use crate::scene::PressureLaw;

use super::friction::{Friction, Traction};
use crate::search;

/// No corner: a row's unused slot (a plane's, or a rigid body's after its node).
pub(super) const NO_NODE: u32 = u32::MAX;

/// The pressed rows: (interface, point, the corners it presses on) of each.
pub(super) type ActiveSet = Vec<(u32, u32, [u32; 4])>;

/// One secondary node's linearised gap: $b$ is $-n$ on `node` and $w_k n$ on `others[k]`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Row {
    pub interface: usize,
    /// The node's index among its interface's secondary nodes.
    pub point: usize,
    pub node: u32,
    pub others: [u32; 4],
    pub weights: [f64; 4],
    pub normal: [f64; 3],
    /// The gap at the increment's start, and at the iterate ([`StaticContact::linear_gaps`]).
    pub start_gap: f64,
    pub gap: f64,
    pub area: f64,
    /// The node's motion against its face over the increment, $-\sum_j c_j \Delta u_j$.
    pub dx: [f64; 3],
}

impl Row {
    /// The row's nodes with the factor of the normal in b on each.
    pub fn entries(&self) -> impl Iterator<Item = (u32, f64)> + '_ {
        std::iter::once((self.node, -1.0)).chain(
            (self.others.iter().zip(&self.weights))
                .filter(|(&n, &w)| n != NO_NODE && w != 0.0)
                .map(|(&n, &w)| (n, w)),
        )
    }
}

/// The contact of a static run: the surface queries, each interface's multipliers and
/// penalties, and the rows and pressures of the last kinematics.
pub(super) struct StaticContact {
    queries: ContactQueries,
    lists: Vec<Vec<u32>>,
    pub face_size: f64,
    /// Per interface and secondary node: the multiplier (pressure) and the penalty.
    pub lambda: Vec<Vec<f64>>,
    pub eps: Vec<Vec<f64>>,
    /// Each interface's soft law (none: hard contact, its multipliers iterating).
    laws: Vec<Option<PressureLaw>>,
    pub friction: Friction,
    pub rows: Vec<Row>,
    points: Vec<ContactPoint>,
}

impl StaticContact {
    /// The contact of `model`, each node's penalty $\epsilon$ from `node_stiffness` (a
    /// stiffness per node, force per length): `factor` times it over the node's area, or
    /// the interface's own stiffness.
    pub fn new(model: &Model, node_stiffness: &[f64], factor: f64) -> Self {
        let (mut lambda, mut eps) = (Vec::new(), Vec::new());
        let mut friction = Friction {
            mu: Vec::new(),
            slope: Vec::new(),
            tau: Vec::new(),
        };
        for itf in &model.interfaces {
            friction.mu.push(itf.law.coefficient());
            friction.tau.push(vec![[0.0; 3]; itf.nodes.len()]);
            lambda.push(vec![0.0; itf.nodes.len()]);
            eps.push(
                (itf.nodes.iter().zip(&itf.area))
                    .map(|(&n, &a)| factor * node_stiffness[n as usize] / a.max(f64::MIN_POSITIVE))
                    .collect(),
            );
            // the stick slope given, or the node's own stiffness over its area (the hard
            // contact's penalty over its factor: CalculiX's advice, a hundredth of the
            // normal penalty)
            let own: &Vec<f64> = eps.last().expect("pushed just now");
            friction.slope.push(match itf.stick_slope {
                Some(k) => vec![k; itf.nodes.len()],
                None => own.iter().map(|e| e / factor).collect(),
            });
        }
        let nq = model.queries.len();
        StaticContact {
            queries: model.queries.clone(),
            lists: vec![Vec::new(); nq],
            face_size: search::largest_face_size(model),
            lambda,
            eps,
            laws: model.interfaces.iter().map(|i| i.pressure_law).collect(),
            friction,
            rows: Vec::new(),
            points: vec![ContactPoint::default(); nq],
        }
    }

    /// The surfaces' candidate faces at `u`, within `margin`.
    pub fn broad_phase(&mut self, model: &Model, u: &[f64], margin: f64) {
        search::surface_candidates(model, &mut self.queries, &mut self.lists, u, margin);
    }

    /// The rows of every secondary node that faces something at `u`.
    pub fn kinematics(
        &mut self,
        model: &Model,
        kernels: &mut dyn Kernels,
        u: &[f64],
        zero: &[f64],
    ) -> Result<()> {
        if !self.queries.is_empty() {
            kernels.contact_gap_into(u, zero, &self.queries, &mut self.points)?;
        }
        self.rows.clear();
        for (k, itf) in model.interfaces.iter().enumerate() {
            for (i, &n) in itf.nodes.iter().enumerate() {
                let row = |others, weights, p: ContactPoint| Row {
                    interface: k,
                    point: i,
                    node: n,
                    others,
                    weights,
                    normal: p.normal,
                    start_gap: p.gap,
                    gap: p.gap,
                    area: itf.area[i],
                    dx: [0.0; 3],
                };
                match &itf.primary {
                    Primary::Surface { queries, .. } => {
                        let p = self.points[queries.start + i];
                        if p.face != NO_FACE {
                            let corners = self.queries.faces[p.face as usize];
                            self.rows.push(row(corners, face::shape(&corners, p.xi), p));
                        }
                    }
                    Primary::Plane { point, normal } => {
                        let x = vector::add(model.mesh.nodes[n as usize], at(u, n as usize));
                        let p = ContactPoint {
                            normal: *normal,
                            gap: -vector::dot(vector::sub(x, *point), *normal),
                            ..Default::default()
                        };
                        self.rows.push(row([NO_NODE; 4], [0.0; 4], p));
                    }
                    Primary::Rigid { body, node: b, .. } => {
                        let rb = &model.rigid[*body];
                        let xb0 = model.mesh.nodes[*b as usize];
                        let x = vector::add(model.mesh.nodes[n as usize], at(u, n as usize));
                        let (distance, normal) = rb.distance(xb0, at(u, *b as usize), x);
                        let p = ContactPoint {
                            normal,
                            gap: -distance,
                            ..Default::default()
                        };
                        let others = [*b, NO_NODE, NO_NODE, NO_NODE];
                        self.rows.push(row(others, [1.0, 0.0, 0.0, 0.0], p));
                    }
                }
            }
        }
        Ok(())
    }

    /// Each row's gap at `u`, linearised about the increment's start `u0`:
    /// $g = g_0 + b \cdot (u - u_0)$ (the gap increment is the gap rate times the increment,
    /// with the row's normal and face held over it).
    pub fn linear_gaps(&mut self, u: &[f64], u0: &[f64]) {
        for r in &mut self.rows {
            let (mut g, mut dx) = (r.start_gap, [0.0; 3]);
            for (n, c) in r.entries() {
                let d = 3 * n as usize;
                for a in 0..3 {
                    g += c * r.normal[a] * (u[d + a] - u0[d + a]);
                    dx[a] -= c * (u[d + a] - u0[d + a]);
                }
            }
            r.gap = g;
            r.dx = dx;
        }
    }

    /// The pressure of a row at its gap.
    pub fn pressure(&self, r: &Row) -> f64 {
        self.pressure_slope(r).0
    }

    /// The pressure of a row at its gap and its slope dT/dg.
    fn pressure_slope(&self, r: &Row) -> (f64, f64) {
        if let Some(law) = &self.laws[r.interface] {
            return law.at(r.gap);
        }
        let e = self.eps[r.interface][r.point];
        let t = self.lambda[r.interface][r.point] + e * r.gap;
        if t > 0.0 {
            (t, e)
        } else {
            (0.0, 0.0)
        }
    }

    /// Whether every pressed row's slope is constant over the increment (no exponential
    /// law pressed), so that a factor of the same active set is the exact tangent.
    pub fn slopes_fixed(&self) -> bool {
        !(self.rows.iter()).any(|r| {
            let curved = matches!(
                self.laws[r.interface],
                Some(PressureLaw::Exponential { .. })
            );
            (curved || self.friction.is_frictional(r.interface)) && self.pressure(r) > 0.0
        })
    }

    /// The friction traction of a pressed row of a frictional interface.
    pub fn traction(&self, r: &Row) -> Option<Traction> {
        let t = self.pressure(r);
        (t > 0.0 && self.friction.is_frictional(r.interface))
            .then(|| self.friction.traction(r, t, r.dx))
    }

    /// Ends an accepted increment: each node keeps its traction for the next (none where
    /// it is not pressed). Returns the friction's work on the bodies over the increment,
    /// $\sum A \tfrac12 (\tau_n + \tau) \cdot \Delta x$.
    pub fn commit_friction(&mut self) -> Vec<f64> {
        let mut next: Vec<Vec<[f64; 3]>> = (self.friction.tau.iter())
            .map(|t| vec![[0.0; 3]; t.len()])
            .collect();
        let mut work = vec![0.0; next.len()];
        for r in &self.rows {
            if let Some(f) = self.traction(r) {
                let old = self.friction.tau[r.interface][r.point];
                work[r.interface] += r.area
                    * (0..3)
                        .map(|a| 0.5 * (old[a] + f.tau[a]) * r.dx[a])
                        .sum::<f64>();
                next[r.interface][r.point] = f.tau;
            }
        }
        self.friction.tau = next;
        // the next increment's motion starts here
        for r in &mut self.rows {
            r.dx = [0.0; 3];
        }
        work
    }

    /// Brings each node's traction inside its interface's cone at its pressure, as a step
    /// that lowers the friction finds them: the stick slopes let go of the difference
    /// (dissipated; no node moves, so no work is done).
    pub fn fit_to_cones(&mut self) {
        for r in &self.rows {
            let limit = self.friction.mu[r.interface] * self.pressure(r);
            let tau = &mut self.friction.tau[r.interface][r.point];
            let size = vector::norm(*tau);
            if size > limit {
                let s = limit / size;
                *tau = [tau[0] * s, tau[1] * s, tau[2] * s];
            }
        }
    }

    /// The energy interface `k`'s stick slopes hold: $\sum A |\tau|^2 / (2 k_t)$.
    pub fn stick_energy(&self, k: usize) -> f64 {
        (self.rows.iter().filter(|r| r.interface == k))
            .map(|r| {
                let t = self.friction.tau[r.interface][r.point];
                let kt = self.friction.slope[r.interface][r.point];
                match kt > 0.0 {
                    true => r.area * vector::dot(t, t) / (2.0 * kt),
                    false => 0.0,
                }
            })
            .sum()
    }

    /// The rows carrying pressure, as (interface, point) pairs: the active set.
    pub fn active_set(&self) -> ActiveSet {
        (self.rows.iter())
            .filter(|r| self.pressure(r) > 0.0)
            .map(|r| (r.interface as u32, r.point as u32, r.others))
            .collect()
    }

    /// Adds every pressed row's force $-T A b$ to `f` (per dof).
    pub fn add_forces(&self, f: &mut [f64]) {
        for r in &self.rows {
            let t = self.pressure(r);
            if t > 0.0 {
                let tau = self.traction(r).map_or([0.0; 3], |x| x.tau);
                for (n, c) in r.entries() {
                    for a in 0..3 {
                        f[3 * n as usize + a] -= r.area * c * (t * r.normal[a] + tau[a]);
                    }
                }
            }
        }
    }

    /// The stiffness $\epsilon A\, b b^T$ of every pressed row, as triplets on the
    /// equations `equation` gives (fixed dofs left out).
    pub fn triplets(&self, equation: &[u32], out: &mut Vec<(u32, u32, f64)>) {
        for r in self.rows.iter().filter(|r| self.pressure(r) > 0.0) {
            let k = self.pressure_slope(r).1 * r.area;
            let friction = self.traction(r);
            for (m, cm) in r.entries() {
                for (n, cn) in r.entries() {
                    for a in 0..3 {
                        let row = equation[3 * m as usize + a];
                        if row == u32::MAX {
                            continue;
                        }
                        for b in 0..3 {
                            let col = equation[3 * n as usize + b];
                            if col != u32::MAX {
                                let mut v = k * cm * cn * r.normal[a] * r.normal[b];
                                if let Some(f) = &friction {
                                    let block = Friction::block(r, f.sliding, a, b);
                                    v += f.stiffness * r.area * cm * cn * block;
                                }
                                out.push((row, col, v));
                            }
                        }
                    }
                }
            }
        }
    }

    /// The largest gap, open or closed, of a hard interface's pressed node: zero where the
    /// multipliers hold the contact exactly (a pressed node whose gap opened carries a
    /// multiplier that the next update lowers).
    pub fn hard_violation(&self) -> f64 {
        (self.rows.iter())
            .filter(|r| self.laws[r.interface].is_none() && self.pressure(r) > 0.0)
            .fold(0.0, |m, r| m.max(r.gap.abs()))
    }

    /// The multipliers' update $\lambda \leftarrow T$ on the hard interfaces; a node that
    /// no longer faces anything keeps none.
    pub fn update_multipliers(&mut self) {
        let mut next: Vec<Vec<f64>> = (self.lambda.iter()).map(|l| vec![0.0; l.len()]).collect();
        for r in &self.rows {
            if self.laws[r.interface].is_none() {
                next[r.interface][r.point] = self.pressure(r);
            }
        }
        for (k, l) in next.into_iter().enumerate() {
            if self.laws[k].is_none() {
                self.lambda[k] = l;
            }
        }
    }

    /// The energy the pressed rows hold: a soft law's integral of its pressure, and
    /// $A (\lambda g + \tfrac12 \epsilon g^2)$ on a hard contact (about zero converged).
    pub fn stored_energy(&self) -> f64 {
        (self.rows.iter())
            .filter(|r| self.pressure(r) > 0.0)
            .map(|r| {
                if let Some(law) = &self.laws[r.interface] {
                    return r.area * law.energy(r.gap);
                }
                let (l, e) = (
                    self.lambda[r.interface][r.point],
                    self.eps[r.interface][r.point],
                );
                r.area * (l * r.gap + 0.5 * e * r.gap * r.gap)
            })
            .sum()
    }

    /// Each interface's report at the last kinematics: the normal force, the pressed nodes,
    /// the largest penetration and the force on the primary side.
    pub fn reports(&self, model: &Model) -> Vec<ContactReport> {
        let mut out = vec![ContactReport::default(); model.interfaces.len()];
        let mut tangential = vec![[0.0; 3]; model.interfaces.len()];
        for r in &self.rows {
            let t = self.pressure(r);
            if t > 0.0 {
                let friction = self.traction(r);
                let tau = friction.as_ref().map_or([0.0; 3], |f| f.tau);
                let rep = &mut out[r.interface];
                rep.normal_force += t * r.area;
                rep.active += 1;
                // on the cone (an accepted increment's traction returns as its own trial)
                let limit = self.friction.mu[r.interface] * t;
                rep.sliding +=
                    usize::from(limit > 0.0 && vector::norm(tau) >= (1.0 - 1e-9) * limit);
                rep.max_penetration = rep.max_penetration.max(r.gap);
                for a in 0..3 {
                    rep.force[a] -= r.area * (t * r.normal[a] + tau[a]);
                    tangential[r.interface][a] += r.area * tau[a];
                }
            }
        }
        for (rep, t) in out.iter_mut().zip(tangential) {
            rep.tangential_force = vector::norm(t);
        }
        out
    }

    /// The pressure and gap of point `point` of `interface` (the gap NaN where it faces
    /// nothing).
    pub fn node_contact(&self, interface: usize, point: usize) -> (f64, f64) {
        (self.rows.iter())
            .find(|r| r.interface == interface && r.point == point)
            .map_or((0.0, f64::NAN), |r| (self.pressure(r), r.gap))
    }
}

fn at(x: &[f64], n: usize) -> [f64; 3] {
    [x[3 * n], x[3 * n + 1], x[3 * n + 2]]
}
