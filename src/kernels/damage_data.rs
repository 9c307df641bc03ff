//! The flat inputs and the state of the damage kernels (`hex8_damage`, `hex8i_damage`,
//! `tet4_damage`; [`crate::element::damage`]).
//!
//! Each element block has a list of its damageable elements (those of a material with
//! `fracture_energy`), each with its plies ([`DamagePly`]), its layup axis, its sieve and,
//! for a hex8i, its elastic condensation. The state is [`POINT_STATE`] values per point, a
//! hex's 8 per ply and a tet's one, and a flag per element once any of its points holds
//! damage.
//!
//! **The sieve.** The element kernels first give every element its elastic forces. A
//! damageable element without damage keeps them when no point can have reached a Hashin
//! index of 1: every point's reach ([`PlyDamage::reach`], at least each mode's r) is at most
//! $\sqrt{\kappa U}$, $U = \tfrac12 \sum_k f_k \cdot u_k$ the element's strain energy and
//! $\kappa$ its sieve ([`crate::element::damage::hex_sieve`]; a tet's $2 \beta^2 / V$,
//! [`PlyDamage::sieve_factor`]). The device's kernels skip an element with $\kappa U < 1$;
//! the CPU's remember where they last looked ([`super::damage_sieve`]).

use crate::element::damage::{DamagePly, HexOperators, NO_LAW};
use crate::element::ElementKind;
use crate::material::damage::{PlyDamage, POINT_STATE};
use crate::material::Rotation;

/// Each block's element count, in [`ElementKind::ALL`] order.
pub fn block_counts(elements: &crate::element::Elements) -> Vec<usize> {
    elements.blocks.iter().map(|b| b.len()).collect()
}

/// Words of a damageable element's record on the device (flag, first step, first point,
/// dissipation's bits, its fibre share's bits), after the step counter
/// (`shaders/shared/types.wgsl`).
pub const DAMAGE_RECORD: usize = 5;

/// Everything the damage kernels read that does not change.
#[derive(Debug, Clone, Default)]
pub struct DamageData {
    /// The laws, one per damaging scene material.
    pub laws: Vec<PlyDamage>,
    /// Each material entry's law ([`NO_LAW`] for one that does not damage).
    pub law_of: Vec<u32>,
    /// Each material entry's axes.
    pub axes: Vec<Rotation>,
    /// One per element kind, in [`ElementKind::ALL`] order.
    pub blocks: Vec<DamageBlock>,
}

/// A block's damageable elements.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DamageBlock {
    /// Their numbers in the block, increasing.
    pub elements: Vec<u32>,
    /// Each one's first ply in `plies` (one more entry than elements).
    pub first_ply: Vec<u32>,
    pub plies: Vec<DamagePly>,
    /// Each one's first point (one more entry than elements): 8 per ply of a hex, 1 of a
    /// tet.
    pub first_point: Vec<u32>,
    /// Each one's layup axis (0 where it has one ply).
    pub axis: Vec<u32>,
    /// Each one's sieve factor kappa.
    pub sieve: Vec<f64>,
    /// A hex8i block: each one's elastic condensation (216 values).
    pub condensation: Vec<f64>,
    /// A hex block: each one's point operators in `operators`, [`NO_OPERATOR`] for one that
    /// steps from its corners.
    pub operator: Vec<u32>,
    /// The point operators of the block's shapes.
    pub operators: Vec<HexOperators>,
}

/// The operator index of an element without one.
pub const NO_OPERATOR: u32 = u32::MAX;

impl DamageBlock {
    pub fn len(&self) -> usize {
        self.elements.len()
    }

    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// Points of all its elements.
    pub fn points(&self) -> usize {
        self.first_point.last().copied().unwrap_or(0) as usize
    }

    /// The plies of damageable element `i`.
    pub fn plies_of(&self, i: usize) -> &[DamagePly] {
        &self.plies[self.first_ply[i] as usize..self.first_ply[i + 1] as usize]
    }

    /// Damageable element `i`'s point operators, where it has them.
    pub fn operators_of(&self, i: usize) -> Option<&HexOperators> {
        match self.operator.get(i).copied().unwrap_or(NO_OPERATOR) {
            NO_OPERATOR => None,
            op => Some(&self.operators[op as usize]),
        }
    }

    /// The state values of damageable element `i`'s points.
    pub fn state_range(&self, i: usize) -> std::ops::Range<usize> {
        POINT_STATE * self.first_point[i] as usize..POINT_STATE * self.first_point[i + 1] as usize
    }
}

impl DamageData {
    /// The damage of the elements `kept` (global numbers, increasing) of a mesh whose
    /// blocks hold `counts` elements, numbered as those elements are in their own blocks
    /// (a rank's), and per block the damageable numbers in `self` of the ones kept.
    pub fn select(&self, counts: &[usize], kept: &[u32]) -> (DamageData, Vec<Vec<u32>>) {
        let mut blocks = Vec::with_capacity(self.blocks.len());
        let mut picked = Vec::with_capacity(self.blocks.len());
        let mut offset = 0;
        for (k, b) in self.blocks.iter().enumerate() {
            // the kept elements of this block, from the first at or past its offset
            let first = kept.partition_point(|&g| (g as usize) < offset);
            let mut out = DamageBlock {
                first_ply: vec![0],
                first_point: vec![0],
                ..Default::default()
            };
            let mut mine = Vec::new();
            let mut operator_of = std::collections::HashMap::new();
            for i in 0..b.len() {
                let g = (offset + b.elements[i] as usize) as u32;
                let Ok(at) = kept.binary_search(&g) else {
                    continue;
                };
                mine.push(i as u32);
                out.elements.push((at - first) as u32);
                out.plies.extend_from_slice(b.plies_of(i));
                out.first_ply.push(out.plies.len() as u32);
                let points = b.first_point[i + 1] - b.first_point[i];
                let last = *out.first_point.last().expect("first point");
                out.first_point.push(last + points);
                out.axis.push(b.axis[i]);
                out.sieve.push(b.sieve[i]);
                if !b.condensation.is_empty() {
                    out.condensation
                        .extend_from_slice(&b.condensation[216 * i..216 * (i + 1)]);
                }
                let op = b.operator.get(i).copied().unwrap_or(NO_OPERATOR);
                out.operator.push(match op {
                    NO_OPERATOR => NO_OPERATOR,
                    op => *operator_of.entry(op).or_insert_with(|| {
                        out.operators.push(b.operators[op as usize].clone());
                        (out.operators.len() - 1) as u32
                    }),
                });
            }
            offset += counts[k];
            blocks.push(out);
            picked.push(mine);
        }
        let data = DamageData {
            laws: self.laws.clone(),
            law_of: self.law_of.clone(),
            axes: self.axes.clone(),
            blocks,
        };
        (data, picked)
    }

    /// Whether any element damages.
    pub fn any(&self) -> bool {
        self.blocks.iter().any(|b| !b.is_empty())
    }

    /// The block of a kind.
    pub fn block(&self, kind: ElementKind) -> &DamageBlock {
        &self.blocks[kind.index()]
    }

    /// Whether material entry `m` damages.
    pub fn damages(&self, m: u32) -> bool {
        self.law_of.get(m as usize).is_some_and(|&l| l != NO_LAW)
    }

    /// The laws' view for [`crate::element::damage`].
    pub fn laws(&self) -> crate::element::damage::DamageLaws<'_> {
        crate::element::damage::DamageLaws {
            laws: &self.laws,
            law_of: &self.law_of,
            axes: &self.axes,
        }
    }
}

/// The damage state: each block's points' values, each damageable element's flag and first
/// damage (the step it damaged in, 0 for none yet, and there `4 point + mode`: its lowest
/// damaged point and the mode with the most damage there), and the steps the state took.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DamageState {
    pub points: Vec<Vec<f64>>,
    pub damaged: Vec<Vec<bool>>,
    pub first: Vec<Vec<[u32; 2]>>,
    pub steps: u32,
}

impl DamageState {
    /// No damage anywhere.
    pub fn new(data: &DamageData) -> Self {
        DamageState {
            points: (data.blocks.iter())
                .map(|b| vec![0.0; POINT_STATE * b.points()])
                .collect(),
            damaged: data.blocks.iter().map(|b| vec![false; b.len()]).collect(),
            first: data.blocks.iter().map(|b| vec![[0, 0]; b.len()]).collect(),
            steps: 0,
        }
    }

    /// The state as values (a checkpoint's part): every point's values block after block,
    /// then each damageable element's first damage (two values), then the steps.
    pub fn flat(&self) -> Vec<f64> {
        let first = self.first.iter().flatten().flat_map(|f| f.map(f64::from));
        (self.points.concat().into_iter())
            .chain(first)
            .chain([f64::from(self.steps)])
            .collect()
    }

    /// The state of [`Self::flat`]'s values; the flags follow from the points.
    pub fn restore(
        &mut self,
        data: &DamageData,
        values: &[f64],
    ) -> std::result::Result<(), String> {
        let points: usize = self.points.iter().map(Vec::len).sum();
        let elements: usize = self.first.iter().map(Vec::len).sum();
        let want = points + 2 * elements + 1;
        if values.len() != want {
            return Err(format!(
                "the checkpoint holds {} damage values and the model's damage state {want}",
                values.len()
            ));
        }
        let (mut at, mut first_at) = (0, points);
        for (k, b) in data.blocks.iter().enumerate() {
            let n = self.points[k].len();
            self.points[k].copy_from_slice(&values[at..at + n]);
            at += n;
            for i in 0..b.len() {
                let s = &self.points[k][b.state_range(i)];
                self.damaged[k][i] = crate::element::damage::any_damage(s);
                let f = &values[first_at + 2 * i..first_at + 2 * i + 2];
                // an element without damage has no first damage
                self.first[k][i] = match self.damaged[k][i] {
                    true => [f[0] as u32, f[1] as u32],
                    false => [0, 0],
                };
            }
            first_at += 2 * b.len();
        }
        self.steps = values[want - 1] as u32;
        Ok(())
    }
}

impl DamageState {
    /// Each damageable element's values in a piece's state (`self`, of `data`), as `(ids,
    /// values)`: the id `k 2^32 + i` of block k's damageable element i of the whole model
    /// (`picked` maps the piece's numbers to the model's), its first damage and its points'
    /// values.
    pub fn records(&self, data: &DamageData, picked: &[Vec<u32>]) -> (Vec<f64>, Vec<f64>) {
        let (mut ids, mut values) = (Vec::new(), Vec::new());
        for (k, b) in data.blocks.iter().enumerate() {
            for i in 0..b.len() {
                ids.push(((k as u64) << 32 | u64::from(picked[k][i])) as f64);
                values.extend(self.first[k][i].map(f64::from));
                values.extend_from_slice(&self.points[k][b.state_range(i)]);
            }
        }
        (ids, values)
    }

    /// Writes the records of [`Self::records`] (from any number of pieces, concatenated)
    /// into this state of the whole model (`data`).
    pub fn put_records(&mut self, data: &DamageData, ids: &[f64], values: &[f64]) {
        let mut at = 0;
        for &id in ids {
            let id = id as u64;
            let (k, i) = ((id >> 32) as usize, (id & 0xffff_ffff) as usize);
            let range = data.blocks[k].state_range(i);
            self.first[k][i] = [values[at] as u32, values[at + 1] as u32];
            let n = range.len();
            self.points[k][range.clone()].copy_from_slice(&values[at + 2..at + 2 + n]);
            self.damaged[k][i] = crate::element::damage::any_damage(&self.points[k][range]);
            at += 2 + n;
        }
    }

    /// The state of a piece (`sub`, whose elements `picked` are of this state's `data`).
    pub fn pick(&self, data: &DamageData, sub: &DamageData, picked: &[Vec<u32>]) -> DamageState {
        let mut out = DamageState::new(sub);
        out.steps = self.steps;
        for (k, b) in sub.blocks.iter().enumerate() {
            for i in 0..b.len() {
                let g = picked[k][i] as usize;
                out.points[k][b.state_range(i)]
                    .copy_from_slice(&self.points[k][data.blocks[k].state_range(g)]);
                out.first[k][i] = self.first[k][g];
                out.damaged[k][i] = self.damaged[k][g];
            }
        }
        out
    }
}

/// Where a point first damaged: `4 point + mode`, the element's lowest damaged point (in
/// `state`, its points' values) and the mode with the most damage there.
pub fn first_where(state: &[f64]) -> u32 {
    let (p, values) = (state.chunks_exact(POINT_STATE).enumerate())
        .find(|(_, s)| s.iter().any(|&d| d > 0.0))
        .unwrap_or((0, &[0.0; POINT_STATE][..]));
    let mode = (0..4).fold(0, |m, j| if values[j] > values[m] { j } else { m });
    (4 * p + mode) as u32
}

/// A damaged point: its element's global number, its ply's material entry and the mode
/// whose acting damage is the largest there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DamagedPoint {
    pub step: u32,
    pub element: usize,
    pub entry: u32,
    pub mode: usize,
}

impl DamageState {
    /// Each element's acting damage of each mode, the largest over its points (zero for the
    /// elements that do not damage), in global element order (`blocks`: each kind's
    /// element count).
    pub fn cells(&self, data: &DamageData, blocks: &[usize]) -> Vec<[f64; 4]> {
        let mut out = vec![[0.0f64; 4]; blocks.iter().sum()];
        for (k, b) in data.blocks.iter().enumerate() {
            let offset: usize = blocks[..k].iter().sum();
            for (i, &e) in b.elements.iter().enumerate() {
                let cell = &mut out[offset + e as usize];
                for p in self.points[k][b.state_range(i)].chunks_exact(POINT_STATE) {
                    for m in 0..4 {
                        cell[m] = cell[m].max(p[4 + m]);
                    }
                }
            }
        }
        out
    }

    /// The first damaged point: of the earliest step, the lowest element number's (`blocks`
    /// as for [`Self::cells`]).
    pub fn first_damaged(&self, data: &DamageData, blocks: &[usize]) -> Option<DamagedPoint> {
        let mut best: Option<DamagedPoint> = None;
        for (k, b) in data.blocks.iter().enumerate() {
            let offset: usize = blocks[..k].iter().sum();
            let per_ply = if ElementKind::ALL[k] == ElementKind::Tet4 {
                1
            } else {
                8
            };
            for (i, &[step, at]) in self.first[k].iter().enumerate() {
                if step == 0 || best.is_some_and(|q| q.step <= step) {
                    continue;
                }
                let (p, mode) = (at as usize / 4, at as usize % 4);
                best = Some(DamagedPoint {
                    step,
                    element: offset + b.elements[i] as usize,
                    entry: b.plies_of(i)[p / per_ply].entry,
                    mode,
                });
            }
        }
        best
    }
}
