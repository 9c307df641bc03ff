//! CPU twin of `shaders/contact_gap.wgsl`: closest-point projection of secondary nodes onto
//! candidate primary faces (quads or triangles), with the normal, gap and gap rate of `method.md`:
//! $g = -(x_1 - y(\bar\xi)) \cdot n$ (positive = penetration, n the primary's outward normal),
//! $\dot g = -(v_1 - v_2(\bar\xi)) \cdot n$ (positive = approaching).

use crate::geometry::{
    face::{self, FaceKind},
    vector::{dot, norm, sub, V3},
};

pub use crate::geometry::point::{ContactPoint, NO_FACE};

/// Secondary nodes and their candidate primary faces, flattened (CSR), for all pairs at once.
#[derive(Debug, Clone, Default)]
pub struct ContactQueries {
    /// Global node number of each query.
    pub secondary: Vec<u32>,
    /// `candidates[offsets[q]..offsets[q + 1]]` are the candidate faces of query q.
    pub offsets: Vec<u32>,
    pub candidates: Vec<u32>,
    /// Primary faces (global node numbers), outward-oriented, as their four slots
    /// ([`crate::geometry::face::Face::slots`]: a triangle's fourth repeats its third).
    pub faces: Vec<[u32; 4]>,
}

impl ContactQueries {
    pub fn len(&self) -> usize {
        self.secondary.len()
    }
    pub fn is_empty(&self) -> bool {
        self.secondary.is_empty()
    }
    pub fn candidates_of(&self, q: usize) -> &[u32] {
        &self.candidates[self.offsets[q] as usize..self.offsets[q + 1] as usize]
    }
}

#[inline]
fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Contact kinematics of every query (overwrites `out`).
pub fn contact_gap(
    reference: &[[f64; 3]],
    u: &[[f64; 3]],
    v: &[[f64; 3]],
    q: &ContactQueries,
    out: &mut [ContactPoint],
) {
    use rayon::prelude::*;
    // each query writes its own point: any thread count gives the same points
    out[..q.len()]
        .par_iter_mut()
        .with_min_len(256)
        .enumerate()
        .for_each(|(i, o)| {
            *o = closest_point(reference, (u, v), q, q.secondary[i], q.candidates_of(i));
        });
}

/// The contact kinematics of secondary node `s` against the closest of its `candidates`
/// (faces of `q`), the first of equally close ones: one query of [`contact_gap`].
pub(crate) fn closest_point(
    reference: &[[f64; 3]],
    (u, v): (&[[f64; 3]], &[[f64; 3]]),
    q: &ContactQueries,
    s: u32,
    candidates: &[u32],
) -> ContactPoint {
    let mut best = (NO_FACE, [0.0; 2], f64::INFINITY);
    for &fi in candidates {
        let (xi, d) = closest_on_face(reference, u, q, s, fi);
        if d < best.2 {
            best = (fi, xi, d);
        }
    }
    match best.0 {
        NO_FACE => ContactPoint::default(),
        fi => face_point(reference, u, v, q, s, fi, best.1),
    }
}

/// The position of node n at displacement u.
#[inline]
pub(super) fn position(reference: &[[f64; 3]], u: &[[f64; 3]], n: u32) -> V3 {
    add(reference[n as usize], u[n as usize])
}

/// The convected coordinates of the closest point of face `fi` to secondary node `s`, and
/// the node's distance from it.
pub(crate) fn closest_on_face(
    reference: &[[f64; 3]],
    u: &[[f64; 3]],
    q: &ContactQueries,
    s: u32,
    fi: u32,
) -> ([f64; 2], f64) {
    let x = position(reference, u, s);
    let face = q.faces[fi as usize];
    let p = face.map(|n| position(reference, u, n));
    let kind = FaceKind::of(&face);
    let xi = kind.project(&p, x);
    let (y, ..) = kind.geometry(&p, xi);
    (xi, norm(sub(x, y)))
}

/// The contact point of secondary node `s` on face `fi` at xi: the normal, gap and gap rate
/// there.
pub(crate) fn face_point(
    reference: &[[f64; 3]],
    u: &[[f64; 3]],
    v: &[[f64; 3]],
    q: &ContactQueries,
    s: u32,
    fi: u32,
    xi: [f64; 2],
) -> ContactPoint {
    let x = position(reference, u, s);
    let face = q.faces[fi as usize];
    let p = face.map(|n| position(reference, u, n));
    let kind = FaceKind::of(&face);
    let (y, ..) = kind.geometry(&p, xi);
    let n = kind.normal(&p, xi);
    let v2 = face::interpolate(&face, kind.shape(xi), v);
    ContactPoint {
        face: fi,
        xi,
        normal: n,
        gap: -dot(sub(x, y), n),
        gap_rate: -dot(sub(v[s as usize], v2), n),
    }
}
