//! A rigid body's meshed surface: triangles in the body's frame (quads split in two), with a
//! bounding-box tree over them for the nearest-triangle search. Its signed distance is the
//! distance to the nearest triangle, positive on the side its outward normal points to.

use super::vector::{cross, dot, norm, sub};

type V3 = [f64; 3];

/// Triangles per leaf of the tree.
const LEAF: usize = 4;

/// A node of the tree: its box, and either two children (`count` 0, the first at `index`)
/// or `count` triangles from `index` in the tree's order.
#[derive(Debug, Clone, PartialEq)]
struct BoxNode {
    lo: V3,
    hi: V3,
    index: u32,
    count: u32,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RigidMesh {
    /// The triangles, in the tree's leaf order.
    triangles: Vec<[V3; 3]>,
    /// Each triangle's unit outward normal.
    normals: Vec<V3>,
    nodes: Vec<BoxNode>,
}

impl RigidMesh {
    /// The surface of `triangles` (corners counter-clockwise seen from outside); None if it
    /// has no triangle of positive area.
    pub fn new(triangles: Vec<[V3; 3]>) -> Option<RigidMesh> {
        let mut triangles: Vec<[V3; 3]> = (triangles.into_iter())
            .filter(|t| norm(cross(sub(t[1], t[0]), sub(t[2], t[0]))) > 0.0)
            .collect();
        if triangles.is_empty() {
            return None;
        }
        let mut nodes = vec![BoxNode {
            lo: [0.0; 3],
            hi: [0.0; 3],
            index: 0,
            count: 0,
        }];
        split(&mut triangles, 0, &mut nodes, 0);
        let normals = (triangles.iter())
            .map(|t| {
                let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
                let l = norm(n);
                n.map(|x| x / l)
            })
            .collect();
        Some(RigidMesh {
            triangles,
            normals,
            nodes,
        })
    }

    /// Signed distance from `r` to the surface (positive on the side the nearest triangle's
    /// normal points to) and the unit outward normal there: the tree's boxes nearer than
    /// the best triangle so far, nearest first.
    pub fn distance(&self, r: V3) -> (f64, V3) {
        let mut best: Option<(f64, usize, V3)> = None;
        let mut stack = vec![0usize];
        let tie = 1e-12 * norm(sub(self.nodes[0].hi, self.nodes[0].lo)).max(f64::MIN_POSITIVE);
        while let Some(k) = stack.pop() {
            let node = &self.nodes[k];
            if best.is_some_and(|b| box_distance(node, r) > b.0 + tie) {
                continue;
            }
            if node.count == 0 {
                let (a, b) = (node.index as usize, node.index as usize + 1);
                // the nearer child is searched first
                let (near, far) =
                    match box_distance(&self.nodes[a], r) <= box_distance(&self.nodes[b], r) {
                        true => (a, b),
                        false => (b, a),
                    };
                stack.push(far);
                stack.push(near);
                continue;
            }
            for t in node.index as usize..(node.index + node.count) as usize {
                let c = closest_on_triangle(&self.triangles[t], r);
                let d = norm(sub(r, c));
                let better = match best {
                    None => true,
                    Some((bd, bt, bc)) => {
                        d < bd - tie || (d <= bd + tie && self.clearer(t, c, bt, bc, r))
                    }
                };
                if better {
                    best = Some((d, t, c));
                }
            }
        }
        let (d, t, c) = best.expect("a rigid mesh has triangles");
        let n = self.normals[t];
        let sign = if dot(sub(r, c), n) < 0.0 { -1.0 } else { 1.0 };
        if d > tie {
            (sign * d, sub(r, c).map(|x| sign * x / d))
        } else {
            (0.0, n)
        }
    }

    /// Of two triangles equally near `r` (at an edge or a corner they share), whether `t`'s
    /// normal says more plainly which side `r` is on.
    fn clearer(&self, t: usize, c: V3, bt: usize, bc: V3, r: V3) -> bool {
        let along = |t: usize, c: V3| dot(sub(r, c), self.normals[t]).abs();
        along(t, c) > along(bt, bc)
    }
}

/// Fills node `k` with the box of `triangles` (which start at `offset` in the tree's order)
/// and, above [`LEAF`] triangles, splits them at the median of their centroids along the
/// box's longest axis into two children appended to `nodes`.
fn split(triangles: &mut [[V3; 3]], offset: usize, nodes: &mut Vec<BoxNode>, k: usize) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in triangles.iter().flatten() {
        for a in 0..3 {
            (lo[a], hi[a]) = (lo[a].min(p[a]), hi[a].max(p[a]));
        }
    }
    nodes[k] = BoxNode {
        lo,
        hi,
        index: offset as u32,
        count: triangles.len() as u32,
    };
    if triangles.len() <= LEAF {
        return;
    }
    let axis = (0..3)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
        .unwrap_or(0);
    let centre = |t: &[V3; 3]| t[0][axis] + t[1][axis] + t[2][axis];
    let mid = triangles.len() / 2;
    triangles.select_nth_unstable_by(mid, |a, b| centre(a).total_cmp(&centre(b)));
    let first = nodes.len();
    nodes[k].index = first as u32;
    nodes[k].count = 0;
    let empty = BoxNode {
        lo,
        hi,
        index: 0,
        count: 0,
    };
    nodes.extend([empty.clone(), empty]);
    let (left, right) = triangles.split_at_mut(mid);
    split(left, offset, nodes, first);
    split(right, offset + mid, nodes, first + 1);
}

/// The distance from `r` to a node's box (0 inside it).
fn box_distance(node: &BoxNode, r: V3) -> f64 {
    (0..3)
        .map(|a| (node.lo[a] - r[a]).max(r[a] - node.hi[a]).max(0.0).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The point of the triangle `t` nearest `p` (Ericson, Real-Time Collision Detection, 5.1.5).
fn closest_on_triangle(t: &[V3; 3], p: V3) -> V3 {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let at = |x: V3, y: V3, s: f64| std::array::from_fn(|k| x[k] + s * y[k]);
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return at(a, ab, d1 / (d1 - d3));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return at(a, ac, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return at(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    std::array::from_fn(|k| a[k] + ab[k] * v + ac[k] * w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};

    /// The unit cube's surface, two triangles a face, outward.
    fn cube() -> RigidMesh {
        let quads: [[V3; 4]; 6] = [
            [
                [0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 1.0, 0.0],
                [1.0, 0.0, 0.0],
            ],
            [
                [0.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
                [0.0, 1.0, 1.0],
            ],
            [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 0.0, 1.0],
                [0.0, 0.0, 1.0],
            ],
            [
                [0.0, 1.0, 0.0],
                [0.0, 1.0, 1.0],
                [1.0, 1.0, 1.0],
                [1.0, 1.0, 0.0],
            ],
            [
                [0.0, 0.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.0, 1.0, 1.0],
                [0.0, 1.0, 0.0],
            ],
            [
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [1.0, 1.0, 1.0],
                [1.0, 0.0, 1.0],
            ],
        ];
        let triangles = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        RigidMesh::new(triangles).expect("a surface")
    }

    #[test]
    fn a_cube_surface_gives_the_cube_distance() {
        let m = cube();
        let (d, n) = m.distance([0.5, 0.5, 1.25]);
        assert!(
            (d - 0.25).abs() < 1e-12 && (n[2] - 1.0).abs() < 1e-12,
            "{d} {n:?}"
        );
        let (d, n) = m.distance([0.5, 0.4, 0.9]);
        assert!(
            (d + 0.1).abs() < 1e-12 && (n[2] - 1.0).abs() < 1e-12,
            "{d} {n:?}"
        );
        // off an edge and a corner, far and near
        let (d, _) = m.distance([2.0, 0.5, 2.0]);
        assert!((d - 2f64.sqrt()).abs() < 1e-12, "{d}");
        let (d, _) = m.distance([-3.0, -4.0, 0.5]);
        assert!((d - 5.0).abs() < 1e-12, "{d}");
        let (d, _) = m.distance([10.0, 10.0, 10.0]);
        assert!((d - 9.0 * 3f64.sqrt()).abs() < 1e-9, "{d}");
    }

    /// The distance equals a brute-force search over every triangle at random points.
    #[test]
    fn the_tree_search_finds_the_nearest_triangle() {
        let m = cube();
        let mut rng = StdRng::seed_from_u64(11);
        let mut next = || rng.random_range(-1.0..2.0);
        for _ in 0..500 {
            let r = [next(), next(), next()];
            let brute = (m.triangles.iter())
                .map(|t| norm(sub(r, closest_on_triangle(t, r))))
                .fold(f64::INFINITY, f64::min);
            let (d, _) = m.distance(r);
            assert!(
                (d.abs() - brute).abs() < 1e-12,
                "{r:?}: {d} against {brute}"
            );
            let inside = r.iter().all(|&x| (0.0..=1.0).contains(&x));
            assert_eq!(d < 0.0, inside && brute > 1e-12, "{r:?}: {d}");
        }
    }
}
