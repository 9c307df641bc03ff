//! Each element's stable explicit step by Gershgorin's bound (CPU twin of
//! `shaders/stable_step.wgsl`): [`crate::element::stable_step::element_stable_step`] of
//! every element, hexes then tets.

use super::ElementData;
use crate::element::stable_step::element_stable_step;

pub fn stable_step(data: &ElementData) -> Vec<f64> {
    let corners = |nodes: &[u32]| -> Vec<[f64; 3]> {
        nodes.iter().map(|&n| data.reference[n as usize]).collect()
    };
    let hexes = data
        .hexes
        .iter()
        .zip(&data.hex_material)
        .map(|(h, &m)| element_stable_step(&corners(h), &data.materials[m as usize]));
    let tets = data
        .tets
        .iter()
        .zip(&data.tet_material)
        .map(|(t, &m)| element_stable_step(&corners(t), &data.materials[m as usize]));
    hexes.chain(tets).collect()
}
