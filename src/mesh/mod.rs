//! Nodes, elements (hex8 and tet4), surfaces and node sets of all bodies in one numbering.
//!
//! A body comes either from a structured box ([`box_mesh`]) or from a mesh file
//! ([`import`]: Gmsh `.msh` 4.1 or Abaqus/CalculiX `.inp`). Either way it arrives as
//! [`BodyParts`] in its own node numbering and is appended to the [`Mesh`] by
//! [`Mesh::push_body`].
//!
//! Surfaces are lists of outward-oriented faces stored as quads; a triangle (a tet4 face)
//! is the degenerate quad `[a, b, c, c]` ([`is_triangle`]).

pub mod abaqus;
pub mod boundary;
pub mod box_mesh;
pub mod deck;
pub mod gmsh;
pub mod import;
pub mod orientation;

pub use box_mesh::box_mesh;
pub use import::import;

use std::ops::Range;

use box_mesh::BoxFace;

use crate::geometry::face::FaceKind;

/// A named list of outward-oriented boundary faces (local or global node numbers).
#[derive(Debug, Clone, PartialEq)]
pub struct Surface {
    pub name: String,
    pub faces: Vec<[u32; 4]>,
}

/// A named set of nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeSet {
    pub name: String,
    pub nodes: Vec<u32>,
}

/// True for a face stored as the degenerate quad `[a, b, c, c]` of a triangle.
pub fn is_triangle(face: &[u32; 4]) -> bool {
    FaceKind::of(face) == FaceKind::Triangle
}

/// One body's mesh in its own node numbering, as a mesher or a file reader produces it.
#[derive(Debug, Clone, Default)]
pub struct BodyParts {
    pub nodes: Vec<[f64; 3]>,
    pub hexes: Vec<[u32; 8]>,
    pub tets: Vec<[u32; 4]>,
    /// Every face of the body's boundary, outward.
    pub boundary: Vec<[u32; 4]>,
    pub surfaces: Vec<Surface>,
    pub node_sets: Vec<NodeSet>,
    /// Material axes the mesh file gives its elements (none for a box).
    pub axes: orientation::ElementAxes,
}

impl BodyParts {
    pub fn surface(&self, name: &str) -> Option<&Surface> {
        self.surfaces.iter().find(|s| s.name == name)
    }

    pub fn node_set(&self, name: &str) -> Option<&NodeSet> {
        self.node_sets.iter().find(|s| s.name == name)
    }

    pub fn element_count(&self) -> usize {
        self.hexes.len() + self.tets.len()
    }
}

/// One body's part of the global mesh.
#[derive(Debug, Clone)]
pub struct BodyMesh {
    pub nodes: Range<usize>,
    pub hexes: Range<usize>,
    pub tets: Range<usize>,
    pub material: usize,
    /// Every boundary face, outward (global node numbers).
    pub boundary: Vec<[u32; 4]>,
    /// Named surfaces; a box body has its six faces here, in [`BoxFace::ALL`] order.
    pub surfaces: Vec<Surface>,
    pub node_sets: Vec<NodeSet>,
}

impl BodyMesh {
    /// The faces of a box face (box bodies only: their surfaces are the six faces in order).
    pub fn face(&self, f: BoxFace) -> &[[u32; 4]] {
        &self.surfaces[f as usize].faces
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
    /// Material index of each hex8.
    pub hex_material: Vec<u32>,
    /// Tet4 connectivity, positively oriented (see [`crate::element::tet4`]).
    pub tets: Vec<[u32; 4]>,
    /// Material index of each tet4.
    pub tet_material: Vec<u32>,
    pub bodies: Vec<BodyMesh>,
}

impl Mesh {
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Hex8 and tet4 elements together.
    pub fn element_count(&self) -> usize {
        self.hexes.len() + self.tets.len()
    }

    /// Every element's corner nodes and material: the hex8s (indices `0..hexes.len()`), then
    /// the tet4s. Element indices elsewhere (stable step, VTU cells) follow this order.
    pub fn elements(&self) -> impl Iterator<Item = (&[u32], u32)> {
        self.hexes
            .iter()
            .map(|h| h.as_slice())
            .zip(self.hex_material.iter().copied())
            .chain(
                self.tets
                    .iter()
                    .map(|t| t.as_slice())
                    .zip(self.tet_material.iter().copied()),
            )
    }

    /// Element `e` of [`Self::elements`]: its corner nodes and material.
    pub fn element(&self, e: usize) -> (&[u32], u32) {
        match e.checked_sub(self.hexes.len()) {
            None => (&self.hexes[e], self.hex_material[e]),
            Some(t) => (&self.tets[t], self.tet_material[t]),
        }
    }

    /// Corner coordinates of an element given by its nodes.
    pub fn corners(&self, element: &[u32]) -> Vec<[f64; 3]> {
        element.iter().map(|&n| self.nodes[n as usize]).collect()
    }

    /// Appends a body (node numbers in `parts` local to it).
    pub fn push_body(&mut self, parts: BodyParts, material: usize) -> usize {
        let n0 = self.nodes.len() as u32;
        let node_range = self.nodes.len()..self.nodes.len() + parts.nodes.len();
        let (h0, t0) = (self.hexes.len(), self.tets.len());
        self.nodes.extend(parts.nodes);
        self.hexes
            .extend(parts.hexes.iter().map(|h| h.map(|i| i + n0)));
        self.hex_material
            .extend(std::iter::repeat_n(material as u32, parts.hexes.len()));
        self.tets
            .extend(parts.tets.iter().map(|t| t.map(|i| i + n0)));
        self.tet_material
            .extend(std::iter::repeat_n(material as u32, parts.tets.len()));
        let shift = |faces: Vec<[u32; 4]>| -> Vec<[u32; 4]> {
            faces.into_iter().map(|q| q.map(|i| i + n0)).collect()
        };
        self.bodies.push(BodyMesh {
            nodes: node_range,
            hexes: h0..self.hexes.len(),
            tets: t0..self.tets.len(),
            material,
            boundary: shift(parts.boundary),
            surfaces: parts
                .surfaces
                .into_iter()
                .map(|s| Surface {
                    name: s.name,
                    faces: shift(s.faces),
                })
                .collect(),
            node_sets: parts
                .node_sets
                .into_iter()
                .map(|s| NodeSet {
                    name: s.name,
                    nodes: s.nodes.into_iter().map(|i| i + n0).collect(),
                })
                .collect(),
        });
        self.bodies.len() - 1
    }

    /// Distinct nodes of a set of faces, sorted.
    pub fn quad_nodes(quads: &[[u32; 4]]) -> Vec<u32> {
        let mut v: Vec<u32> = quads.iter().flatten().copied().collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Smallest edge length over all elements (for time step and tolerance scales).
    pub fn min_edge(&self) -> f64 {
        const HEX_EDGES: [(usize, usize); 12] = [
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
        const TET_EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
        let mut h = f64::INFINITY;
        for (e, _) in self.elements() {
            let edges: &[(usize, usize)] = if e.len() == 8 { &HEX_EDGES } else { &TET_EDGES };
            for &(a, b) in edges {
                let (p, q) = (self.nodes[e[a] as usize], self.nodes[e[b] as usize]);
                let d =
                    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
                h = h.min(d);
            }
        }
        h
    }
}
