//! Nodes, elements (a block per kind), surfaces and node sets of all bodies in one numbering.
//!
//! A body comes either from a structured box ([`box_mesh`]) or from a mesh file
//! ([`import`]: Gmsh `.msh` 4.1 or Abaqus/CalculiX `.inp`). Either way it arrives as
//! [`BodyParts`] in its own node numbering and is appended to the [`Mesh`] by
//! [`Mesh::push_body`].
//!
//! Surfaces are lists of outward-oriented [`Face`]s: quads (hex8 faces) and triangles
//! (tet4 faces).

pub mod abaqus;
pub mod boundary;
pub mod box_mesh;
pub mod deck;
pub mod file_mesh;
pub mod gmsh;
pub mod grading;
pub mod import;
pub mod lsdyna;
pub mod orientation;
pub mod parse_error;
pub mod pieces;
pub mod split;

pub use box_mesh::box_mesh;
pub use import::import;

use std::ops::Range;

use box_mesh::BoxFace;

use crate::element::{ElementKind, ElementRef, Elements};
pub use crate::geometry::face::Face;

/// A named list of outward-oriented boundary faces (local or global node numbers).
#[derive(Debug, Clone, PartialEq)]
pub struct Surface {
    pub name: String,
    pub faces: Vec<Face>,
}

/// A named set of nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeSet {
    pub name: String,
    pub nodes: Vec<u32>,
}

/// One body's mesh in its own node numbering, as a mesher or a file reader produces it.
#[derive(Debug, Clone, Default)]
pub struct BodyParts {
    pub nodes: Vec<[f64; 3]>,
    /// The elements (materials unset: the body's material is given when it joins a mesh).
    pub elements: Elements,
    /// Every face of the body's boundary, outward.
    pub boundary: Vec<Face>,
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
        self.elements.count()
    }
}

/// One body's part of the global mesh.
#[derive(Debug, Clone)]
pub struct BodyMesh {
    pub nodes: Range<usize>,
    /// The body's elements in each block of the mesh (block-local numbers, one range per
    /// [`ElementKind`] in [`ElementKind::ALL`] order).
    pub elements: Vec<Range<usize>>,
    pub material: usize,
    /// Every boundary face, outward (global node numbers).
    pub boundary: Vec<Face>,
    /// Named surfaces; a box body has its six faces here, in [`BoxFace::ALL`] order.
    pub surfaces: Vec<Surface>,
    pub node_sets: Vec<NodeSet>,
}

impl BodyMesh {
    /// The faces of a box face (box bodies only: their surfaces are the six faces in order).
    pub fn face(&self, f: BoxFace) -> &[Face] {
        &self.surfaces[f as usize].faces
    }

    /// The body's elements of one kind (block-local numbers).
    pub fn of_kind(&self, kind: ElementKind) -> Range<usize> {
        self.elements[kind.index()].clone()
    }

    /// Elements in the body.
    pub fn element_count(&self) -> usize {
        self.elements.iter().map(|r| r.len()).sum()
    }

    /// The body's element count of each kind it holds, as "8 hex8, 48 tet4".
    pub fn kind_counts(&self) -> String {
        (ElementKind::ALL.iter())
            .filter(|&&k| !self.of_kind(k).is_empty())
            .map(|&k| format!("{} {k}", self.of_kind(k).len()))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The global numbers of the body's elements, in order.
    pub fn element_numbers<'a>(&'a self, all: &'a Elements) -> impl Iterator<Item = usize> + 'a {
        ElementKind::ALL
            .into_iter()
            .flat_map(move |k| all.global(k, self.of_kind(k)))
    }
}

/// The mesh of every body of a scene.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Reference coordinates.
    pub nodes: Vec<[f64; 3]>,
    /// Every element (global node numbers), a block per kind. A hex8's corners are in the
    /// usual order (bottom face counter-clockwise seen from +z, then the top face), a
    /// tet4's positively oriented (see [`crate::element::tet4`]).
    pub elements: Elements,
    pub bodies: Vec<BodyMesh>,
}

impl Mesh {
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Elements of every kind.
    pub fn element_count(&self) -> usize {
        self.elements.count()
    }

    /// Every element in global order (the blocks in kind order). Element numbers elsewhere
    /// (stable step, VTU cells, partitions) follow this order.
    pub fn elements(&self) -> impl Iterator<Item = ElementRef<'_>> + '_ {
        self.elements.iter()
    }

    /// Element `e` of [`Self::elements`].
    pub fn element(&self, e: usize) -> ElementRef<'_> {
        self.elements.element(e)
    }

    /// The body that holds global element `e`.
    pub fn body_of(&self, e: usize) -> Option<usize> {
        let (kind, local) = self.elements.locate(e);
        (self.bodies.iter()).position(|b| b.of_kind(kind).contains(&local))
    }

    /// Corner coordinates of an element given by its nodes.
    pub fn corners(&self, element: &[u32]) -> Vec<[f64; 3]> {
        element.iter().map(|&n| self.nodes[n as usize]).collect()
    }

    /// Appends a body (node numbers in `parts` local to it).
    pub fn push_body(&mut self, parts: BodyParts, material: usize) -> usize {
        let n0 = self.nodes.len() as u32;
        let node_range = self.nodes.len()..self.nodes.len() + parts.nodes.len();
        self.nodes.extend(parts.nodes);
        let elements = (self.elements).append(&parts.elements, n0, Some(material as u32));
        let shift = |faces: Vec<Face>| -> Vec<Face> {
            faces.into_iter().map(|q| q.map(|i| i + n0)).collect()
        };
        self.bodies.push(BodyMesh {
            nodes: node_range,
            elements,
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
    pub fn face_nodes(faces: &[Face]) -> Vec<u32> {
        let mut v: Vec<u32> = faces.iter().flat_map(|f| f.corners()).copied().collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Smallest edge length over all elements (for time step and tolerance scales).
    pub fn min_edge(&self) -> f64 {
        let mut h = f64::INFINITY;
        for e in self.elements() {
            for &(a, b) in e.kind.edges() {
                let (p, q) = (
                    self.nodes[e.nodes[a] as usize],
                    self.nodes[e.nodes[b] as usize],
                );
                let d =
                    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
                h = h.min(d);
            }
        }
        h
    }
}
