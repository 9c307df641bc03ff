//! Narrow phase of the GPU contact search (CPU twin of `shaders/contact_search.wgsl`): for
//! each query, the faces of its interface in the 27 grid cells around the node (every face
//! of the interface where the grid no longer holds: [`SearchGrid::all_faces`]) whose box,
//! grown by the margin, holds the node; of those the closest by projection, with the
//! kinematics of [`super::contact_gap`] (ties: the lower face index).

use super::contact_gap::{contact_gap, ContactPoint, ContactQueries};
use super::face_cells::{cell_key, cell_of};

/// The search grid: the cell side and table mask the faces were last sorted with, this
/// step's candidate margin, and whether the grid still holds (see `search_grid`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SearchGrid {
    pub cell: f64,
    pub margin: f64,
    pub mask: u32,
    /// The grid kept from an earlier sort no longer holds: every face of the query's
    /// interface is tested.
    pub all_faces: bool,
    /// The margin's base, the largest face size.
    pub face_size: f64,
    /// The largest share of the cell the steps that kept the grid needed since the last
    /// reset, and the steps that tested every face.
    pub fill: f64,
    pub stale_steps: u32,
}

impl SearchGrid {
    /// A grid the faces are sorted with at this step: cell side, margin, mask.
    pub fn at(cell: f64, margin: f64, mask: u32) -> Self {
        SearchGrid {
            cell,
            margin,
            mask,
            ..Self::default()
        }
    }
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
        let candidate = |fi: u32| {
            let p = faces[fi as usize].map(pos);
            (0..3).all(|a| {
                let lo = p.iter().map(|y| y[a]).fold(f64::INFINITY, f64::min);
                let hi = p.iter().map(|y| y[a]).fold(f64::NEG_INFINITY, f64::max);
                lo - grid.margin <= x[a] && x[a] <= hi + grid.margin
            })
        };
        let mut list = Vec::new();
        if grid.all_faces {
            list.extend((first..end).filter(|&fi| candidate(fi)));
        } else {
            let home = cell_of(x, grid.cell);
            for c in 0..27i32 {
                let cell = [
                    home[0] + c % 3 - 1,
                    home[1] + (c / 3) % 3 - 1,
                    home[2] + c / 9 - 1,
                ];
                let key = cell_key(cell, first, grid.mask) as usize;
                for &fi in &sorted[starts[key] as usize..starts[key + 1] as usize] {
                    if fi >= first && fi < end && !list.contains(&fi) && candidate(fi) {
                        list.push(fi);
                    }
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
