//! The boundary of an imported body: element orientation, outward boundary faces, and the
//! matching of a file's surface faces (given in any node order) to them.

use std::collections::HashMap;

use crate::element::{ElementKind, Elements};
use crate::geometry::face::Face;

/// A face's identity regardless of node order and starting corner: its sorted nodes
/// (a triangle's sorted three, then its largest again).
pub(crate) fn face_key(face: &[u32]) -> [u32; 4] {
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
    pub kind: ElementKind,
    /// Index in the kind's block.
    pub index: usize,
    pub volume: f64,
    /// Its largest extent along an axis.
    pub extent: f64,
}

/// Reorders the corners of every element whose volume is negative (a mirrored corner
/// order, as some writers use), so that every element has positive volume. An element
/// whose volume is zero (to 1e-12 of its bounding box) cannot be repaired and is reported.
pub fn orient(nodes: &[[f64; 3]], elements: &mut Elements) -> Result<(), Degenerate> {
    for block in &mut elements.blocks {
        let (kind, n) = (block.kind, block.kind.corners());
        for (index, e) in block.nodes.chunks_exact_mut(n).enumerate() {
            let x: Vec<[f64; 3]> = e.iter().map(|&i| nodes[i as usize]).collect();
            let v = kind.volume(&x);
            let d = crate::element::extent(&x);
            if v.abs() <= 1e-12 * (d * d * d) || !v.is_finite() {
                return Err(Degenerate {
                    kind,
                    index,
                    volume: v,
                    extent: d,
                });
            }
            if v < 0.0 {
                kind.mirror(e);
            }
        }
    }
    Ok(())
}

/// Every element face that belongs to one element only, outward. Elements must be oriented
/// ([`orient`]).
pub(crate) fn boundary_faces(elements: &Elements) -> Vec<Face> {
    let mut seen: HashMap<[u32; 4], (usize, Face)> = HashMap::new();
    let mut order = 0usize;
    for e in elements.iter() {
        for f in e.kind.faces() {
            let nodes: Vec<u32> = f.iter().map(|&k| e.nodes[k]).collect();
            let key = face_key(&nodes);
            if seen.remove(&key).is_none() {
                seen.insert(key, (order, Face::of_corners(&nodes)));
            }
            order += 1;
        }
    }
    // keep the element order, so the result does not depend on the hash map
    let mut faces: Vec<(usize, Face)> = seen.into_values().collect();
    faces.sort_unstable_by_key(|f| f.0);
    faces.into_iter().map(|f| f.1).collect()
}

/// Looks faces up by their nodes in any order.
pub(crate) struct BoundaryIndex {
    by_key: HashMap<[u32; 4], Face>,
}

impl BoundaryIndex {
    pub fn new(boundary: &[Face]) -> BoundaryIndex {
        let by_key = boundary
            .iter()
            .map(|f| (face_key(f.corners()), *f))
            .collect();
        BoundaryIndex { by_key }
    }

    /// The outward boundary face with these nodes (3 or 4, any order), if there is one.
    pub fn find(&self, nodes: &[u32]) -> Option<Face> {
        self.by_key.get(&face_key(nodes)).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::tet4;

    /// Elements of one kind from their concatenated corner nodes.
    fn of_kind(kind: ElementKind, nodes: &[u32]) -> Elements {
        let mut els = Elements::default();
        for e in nodes.chunks_exact(kind.corners()) {
            els.push(kind, e, 0);
        }
        els
    }

    fn unit_hex() -> (Vec<[f64; 3]>, [u32; 8]) {
        // the unit cube, corners in hex8 order
        let nodes = crate::element::hex8::CORNERS
            .map(|c| c.map(|v| 0.5 * (v + 1.0)))
            .to_vec();
        (nodes, [0, 1, 2, 3, 4, 5, 6, 7])
    }

    fn normal(nodes: &[[f64; 3]], f: &Face) -> [f64; 3] {
        let q = f.slots();
        let p = |k: usize| nodes[q[k] as usize];
        let (a, b) = if matches!(f, Face::Triangle(_)) {
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
    fn assert_outward(nodes: &[[f64; 3]], faces: &[Face]) {
        let n = nodes.len() as f64;
        let c = [0, 1, 2].map(|a| nodes.iter().map(|p| p[a]).sum::<f64>() / n);
        for q in faces {
            let m = normal(nodes, q);
            let p = nodes[q.corners()[0] as usize];
            let d: f64 = (0..3).map(|a| m[a] * (p[a] - c[a])).sum();
            assert!(d > 0.0, "face {q:?} points inward");
        }
    }

    #[test]
    fn a_cube_split_into_tets_has_twelve_outward_triangles() {
        let (nodes, h) = unit_hex();
        // six tets around the diagonal 0-6, some given with negative orientation
        let mut tets = [
            [h[0], h[1], h[2], h[6]],
            [h[0], h[2], h[3], h[6]],
            [h[0], h[3], h[7], h[6]],
            [h[0], h[7], h[4], h[6]],
            [h[0], h[4], h[5], h[6]],
            [h[0], h[5], h[1], h[6]],
        ];
        tets[1].swap(0, 3);
        let mut els = of_kind(ElementKind::Tet4, &tets.concat());
        orient(&nodes, &mut els).unwrap();
        let vol: f64 = (els.iter())
            .map(|t| tet4::volume(&std::array::from_fn(|k| nodes[t.nodes[k] as usize])))
            .sum();
        assert!((vol - 1.0).abs() < 1e-12);
        let faces = boundary_faces(&els);
        assert_eq!(faces.len(), 12);
        assert!(faces.iter().all(|f| matches!(f, Face::Triangle(_))));
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
        let mut hexes = of_kind(ElementKind::Hex8, &[h, [8, 9, 10, 11, 4, 5, 6, 7]].concat());
        orient(&nodes, &mut hexes).unwrap();
        assert_eq!(hexes.element(1).nodes, [4, 5, 6, 7, 8, 9, 10, 11]);
        let faces = boundary_faces(&hexes);
        assert_eq!(faces.len(), 10);
        assert_outward(&nodes, &faces);
        let index = BoundaryIndex::new(&faces);
        assert_eq!(
            index.find(&[11, 10, 9, 8]),
            Some(Face::Quad([8, 9, 10, 11]))
        );
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
        let err = orient(&nodes, &mut of_kind(ElementKind::Hex8, &h)).unwrap_err();
        assert_eq!((err.index, err.kind), (0, ElementKind::Hex8));
    }
}
