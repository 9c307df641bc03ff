//! Nodes, hex8 elements, boundary quads and node sets of all bodies in one numbering.

pub mod box_mesh;

pub use box_mesh::box_mesh;

use std::ops::Range;

use crate::scene::BoxFace;

/// One body's part of the global mesh.
#[derive(Debug, Clone)]
pub struct BodyMesh {
    pub nodes: Range<usize>,
    pub elements: Range<usize>,
    pub material: usize,
    /// Boundary quads of each box face (indexed by `BoxFace as usize`), global node numbers,
    /// ordered so that `tau_1 x tau_2` (see [`crate::contact::quad`]) is the outward normal.
    pub faces: [Vec<[u32; 4]>; 6],
}

impl BodyMesh {
    pub fn face(&self, f: BoxFace) -> &[[u32; 4]] {
        &self.faces[f as usize]
    }

    /// All boundary quads of the body.
    pub fn boundary(&self) -> impl Iterator<Item = &[u32; 4]> {
        self.faces.iter().flatten()
    }
}

/// The mesh of every body of a scene.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Reference coordinates.
    pub nodes: Vec<[f64; 3]>,
    /// Hex8 connectivity (global node numbers, the usual corner order: bottom face
    /// counter-clockwise seen from +z, then the top face).
    pub hexes: Vec<[u32; 8]>,
    /// Material index of each element.
    pub element_material: Vec<u32>,
    pub bodies: Vec<BodyMesh>,
}

impl Mesh {
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Appends a body meshed elsewhere (node numbers in `hexes` and `faces` local to it).
    pub fn push_body(
        &mut self,
        nodes: Vec<[f64; 3]>,
        hexes: Vec<[u32; 8]>,
        faces: [Vec<[u32; 4]>; 6],
        material: usize,
    ) -> usize {
        let n0 = self.nodes.len() as u32;
        let e0 = self.hexes.len();
        let node_range = self.nodes.len()..self.nodes.len() + nodes.len();
        self.nodes.extend(nodes);
        self.hexes.extend(hexes.iter().map(|h| h.map(|i| i + n0)));
        self.element_material
            .extend(std::iter::repeat_n(material as u32, hexes.len()));
        let faces = faces.map(|f| f.into_iter().map(|q| q.map(|i| i + n0)).collect());
        self.bodies.push(BodyMesh {
            nodes: node_range,
            elements: e0..self.hexes.len(),
            material,
            faces,
        });
        self.bodies.len() - 1
    }

    /// Distinct nodes of a set of quads, sorted.
    pub fn quad_nodes(quads: &[[u32; 4]]) -> Vec<u32> {
        let mut v: Vec<u32> = quads.iter().flatten().copied().collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Smallest edge length over all elements (for time step and tolerance scales).
    pub fn min_edge(&self) -> f64 {
        const EDGES: [(usize, usize); 12] = [
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 0),
            (4, 5),
            (5, 6),
            (6, 7),
            (7, 4),
            (0, 4),
            (1, 5),
            (2, 6),
            (3, 7),
        ];
        let mut h = f64::INFINITY;
        for e in &self.hexes {
            for &(a, b) in &EDGES {
                let (p, q) = (self.nodes[e[a] as usize], self.nodes[e[b] as usize]);
                let d =
                    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
                h = h.min(d);
            }
        }
        h
    }
}
