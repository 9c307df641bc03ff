//! A body's mesh split across planes normal to an axis: each node on a plane gets a twin,
//! which the elements above the plane take in its place, so the layers below and above meet
//! at coincident nodes without sharing them (a cohesive interface then bonds each pair).
//!
//! An element is above a plane where its centroid is; boundary faces follow the same rule
//! (a side face of an element above takes the twins). The twins are numbered after the
//! body's nodes, plane by plane, in the order of their originals.

use super::{BodyParts, Face};

/// The split mesh, the pairs of coincident nodes (the twin above, the original below) and
/// the faces of the layers below each plane that lie on it, oriented along +axis (in the
/// originals' numbers): the interface's faces.
#[derive(Debug, Clone)]
pub struct Split {
    pub parts: BodyParts,
    pub pairs: Vec<(u32, u32)>,
    pub faces: Vec<Face>,
}

/// Splits `parts` across the planes `axis = c` for each c in `planes` (within `tol`).
/// Elements of 4 or 8 corners (tets and hexes); a face on a plane is a hex's 4 corners there.
pub fn split_layers(mut parts: BodyParts, axis: usize, planes: &[f64], tol: f64) -> Split {
    let count = parts.nodes.len();
    // each node's plane (the index into `planes`), if it lies on one
    let plane_of: Vec<Option<usize>> = (parts.nodes.iter())
        .map(|x| planes.iter().position(|c| (x[axis] - c).abs() <= tol))
        .collect();
    let mut twin = vec![u32::MAX; count];
    let mut pairs = Vec::new();
    for p in 0..planes.len() {
        for n in (0..count).filter(|&n| plane_of[n] == Some(p)) {
            twin[n] = parts.nodes.len() as u32;
            pairs.push((twin[n], n as u32));
            parts.nodes.push(parts.nodes[n]);
        }
    }
    let lift = |nodes: &[u32], x: &[[f64; 3]]| -> Vec<u32> {
        let centre = nodes.iter().map(|&n| x[n as usize][axis]).sum::<f64>() / nodes.len() as f64;
        (nodes.iter())
            .map(|&n| match plane_of[n as usize] {
                Some(p) if centre > planes[p] => twin[n as usize],
                _ => n,
            })
            .collect()
    };
    let x = parts.nodes.clone();
    let mut faces = Vec::new();
    for block in &mut parts.elements.blocks {
        let k = block.kind.corners();
        let lifted: Vec<u32> = (block.nodes.chunks_exact(k))
            .flat_map(|e| {
                faces.extend(face_on_plane(e, &x, axis, (planes, &plane_of)));
                lift(e, &x)
            })
            .collect();
        block.nodes = lifted;
    }
    let lift_face = |f: &Face| Face::of_corners(&lift(f.corners(), &x));
    parts.boundary = parts.boundary.iter().map(lift_face).collect();
    for s in &mut parts.surfaces {
        s.faces = s.faces.iter().map(lift_face).collect();
    }
    Split {
        parts,
        pairs,
        faces,
    }
}

/// The face of element `e` that lies on a plane with the element below it: its corners
/// there, ordered counter-clockwise about +axis.
fn face_on_plane(
    e: &[u32],
    x: &[[f64; 3]],
    axis: usize,
    (planes, plane_of): (&[f64], &[Option<usize>]),
) -> Option<Face> {
    let centre = e.iter().map(|&n| x[n as usize][axis]).sum::<f64>() / e.len() as f64;
    let on: Vec<u32> = (e.iter().copied())
        .filter(|&n| plane_of[n as usize].is_some_and(|p| planes[p] > centre))
        .collect();
    if on.len() < 3 {
        return None;
    }
    // the plane's own axes, right-handed with +axis
    let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
    let mid = [a, b].map(|c| on.iter().map(|&n| x[n as usize][c]).sum::<f64>() / on.len() as f64);
    let mut ordered = on;
    ordered.sort_by(|&p, &q| {
        let angle = |n: u32| (x[n as usize][b] - mid[1]).atan2(x[n as usize][a] - mid[0]);
        angle(p).total_cmp(&angle(q))
    });
    Some(Face::of_corners(&ordered))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::box_mesh::{BoxElement, BoxSpec};

    /// A 2 x 2 x 3 box split at its two inner layer planes: 2 x 9 twins, every element of
    /// the upper layers on twins where it touched a plane, the faces on each plane the 4
    /// quads of the layer below, facing +z, and each pair coincident.
    #[test]
    fn a_box_splits_at_its_layer_planes() {
        let spec = BoxSpec {
            min: [0.0; 3],
            max: [2.0, 2.0, 3.0],
            divisions: [2, 2, 3],
            element: BoxElement::Hex8,
            refine: None,
        };
        let parts = crate::mesh::box_mesh(&spec);
        let n = parts.nodes.len();
        let s = split_layers(parts.clone(), 2, &[1.0, 2.0], 1e-9);
        assert_eq!(s.pairs.len(), 18);
        assert_eq!(s.parts.nodes.len(), n + 18);
        for &(up, low) in &s.pairs {
            assert_eq!(s.parts.nodes[up as usize], s.parts.nodes[low as usize]);
            assert!(up as usize >= n && (low as usize) < n);
        }
        assert_eq!(s.faces.len(), 8);
        for f in &s.faces {
            let p = f.slots().map(|n| s.parts.nodes[n as usize]);
            let normal = crate::geometry::quad::normal(&p, [0.0, 0.0]);
            assert!((normal[2] - 1.0).abs() < 1e-12, "{normal:?}");
        }
        // no element shares a node across a plane
        let block = s.parts.elements.block(crate::element::ElementKind::Hex8);
        for (e, _) in block.iter() {
            let z: Vec<f64> = e.iter().map(|&n| s.parts.nodes[n as usize][2]).collect();
            let centre = z.iter().sum::<f64>() / 8.0;
            for (&node, &zn) in e.iter().zip(&z) {
                let on_plane = (zn - 1.0).abs() < 1e-9 || (zn - 2.0).abs() < 1e-9;
                if on_plane {
                    assert_eq!((node as usize) >= n, centre > zn, "element {e:?}");
                }
            }
        }
        // the side faces above a plane take the twins; the boundary keeps its count
        assert_eq!(s.parts.boundary.len(), parts.boundary.len());
    }
}
