//! Global assembly of stiffness and mass on the free degrees of freedom.

use crate::model::Model;
use crate::scene::MassKind;

/// A compressed sparse column matrix (full storage, sorted row indices).
#[derive(Debug, Clone, Default)]
pub struct Csc {
    pub n: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    pub values: Vec<f64>,
}

impl Csc {
    /// Builds from (row, col, value) triplets, summing duplicates.
    pub fn from_triplets(n: usize, mut t: Vec<(u32, u32, f64)>) -> Csc {
        t.sort_unstable_by_key(|&(r, c, _)| ((c as u64) << 32) | r as u64);
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = Vec::with_capacity(t.len() / 2);
        let mut values: Vec<f64> = Vec::with_capacity(t.len() / 2);
        let mut last = (u32::MAX, u32::MAX);
        for (r, c, v) in t {
            if (r, c) == last {
                *values.last_mut().expect("a previous entry") += v;
            } else {
                row_idx.push(r as usize);
                values.push(v);
                col_ptr[c as usize + 1] += 1;
                last = (r, c);
            }
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        Csc {
            n,
            col_ptr,
            row_idx,
            values,
        }
    }

    /// y = A x
    pub fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for (j, &xj) in x.iter().enumerate().take(self.n) {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                y[self.row_idx[p]] += self.values[p] * xj;
            }
        }
    }

    pub fn nnz(&self) -> usize {
        self.values.len()
    }
}

/// Everything the implicit integrator needs from assembly.
#[derive(Debug, Clone)]
pub struct Assembled {
    /// Free dof -> equation number, or `u32::MAX` for a fixed dof.
    pub equation: Vec<u32>,
    /// Equation number -> dof.
    pub dof_of: Vec<u32>,
    /// K + c_m M on the free dofs.
    pub effective: Csc,
    /// Consistent mass on the free dofs (None for lumped mass).
    pub consistent_mass: Option<Csc>,
    /// Lumped (row-sum) nodal mass, one per node; used for momentum and lumped dynamics.
    pub nodal_mass: Vec<f64>,
    /// The mass a node answers an impulse with at first: the lumped mass, or the consistent
    /// mass's diagonal (its inverse bounds the consistent inverse's diagonal from below).
    pub impulse_mass: Vec<f64>,
}

/// Elements per task of the parallel assembly, and tasks per round (a round's triplets are
/// appended in element order before the next starts, which bounds the extra memory).
const ASSEMBLY_BLOCK: usize = 1024;
const ASSEMBLY_ROUND: usize = 64;

/// One block's contributions, in element order: stiffness (+ c_m M) triplets, consistent
/// mass triplets, and (node, row sum, diagonal) of each element's mass.
type BlockParts = (
    Vec<(u32, u32, f64)>,
    Vec<(u32, u32, f64)>,
    Vec<(u32, f64, f64)>,
);

/// Assembles K + `c_m` M on the free dofs, and the masses.
///
/// Elements are computed on all threads in blocks; the blocks' triplets and masses are
/// appended and summed in element order, so the result is the one-thread result, bit for bit.
/// The rigid bodies' masses go on their nodes' diagonals last.
pub fn assemble(model: &Model, mass: MassKind, c_m: f64) -> Assembled {
    use rayon::prelude::*;
    let ndof = model.dofs();
    let mut equation = vec![u32::MAX; ndof];
    let mut dof_of = Vec::new();
    for (d, eq) in equation.iter_mut().enumerate() {
        if !model.fixed[d] {
            *eq = dof_of.len() as u32;
            dof_of.push(d as u32);
        }
    }
    let n = dof_of.len();
    let mesh = &model.mesh;
    let mut nodal_mass = vec![0.0; mesh.node_count()];
    let mut diagonal_mass = vec![0.0; mesh.node_count()];
    let triplets = (mesh.elements.blocks.iter()).map(|b| 9 * b.kind.corners() * b.nodes.len());
    let mut kt = Vec::with_capacity(triplets.sum());
    let mut mt = Vec::new();
    let elements = mesh.element_count();
    let blocks = elements.div_ceil(ASSEMBLY_BLOCK);
    for round in (0..blocks).step_by(ASSEMBLY_ROUND) {
        let parts: Vec<BlockParts> = (round..(round + ASSEMBLY_ROUND).min(blocks))
            .into_par_iter()
            .map(|b| {
                let range = b * ASSEMBLY_BLOCK..((b + 1) * ASSEMBLY_BLOCK).min(elements);
                block_parts(model, &equation, mass, c_m, range)
            })
            .collect();
        for (k, m, masses) in parts {
            kt.extend(k);
            mt.extend(m);
            for (node, row_sum, diagonal) in masses {
                nodal_mass[node as usize] += row_sum;
                diagonal_mass[node as usize] += diagonal;
            }
        }
    }
    for (node, m) in model.point_masses() {
        nodal_mass[node as usize] += m;
        diagonal_mass[node as usize] += m;
        let n = 3 * node as usize;
        for &r in &equation[n..n + 3] {
            if r != u32::MAX {
                kt.push((r, r, c_m * m));
                mt.push((r, r, m));
            }
        }
    }
    Assembled {
        equation,
        dof_of,
        effective: Csc::from_triplets(n, kt),
        consistent_mass: (mass == MassKind::Consistent).then(|| Csc::from_triplets(n, mt)),
        impulse_mass: match mass {
            MassKind::Lumped => nodal_mass.clone(),
            MassKind::Consistent => diagonal_mass,
        },
        nodal_mass,
    }
}

/// The contributions of the elements in `range`, in order.
fn block_parts(
    model: &Model,
    equation: &[u32],
    mass: MassKind,
    c_m: f64,
    range: std::ops::Range<usize>,
) -> BlockParts {
    let mesh = &model.mesh;
    let (mut kt, mut mt, mut masses) = (Vec::new(), Vec::new(), Vec::new());
    for e in range {
        let element = mesh.element(e);
        let (el, m) = (element.nodes, &model.materials[element.material as usize]);
        let x = mesh.corners(el);
        let ke = element.kind.stiffness(&x, model.section(element.material));
        let me = element.kind.consistent_mass(&x, m.density);
        let n = el.len();
        for i in 0..n {
            masses.push((el[i], me[i].iter().sum::<f64>(), me[i][i]));
        }
        for i in 0..n {
            for a in 0..3 {
                let r = equation[3 * el[i] as usize + a];
                if r == u32::MAX {
                    continue;
                }
                for j in 0..n {
                    for b in 0..3 {
                        let c = equation[3 * el[j] as usize + b];
                        if c == u32::MAX {
                            continue;
                        }
                        let mut v = ke[3 * i + a][3 * j + b];
                        if a == b {
                            let mij = match mass {
                                MassKind::Consistent => {
                                    mt.push((r, c, me[i][j]));
                                    me[i][j]
                                }
                                MassKind::Lumped => {
                                    if i == j {
                                        me[i].iter().sum()
                                    } else {
                                        0.0
                                    }
                                }
                            };
                            v += c_m * mij;
                        }
                        kt.push((r, c, v));
                    }
                }
            }
        }
    }
    (kt, mt, masses)
}
