//! The plies an element spans: along one of its natural axes, each ply fills a range of the
//! natural coordinate with its own law, so that an element may hold several plies and each is
//! integrated over its own thickness (layered integration).

use super::Elastic;

/// One ply of a [`Layup`]: the natural-coordinate range `lo..hi` (within -1..1) it fills, its
/// law in the global axes and its entry in the model's material table (its axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LayupPly {
    pub lo: f64,
    pub hi: f64,
    pub elastic: Elastic,
    pub material: u32,
}

/// The plies of an element along its natural axis `axis` (0, 1, 2 for xi, eta, zeta), in
/// increasing order and covering -1..1.
#[derive(Debug, Clone, PartialEq)]
pub struct Layup {
    pub axis: usize,
    pub plies: Vec<LayupPly>,
}

impl Layup {
    /// The thickness-weighted mean of the plies' stiffnesses and densities (the Voigt
    /// average): the element's density, and its law where one law must stand for all.
    pub fn average(&self) -> Elastic {
        let mut c = [[0.0; 6]; 6];
        let mut density = 0.0;
        for p in &self.plies {
            let w = 0.5 * (p.hi - p.lo);
            let cp = p.elastic.voigt();
            for i in 0..6 {
                for j in 0..6 {
                    c[i][j] += w * cp[i][j];
                }
            }
            density += w * p.elastic.density;
        }
        Elastic::anisotropic(c, density)
    }

    /// The ply at natural coordinate `s` along the layup's axis (the upper one on a boundary).
    pub fn ply_at(&self, s: f64) -> &LayupPly {
        (self.plies.iter())
            .find(|p| s < p.hi)
            .unwrap_or_else(|| self.plies.last().expect("a layup has plies"))
    }
}
