//! The constraints of the explicit step's contact iteration on the device (CPU twin of
//! `shaders/contact_constraints.wgsl`), gathered as the host path gathers them
//! (`integrate::explicit`): a surface pair takes its query's contact point and is in reach
//! if a face was found with $g \ge -$margin; a plane pair takes the plane's normal and gap
//! and is in reach if $g \ge -4 \Delta t |v^*|$; a rigid body's pair takes the gap and normal
//! of the body's surface ([`RigidShape::distance`], `shaders/shared/rigid_shape.wgsl`) and a
//! face of one node, the body's, and is in reach if $g \ge -4 \Delta t |v^* - v^*_b|$. The
//! relative velocity at $v_{n-1/2} = v^* - \Delta t\, a_n$ is kept for the friction work and
//! the impact loss. Against a face or
//! a rigid body the impulses start from the last step's (the warm start; the report's
//! `results`), the tangential one without its part along the new normal and returned onto
//! the law's set ([`ContactLaw::projected`]); against a plane from zero.

use super::contact_gap::{ContactPoint, NO_FACE};
use super::plane_contact::{slot, SLOT};
use crate::contact::law::ContactLaw;
use crate::geometry::rigid_shape::RigidShape;
use crate::geometry::{
    face,
    vector::{dot, norm, sub},
};
use crate::kernels::impulse::relative_velocity;

/// A pair of the iteration: secondary node `node` against surface query `query`, against the
/// rigid body's surface `body` (`query == NO_FACE`), or against a rigid plane (`query ==
/// body == NO_FACE`: its point and unit normal), with its interface's law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPair {
    pub node: u32,
    pub query: u32,
    pub law: ContactLaw,
    pub point: [f64; 3],
    pub normal: [f64; 3],
    pub body: u32,
}

impl Default for ContactPair {
    fn default() -> Self {
        ContactPair {
            node: 0,
            query: NO_FACE,
            law: ContactLaw::default(),
            point: [0.0; 3],
            normal: [0.0; 3],
            body: NO_FACE,
        }
    }
}

/// The analytic surface of the rigid body on node `node` (a meshed surface has no device
/// form); `driven` where a driver moves it (its work is reported).
#[derive(Debug, Clone, PartialEq)]
pub struct RigidSurface {
    pub node: u32,
    pub driven: bool,
    pub shape: RigidShape,
}

/// One constraint of the step (`face[0] == NO_FACE` for a plane).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Constraint {
    pub face: [u32; 4],
    pub weights: [f64; 4],
    pub normal: [f64; 3],
    pub gap: f64,
    pub compliance: f64,
    pub jn: f64,
    pub jt: [f64; 3],
    /// The relative velocity at $v_{n-1/2}$ (for the friction work and the impact loss).
    pub before: [f64; 3],
    pub in_reach: bool,
}

impl Default for Constraint {
    fn default() -> Self {
        Constraint {
            face: [NO_FACE; 4],
            weights: [0.0; 4],
            normal: [0.0; 3],
            gap: 0.0,
            compliance: 0.0,
            jn: 0.0,
            jt: [0.0; 3],
            before: [0.0; 3],
            in_reach: false,
        }
    }
}

/// The relative velocity of a constraint's secondary node `node` against its primary point
/// in the velocity field `v` (3 per node).
pub fn relative(c: &Constraint, node: u32, v: &[f64]) -> [f64; 3] {
    relative_velocity(
        v,
        node,
        (c.face[0] != NO_FACE).then_some((&c.face, &c.weights)),
    )
}

/// The gap and normal of node `n` against the rigid surface `s` and whether it is within
/// four steps of their relative motion `rel` of it.
fn rigid_constraint(
    dt: f64,
    (reference, u): (&[[f64; 3]], &[f64]),
    s: &RigidSurface,
    n: usize,
    rel: [f64; 3],
) -> (f64, [f64; 3], bool) {
    let b = s.node as usize;
    let x = |m: usize| std::array::from_fn(|ax| reference[m][ax] + u[3 * m + ax]);
    let (distance, normal) = s.shape.distance(sub(x(n), x(b)));
    (-distance, normal, -distance >= -4.0 * dt * norm(rel))
}

/// The impulses pair `p` (`pair`) starts from against the normal `normal`, from the last
/// step's `results` ([`SLOT`] per pair).
fn warm_impulses(
    results: &[f64],
    p: usize,
    pair: &ContactPair,
    normal: [f64; 3],
) -> (f64, [f64; 3]) {
    let o = SLOT * p;
    let jn = results[o + slot::NORMAL_IMPULSE].max(0.0);
    let t = std::array::from_fn(|a| results[o + slot::FRICTION_IMPULSE + a]);
    (jn, pair.law.projected(t, normal, jn))
}

/// Returns the constraints and the bucket keys (the face of an in-reach surface pair,
/// otherwise `faces.len()`). `v` is $v^*$, `a` is $a_n$ (3 per node); `results` the last
/// step's report ([`SLOT`] per pair).
#[allow(clippy::too_many_arguments)]
pub fn contact_constraints(
    dt: f64,
    margin: f64,
    reference: &[[f64; 3]],
    u: &[f64],
    v: &[f64],
    a: &[f64],
    pairs: &[ContactPair],
    points: &[ContactPoint],
    faces: &[[u32; 4]],
    rigid: &[RigidSurface],
    results: &[f64],
) -> (Vec<Constraint>, Vec<u32>) {
    let sentinel = faces.len() as u32;
    let mut out = Vec::with_capacity(pairs.len());
    let mut keys = Vec::with_capacity(pairs.len());
    let before: Vec<f64> = v.iter().zip(a).map(|(v, a)| v - dt * a).collect();
    for (p, pair) in pairs.iter().enumerate() {
        let n = pair.node as usize;
        let mut c = Constraint::default();
        let mut key = sentinel;
        if pair.query != NO_FACE {
            let pt = points[pair.query as usize];
            if pt.face != NO_FACE {
                c.normal = pt.normal;
                c.gap = pt.gap;
            }
            if pt.face != NO_FACE && pt.gap >= -margin.max(1e-30) {
                c.in_reach = true;
                c.face = faces[pt.face as usize];
                c.weights = face::shape(&c.face, pt.xi);
                key = pt.face;
            }
        } else if pair.body != NO_FACE {
            let s = &rigid[pair.body as usize];
            let b = s.node as usize;
            let rel = std::array::from_fn(|ax| v[3 * n + ax] - v[3 * b + ax]);
            (c.gap, c.normal, c.in_reach) = rigid_constraint(dt, (reference, u), s, n, rel);
            if c.in_reach {
                (c.face, c.weights) = ([s.node; 4], [1.0, 0.0, 0.0, 0.0]);
            }
        } else {
            c.normal = pair.normal;
            let x: [f64; 3] =
                std::array::from_fn(|ax| reference[n][ax] + u[3 * n + ax] - pair.point[ax]);
            c.gap = -dot(x, pair.normal);
            let speed = norm([v[3 * n], v[3 * n + 1], v[3 * n + 2]]);
            c.in_reach = c.gap >= -4.0 * dt * speed;
        }
        c.before = relative(&c, pair.node, &before);
        if c.in_reach && c.face[0] != NO_FACE {
            (c.jn, c.jt) = warm_impulses(results, p, pair, c.normal);
        }
        out.push(c);
        keys.push(key);
    }
    (out, keys)
}
