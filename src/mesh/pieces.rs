//! The connected pieces of a mesh: elements joined through shared nodes. A deck may put
//! several separate parts in one section (CalculiX's contact tests put both contacting
//! bodies in one `*SOLID SECTION`); each piece is then a body of its own (`[[body]] piece`).
//!
//! Pieces are numbered from 1 in the order of their first element, the elements taken in
//! the mesh's order (its blocks by kind, each in file order).

use super::file_mesh::{FileMesh, FileSurface};
use super::orientation::ElementAxes;
use crate::element::Elements;

/// Each element's piece (0-based, in the mesh's element order) over `nodes` nodes, and the
/// number of pieces.
pub fn pieces(elements: &Elements, nodes: usize) -> (Vec<usize>, usize) {
    let mut parent: Vec<usize> = (0..nodes).collect();
    fn root(parent: &mut [usize], mut n: usize) -> usize {
        while parent[n] != n {
            parent[n] = parent[parent[n]];
            n = parent[n];
        }
        n
    }
    for e in elements.iter() {
        let first = root(&mut parent, e.nodes[0] as usize);
        for &n in &e.nodes[1..] {
            let r = root(&mut parent, n as usize);
            parent[r] = first;
        }
    }
    let mut number = vec![usize::MAX; nodes];
    let mut count = 0;
    let of: Vec<usize> = (elements.iter())
        .map(|e| {
            let r = root(&mut parent, e.nodes[0] as usize);
            if number[r] == usize::MAX {
                number[r] = count;
                count += 1;
            }
            number[r]
        })
        .collect();
    (of, count)
}

/// `file` cut to its piece `piece` (1-based): its elements and their axes, and the surface
/// faces whose nodes the piece's elements hold (a surface left without faces is dropped).
/// The error says how many pieces there are.
pub fn keep_piece(file: FileMesh, piece: usize) -> Result<FileMesh, String> {
    let (of, count) = pieces(&file.elements, file.nodes.len());
    if piece == 0 || piece > count {
        return Err(format!(
            "piece {piece}: the selected elements make {count} connected piece(s), numbered from 1"
        ));
    }
    let mut elements = Elements::default();
    let mut axes = ElementAxes::default();
    let mut held = vec![false; file.nodes.len()];
    let mut k = 0;
    for b in &file.elements.blocks {
        let given = file.axes.of_kind(b.kind);
        for (i, (nodes, material)) in b.iter().enumerate() {
            if of[k] == piece - 1 {
                elements.push(b.kind, nodes, material);
                nodes.iter().for_each(|&n| held[n as usize] = true);
                if !file.axes.is_empty() {
                    axes.push(b.kind, given.get(i).copied().flatten());
                }
            }
            k += 1;
        }
    }
    let surfaces = (file.surfaces.into_iter())
        .map(|s| FileSurface {
            faces: (s.faces.into_iter())
                .filter(|f| f.iter().all(|&n| held[n as usize]))
                .collect(),
            ..s
        })
        .filter(|s| !s.faces.is_empty())
        .collect();
    Ok(FileMesh {
        elements,
        axes,
        surfaces,
        ..file
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::ElementKind;

    /// Two tets sharing a node are one piece; a third apart is another, numbered after.
    #[test]
    fn elements_joined_by_a_node_are_one_piece() {
        let mut e = Elements::default();
        e.push(ElementKind::Tet4, &[0, 1, 2, 3], 0);
        e.push(ElementKind::Tet4, &[5, 6, 7, 8], 0);
        e.push(ElementKind::Tet4, &[3, 4, 9, 10], 0);
        let (of, count) = pieces(&e, 11);
        assert_eq!((of, count), (vec![0, 1, 0], 2));
    }
}
