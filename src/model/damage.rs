//! The damage kernels' inputs of a model ([`DamageData`]): each damaging scene material's
//! law, and each element of such a material as a damageable element with its plies, bands,
//! sieve, (hex8i) elastic condensation and (hexes) point operators, found once per shape
//! ([`super::damage_shapes`]).

use std::collections::HashMap;

use rayon::prelude::*;

use super::damage_shapes::{HexShape, HexShapes};
use super::Model;
use crate::element::damage::{
    hex_bands, hex_operators, hex_sieve, tet_bands, DamagePly, HexOperators, Modes, NO_LAW,
};
use crate::element::{hex8, hex8i, ElementKind};
use crate::kernels::damage_data::{DamageBlock, DamageData, NO_OPERATOR};
use crate::material::PlyDamage;

/// A scene material's law: its stiffness in its own axes with its strengths and damage.
pub(crate) fn law_of_material(m: &crate::scene::Material) -> Option<PlyDamage> {
    let d = m.damage?;
    let strength = m.strength?;
    let law = PlyDamage::new(m.elastic.voigt(), strength, d.energy, d.viscosity);
    Some(PlyDamage {
        in_plane: d.in_plane,
        lower_strength: d.lower_strength,
        ..law
    })
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
        let mut out = DamageBlock {
            elements,
            first_ply: vec![0],
            first_point: vec![0],
            ..Default::default()
        };
        let (each, shape_of): (Vec<DamageElement>, Vec<u32>) = match kind {
            ElementKind::Tet4 => {
                let each = (out.elements.par_iter())
                    .map(|&e| self.damage_tet(data, e as usize))
                    .collect::<Vec<_>>();
                let n = each.len() as u32;
                (each, (0..n).collect())
            }
            _ => self.damage_hex_shapes(data, kind, &out.elements),
        };
        let per_ply = if kind == ElementKind::Tet4 { 1 } else { 8 };
        let mut operator_of = HashMap::new();
        for &s in &shape_of {
            let d = &each[s as usize];
            out.plies.extend_from_slice(&d.plies);
            out.first_ply.push(out.plies.len() as u32);
            let last = *out.first_point.last().expect("first point");
            out.first_point
                .push(last + (per_ply * d.plies.len()) as u32);
            out.axis.push(d.axis as u32);
            out.sieve.push(d.sieve);
            out.condensation.extend_from_slice(&d.condensation);
            let op = match &d.operators {
                Some(ops) => *operator_of.entry(s).or_insert_with(|| {
                    out.operators.push(ops.clone());
                    (out.operators.len() - 1) as u32
                }),
                None => NO_OPERATOR,
            };
            out.operator.push(op);
        }
        out
    }

    /// The data of each shape of a hex block's damageable `elements`, and each element's
    /// shape. Shapes get their point operators in the order they appear, while their total
    /// stays within [`OPERATOR_BUDGET`] bytes (the rest step from their corners).
    fn damage_hex_shapes(
        &self,
        data: &DamageData,
        kind: ElementKind,
        elements: &[u32],
    ) -> (Vec<DamageElement>, Vec<u32>) {
        let block = self.mesh.elements.block(kind);
        let hexes: Vec<HexShape> = (elements.par_iter())
            .map(|&e| {
                let x = self.mesh.corners(block.element(e as usize));
                (block.material[e as usize], std::array::from_fn(|k| x[k]))
            })
            .collect();
        let shapes = HexShapes::of(&hexes);
        let mut budget = OPERATOR_BUDGET;
        let operated: Vec<bool> = (shapes.shapes.iter())
            .map(|(m, _)| {
                let plies = self.layups[*m as usize]
                    .as_ref()
                    .map_or(1, |l| l.plies.len());
                let bytes = 8 * plies * std::mem::size_of::<[[f64; 6]; 21]>();
                let fits = bytes <= budget;
                budget -= if fits { bytes } else { 0 };
                fits
            })
            .collect();
        let each = (shapes.shapes.par_iter())
            .zip(operated)
            .map(|((m, x), operated)| self.damage_hex(data, kind, (*m, x), operated))
            .collect();
        (each, shapes.of)
    }

    /// A tet4 element's data: element `e` of the block.
    fn damage_tet(&self, data: &DamageData, e: usize) -> DamageElement {
        let el = self.mesh.elements.block(ElementKind::Tet4);
        let m = el.material[e];
        let x = self.mesh.corners(el.element(e));
        let t: [[f64; 3]; 4] = std::array::from_fn(|k| x[k]);
        let (mut plies, axis) = self.damage_plies(m);
        for p in &mut plies {
            p.bands = tet_bands(&t, &data.axes[p.entry as usize]);
        }
        // a tet's one point holds all its energy
        let concentration = 1.0 / crate::element::tet4::gradients(&t).1;
        DamageElement {
            sieve: 2.0 * self.sieve_factor(data, &plies) * concentration,
            plies,
            axis,
            condensation: Vec::new(),
            operators: None,
        }
    }

    /// A hex shape's data: material index `m`, corners `x`, with its point operators where
    /// `operated`.
    fn damage_hex(
        &self,
        data: &DamageData,
        kind: ElementKind,
        (m, x): (u32, &[[f64; 3]; 8]),
        operated: bool,
    ) -> DamageElement {
        let (mut plies, axis) = self.damage_plies(m);
        for p in &mut plies {
            p.bands = hex_bands(x, &data.axes[p.entry as usize]);
        }
        let incompatible = kind == ElementKind::Hex8i;
        let condensation = match incompatible {
            true => hex8i::condensation(x, self.section(m)),
            false => Vec::new(),
        };
        let modes = match incompatible {
            true => Modes::Elastic(&condensation),
            false => Modes::None,
        };
        let axes = |p: &DamagePly| data.axes[p.entry as usize];
        let ops = hex_operators(x, (&plies, axis), &axes, modes);
        let k = match incompatible {
            true => hex8i::stiffness(x, self.section(m)),
            false => hex8::stiffness(x, &self.section(m).elastic()),
        };
        DamageElement {
            sieve: hex_sieve(&k, &ops, &plies, &data.laws()),
            plies,
            axis,
            condensation,
            operators: operated.then_some(ops),
        }
    }

    /// The plies of material index `m` (bands still zero) and its layup axis.
    fn damage_plies(&self, m: u32) -> (Vec<DamagePly>, usize) {
        match &self.layups[m as usize] {
            Some(l) => (
                (l.plies.iter())
                    .map(|p| ply(p.material, p.lo, p.hi))
                    .collect::<Vec<_>>(),
                l.axis,
            ),
            None => (vec![ply(m, -1.0, 1.0)], 0),
        }
    }

    /// The largest sieve factor beta^2 of the plies' laws, each over its lowest onset
    /// squared (the reach in those units).
    fn sieve_factor(&self, data: &DamageData, plies: &[DamagePly]) -> f64 {
        (plies.iter())
            .map(|p| {
                let law = &data.laws[data.law_of[p.entry as usize] as usize];
                law.sieve_factor() / law.lowest_onset(p.bands).powi(2)
            })
            .fold(0.0, f64::max)
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
    operators: Option<HexOperators>,
}

/// The most bytes of point operators a block keeps (126 f64 a point: 48 points, 6 plies of a
/// hex, take 48 KiB).
const OPERATOR_BUDGET: usize = 128 << 20;
