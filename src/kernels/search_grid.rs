//! The step's search grid from its bounds (CPU twin of `shaders/search_grid.wgsl`), the host
//! path's rule (`search::{margin, search_cell}`).

use super::contact_search::SearchGrid;

/// `bounds` from [`super::search_bounds`]; `face_size` the largest face size (a quad's
/// diagonal, a triangle's edge).
pub fn search_grid(bounds: [f64; 2], dt: f64, face_size: f64, mask: u32) -> SearchGrid {
    let margin = face_size + 4.0 * dt * bounds[0];
    SearchGrid {
        cell: ((bounds[1] + margin) * 1.001).max(1e-30),
        margin,
        mask,
    }
}
