//! The constraints of the explicit step's contact iteration on the device (CPU twin of
//! `shaders/contact_constraints.wgsl`), gathered as the host path gathers them
//! (`integrate::explicit`): a surface pair takes its query's contact point and is in reach
//! if a face was found with $g \ge -$margin; a plane pair takes the plane's normal and gap
//! and is in reach if $g \ge -4 \Delta t |v^*|$. The slip at
//! $v_{n-1/2} = v^* - \Delta t\, a_n$ is kept for the friction work.

use super::contact_gap::{ContactPoint, NO_FACE};
use crate::contact::law::ContactLaw;
use crate::geometry::{
    face,
    vector::{dot, norm},
};
use crate::kernels::impulse::relative_velocity;

/// A pair of the iteration: secondary node `node` against surface query `query`, or against
/// a rigid plane (`query == NO_FACE`: its point and unit normal), with its interface's law.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactPair {
    pub node: u32,
    pub query: u32,
    pub law: ContactLaw,
    pub point: [f64; 3],
    pub normal: [f64; 3],
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
    /// Relative tangential velocity at $v_{n-1/2}$.
    pub slip: [f64; 3],
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
            slip: [0.0; 3],
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

/// Returns the constraints and the bucket keys (the face of an in-reach surface pair,
/// otherwise `faces.len()`). `v` is $v^*$, `a` is $a_n$ (3 per node).
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
) -> (Vec<Constraint>, Vec<u32>) {
    let sentinel = faces.len() as u32;
    let mut out = Vec::with_capacity(pairs.len());
    let mut keys = Vec::with_capacity(pairs.len());
    let before: Vec<f64> = v.iter().zip(a).map(|(v, a)| v - dt * a).collect();
    for pair in pairs {
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
        } else {
            c.normal = pair.normal;
            let x: [f64; 3] =
                std::array::from_fn(|ax| reference[n][ax] + u[3 * n + ax] - pair.point[ax]);
            c.gap = -dot(x, pair.normal);
            let speed = norm([v[3 * n], v[3 * n + 1], v[3 * n + 2]]);
            c.in_reach = c.gap >= -4.0 * dt * speed;
        }
        let rel = relative(&c, pair.node, &before);
        let rn = dot(rel, c.normal);
        c.slip = std::array::from_fn(|ax| rel[ax] - rn * c.normal[ax]);
        out.push(c);
        keys.push(key);
    }
    (out, keys)
}
