//! Reading a body's mesh from a file: the format readers ([`super::gmsh`],
//! [`super::abaqus`], [`super::lsdyna`]) produce a [`FileMesh`] in the file's terms
//! ([`super::file_mesh`]); this module turns it into
//! [`BodyParts`]: nodes that no element uses dropped, scale and translation applied, elements
//! oriented, the boundary found, and every surface face matched to an outward boundary face.

use std::path::Path;

use super::boundary::{boundary_faces, orient, BoundaryIndex};
use super::deck::{Deck, Dialect};
pub use super::file_mesh::{FileMesh, FileSurface};
pub use super::parse_error::ParseError;
use super::{BodyParts, Face, NodeSet, Surface};
use crate::error::{ImpactError, Result};

/// Reads a `.msh` (Gmsh 4.1, ASCII or binary), `.inp` (Abaqus/CalculiX, with its
/// `*INCLUDE`s) or `.k` (LS-DYNA keywords) file, scales the coordinates by `scale` about the
/// origin, then translates them by `translate`. With `elset`, a deck's body is the elements
/// of that `*ELSET` (`.inp`) or of the part of that id (`.k`) only (a deck may hold several
/// bodies). Returns the body and the notices to show (keywords a deck
/// holds that were not read).
pub fn import(
    path: &Path,
    scale: f64,
    translate: [f64; 3],
    elset: Option<&str>,
) -> Result<(BodyParts, Vec<String>)> {
    import_piece(path, scale, translate, elset, None)
}

/// [`import`] of one connected piece (1-based, [`super::pieces`]) of the selected elements,
/// or of them all.
pub fn import_piece(
    path: &Path,
    scale: f64,
    translate: [f64; 3],
    elset: Option<&str>,
    piece: Option<usize>,
) -> Result<(BodyParts, Vec<String>)> {
    let located = |e: ParseError| ImpactError::Mesh {
        path: e.file.unwrap_or_else(|| path.to_path_buf()),
        line: e.line,
        message: e.message,
    };
    let bytes = crate::limits::read_input(path)
        .map_err(|e| located(ParseError::whole(format!("cannot read: {e}"))))?;
    // a byte-order mark some editors write is no part of either format
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&bytes);
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let (file, deck) = match ext.as_str() {
        "msh" if elset.is_some() => {
            return Err(located(ParseError::whole(
                "an element set selects a body of an Abaqus/CalculiX deck (.inp); a .msh file is one body",
            )))
        }
        "msh" => (super::gmsh::read(bytes).map_err(located)?, None),
        "k" | "key" | "dyn" => {
            let text = std::str::from_utf8(bytes)
                .map_err(|e| located(ParseError::whole(format!("not a text file: {e}"))))?;
            let deck = Deck::expand_as(Dialect::Keyword, text, Some(path)).map_err(located)?;
            let file =
                super::lsdyna::read(&deck.text, elset).map_err(|e| located(deck.locate(e)))?;
            (file, Some(deck))
        }
        "inp" => {
            let text = std::str::from_utf8(bytes)
                .map_err(|e| located(ParseError::whole(format!("not a text file: {e}"))))?;
            let deck = Deck::expand(text, Some(path)).map_err(located)?;
            let file =
                super::abaqus::read(&deck.text, elset).map_err(|e| located(deck.locate(e)))?;
            (file, Some(deck))
        }
        _ => {
            return Err(located(ParseError::whole(format!(
            "unknown mesh format `.{ext}`: expected `.msh` (Gmsh 4.1), `.inp` (Abaqus/CalculiX) or `.k` (LS-DYNA)"
        ))))
        }
    };
    let notices = match &deck {
        Some(d) => skipped_notice(path, &|l| d.origin(l), &file.skipped),
        None => None,
    }
    .into_iter()
    .collect();
    let in_file = |e: ParseError| match &deck {
        Some(d) => d.locate(e),
        None => e,
    };
    let file = match piece {
        Some(k) => super::pieces::keep_piece(file, k).map_err(|m| located(ParseError::whole(m)))?,
        None => file,
    };
    let parts = finish(file, scale, translate).map_err(|e| located(in_file(e)))?;
    Ok((parts, notices))
}

/// One line naming every keyword of a deck that was not read, each with its lines.
fn skipped_notice<'a>(
    path: &Path,
    origin: &dyn Fn(usize) -> (Option<&'a Path>, usize),
    skipped: &[(String, usize)],
) -> Option<String> {
    const SHOWN: usize = 8;
    let mut keywords: Vec<(&str, Vec<String>)> = Vec::new();
    for (name, line) in skipped {
        let at = match origin(*line) {
            (None, l) => format!("{l}"),
            (Some(f), l) => format!("{}:{l}", f.display()),
        };
        match keywords.iter_mut().find(|(k, _)| k == name) {
            Some((_, lines)) => lines.push(at),
            None => keywords.push((name, vec![at])),
        }
    }
    if keywords.is_empty() {
        return None;
    }
    let listed: Vec<String> = keywords
        .iter()
        .map(|(k, lines)| {
            let more = lines.len().saturating_sub(SHOWN);
            let shown = lines[..lines.len().min(SHOWN)].join(", ");
            let more = if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            };
            let word = if lines.len() == 1 { "line" } else { "lines" };
            format!("*{k} ({word} {shown}{more})")
        })
        .collect();
    Some(format!(
        "{}: keywords not read (the scene gives the materials, supports, velocities, contacts and run): {}",
        path.display(),
        listed.join(", ")
    ))
}

/// Turns a reader's mesh into a body (see the module documentation).
pub(crate) fn finish(
    file: FileMesh,
    scale: f64,
    translate: [f64; 3],
) -> std::result::Result<BodyParts, ParseError> {
    if file.elements.count() == 0 {
        return Err(ParseError::whole(
            "the file has no hex8, hex8i or tet4 elements (a body needs volume elements)",
        ));
    }
    let new_index = used_node_index(&file);
    let nodes = used_nodes(&file.nodes, &new_index, scale, translate);
    let mut elements = file.elements;
    for b in &mut elements.blocks {
        b.nodes.iter_mut().for_each(|n| *n = new_index[*n as usize]);
    }
    orient(&nodes, &mut elements).map_err(|d| {
        let (kind, number) = (d.kind, d.index + 1);
        ParseError::whole(match (d.extent.powi(3) * 1e12).is_finite() {
            true => format!(
                "{kind} number {number} (in file order) has zero volume ({:.3e}); it cannot be oriented",
                d.volume
            ),
            false => format!(
                "{kind} number {number} (in file order) spans {:.3e}: its volume overflows a double (coordinates this large cannot be computed with; scale the model)",
                d.extent
            ),
        })
    })?;
    let boundary = boundary_faces(&elements);
    let index = BoundaryIndex::new(&boundary);
    let surfaces: Vec<Surface> = file
        .surfaces
        .into_iter()
        .map(|s| boundary_surface(s, &new_index, &index))
        .collect::<std::result::Result<_, _>>()?;
    let node_sets: Vec<NodeSet> = file
        .node_sets
        .into_iter()
        .map(|s| renumber_node_set(s, &new_index))
        .collect();
    Ok(BodyParts {
        nodes,
        elements,
        boundary,
        surfaces,
        node_sets,
        axes: file.axes,
    })
}

/// Unused file nodes (`new_index[n] == u32::MAX`).
const UNUSED: u32 = u32::MAX;

/// The new index of each file node: the nodes the elements use, numbered in file order;
/// [`UNUSED`] for the others.
fn used_node_index(file: &FileMesh) -> Vec<u32> {
    let mut used = vec![false; file.nodes.len()];
    for n in file.elements.corner_nodes() {
        used[n as usize] = true;
    }
    let mut next = 0;
    used.iter()
        .map(|&u| {
            if !u {
                return UNUSED;
            }
            next += 1;
            next - 1
        })
        .collect()
}

/// The used nodes, in file order, scaled by `scale` about the origin and then translated.
fn used_nodes(
    nodes: &[[f64; 3]],
    new_index: &[u32],
    scale: f64,
    translate: [f64; 3],
) -> Vec<[f64; 3]> {
    nodes
        .iter()
        .zip(new_index)
        .filter(|&(_, &i)| i != UNUSED)
        .map(|(p, _)| [0, 1, 2].map(|a| scale * p[a] + translate[a]))
        .collect()
}

/// A file surface as the outward boundary faces it names (sorted, without repeats); an
/// error names the first face that is not on the boundary.
fn boundary_surface(
    s: FileSurface,
    new_index: &[u32],
    index: &BoundaryIndex,
) -> std::result::Result<Surface, ParseError> {
    let mut faces = Vec::with_capacity(s.faces.len());
    for f in &s.faces {
        let local: Option<Vec<u32>> = f
            .iter()
            .map(|&n| Some(new_index[n as usize]).filter(|&i| i != UNUSED))
            .collect();
        let Some(q) = local.and_then(|l| index.find(&l)) else {
            return Err(ParseError::at(
                s.line,
                format!(
                    "surface `{}`: the face with nodes {:?} (0-based, in file order) is not on the boundary of the body's elements",
                    s.name, f
                ),
            ));
        };
        faces.push(q);
    }
    // the order of the kernels' slots (a quad's corners; a triangle's with its last again)
    faces.sort_unstable_by_key(Face::slots);
    faces.dedup();
    Ok(Surface {
        name: s.name,
        faces,
    })
}

/// A node set by the new indices (sorted, without repeats), its nodes that no element uses
/// left out.
fn renumber_node_set(s: NodeSet, new_index: &[u32]) -> NodeSet {
    let mut nodes: Vec<u32> = s
        .nodes
        .iter()
        .map(|&n| new_index[n as usize])
        .filter(|&i| i != UNUSED)
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    NodeSet {
        name: s.name,
        nodes,
    }
}
