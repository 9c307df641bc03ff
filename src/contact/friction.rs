//! Coulomb friction in the augmented Lagrange iteration (method.md sections 1 and 3).
//!
//! **Kinematics, convected.** The `slip_rate` kernel gives the covariant slip rates
//! $\dot g_{T,a} = (v_1 - v_2(\bar\xi)) \cdot \tau_a$ of each secondary node in the convected
//! basis of its primary face; the tangential relative velocity is
//! $v_T = m^{ab} \dot g_{T,b}\, \tau_a$ ($m^{ab}$ the inverse metric). A rigid plane's basis is
//! a fixed orthonormal pair, so there $v_T = \dot g_{T,a} e_a$.
//!
//! **Update (eq. 16, tangential).** With the traction $T_T$ on the secondary node (the force
//! per unit area acting on it; the primary face gets the opposite, spread by the shape
//! functions), iteration k+1 forms the trial
//!
//! $T^{*} = T_T^{(k)} - \epsilon_T\, (v_{T,n} + v_{T,n+1}^{(k+1)})$,
//!
//! in covariant components $T_{Ta} \leftarrow T_{Ta} - \epsilon_T (\dot g_{Ta,n} + \dot
//! g_{Ta,n+1})$, and returns it to the Coulomb cone of the same iteration's pressure:
//! $T_T^{(k+1)} = T^{*}$ if $|T^{*}| \le \mu T_N^{(k+1)}$ (stick), else
//! $\mu T_N^{(k+1)} T^{*}/|T^{*}|$ (slip). A node without pressure carries no traction
//! ($H$, and $\mu T_N = 0$).
//!
//! **Which slip rate: the step's mean [interpretation].** The normal constraint acts on the
//! end-of-step gap rate, as the paper prints it. The tangential one acts on the mean slip
//! velocity of the step, $\tfrac12(v_{T,n} + v_{T,n+1})$, which for the trapezoidal rule is
//! the relative tangential displacement of the step over dt. At the fixed point a sticking node
//! does not slip over the step, and a sliding node has $T_T$ parallel to minus its slip over
//! the step with $|T_T| = \mu T_N$: the paper's direction law. With the force held constant
//! over the step the friction work of the step is $\Delta t \sum_i A_i T_{T,i} \cdot
//! \tfrac12 (v_{T,n} + v_{T,n+1})$, which is then $0$ for sticking and
//! $-\Delta t\,\mu T_N A |\bar v_T|$ for sliding nodes: friction can only dissipate, exactly.
//! Acting on $v_{T,n+1}$ instead leaves a term $\tfrac{\Delta t}{2} T_T \cdot v_{T,n}$ of
//! either sign at every stick transition, and on a stiff block it raised the total energy
//! by up to 1e-5 of its scale per step (docs/method-notes.md). The price: a node that comes
//! to rest in a step keeps a velocity that alternates in sign, bounded by the velocity change
//! friction can make in one step ($\mu g \Delta t$ for a block on a floor), with no drift.
//!
//! **Penalty.** eps_T has its own [`Penalty`], adapted by the same law as eps_N
//! ([`augmented_lagrange::update_with`]): the measured tangential compliance along the last
//! traction change, an oscillation test on the traction change, and the largest sliding
//! speed of a sticking node against MAR.
//!
//! **From step to step.** The converged traction is stored as its convected covariant
//! components $T_a = T_T \cdot \tau_a$ with the face they refer to. The next step starts
//! from $T_T = m^{ab} T_b \tau_a$ in the face's new basis, so the traction turns and
//! stretches with the surface. When the contact point has moved to another face, the
//! stored vector is projected onto the new tangent plane and rescaled to its old magnitude.
//!
//! **Work.** The contact force is held constant over a step, and for the trapezoidal rule
//! the relative displacement over the step is $\tfrac{\Delta t}{2}(v_{T,n} + v_{T,n+1})$, so
//! the friction force does the work $\tfrac{\Delta t}{2}\sum_i A_i T_{T,i}\cdot(v_{T,n} +
//! v_{T,n+1})$; [`Friction::work`] accumulates its negative, the energy friction dissipated.

use super::augmented_lagrange::{update_with, IterationMemory, Penalty, UpdateReport};
use super::law::ContactLaw;
use crate::geometry::point::{ContactPoint, NO_FACE};
use crate::geometry::vector::{cross, dot, norm, V3};

/// A node slides when its traction is within this relative distance of the cone.
const ON_CONE: f64 = 1e-9;

/// Two orthonormal tangents of a plane with unit normal `n`.
pub(crate) fn plane_basis(n: V3) -> [V3; 2] {
    // the coordinate axis least aligned with n
    let k = (0..3)
        .min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .unwrap_or(0);
    let mut e = [0.0; 3];
    e[k] = 1.0;
    let t1 = cross(n, e);
    let l = norm(t1);
    let t1 = [t1[0] / l, t1[1] / l, t1[2] / l];
    [t1, cross(n, t1)]
}

/// `t` without its component along the unit normal `n`.
fn tangential_part(t: V3, n: V3) -> V3 {
    let tn = dot(t, n);
    [t[0] - tn * n[0], t[1] - tn * n[1], t[2] - tn * n[2]]
}

/// The force bound of a node's law under `pressure` where it is a candidate with a contact
/// point, else 0.
fn bound_of(law: &ContactLaw, pressure: f64, candidate: bool, point: &ContactPoint) -> f64 {
    if candidate && point.face != NO_FACE {
        law.bound(pressure)
    } else {
        0.0
    }
}

/// The traction of a node's law from the trial `t`: returned onto the law's set for
/// `pressure` where the node is a candidate with a contact point, else zero.
pub(crate) fn returned_traction(
    law: &ContactLaw,
    t: V3,
    pressure: f64,
    candidate: bool,
    point: &ContactPoint,
) -> V3 {
    if bound_of(law, pressure, candidate, point) <= 0.0 {
        return [0.0; 3];
    }
    law.projected(t, point.normal, pressure)
}

/// $m^{ab} c_b \tau_a$: the vector whose covariant components in the basis `t` are `c`.
pub(crate) fn from_covariant(t: &[V3; 2], c: [f64; 2]) -> V3 {
    let (m11, m12, m22) = (dot(t[0], t[0]), dot(t[0], t[1]), dot(t[1], t[1]));
    let det = m11 * m22 - m12 * m12;
    if det <= 0.0 {
        return [0.0; 3];
    }
    let a1 = (m22 * c[0] - m12 * c[1]) / det;
    let a2 = (m11 * c[1] - m12 * c[0]) / det;
    [0, 1, 2].map(|k| a1 * t[0][k] + a2 * t[1][k])
}

/// Friction state of one interface whose law is frictional, kept from step to step.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Friction {
    pub law: ContactLaw,
    pub penalty: Penalty,
    memory: IterationMemory,
    /// Tangential traction of each secondary node, 3 global components per node: the iterate
    /// whose forces were applied in the last solve.
    pub traction: Vec<f64>,
    /// The last update's tractions, 3 per node.
    pub next: Vec<f64>,
    /// $-(v_{T,n} + v_{T,n+1})$ of each node, 3 per node (the update is `T + eps * measure`).
    measure: Vec<f64>,
    /// Tributary area of each component.
    weight: Vec<f64>,
    /// Covariant tangents tau_1, tau_2 at each node's contact point (latest kinematics).
    pub tangents: Vec<[V3; 2]>,
    /// Covariant slip rates at each node's contact point (latest kinematics).
    pub slip: Vec<[f64; 2]>,
    /// Converged traction of the last step: covariant components, their face, the vector.
    carried: Vec<[f64; 2]>,
    carried_face: Vec<u32>,
    carried_vector: Vec<V3>,
    /// Tangential relative velocity at the start of the step.
    start_velocity: Vec<V3>,
    /// Energy dissipated by friction since the start of the run.
    pub work: f64,
}

impl Friction {
    pub fn new(law: ContactLaw, penalty: Penalty, area: &[f64]) -> Self {
        let n = area.len();
        Friction {
            law,
            penalty,
            memory: IterationMemory::default(),
            traction: vec![0.0; 3 * n],
            next: vec![0.0; 3 * n],
            measure: vec![0.0; 3 * n],
            weight: area.iter().flat_map(|&a| [a; 3]).collect(),
            tangents: vec![[[0.0; 3]; 2]; n],
            slip: vec![[0.0; 2]; n],
            carried: vec![[0.0; 2]; n],
            carried_face: vec![NO_FACE; n],
            carried_vector: vec![[0.0; 3]; n],
            start_velocity: vec![[0.0; 3]; n],
            work: 0.0,
        }
    }

    /// Tangential relative velocity $v_T$ of node i at the latest kinematics.
    pub fn slip_velocity(&self, i: usize) -> V3 {
        from_covariant(&self.tangents[i], self.slip[i])
    }

    /// Traction vector of node i (current iterate).
    pub fn traction_of(&self, i: usize) -> V3 {
        [
            self.traction[3 * i],
            self.traction[3 * i + 1],
            self.traction[3 * i + 2],
        ]
    }

    /// Starts a step from the start-of-step kinematics: the carried traction in the current
    /// basis (transported to a new face where the point has moved), zero where the node is
    /// not a candidate.
    pub fn start_step(&mut self, points: &[ContactPoint], candidate: &[bool]) {
        self.memory.reset();
        self.penalty.new_step();
        for i in 0..points.len() {
            self.start_velocity[i] = self.slip_velocity(i);
            let t = if !candidate[i] || points[i].face == NO_FACE {
                [0.0; 3]
            } else if points[i].face == self.carried_face[i] {
                from_covariant(&self.tangents[i], self.carried[i])
            } else {
                // moved to another face: project onto the new plane, keep the magnitude
                let c = self.carried_vector[i];
                let n = points[i].normal;
                let cn = dot(c, n);
                let p = [c[0] - cn * n[0], c[1] - cn * n[1], c[2] - cn * n[2]];
                let (lp, lc) = (norm(p), norm(c));
                if lp > 0.0 {
                    p.map(|x| x * lc / lp)
                } else {
                    [0.0; 3]
                }
            };
            self.traction[3 * i..3 * i + 3].copy_from_slice(&t);
        }
    }

    /// One tangential update after the normal one: `pressure` is the new normal pressure
    /// $T_N^{(k+1)}$ of each node, `points` the latest kinematics.
    pub fn update(
        &mut self,
        pressure: &[f64],
        candidate: &[bool],
        points: &[ContactPoint],
    ) -> UpdateReport {
        let n = pressure.len();
        for i in 0..n {
            // twice the mean slip velocity of the step: v_T,n+1 + v_T,n
            let v = self.slip_velocity(i);
            let v0 = self.start_velocity[i];
            for a in 0..3 {
                self.measure[3 * i + a] = -(v[a] + v0[a]);
            }
        }
        let (traction, measure) = (&self.traction, &self.measure);
        let law = self.law;
        let radius = |i: usize| bound_of(&law, pressure[i], candidate[i], &points[i]);
        let mut project = |eps: f64, next: &mut [f64]| {
            for i in 0..n {
                let t = [0, 1, 2].map(|a| traction[3 * i + a] + eps * measure[3 * i + a]);
                let t = returned_traction(&law, t, pressure[i], candidate[i], &points[i]);
                next[3 * i..3 * i + 3].copy_from_slice(&t);
            }
        };
        // a sticking node should not slide: its sliding speed is the violation
        let violation = |next: &[f64]| {
            (0..n)
                .filter(|&i| {
                    let r = radius(i);
                    r > 0.0
                        && norm([next[3 * i], next[3 * i + 1], next[3 * i + 2]])
                            < r * (1.0 - ON_CONE)
                })
                .map(|i| norm([measure[3 * i], measure[3 * i + 1], measure[3 * i + 2]]))
                .fold(0.0, f64::max)
        };
        update_with(
            &mut self.penalty,
            &mut self.memory,
            traction,
            measure,
            &self.weight,
            &mut project,
            &violation,
            None,
            &mut self.next,
        )
    }

    /// Makes the last update's tractions the current iterate.
    pub fn accept_update(&mut self) {
        std::mem::swap(&mut self.traction, &mut self.next);
    }

    /// Ends a step: stores the converged traction in convected components, adds the step's
    /// dissipation, and returns the total friction force on the secondary side and the number
    /// of sliding nodes.
    pub fn end_step(
        &mut self,
        dt: f64,
        area: &[f64],
        pressure: &[f64],
        points: &[ContactPoint],
    ) -> (V3, usize) {
        let mut total = [0.0; 3];
        let mut sliding = 0;
        let mut power = 0.0;
        for i in 0..area.len() {
            let t = self.traction_of(i);
            let v1 = self.slip_velocity(i);
            let v0 = self.start_velocity[i];
            power += area[i] * (dot(t, v0) + dot(t, v1));
            for a in 0..3 {
                total[a] += area[i] * t[a];
            }
            // sliding: the trial of the last update lies outside the cone (a sliding node's
            // trial exceeds it by eps |v_T,n + v_T,n+1|; a sticking node's is its traction)
            let r = self.law.bound(pressure[i]);
            let trial = [0, 1, 2].map(|a| t[a] + self.penalty.eps * self.measure[3 * i + a]);
            let tangential = tangential_part(trial, points[i].normal);
            if r > 0.0 && norm(tangential) > r * (1.0 + ON_CONE) {
                sliding += 1;
            }
            self.carried[i] = [dot(t, self.tangents[i][0]), dot(t, self.tangents[i][1])];
            self.carried_face[i] = points[i].face;
            self.carried_vector[i] = t;
        }
        self.work -= 0.5 * dt * power;
        (total, sliding)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_basis_is_orthonormal_and_right_handed() {
        for n in [[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.6, 0.0, 0.8]] {
            let [t1, t2] = plane_basis(n);
            for (a, b, want) in [(t1, t1, 1.0), (t2, t2, 1.0), (t1, t2, 0.0), (t1, n, 0.0)] {
                assert!((dot(a, b) - want).abs() < 1e-14);
            }
            let c = cross(t1, t2);
            assert!((dot(c, n) - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn covariant_components_round_trip_in_a_skew_basis() {
        let t = [[2.0, 0.0, 0.0], [0.5, 1.5, 0.0]];
        let v = [0.3, -0.7, 0.0];
        let c = [dot(v, t[0]), dot(v, t[1])];
        let w = from_covariant(&t, c);
        for a in 0..3 {
            assert!((w[a] - v[a]).abs() < 1e-14, "{w:?} vs {v:?}");
        }
    }
}
