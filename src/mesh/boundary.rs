//! The boundary of an imported body: element orientation, outward boundary faces, and the
//! matching of a file's surface faces (given in any node order) to them.

use std::collections::HashMap;

use crate::element::{hex8, tet4};
use crate::geometry::face::FaceKind;

/// The six faces of a hex8 in our corner order (bottom face counter-clockwise seen from
/// +z, then the top face), each ordered so that its normal points out of a positive element.
pub const HEX_FACES: [[usize; 4]; 6] = [
    [0, 3, 2, 1],
    [4, 5, 6, 7],
    [0, 1, 5, 4],
    [1, 2, 6, 5],
    [2, 3, 7, 6],
    [3, 0, 4, 7],
];

/// A face's identity regardless of node order and starting corner: its sorted nodes
/// (a triangle's sorted three, then its largest again).
pub fn face_key(face: &[u32]) -> [u32; 4] {
    let mut k = [0u32; 4];
    k[..face.len()].copy_from_slice(face);
    k[..face.len()].sort_unstable();
    if face.len() == 3 {
        k[3] = k[2];
    }
    k
}

/// Why an element could not be oriented.
#[derive(Debug, Clone, PartialEq)]
pub struct Degenerate {
    /// Index in the hex8 array or the tet4 array.
    pub index: usize,
    pub tet: bool,
    pub volume: f64,
}

/// Reorders the corners of every element whose volume is negative (a mirrored corner
/// order, as some writers use), so that every element has positive volume. An element
/// whose volume is zero (to 1e-12 of its bounding box) cannot be repaired and is reported.
pub fn orient(
    nodes: &[[f64; 3]],
    hexes: &mut [[u32; 8]],
    tets: &mut [[u32; 4]],
) -> Result<(), Degenerate> {
    let scale = |x: &[[f64; 3]]| {
        let d = crate::element::extent(x);
        d * d * d
    };
    for (index, h) in hexes.iter_mut().enumerate() {
        let x = h.map(|n| nodes[n as usize]);
        let v = hex8::volume(&x);
        if v.abs() <= 1e-12 * scale(&x) || !v.is_finite() {
            return Err(Degenerate {
                index,
                tet: false,
                volume: v,
            });
        }
        if v < 0.0 {
            *h = [h[4], h[5], h[6], h[7], h[0], h[1], h[2], h[3]];
        }
    }
    for (index, t) in tets.iter_mut().enumerate() {
        let x = t.map(|n| nodes[n as usize]);
        let v = tet4::volume(&x);
        if v.abs() <= 1e-12 * scale(&x) || !v.is_finite() {
            return Err(Degenerate {
                index,
                tet: true,
                volume: v,
            });
        }
        if v < 0.0 {
            t.swap(1, 2);
        }
    }
    Ok(())
}

/// Every element face that belongs to one element only, outward, as quads (a triangle as
/// `[a, b, c, c]`). Elements must be oriented ([`orient`]).
pub fn boundary_faces(hexes: &[[u32; 8]], tets: &[[u32; 4]]) -> Vec<[u32; 4]> {
    let mut seen: HashMap<[u32; 4], (usize, [u32; 4])> = HashMap::new();
    let mut order = 0usize;
    let mut add = |face: [u32; 4], nodes: &[u32]| {
        let key = face_key(nodes);
        if seen.remove(&key).is_none() {
            seen.insert(key, (order, face));
        }
        order += 1;
    };
    for h in hexes {
        for f in HEX_FACES {
            let q = f.map(|k| h[k]);
            add(q, &q);
        }
    }
    for t in tets {
        for f in tet4::FACES {
            let tri = f.map(|k| t[k]);
            add([tri[0], tri[1], tri[2], tri[2]], &tri);
        }
    }
    // keep the element order, so the result does not depend on the hash map
    let mut faces: Vec<(usize, [u32; 4])> = seen.into_values().collect();
    faces.sort_unstable_by_key(|f| f.0);
    faces.into_iter().map(|f| f.1).collect()
}

/// Looks faces up by their nodes in any order.
pub struct BoundaryIndex {
    by_key: HashMap<[u32; 4], [u32; 4]>,
}

impl BoundaryIndex {
    pub fn new(boundary: &[[u32; 4]]) -> BoundaryIndex {
        let by_key = boundary
            .iter()
            .map(|q| (face_key(FaceKind::of(q).corners(q)), *q))
            .collect();
        BoundaryIndex { by_key }
    }

    /// The outward boundary face with these nodes (3 or 4, any order), if there is one.
    pub fn find(&self, nodes: &[u32]) -> Option<[u32; 4]> {
        self.by_key.get(&face_key(nodes)).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_hex() -> (Vec<[f64; 3]>, [u32; 8]) {
        // the unit cube, corners in hex8 order
        let nodes = crate::element::hex8::CORNERS
            .map(|c| c.map(|v| 0.5 * (v + 1.0)))
            .to_vec();
        (nodes, [0, 1, 2, 3, 4, 5, 6, 7])
    }

    fn normal(nodes: &[[f64; 3]], q: &[u32; 4]) -> [f64; 3] {
        let p = |k: usize| nodes[q[k] as usize];
        let (a, b) = if super::super::is_triangle(q) {
            (sub(p(1), p(0)), sub(p(2), p(0)))
        } else {
            (sub(p(2), p(0)), sub(p(3), p(1)))
        };
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    /// Every boundary face's normal points away from the body's centroid (a convex body).
    fn assert_outward(nodes: &[[f64; 3]], faces: &[[u32; 4]]) {
        let n = nodes.len() as f64;
        let c = [0, 1, 2].map(|a| nodes.iter().map(|p| p[a]).sum::<f64>() / n);
        for q in faces {
            let m = normal(nodes, q);
            let p = nodes[q[0] as usize];
            let d: f64 = (0..3).map(|a| m[a] * (p[a] - c[a])).sum();
            assert!(d > 0.0, "face {q:?} points inward");
        }
    }

    #[test]
    fn a_cube_split_into_tets_has_twelve_outward_triangles() {
        let (nodes, h) = unit_hex();
        // six tets around the diagonal 0-6, some given with negative orientation
        let mut tets = vec![
            [h[0], h[1], h[2], h[6]],
            [h[0], h[2], h[3], h[6]],
            [h[0], h[3], h[7], h[6]],
            [h[0], h[7], h[4], h[6]],
            [h[0], h[4], h[5], h[6]],
            [h[0], h[5], h[1], h[6]],
        ];
        tets[1].swap(0, 3);
        orient(&nodes, &mut [], &mut tets).unwrap();
        let vol: f64 = tets
            .iter()
            .map(|t| tet4::volume(&t.map(|n| nodes[n as usize])))
            .sum();
        assert!((vol - 1.0).abs() < 1e-12);
        let faces = boundary_faces(&[], &tets);
        assert_eq!(faces.len(), 12);
        assert!(faces.iter().all(super::super::is_triangle));
        assert_outward(&nodes, &faces);
    }

    #[test]
    fn two_hexes_share_a_face_and_a_mirrored_hex_is_repaired() {
        let (mut nodes, h) = unit_hex();
        nodes.extend([
            [0.0, 0.0, 2.0],
            [1.0, 0.0, 2.0],
            [1.0, 1.0, 2.0],
            [0.0, 1.0, 2.0],
        ]);
        // the upper hex written top face first (negative volume)
        let mut hexes = vec![h, [8, 9, 10, 11, 4, 5, 6, 7]];
        orient(&nodes, &mut hexes, &mut []).unwrap();
        assert_eq!(hexes[1], [4, 5, 6, 7, 8, 9, 10, 11]);
        let faces = boundary_faces(&hexes, &[]);
        assert_eq!(faces.len(), 10);
        assert_outward(&nodes, &faces);
        let index = BoundaryIndex::new(&faces);
        assert_eq!(index.find(&[11, 10, 9, 8]), Some([8, 9, 10, 11]));
        assert_eq!(index.find(&[4, 5, 6, 7]), None, "the shared face is inside");
    }

    #[test]
    fn a_face_has_one_key_in_any_order() {
        let key = face_key(&[7, 3, 5]);
        for f in [[3, 5, 7], [5, 7, 3], [7, 5, 3], [3, 7, 5]] {
            assert_eq!(face_key(&f), key);
        }
        assert_eq!(face_key(&[4, 1, 3, 2]), face_key(&[1, 2, 3, 4]));
    }

    #[test]
    fn a_flat_element_is_reported() {
        let (mut nodes, h) = unit_hex();
        for p in nodes.iter_mut().skip(4) {
            p[2] = 0.0;
        }
        let err = orient(&nodes, &mut [h], &mut []).unwrap_err();
        assert_eq!((err.index, err.tet), (0, false));
    }
}
