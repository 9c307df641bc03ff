//! Whether a point lies inside a body: the parity of a ray's crossings of the body's closed
//! boundary. A node-to-surface contact sees a secondary node behind the primary surface; it
//! cannot see the primary surface inside the secondary body (a rigid ball started inside a
//! block, no block node inside the ball). [`Enclosure`] sees that.
//!
//! The ray runs along +z from the point, nudged off the mesh's lines by a small irrational
//! fraction of the bins' size; the boundary's faces are split into triangles and binned by
//! their extent in x and y, so that a ray reads the faces of its bin alone.

use crate::geometry::face::Face;
use crate::geometry::vector::V3;

/// A body's closed boundary, ready for inside tests.
pub struct Enclosure {
    triangles: Vec<[V3; 3]>,
    lo: V3,
    hi: V3,
    cell: f64,
    bins: [usize; 2],
    /// The triangles over each bin (x fastest).
    binned: Vec<Vec<u32>>,
}

impl Enclosure {
    /// The enclosure of the outward boundary `faces` over the coordinates `x`; `None` for a
    /// body without faces.
    pub fn new(x: &[[f64; 3]], faces: &[Face]) -> Option<Enclosure> {
        let mut triangles = Vec::with_capacity(2 * faces.len());
        for f in faces {
            let [a, b, c, d] = f.slots().map(|n| x[n as usize]);
            triangles.push([a, b, c]);
            if d != c {
                triangles.push([a, c, d]);
            }
        }
        let first = triangles.first()?[0];
        let (mut lo, mut hi) = (first, first);
        for p in triangles.iter().flatten() {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let per_side = ((triangles.len() as f64 / 4.0).sqrt().ceil() as usize).clamp(1, 1024);
        let cell = ((hi[0] - lo[0]).max(hi[1] - lo[1]) / per_side as f64).max(f64::MIN_POSITIVE);
        let bins = [0, 1].map(|a| (((hi[a] - lo[a]) / cell).floor() as usize + 1).min(1024));
        let mut e = Enclosure {
            triangles,
            lo,
            hi,
            cell,
            bins,
            binned: vec![Vec::new(); bins[0] * bins[1]],
        };
        let mut binned = std::mem::take(&mut e.binned);
        for (k, t) in e.triangles.iter().enumerate() {
            let (x0, x1) = (t.iter().map(|p| p[0])).fold((f64::MAX, f64::MIN), min_max);
            let (y0, y1) = (t.iter().map(|p| p[1])).fold((f64::MAX, f64::MIN), min_max);
            for j in e.bin(1, y0)..=e.bin(1, y1) {
                for i in e.bin(0, x0)..=e.bin(0, x1) {
                    binned[j * bins[0] + i].push(k as u32);
                }
            }
        }
        e.binned = binned;
        Some(e)
    }

    fn bin(&self, a: usize, v: f64) -> usize {
        (((v - self.lo[a]) / self.cell).floor().max(0.0) as usize).min(self.bins[a] - 1)
    }

    /// Whether `p` lies inside by more than `margin`: `p` and the six points `margin` from
    /// it along the axes are all inside (a point on the boundary, as touching bodies have
    /// them, is not).
    pub fn holds(&self, p: V3, margin: f64) -> bool {
        let outside_box =
            (0..3).any(|a| p[a] - margin <= self.lo[a] || p[a] + margin >= self.hi[a]);
        if outside_box || !self.odd(p) {
            return false;
        }
        (0..6).all(|k| {
            let mut q = p;
            q[k / 2] += if k % 2 == 0 { margin } else { -margin };
            self.odd(q)
        })
    }

    /// Whether a ray from `p` along +z crosses the boundary an odd number of times.
    fn odd(&self, p: V3) -> bool {
        // off the mesh's lines: mesh coordinates are rarely these fractions of a bin
        let (px, py) = (
            p[0] + 1.234_567_9e-7 * self.cell,
            p[1] + 7.654_321e-8 * self.cell,
        );
        let bin = self.bin(1, py) * self.bins[0] + self.bin(0, px);
        let crossings = (self.binned[bin].iter())
            .filter(|&&k| crosses(&self.triangles[k as usize], px, py, p[2]))
            .count();
        crossings % 2 == 1
    }
}

fn min_max((lo, hi): (f64, f64), v: f64) -> (f64, f64) {
    (lo.min(v), hi.max(v))
}

/// Whether the vertical line through (`px`, `py`) meets triangle `t` above `pz`.
fn crosses(t: &[V3; 3], px: f64, py: f64, pz: f64) -> bool {
    let edge = |a: &V3, b: &V3| (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
    let w = [edge(&t[1], &t[2]), edge(&t[2], &t[0]), edge(&t[0], &t[1])];
    let area = w[0] + w[1] + w[2];
    let same_sign = w.iter().all(|&v| v > 0.0) || w.iter().all(|&v| v < 0.0);
    if !same_sign || area == 0.0 {
        return false;
    }
    let z = (w[0] * t[0][2] + w[1] * t[1][2] + w[2] * t[2][2]) / area;
    z > pz
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::box_mesh::{box_mesh, BoxElement, BoxSpec};

    /// A unit cube of 3 x 3 x 3 hexahedra, turned off the axes, holds its centre and the
    /// points inside it, and not those outside or on its faces.
    #[test]
    fn a_turned_box_holds_what_is_inside_it() {
        let parts = box_mesh(&BoxSpec {
            min: [0.0; 3],
            max: [1.0; 3],
            divisions: [3, 3, 3],
            element: BoxElement::Hex8,
            refine: None,
        });
        let (c, s) = (0.6f64.cos(), 0.6f64.sin());
        let turn = |p: V3| [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]];
        let x: Vec<V3> = parts.nodes.iter().map(|&p| turn(p)).collect();
        let e = Enclosure::new(&x, &parts.boundary).expect("faces");
        for (p, inside) in [
            ([0.5, 0.5, 0.5], true),
            ([0.05, 0.9, 0.1], true),
            ([1.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0], true),
            ([1.1, 0.5, 0.5], false),
            ([0.5, 0.5, -0.01], false),
            ([0.5, 0.5, 1.0], false),
            ([0.0, 0.5, 0.5], false),
        ] {
            assert_eq!(e.holds(turn(p), 1e-3), inside, "{p:?}");
        }
    }
}
