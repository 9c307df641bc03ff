//! CPU twin of `shaders/tet4_forces.wgsl`: internal corner forces of linear elastic tet4
//! elements, $f_k = V \sigma \nabla N_k$ with the element's constant strain (see
//! [`crate::element::tet4::forces`]).

use super::ElementData;
use crate::element::tet4;

/// Corner forces of every tet: `corner_forces[4 t + k]` is corner k of tet t (overwrites it;
/// the caller passes the tets' part of the corner array, which follows the hexes' 8 per
/// element). [`super::node_gather`] sums them to the nodes.
pub fn tet4_forces(data: &ElementData, u: &[[f64; 3]], corner_forces: &mut [[f64; 3]]) {
    for (t, tet) in data.tets.iter().enumerate() {
        let m = data.materials[data.tet_material[t] as usize];
        let x = tet.map(|n| data.reference[n as usize]);
        let ue = tet.map(|n| u[n as usize]);
        let fe = tet4::forces(&x, &ue, m.lambda, m.mu);
        corner_forces[4 * t..4 * t + 4].copy_from_slice(&fe);
    }
}
