//! Each element's stable explicit step by Gershgorin's bound (CPU twin of
//! `shaders/stable_step.wgsl`): [`crate::element::stable_step::element_stable_step`] of
//! every element, in global order.

use super::ElementData;
use crate::element::stable_step::element_stable_step;

pub fn stable_step(data: &ElementData) -> Vec<f64> {
    (data.elements.iter())
        .map(|e| {
            let x: Vec<[f64; 3]> = (e.nodes.iter())
                .map(|&n| data.reference[n as usize])
                .collect();
            element_stable_step(e.kind, &x, data.section(e.material))
        })
        .collect()
}
