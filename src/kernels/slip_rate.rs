//! CPU twin of `shaders/slip_rate.wgsl`: covariant slip rates
//! $\dot g_{T,a} = (v_1 - v_2(\bar\xi)) \cdot \tau_a(\bar\xi)$ of each contact point in the
//! convected basis of its primary face.

use super::contact_gap::{ContactPoint, ContactQueries, NO_FACE};
use crate::geometry::quad::{self, dot, sub};

pub fn slip_rate(
    reference: &[[f64; 3]],
    u: &[[f64; 3]],
    v: &[[f64; 3]],
    q: &ContactQueries,
    points: &[ContactPoint],
    out: &mut [[f64; 2]],
) {
    for (i, o) in out.iter_mut().enumerate().take(q.len()) {
        let cp = points[i];
        if cp.face == NO_FACE {
            *o = [0.0; 2];
            continue;
        }
        let face = q.faces[cp.face as usize];
        let p = face.map(|n| {
            let (x, d) = (reference[n as usize], u[n as usize]);
            [x[0] + d[0], x[1] + d[1], x[2] + d[2]]
        });
        let (_, t1, t2, _) = quad::geometry(&p, cp.xi);
        let nsh = quad::shape(cp.xi);
        let mut v2 = [0.0; 3];
        for k in 0..4 {
            for a in 0..3 {
                v2[a] += nsh[k] * v[face[k] as usize][a];
            }
        }
        let rel = sub(v[q.secondary[i] as usize], v2);
        *o = [dot(rel, t1), dot(rel, t2)];
    }
}
