//! The damage kernels' inputs of a model ([`DamageData`]): each damaging scene material's
//! law, and each element of such a material as a damageable element with its plies, bands,
//! sieve and (hex8i) elastic condensation.

use rayon::prelude::*;

use super::Model;
use crate::element::damage::{hex_bands, hex_concentration, tet_bands, DamagePly, NO_LAW};
use crate::element::{hex8i, ElementKind};
use crate::kernels::damage_data::{DamageBlock, DamageData};
use crate::material::PlyDamage;

/// A scene material's law: its stiffness in its own axes with its strengths and damage.
pub(crate) fn law_of_material(m: &crate::scene::Material) -> Option<PlyDamage> {
    let d = m.damage?;
    let strength = m.strength?;
    Some(PlyDamage::new(
        m.elastic.voigt(),
        strength,
        d.energy,
        d.viscosity,
    ))
}

impl Model {
    /// The damage kernels' inputs, where any material damages.
    pub fn damage_data(&self) -> Option<DamageData> {
        if self.damage_laws.iter().all(Option::is_none) {
            return None;
        }
        let mut laws = Vec::new();
        let law_index: Vec<u32> = (self.damage_laws.iter())
            .map(|l| match l {
                Some(l) => {
                    laws.push(*l);
                    (laws.len() - 1) as u32
                }
                None => NO_LAW,
            })
            .collect();
        let law_of: Vec<u32> = (self.material_source.iter())
            .map(|&s| law_index[s])
            .collect();
        let data = DamageData {
            laws,
            law_of,
            axes: self.material_axes.clone(),
            blocks: Vec::new(),
        };
        let blocks = ElementKind::ALL
            .map(|k| self.damage_block(&data, k))
            .to_vec();
        Some(DamageData { blocks, ..data })
    }

    /// The damageable elements of a kind's block.
    fn damage_block(&self, data: &DamageData, kind: ElementKind) -> DamageBlock {
        let block = self.mesh.elements.block(kind);
        let elements: Vec<u32> = (0..block.len() as u32)
            .filter(|&e| data.damages(block.material[e as usize]))
            .collect();
        let each: Vec<DamageElement> = (elements.par_iter())
            .map(|&e| self.damage_element(data, kind, e as usize))
            .collect();
        let mut out = DamageBlock {
            elements,
            first_ply: vec![0],
            first_point: vec![0],
            ..Default::default()
        };
        let per_ply = if kind == ElementKind::Tet4 { 1 } else { 8 };
        for d in each {
            out.plies.extend_from_slice(&d.plies);
            out.first_ply.push(out.plies.len() as u32);
            let last = *out.first_point.last().expect("first point");
            out.first_point
                .push(last + (per_ply * d.plies.len()) as u32);
            out.axis.push(d.axis as u32);
            out.sieve.push(d.sieve);
            out.condensation.extend_from_slice(&d.condensation);
        }
        out
    }

    /// One damageable element: element `e` of the kind's block.
    fn damage_element(&self, data: &DamageData, kind: ElementKind, e: usize) -> DamageElement {
        let el = self.mesh.elements.block(kind);
        let nodes = el.element(e);
        let m = el.material[e];
        let x = self.mesh.corners(nodes);
        let (mut plies, axis) = match &self.layups[m as usize] {
            Some(l) => (
                (l.plies.iter())
                    .map(|p| ply(p.material, p.lo, p.hi))
                    .collect::<Vec<_>>(),
                l.axis,
            ),
            None => (vec![ply(m, -1.0, 1.0)], 0),
        };
        let beta2 = (plies.iter())
            .map(|p| data.laws[data.law_of[p.entry as usize] as usize].sieve_factor())
            .fold(0.0, f64::max);
        // the largest share of the element's strain energy a point's density can hold
        let (concentration, condensation) = match kind {
            ElementKind::Tet4 => {
                let t: [[f64; 3]; 4] = std::array::from_fn(|k| x[k]);
                for p in &mut plies {
                    p.bands = tet_bands(&t, &data.axes[p.entry as usize]);
                }
                (1.0 / crate::element::tet4::gradients(&t).1, Vec::new())
            }
            _ => {
                let h: [[f64; 3]; 8] = std::array::from_fn(|k| x[k]);
                for p in &mut plies {
                    p.bands = hex_bands(&h, &data.axes[p.entry as usize]);
                }
                let condensation = match kind {
                    ElementKind::Hex8i => hex8i::condensation(&h, self.section(m)),
                    _ => Vec::new(),
                };
                let incompatible = kind == ElementKind::Hex8i;
                (
                    hex_concentration(&h, self.section(m), incompatible),
                    condensation,
                )
            }
        };
        DamageElement {
            plies,
            axis,
            sieve: 2.0 * beta2 * concentration,
            condensation,
        }
    }
}

/// A ply of material entry `entry` over `lo..hi` (its bands found afterwards).
fn ply(entry: u32, lo: f64, hi: f64) -> DamagePly {
    DamagePly {
        entry,
        lo,
        hi,
        bands: [0.0; 2],
    }
}

/// What [`Model::damage_block`] gathers of one element.
struct DamageElement {
    plies: Vec<DamagePly>,
    axis: usize,
    sieve: f64,
    condensation: Vec<f64>,
}
