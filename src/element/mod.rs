//! Finite elements: shape functions, quadrature, element matrices.
//!
//! A mesh holds hex8 and tet4 elements in two arrays; the functions here take an element's
//! corner coordinates of either kind (8 or 4 corners) and dispatch on the count, for the code
//! that runs once per element (assembly, mass lumping, stable step, stresses for output).

pub mod hex8;
pub mod tet4;

use crate::material::Elastic;

fn as_hex(x: &[[f64; 3]]) -> Option<&[[f64; 3]; 8]> {
    x.try_into().ok()
}

fn as_tet(x: &[[f64; 3]]) -> &[[f64; 3]; 4] {
    x.try_into()
        .expect("an element has 8 (hex8) or 4 (tet4) corners")
}

/// Element stiffness, (3 n) x (3 n) in (node, component) order, for n = 8 or 4 corners.
pub fn stiffness(x: &[[f64; 3]], m: &Elastic) -> Vec<Vec<f64>> {
    match as_hex(x) {
        Some(h) => hex8::stiffness(h, m).iter().map(|r| r.to_vec()).collect(),
        None => tet4::stiffness(as_tet(x), m)
            .iter()
            .map(|r| r.to_vec())
            .collect(),
    }
}

/// Consistent mass per node pair, n x n.
pub fn consistent_mass(x: &[[f64; 3]], density: f64) -> Vec<Vec<f64>> {
    match as_hex(x) {
        Some(h) => hex8::consistent_mass(h, density)
            .iter()
            .map(|r| r.to_vec())
            .collect(),
        None => tet4::consistent_mass(as_tet(x), density)
            .iter()
            .map(|r| r.to_vec())
            .collect(),
    }
}

/// Lumped mass of each corner.
pub fn lumped_mass(x: &[[f64; 3]], density: f64) -> Vec<f64> {
    match as_hex(x) {
        Some(h) => hex8::lumped_mass(h, density).to_vec(),
        None => tet4::lumped_mass(as_tet(x), density).to_vec(),
    }
}

/// Element volume.
pub fn volume(x: &[[f64; 3]]) -> f64 {
    match as_hex(x) {
        Some(h) => hex8::volume(h),
        None => tet4::volume(as_tet(x)),
    }
}
