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
    let boxes: Vec<FaceBox> = (q.faces.par_iter())
        .with_min_len(1024)
        .map(|f| FaceBox::new(&f.map(|n| position(reference, u, n))))
        .collect();
    // each query writes its own point: any thread count gives the same points
    out[..q.len()]
        .par_iter_mut()
        .with_min_len(256)
        .enumerate()
        .for_each(|(i, o)| {
            let bound = |fi: u32, x: V3| boxes[fi as usize].distance(x);
            let (s, candidates) = (q.secondary[i], q.candidates_of(i));
            *o = closest_point_bounded(reference, (u, v), q, (s, candidates), bound);
        });
}

/// The contact kinematics of secondary node `s` against the closest of its `candidates`
/// (faces of `q`), the first of equally close ones: one query of [`contact_gap`].
///
/// The face whose corners' box is nearest is projected on first; a face whose box is
/// farther than the closest distance found so far cannot be closer and is not projected
/// on ([`box_distance`]). The choice is the sequential scan's, bit for bit.
pub(crate) fn closest_point(
    reference: &[[f64; 3]],
    (u, v): (&[[f64; 3]], &[[f64; 3]]),
    q: &ContactQueries,
    s: u32,
    candidates: &[u32],
) -> ContactPoint {
    let bound = |fi: u32, x: V3| {
        FaceBox::new(&q.faces[fi as usize].map(|n| position(reference, u, n))).distance(x)
    };
    closest_point_bounded(reference, (u, v), q, (s, candidates), bound)
}

/// [`closest_point`] with `bound(face, x)` a lower bound on the distance from x to the face.
fn closest_point_bounded(
    reference: &[[f64; 3]],
    (u, v): (&[[f64; 3]], &[[f64; 3]]),
    q: &ContactQueries,
    (s, candidates): (u32, &[u32]),
    bound: impl Fn(u32, V3) -> f64,
) -> ContactPoint {
    let x = position(reference, u, s);
    let bound = |fi: u32| bound(fi, x);
    let first = (candidates.iter().enumerate())
        .map(|(i, &fi)| (bound(fi), i))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, i)| i);
    let order = first
        .into_iter()
        .chain((0..candidates.len()).filter(|&i| Some(i) != first));
    // (face, xi, distance, place in the list)
    let mut best = (NO_FACE, [0.0; 2], f64::INFINITY, usize::MAX);
    for i in order {
        let fi = candidates[i];
        if bound(fi) > best.2 {
            continue;
        }
        let (xi, d) = closest_on_face(reference, u, q, s, fi);
        if d < best.2 || (best.0 != NO_FACE && d == best.2 && i < best.3) {
            best = (fi, xi, d, i);
        }
    }
    match best.0 {
        NO_FACE => ContactPoint::default(),
        fi => face_point(reference, u, v, q, s, fi, best.1),
    }
}

/// A face's corners' box: every point of the face is a convex combination of its corners,
/// so the distance to the box bounds the distance to the face from below.
struct FaceBox {
    lo: V3,
    hi: V3,
    /// The largest coordinate's size.
    scale: f64,
}

impl FaceBox {
    fn new(p: &[V3; 4]) -> FaceBox {
        let lo: V3 = std::array::from_fn(|a| p.iter().fold(f64::INFINITY, |m, c| m.min(c[a])));
        let hi: V3 = std::array::from_fn(|a| p.iter().fold(f64::NEG_INFINITY, |m, c| m.max(c[a])));
        let scale = (0..3).fold(0.0f64, |m, a| m.max(lo[a].abs()).max(hi[a].abs()));
        FaceBox { lo, hi, scale }
    }

    /// The distance from `x` to the box, less [`BOX_ROUNDING`] of the coordinates' size for
    /// the rounding of both it and a projected point.
    fn distance(&self, x: V3) -> f64 {
        let (mut d2, mut scale) = (0.0f64, self.scale);
        for a in 0..3 {
            let e = (self.lo[a] - x[a]).max(x[a] - self.hi[a]).max(0.0);
            d2 += e * e;
            scale = scale.max(x[a].abs());
        }
        d2.sqrt() - BOX_ROUNDING * scale
    }
}

/// The rounding allowance of [`FaceBox::distance`], relative to the coordinates' size: far
/// above the few units of roundoff in a projected point.
const BOX_ROUNDING: f64 = 1e-9;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::test_matrices::Lcg;

    /// The plain scan: every candidate projected on, the first of equally close ones.
    fn scanned(
        reference: &[V3],
        (u, v): (&[V3], &[V3]),
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

    fn bits(p: &ContactPoint) -> Vec<u64> {
        let mut b = vec![u64::from(p.face), p.gap.to_bits(), p.gap_rate.to_bits()];
        b.extend(p.xi.iter().chain(&p.normal).map(|x| x.to_bits()));
        b
    }

    /// A warped, distorted surface of quads and triangles (some faces twice, for exact ties)
    /// and nodes above, below and on it: the projection that skips the faces whose corners'
    /// box is farther than the closest face so far picks what the plain scan picks, bit for
    /// bit, through both the boxes made once per call and those made per candidate.
    #[test]
    fn skipping_faces_by_their_boxes_gives_the_plain_scan_bit_for_bit() {
        let mut rng = Lcg(0x9e37_79b9_7f4a_7c15);
        let mut random = move || rng.next() - 0.5;
        let n = 9;
        let mut reference: Vec<V3> = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (x, y) = (i as f64 + 0.3 * random(), j as f64 + 0.3 * random());
                reference.push([x, y, 0.4 * random() + 0.1 * (x * y).sin()]);
            }
        }
        let id = |i: usize, j: usize| (i * n + j) as u32;
        let mut faces = Vec::new();
        for i in 0..n - 1 {
            for j in 0..n - 1 {
                let quad = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                match (i + j) % 5 {
                    0 => {
                        faces.push([quad[0], quad[1], quad[2], quad[2]]);
                        faces.push([quad[0], quad[2], quad[3], quad[3]]);
                    }
                    1 => faces.extend([quad, quad]),
                    _ => faces.push(quad),
                }
            }
        }
        // secondary nodes: random points near the surface, and copies of its nodes
        let surface = reference.len();
        for k in 0..300 {
            let p = match k % 6 {
                0 => reference[k % surface],
                _ => [
                    (n - 1) as f64 * (random() + 0.5),
                    (n - 1) as f64 * (random() + 0.5),
                    1.5 * random(),
                ],
            };
            reference.push(p);
        }
        let u: Vec<V3> = (0..reference.len())
            .map(|_| [0.01 * random(), 0.01 * random(), 0.01 * random()])
            .collect();
        let v: Vec<V3> = (0..reference.len())
            .map(|_| [random(), random(), random()])
            .collect();
        let mut q = ContactQueries {
            faces,
            offsets: vec![0],
            ..Default::default()
        };
        for s in surface..reference.len() {
            q.secondary.push(s as u32);
            // every face, in an order of its own, or a few
            let count = q.faces.len() as u32;
            let start = (random() + 0.5) * f64::from(count);
            let take = if s % 4 == 0 { 5 } else { count };
            q.candidates
                .extend((0..take).map(|k| (start as u32 + 7 * k) % count));
            q.offsets.push(q.candidates.len() as u32);
        }
        let mut pruned = vec![ContactPoint::default(); q.len()];
        contact_gap(&reference, &u, &v, &q, &mut pruned);
        for (i, p) in pruned.iter().enumerate() {
            let (s, candidates) = (q.secondary[i], q.candidates_of(i));
            let want = bits(&scanned(&reference, (&u, &v), &q, s, candidates));
            assert_eq!(bits(p), want, "query {i}: boxes made once");
            let each = closest_point(&reference, (&u, &v), &q, s, candidates);
            assert_eq!(bits(&each), want, "query {i}: boxes made per candidate");
        }
    }
}
