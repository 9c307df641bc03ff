//! [`FileMesh`]: a mesh as a format reader produces it, in the file's own terms, before
//! [`super::import`] makes a body of it. The readers ([`super::gmsh`], [`super::abaqus`],
//! [`super::lsdyna`]) depend on this module alone; `import` on them and on it.

use super::orientation::ElementAxes;
use super::NodeSet;
use crate::element::Elements;

/// A named list of faces as the file gives them: 3 or 4 node indices each, in any order.
#[derive(Debug, Clone, PartialEq)]
pub struct FileSurface {
    pub name: String,
    pub faces: Vec<Vec<u32>>,
    /// Where the surface is defined, for messages.
    pub line: usize,
}

/// A mesh as a file reader produces it (node indices into `nodes`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FileMesh {
    pub nodes: Vec<[f64; 3]>,
    /// The elements in file order within each kind's block (file node indices).
    pub elements: Elements,
    pub surfaces: Vec<FileSurface>,
    pub node_sets: Vec<NodeSet>,
    /// Material axes per element (Abaqus `*ORIENTATION`), in `elements` order.
    pub axes: ElementAxes,
    /// Keywords the reader passed over, with their lines (an Abaqus deck's materials, steps).
    pub skipped: Vec<(String, usize)>,
}
