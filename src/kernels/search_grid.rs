//! The step's search grid from its bounds (CPU twin of `shaders/search_grid.wgsl` on the
//! steps that sort the faces, and of `shaders/include/kept_grid.wgsl`, which
//! `contact_search` runs on the steps that keep the sort), the host path's rule
//! (`search::{margin, search_cell}`), with a skin that lets the grid be kept across steps
//! while the faces move less than it.

use super::contact_search::SearchGrid;

/// The cell side of a sort is the largest face box side plus the margin, a thousandth more,
/// and this share more (the faces may move by about this share of a cell before the grid
/// must be sorted again).
pub const SEARCH_SKIN: f64 = 0.1;

/// What a step does with the search grid: keep the last sort (checking that it holds), sort
/// the faces again, or sort them again and start a new [`SearchGrid::fill`] (the first step
/// of a submission). The values are the kernel's `params.aux2`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SearchMode {
    Keep = 0,
    Build = 1,
    First = 2,
}

/// `bounds` from [`super::search_bounds`] (speed, side, the faces' drift since the last
/// sort); `grid` the grid before this step (its `face_size` the largest face size: a quad's
/// diagonal, a triangle's edge).
pub fn search_grid(bounds: [f64; 3], dt: f64, grid: &SearchGrid, mode: SearchMode) -> SearchGrid {
    let margin = grid.face_size + 4.0 * dt * bounds[0];
    let mut next = SearchGrid { margin, ..*grid };
    if mode == SearchMode::Keep {
        let need = (bounds[1] + margin + bounds[2]) * 1.001;
        next.fill = grid.fill.max(need / grid.cell);
        next.all_faces = need >= grid.cell;
        next.stale_steps += next.all_faces as u32;
    } else {
        next.cell = ((bounds[1] + margin) * 1.001 * (1.0 + SEARCH_SKIN)).max(1e-30);
        next.all_faces = false;
        if mode == SearchMode::First {
            next.fill = 0.0;
        }
    }
    next
}
