//! The ply failure indices of every step, over the whole model: the largest of each index
//! ([`INDICES`]) for the history, and where and when an index first reaches 1.
//!
//! Each evaluation point is a cell's centre (one law) or the mid-thickness of each ply of a
//! layered hex8i cell (the condensed modes included), exactly where the VTU frames'
//! `failure_index` is evaluated. Its stress in the ply's material axes is linear in the
//! cell's corner displacements: the operator is built once, by the frames' own stress
//! functions applied to unit displacements, and shared by the cells of the same shape and
//! material (a box mesh's cells have a few).

use std::collections::HashMap;

use rayon::prelude::*;

use crate::element::{ElementKind, Section};
use crate::kernels::failure_survey::SURVEY_COLUMNS;
use crate::kernels::{SurveyPoint, SurveySetup, FAILURE_FIELDS};
use crate::material::failure::{failure_indices, INDICES};
use crate::material::Strength;
use crate::model::Model;

/// One evaluation point: its cell, its ply within a layered cell, its strength and its
/// operator.
#[derive(Debug, Clone, Copy)]
struct Point {
    cell: u32,
    ply: Option<u32>,
    strength: u32,
    operator: u32,
}

/// Where an index first reached 1.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FirstFailure {
    /// The index ([`INDICES`]) that was largest there.
    pub index: String,
    pub value: f64,
    pub step: usize,
    pub time: f64,
    pub cell: usize,
    pub body: String,
    /// The ply of the cell's body (counted from its lowest), where the body has plies.
    pub ply: Option<usize>,
    /// The cell's centroid in the reference configuration.
    pub point: [f64; 3],
}

/// The largest of each index over the model at one state, and the point of the largest.
#[derive(Debug, Clone, Copy)]
pub struct FailureMaxima {
    pub max: [f64; 5],
    worst: Option<Worst>,
}

/// The point of the largest index: its value and index ([`INDICES`]), its cell (the whole
/// model's number), the point's place among its cell's plies, the body's ply, the body and
/// the cell's reference centroid.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Worst {
    value: f64,
    index: usize,
    cell: usize,
    place: Option<usize>,
    ply: Option<usize>,
    body: Option<usize>,
    point: [f64; 3],
}

/// Values per rank in [`FailureMaxima::values`]: the five maxima, then the worst point.
pub const RANK_VALUES: usize = 5 + 9;

impl Worst {
    /// Whether it comes before `other` in the single process's order: the larger value,
    /// then the lower cell, then the lower ply place (the order of the points).
    fn before(&self, other: &Worst) -> bool {
        let key = |w: &Worst| (w.cell, w.place.map_or(0, |p| p + 1));
        self.value > other.value || (self.value == other.value && key(self) < key(other))
    }
}

impl FailureMaxima {
    /// Where the maxima's worst point is, if its index reached 1.
    pub fn first_failure(&self, model: &Model, (step, time): (usize, f64)) -> Option<FirstFailure> {
        let w = self.worst?;
        (w.value >= 1.0).then(|| FirstFailure {
            index: INDICES[w.index].to_string(),
            value: w.value,
            step,
            time,
            cell: w.cell,
            body: w
                .body
                .map_or_else(String::new, |b| model.body_names[b].clone()),
            ply: w.ply,
            point: w.point,
        })
    }

    /// The maxima as values for the ranks' gather ([`RANK_VALUES`]; `-1` for none).
    pub fn values(&self) -> [f64; RANK_VALUES] {
        let mut out = [-1.0; RANK_VALUES];
        out[..5].copy_from_slice(&self.max);
        if let Some(w) = self.worst {
            let opt = |x: Option<usize>| x.map_or(-1.0, |x| x as f64);
            let (c, p) = (w.cell as f64, opt(w.place));
            let [x, y, z] = w.point;
            let (ply, body) = (opt(w.ply), opt(w.body));
            out[5..].copy_from_slice(&[w.value, w.index as f64, c, p, ply, body, x, y, z]);
        }
        out
    }

    /// The whole model's maxima from every rank's [`Self::values`], as one process finds
    /// them (the maxima are exact, and the worst point is the first of the largest).
    pub fn of_ranks(all: &[Vec<f64>]) -> FailureMaxima {
        let mut max = [0.0f64; 5];
        let mut worst: Option<Worst> = None;
        for r in all {
            for (m, x) in max.iter_mut().zip(&r[..5]) {
                *m = m.max(*x);
            }
            let opt = |x: f64| (x >= 0.0).then_some(x as usize);
            let Some(index) = opt(r[6]) else { continue };
            let w = Worst {
                value: r[5],
                index,
                cell: r[7] as usize,
                place: opt(r[8]),
                ply: opt(r[9]),
                body: opt(r[10]),
                point: [r[11], r[12], r[13]],
            };
            if worst.is_none_or(|b| w.before(&b)) {
                worst = Some(w);
            }
        }
        FailureMaxima { max, worst }
    }
}

pub struct FailureSurvey {
    /// The whole model's number of each cell of the surveyed model (a rank's piece numbers
    /// its own cells).
    numbers: Option<Vec<u32>>,
    points: Vec<Point>,
    /// The first point of each cell (a cell's points are consecutive).
    cells: Vec<u32>,
    /// Per operator: (3 corners) x 6 values, column by column: the stress (11, 22, 33, 12,
    /// 23, 13) in the material axes of each corner displacement. A point's six stresses are
    /// then six independent sums over the columns (each in the columns' order).
    operators: Vec<Vec<f64>>,
    strengths: Vec<Strength>,
}

impl FailureSurvey {
    /// The survey of the model's cells of materials with strengths; None without any.
    pub fn new(model: &Model) -> Option<FailureSurvey> {
        let strength_of: Vec<Option<usize>> = model.strengths.iter().map(|_| None).collect();
        let mut strengths = Vec::new();
        let mut index_of = strength_of;
        for (i, s) in model.strengths.iter().enumerate() {
            if let Some(s) = s {
                index_of[i] = Some(strengths.len());
                strengths.push(*s);
            }
        }
        if strengths.is_empty() {
            return None;
        }
        let mesh = &model.mesh;
        let mut operators = Vec::new();
        let mut seen: HashMap<(u32, ElementKind, Vec<u64>), u32> = HashMap::new();
        let (mut points, mut cells) = (Vec::new(), Vec::new());
        for c in 0..mesh.element_count() {
            let e = mesh.element(c);
            let Some(strength) = index_of[model.material_source[e.material as usize]] else {
                continue;
            };
            let x = mesh.corners(e.nodes);
            let shape: Vec<u64> = (x.iter())
                .flat_map(|p| (0..3).map(|a| (p[a] - x[0][a]).to_bits()))
                .collect();
            let plies = match &model.layups[e.material as usize] {
                Some(l) => l.plies.len(),
                None => 1,
            };
            let key = (e.material, e.kind, shape);
            let first = match seen.get(&key) {
                Some(&k) => k,
                None => {
                    // from the corners relative to the first, so that every cell of the key
                    // (and every rank's first of them) gets the same bits
                    let k = operators.len() as u32;
                    let r: Vec<[f64; 3]> = (x.iter())
                        .map(|p| std::array::from_fn(|a| p[a] - x[0][a]))
                        .collect();
                    operators.extend(cell_operators(model, e.kind, &r, e.material));
                    seen.insert(key, k);
                    k
                }
            };
            let layered = model.layups[e.material as usize].is_some();
            cells.push(points.len() as u32);
            for p in 0..plies {
                points.push(Point {
                    cell: c as u32,
                    ply: layered.then_some(p as u32),
                    strength: strength as u32,
                    operator: first + p as u32,
                });
            }
        }
        Some(FailureSurvey {
            numbers: None,
            points,
            cells,
            operators,
            strengths,
        })
    }

    /// The survey of a rank's piece of the model, whose cells are the whole model's cells
    /// `numbers`.
    pub fn of_piece(piece: &Model, numbers: &[u32]) -> Option<FailureSurvey> {
        let mut s = FailureSurvey::new(piece)?;
        s.numbers = Some(numbers.to_vec());
        Some(s)
    }

    /// The largest of each index at the displacement `u`, on all threads (the maxima do not
    /// depend on the order; the worst point is the first of the largest). A cell's corner
    /// displacements are gathered once for all its points.
    pub fn maxima(&self, model: &Model, u: &[f64]) -> FailureMaxima {
        let mesh = &model.mesh;
        type Best = ([f64; 5], Option<(usize, f64, usize)>);
        let merge = |(a, wa): Best, (b, wb): Best| -> Best {
            let max = std::array::from_fn(|k| a[k].max(b[k]));
            let worst = match (wa, wb) {
                (Some(x), Some(y)) if y.1 > x.1 || (y.1 == x.1 && y.0 < x.0) => Some(y),
                (None, y) => y,
                (x, _) => x,
            };
            (max, worst)
        };
        let per_cell = |first: usize| -> Best {
            let cell = self.points[first].cell;
            let nodes = mesh.element(cell as usize).nodes;
            let mut ue = [0.0; 24];
            for (k, &n) in nodes.iter().enumerate() {
                ue[3 * k..3 * k + 3].copy_from_slice(&u[3 * n as usize..3 * n as usize + 3]);
            }
            let ue = &ue[..3 * nodes.len()];
            let mut best: Best = ([0.0; 5], None);
            for (i, p) in self.points[first..].iter().enumerate() {
                if p.cell != cell {
                    break;
                }
                let op = &self.operators[p.operator as usize];
                let mut s = [0.0f64; 6];
                for (column, u) in op.chunks_exact(6).zip(ue) {
                    for (s, a) in s.iter_mut().zip(column) {
                        *s += a * u;
                    }
                }
                let f = failure_indices(s, &self.strengths[p.strength as usize]);
                let (k, v) = (0..5).fold((0, f[0]), |b, k| if f[k] > b.1 { (k, f[k]) } else { b });
                best = merge(best, (f, Some((first + i, v, k))));
            }
            best
        };
        let (max, worst) = (self.cells.par_iter())
            .with_min_len(256)
            .map(|&first| per_cell(first as usize))
            .reduce(|| ([0.0; 5], None), merge);
        let worst = worst.map(|(i, value, k)| self.locate(model, i, value, k));
        FailureMaxima { max, worst }
    }

    /// The survey as the device's survey takes it: each point with its cell's corners, the
    /// operators padded to [`SURVEY_COLUMNS`] columns, the strengths.
    pub fn device(&self, model: &Model) -> SurveySetup {
        let points = (self.points.iter())
            .map(|p| {
                let corners = model.mesh.element(p.cell as usize).nodes;
                let mut nodes = [0; 8];
                nodes[..corners.len()].copy_from_slice(corners);
                SurveyPoint {
                    nodes,
                    corners: corners.len() as u32,
                    strength: p.strength,
                    stress_operator: p.operator,
                }
            })
            .collect();
        let mut operators = Vec::with_capacity(6 * SURVEY_COLUMNS * self.operators.len());
        for op in &self.operators {
            let n = op.len() / 6;
            for r in 0..6 {
                operators.extend((0..n).map(|j| op[6 * j + r]));
                operators.extend(std::iter::repeat_n(0.0, SURVEY_COLUMNS - n));
            }
        }
        SurveySetup {
            points,
            operators,
            strengths: self.strengths.clone(),
        }
    }

    /// The model's cell (element number) of each surveyed point, in the points' order (the
    /// device's point numbers).
    pub fn point_cells(&self) -> Vec<u32> {
        self.points.iter().map(|p| p.cell).collect()
    }

    /// The maxima of a device record ([`crate::kernels::failure_reduce`]), its worst point
    /// located.
    pub fn of_record(&self, model: &Model, r: &[f64; FAILURE_FIELDS]) -> FailureMaxima {
        let max = std::array::from_fn(|k| r[k]);
        let worst = (r[6] >= 0.0).then(|| {
            let (i, k) = (r[6].round() as usize, r[7].round() as usize);
            self.locate(model, i, r[5], k)
        });
        FailureMaxima { max, worst }
    }

    /// Point `i` with its largest index `k` of value `value`, located.
    fn locate(&self, model: &Model, i: usize, value: f64, k: usize) -> Worst {
        let p = self.points[i];
        let e = model.mesh.element(p.cell as usize);
        let x = model.mesh.corners(e.nodes);
        let centroid =
            std::array::from_fn(|a| x.iter().map(|c| c[a]).sum::<f64>() / x.len() as f64);
        let body =
            (model.mesh.bodies.iter()).position(|b| b.nodes.contains(&(e.nodes[0] as usize)));
        let ply = match p.ply {
            Some(k) => model.layups[e.material as usize]
                .as_ref()
                .map(|l| l.plies[k as usize].material),
            None => Some(e.material),
        }
        .and_then(|m| model.ply_of(m));
        let cell = self.numbers.as_ref().map_or(p.cell, |n| n[p.cell as usize]);
        Worst {
            value,
            index: k,
            cell: cell as usize,
            place: p.ply.map(|k| k as usize),
            ply,
            body,
            point: centroid,
        }
    }
}

/// The stress operators of one cell: one for a single law, one per ply of a layered cell.
fn cell_operators(
    model: &Model,
    kind: ElementKind,
    x: &[[f64; 3]],
    material: u32,
) -> Vec<Vec<f64>> {
    let n = 3 * x.len();
    // the material-axes stress of the displacement gradient h in the law and axes of entry m
    let stress = |h: &[[f64; 3]; 3], m: u32, law: &crate::material::Elastic| -> [f64; 6] {
        let s = model.material_axes[m as usize].to_material(&law.stress(h));
        [s[0][0], s[1][1], s[2][2], s[0][1], s[1][2], s[0][2]]
    };
    let columns = |gradient: &dyn Fn(usize) -> [[f64; 3]; 3], m: u32, law| -> Vec<f64> {
        (0..n).flat_map(|j| stress(&gradient(j), m, law)).collect()
    };
    match (&model.layups[material as usize], kind) {
        (Some(layup), ElementKind::Hex8i) => {
            let x8: [[f64; 3]; 8] = x.try_into().expect("a hex8i has 8 corners");
            let mids: Vec<[f64; 3]> = (layup.plies.iter())
                .map(|ply| {
                    let mut p = [0.0; 3];
                    p[layup.axis] = 0.5 * (ply.lo + ply.hi);
                    p
                })
                .collect();
            let ops =
                crate::element::hex8i::gradient_operators(&x8, Section::Layered(layup), &mids);
            (layup.plies.iter().zip(&ops))
                .map(|(ply, op)| {
                    let gradient = |j: usize| -> [[f64; 3]; 3] {
                        std::array::from_fn(|a| std::array::from_fn(|b| op[3 * a + b][j]))
                    };
                    columns(&gradient, ply.material, &ply.elastic)
                })
                .collect()
        }
        (layup, _) => {
            // one law: the ply at the centre of a layered cell of another kind
            let law = match layup {
                Some(l) => l.ply_at(0.0).elastic,
                None => model.materials[material as usize],
            };
            let g = kind.centre_gradients(x);
            let gradient = |j: usize| -> [[f64; 3]; 3] {
                std::array::from_fn(|a| {
                    std::array::from_fn(|b| if a == j % 3 { g[j / 3][b] } else { 0.0 })
                })
            };
            vec![columns(&gradient, material, &law)]
        }
    }
}
