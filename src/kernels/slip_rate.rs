//! CPU twin of `shaders/slip_rate.wgsl`: covariant slip rates
//! $\dot g_{T,a} = (v_1 - v_2(\bar\xi)) \cdot \tau_a(\bar\xi)$ of each contact point in the
//! convected basis of its primary face.

use super::contact_gap::{position, ContactPoint, ContactQueries, NO_FACE};
use crate::geometry::{
    face::{self, FaceKind},
    vector::{dot, sub},
};

pub fn slip_rate(
    reference: &[[f64; 3]],
    u: &[[f64; 3]],
    v: &[[f64; 3]],
    q: &ContactQueries,
    points: &[ContactPoint],
    out: &mut [[f64; 2]],
) {
    use rayon::prelude::*;
    // each query writes its own rate: any thread count gives the same rates
    out[..q.len()]
        .par_iter_mut()
        .with_min_len(256)
        .enumerate()
        .for_each(|(i, o)| *o = point_slip(reference, u, v, q, &points[i], q.secondary[i]));
}

/// The slip rate of one contact point of secondary node `s` (zero without a face).
fn point_slip(
    reference: &[[f64; 3]],
    u: &[[f64; 3]],
    v: &[[f64; 3]],
    q: &ContactQueries,
    cp: &ContactPoint,
    s: u32,
) -> [f64; 2] {
    if cp.face == NO_FACE {
        return [0.0; 2];
    }
    let face = q.faces[cp.face as usize];
    let p = face.map(|n| position(reference, u, n));
    let kind = FaceKind::of(&face);
    let (_, t1, t2, _) = kind.geometry(&p, cp.xi);
    let v2 = face::interpolate(&face, kind.shape(cp.xi), v);
    let rel = sub(v[s as usize], v2);
    [dot(rel, t1), dot(rel, t2)]
}
