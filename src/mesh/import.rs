//! Reading a body's mesh from a file: the format readers ([`super::gmsh`],
//! [`super::abaqus`]) produce a [`FileMesh`] in the file's terms; this module turns it into
//! [`BodyParts`]: nodes that no element uses dropped, scale and translation applied, elements
//! oriented, the boundary found, and every surface face matched to an outward boundary face.

use std::path::Path;

use super::boundary::{boundary_faces, orient, BoundaryIndex};
use super::{BodyParts, NodeSet, Surface};
use crate::error::{ImpactError, Result};

/// A reader's error: the 1-based line it concerns (where there is one) and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct ParseError {
    pub line: Option<usize>,
    pub message: String,
}

impl ParseError {
    pub fn at(line: usize, message: impl Into<String>) -> ParseError {
        ParseError {
            line: Some(line),
            message: message.into(),
        }
    }

    pub fn whole(message: impl Into<String>) -> ParseError {
        ParseError {
            line: None,
            message: message.into(),
        }
    }
}

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
    pub hexes: Vec<[u32; 8]>,
    pub tets: Vec<[u32; 4]>,
    pub surfaces: Vec<FileSurface>,
    pub node_sets: Vec<NodeSet>,
}

/// Reads a `.msh` (Gmsh 4.1, ASCII or binary) or `.inp` (Abaqus/CalculiX) file, scales the
/// coordinates by `scale` about the origin, then translates them by `translate`.
pub fn import(path: &Path, scale: f64, translate: [f64; 3]) -> Result<BodyParts> {
    let err = |line: Option<usize>, message: String| ImpactError::Mesh {
        path: path.to_path_buf(),
        line,
        message,
    };
    let bytes = std::fs::read(path).map_err(|e| err(None, format!("cannot read: {e}")))?;
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let file = match ext.as_str() {
        "msh" => super::gmsh::read(&bytes),
        "inp" => match std::str::from_utf8(&bytes) {
            Ok(text) => super::abaqus::read(text),
            Err(e) => Err(ParseError::whole(format!("not a text file: {e}"))),
        },
        _ => {
            return Err(err(
                None,
                format!(
                    "unknown mesh format `.{ext}`: expected `.msh` (Gmsh 4.1) or `.inp` (Abaqus/CalculiX)"
                ),
            ))
        }
    }
    .map_err(|e| err(e.line, e.message))?;
    finish(file, scale, translate).map_err(|e| err(e.line, e.message))
}

/// Turns a reader's mesh into a body (see the module documentation).
pub fn finish(
    file: FileMesh,
    scale: f64,
    translate: [f64; 3],
) -> std::result::Result<BodyParts, ParseError> {
    if file.hexes.is_empty() && file.tets.is_empty() {
        return Err(ParseError::whole(
            "the file has no hex8 or tet4 elements (a body needs volume elements)",
        ));
    }
    // keep the nodes the elements use, in file order
    let mut new_index = vec![u32::MAX; file.nodes.len()];
    let used = file
        .hexes
        .iter()
        .flat_map(|h| h.iter())
        .chain(file.tets.iter().flat_map(|t| t.iter()));
    for &n in used {
        new_index[n as usize] = 0;
    }
    let mut nodes = Vec::new();
    for (i, p) in file.nodes.iter().enumerate() {
        if new_index[i] == 0 {
            new_index[i] = nodes.len() as u32;
            nodes.push([0, 1, 2].map(|a| scale * p[a] + translate[a]));
        }
    }
    let mut hexes: Vec<[u32; 8]> = file
        .hexes
        .iter()
        .map(|h| h.map(|n| new_index[n as usize]))
        .collect();
    let mut tets: Vec<[u32; 4]> = file
        .tets
        .iter()
        .map(|t| t.map(|n| new_index[n as usize]))
        .collect();
    orient(&nodes, &mut hexes, &mut tets).map_err(|d| {
        ParseError::whole(format!(
            "{} number {} (in file order) has zero volume ({:.3e}); it cannot be oriented",
            if d.tet { "tet4" } else { "hex8" },
            d.index + 1,
            d.volume
        ))
    })?;
    let boundary = boundary_faces(&hexes, &tets);
    let index = BoundaryIndex::new(&boundary);
    let mut surfaces = Vec::with_capacity(file.surfaces.len());
    for s in file.surfaces {
        let mut faces = Vec::with_capacity(s.faces.len());
        for f in &s.faces {
            let local: Option<Vec<u32>> = f
                .iter()
                .map(|&n| Some(new_index[n as usize]).filter(|&i| i != u32::MAX))
                .collect();
            let found = local.and_then(|l| index.find(&l));
            match found {
                Some(q) => faces.push(q),
                None => {
                    return Err(ParseError::at(
                        s.line,
                        format!(
                            "surface `{}`: the face with nodes {:?} (0-based, in file order) is not on the boundary of the body's elements",
                            s.name, f
                        ),
                    ))
                }
            }
        }
        faces.sort_unstable();
        faces.dedup();
        surfaces.push(Surface {
            name: s.name,
            faces,
        });
    }
    let node_sets = file
        .node_sets
        .into_iter()
        .map(|s| {
            let mut nodes: Vec<u32> = s
                .nodes
                .iter()
                .map(|&n| new_index[n as usize])
                .filter(|&i| i != u32::MAX)
                .collect();
            nodes.sort_unstable();
            nodes.dedup();
            NodeSet {
                name: s.name,
                nodes,
            }
        })
        .collect();
    Ok(BodyParts {
        nodes,
        hexes,
        tets,
        boundary,
        surfaces,
        node_sets,
    })
}
