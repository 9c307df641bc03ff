//! Narrow phase of the GPU contact search (CPU twin of `shaders/contact_search.wgsl`): for
//! each query, the faces of its interface in the 27 grid cells around the node whose box,
//! grown by the margin, holds the node; of those the closest by projection, with the
//! kinematics of [`super::contact_gap`] (ties: the lower face index).

use super::contact_gap::{contact_gap, ContactPoint, ContactQueries};
use super::face_cells::{cell_key, cell_of};

/// The search grid: cell side, candidate margin, table mask.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchGrid {
    pub cell: f64,
    pub margin: f64,
    pub mask: u32,
}

/// `face_range[q]` is the face range of query q's interface; bucket k of the grid holds
/// `sorted[starts[k]..starts[k + 1]]`.
#[allow(clippy::too_many_arguments)]
pub fn contact_search(
    reference: &[[f64; 3]],
    u: &[[f64; 3]],
    v: &[[f64; 3]],
    secondary: &[u32],
    face_range: &[(u32, u32)],
    faces: &[[u32; 4]],
    starts: &[u32],
    sorted: &[u32],
    grid: SearchGrid,
) -> Vec<ContactPoint> {
    let pos = |n: u32| -> [f64; 3] {
        std::array::from_fn(|a| reference[n as usize][a] + u[n as usize][a])
    };
    let mut q = ContactQueries {
        secondary: secondary.to_vec(),
        offsets: vec![0],
        candidates: Vec::new(),
        faces: faces.to_vec(),
    };
    for (&s, &(first, end)) in secondary.iter().zip(face_range) {
        let x = pos(s);
        let home = cell_of(x, grid.cell);
        let mut list = Vec::new();
        for c in 0..27i32 {
            let cell = [
                home[0] + c % 3 - 1,
                home[1] + (c / 3) % 3 - 1,
                home[2] + c / 9 - 1,
            ];
            let key = cell_key(cell, first, grid.mask) as usize;
            for &fi in &sorted[starts[key] as usize..starts[key + 1] as usize] {
                if fi < first || fi >= end || list.contains(&fi) {
                    continue;
                }
                let p = faces[fi as usize].map(pos);
                let inside = (0..3).all(|a| {
                    let lo = p.iter().map(|y| y[a]).fold(f64::INFINITY, f64::min);
                    let hi = p.iter().map(|y| y[a]).fold(f64::NEG_INFINITY, f64::max);
                    lo - grid.margin <= x[a] && x[a] <= hi + grid.margin
                });
                if inside {
                    list.push(fi);
                }
            }
        }
        // in face order, so that contact_gap's first-wins rule takes the lower index on ties
        list.sort_unstable();
        q.candidates.extend_from_slice(&list);
        q.offsets.push(q.candidates.len() as u32);
    }
    let mut out = vec![ContactPoint::default(); secondary.len()];
    contact_gap(reference, u, v, &q, &mut out);
    out
}
