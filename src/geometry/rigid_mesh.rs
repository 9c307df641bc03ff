//! A rigid body's meshed surface: triangles in the body's frame (quads split in two), with a
//! bounding-box tree over them for the nearest-triangle search. Its signed distance is the
//! distance to the nearest triangle, positive on the side its outward normal points to.
//!
//! A surface may be open (a tup's striking face alone, a table's top): past its rim it has
//! no inside. A point whose nearest point is on the rim (an edge of one triangle only, or a
//! corner on such an edge) is outside, whichever side of the triangle it lies on; on a
//! closed surface nothing changes.

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

/// Where on a triangle its point nearest a given point lies: inside it, at corner k, or on
/// edge k (from corner k to corner k + 1, cyclically).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Feature {
    Inside,
    Corner(usize),
    Edge(usize),
}

#[derive(Debug, Clone, PartialEq)]
pub struct RigidMesh {
    /// The triangles, in the tree's leaf order.
    triangles: Vec<[V3; 3]>,
    /// Each triangle's unit outward normal.
    normals: Vec<V3>,
    /// Each triangle's rim: bit k set where its edge k is no other triangle's, bit 3 + k
    /// where its corner k lies on such an edge (all clear on a closed surface).
    rims: Vec<u8>,
    nodes: Vec<BoxNode>,
}

impl RigidMesh {
    /// Whether the surface is closed (no triangle has an edge that is no other's).
    pub fn is_closed(&self) -> bool {
        self.rims.iter().all(|&r| r == 0)
    }

    /// The corners' bounding box (in the body's frame).
    pub fn bounds(&self) -> (V3, V3) {
        (self.nodes[0].lo, self.nodes[0].hi)
    }

    /// The triangles' corners (in the body's frame).
    pub fn corners(&self) -> impl Iterator<Item = V3> + '_ {
        self.triangles.iter().flatten().copied()
    }

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
        let rims = rims(&triangles);
        Some(RigidMesh {
            triangles,
            normals,
            rims,
            nodes,
        })
    }

    /// Signed distance from `r` to the surface (positive on the side the nearest triangle's
    /// normal points to) and the unit outward normal there: the tree's boxes nearer than
    /// the best triangle so far, nearest first.
    pub fn distance(&self, r: V3) -> (f64, V3) {
        let mut best: Option<(f64, usize, V3, Feature)> = None;
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
                let (c, f) = closest_on_triangle(&self.triangles[t], r);
                let d = norm(sub(r, c));
                let better = match best {
                    None => true,
                    Some((bd, bt, bc, _)) => {
                        d < bd - tie || (d <= bd + tie && self.clearer(t, c, bt, bc, r))
                    }
                };
                if better {
                    best = Some((d, t, c, f));
                }
            }
        }
        let (d, t, c, f) = best.expect("a rigid mesh has triangles");
        let n = self.normals[t];
        let behind = dot(sub(r, c), n) < 0.0 && !self.on_rim(t, f);
        let sign = if behind { -1.0 } else { 1.0 };
        if d > tie {
            (sign * d, sub(r, c).map(|x| sign * x / d))
        } else {
            (0.0, n)
        }
    }

    /// Whether the feature `f` of triangle `t` lies on the surface's rim.
    fn on_rim(&self, t: usize, f: Feature) -> bool {
        let bit = match f {
            Feature::Inside => return false,
            Feature::Edge(k) => k,
            Feature::Corner(k) => 3 + k,
        };
        self.rims[t] & (1 << bit) != 0
    }

    /// Of two triangles equally near `r` (at an edge or a corner they share), whether `t`'s
    /// normal says more plainly which side `r` is on.
    fn clearer(&self, t: usize, c: V3, bt: usize, bc: V3, r: V3) -> bool {
        let along = |t: usize, c: V3| dot(sub(r, c), self.normals[t]).abs();
        along(t, c) > along(bt, bc)
    }
}

/// Each triangle's rim bits ([`RigidMesh::rims`]): its edges that no other triangle has
/// (corners matched by their coordinates' bits, as the mesh's shared nodes give them), and
/// its corners on such an edge.
fn rims(triangles: &[[V3; 3]]) -> Vec<u8> {
    use std::collections::HashMap;
    type Key = [u64; 3];
    let key = |p: V3| p.map(f64::to_bits);
    let edge = |t: &[V3; 3], k: usize| {
        let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
        if a <= b {
            (a, b)
        } else {
            (b, a)
        }
    };
    let mut uses: HashMap<(Key, Key), u32> = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            *uses.entry(edge(t, k)).or_default() += 1;
        }
    }
    let mut rim_corners: std::collections::HashSet<Key> = std::collections::HashSet::new();
    for (&(a, b), &n) in &uses {
        if n == 1 {
            rim_corners.extend([a, b]);
        }
    }
    (triangles.iter())
        .map(|t| {
            (0..3).fold(0u8, |bits, k| {
                let open = (uses[&edge(t, k)] == 1) as u8;
                let corner = rim_corners.contains(&key(t[k])) as u8;
                bits | open << k | corner << (3 + k)
            })
        })
        .collect()
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

/// The point of the triangle `t` nearest `p`, and where on the triangle it lies (Ericson,
/// Real-Time Collision Detection, 5.1.5).
fn closest_on_triangle(t: &[V3; 3], p: V3) -> (V3, Feature) {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Feature::Corner(0));
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Feature::Corner(1));
    }
    let at = |x: V3, y: V3, s: f64| std::array::from_fn(|k| x[k] + s * y[k]);
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (at(a, ab, d1 / (d1 - d3)), Feature::Edge(0));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Feature::Corner(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (at(a, ac, d2 / (d2 - d6)), Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (at(b, sub(c, b), s), Feature::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (
        std::array::from_fn(|k| a[k] + ab[k] * v + ac[k] * w),
        Feature::Inside,
    )
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
                .map(|t| norm(sub(r, closest_on_triangle(t, r).0)))
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

    /// The unit square at z = 0, outward +z, alone: an open surface.
    fn open_square() -> RigidMesh {
        let (a, b, c, d) = ([0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]);
        RigidMesh::new(vec![[a, b, c], [a, c, d]]).expect("a surface")
    }

    #[test]
    fn an_open_surface_has_no_inside_past_its_rim() {
        let m = open_square();
        assert!(
            m.rims.iter().all(|&r| r != 0),
            "every triangle has rim edges"
        );
        let (d, n) = m.distance([0.5, 0.4, -0.1]);
        assert!(
            (d + 0.1).abs() < 1e-12 && (n[2] - 1.0).abs() < 1e-12,
            "{d} {n:?}"
        );
        let (d, _) = m.distance([0.5, 0.4, 0.2]);
        assert!((d - 0.2).abs() < 1e-12, "{d}");
        // beside and below an edge, and a corner: outside, at the distance to the rim, the
        // normal from the rim to the point
        let (d, n) = m.distance([1.05, 0.5, -0.01]);
        let want = (0.05f64.powi(2) + 0.01f64.powi(2)).sqrt();
        assert!((d - want).abs() < 1e-12, "{d} against {want}");
        assert!((n[0] - 0.05 / want).abs() < 1e-12 && (n[2] + 0.01 / want).abs() < 1e-12);
        let (d, _) = m.distance([-0.1, 1.2, -0.3]);
        assert!(d > 0.0, "{d}");
        // the cube without its top: inside through its sides, outside past the open top
        let mut m = cube();
        m.triangles.retain(|t| !t.iter().all(|p| p[2] == 1.0));
        let m = RigidMesh::new(m.triangles).expect("a surface");
        let (d, _) = m.distance([0.5, 0.4, 0.9]);
        assert!((d + 0.4).abs() < 1e-12, "inside the open box: {d}");
        let (d, _) = m.distance([0.5, 0.5, 1.05]);
        assert!(
            (d - (0.25f64 + 0.0025).sqrt()).abs() < 1e-12,
            "above the open top: {d}"
        );
        // closed, nothing is on a rim
        assert!(cube().rims.iter().all(|&r| r == 0));
    }

    /// Each nearest point lies where its feature says: a corner, on an edge's segment, or
    /// the projection inside the triangle, at random points about random triangles.
    #[test]
    fn the_nearest_point_lies_on_its_feature() {
        let mut rng = StdRng::seed_from_u64(5);
        let mut next = || rng.random_range(-1.0..1.0);
        for _ in 0..2000 {
            let t: [V3; 3] = std::array::from_fn(|_| [next(), next(), next()]);
            let p = [2.0 * next(), 2.0 * next(), 2.0 * next()];
            let (c, f) = closest_on_triangle(&t, p);
            let on_segment = |k: usize| {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let ab = sub(b, a);
                let s = dot(sub(c, a), ab) / dot(ab, ab);
                let q: V3 = std::array::from_fn(|i| a[i] + s * ab[i]);
                (-1e-9..=1.0 + 1e-9).contains(&s) && norm(sub(q, c)) < 1e-9
            };
            match f {
                Feature::Corner(k) => assert_eq!(c, t[k]),
                Feature::Edge(k) => assert!(on_segment(k), "{t:?} {p:?}: edge {k}"),
                Feature::Inside => {
                    // the projection of p, with barycentric coordinates in [0, 1]
                    let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
                    let area = |x: V3, y: V3| dot(cross(sub(x, c), sub(y, c)), n) / dot(n, n);
                    let bary = [area(t[1], t[2]), area(t[2], t[0]), area(t[0], t[1])];
                    assert!(bary.iter().all(|&b| b >= -1e-9), "{bary:?}");
                    assert!(norm(cross(sub(p, c), n)) <= 1e-9 * norm(n), "{t:?} {p:?}");
                }
            }
        }
    }
}
