//! The effective matrix's flexibility on the contact nodes: $H = K_{eff}^{-1}$ restricted to
//! the dofs of the nodes the contact iteration has touched, found column by column (one
//! triangular solve pair per dof, the first time a node is a candidate or carries one's
//! face) and kept for the run, since the effective matrix does not change. Where the factor
//! has a contact space, a column is its solve on the contact equations alone
//! ([`SpdSolver::contact_solve_in_place`]): every node the iteration touches is in it.
//!
//! The matrix grows by nodes: a new node's three columns give its rows and, by the symmetry
//! of $K_{eff}^{-1}$, its entries in the columns of the nodes before it. So an entry comes
//! from the column of the later of its two nodes, and the nodes' order decides the last bits:
//! a checkpoint keeps that order ([`Flexibility::nodes`]) and a resumed run rebuilds the
//! same matrix from it ([`Flexibility::resume`]) the first time it needs one.

use std::collections::HashMap;

use crate::linalg::{Assembled, SpdSolver};

/// The most nodes a flexibility holds: 9 n^2 values, 75 MB at this size.
pub(super) const MAX_NODES: usize = 1024;

/// $K_{eff}^{-1}$ on the dofs of a growing set of nodes.
#[derive(Debug, Default)]
pub(super) struct Flexibility {
    slot: HashMap<u32, usize>,
    nodes: Vec<u32>,
    /// Column 3 p + a (node p's dof a) holds its entries at rows 3 q + b of every node q.
    columns: Vec<Vec<f64>>,
    /// A checkpoint's nodes, added first the next time nodes are needed.
    pending: Vec<u32>,
    /// Whether every node held has its free equations in the factor's contact space (then a
    /// column is a solve on the contact space alone).
    in_space: bool,
}

impl Flexibility {
    /// The nodes in the order they joined (a checkpoint's not yet rebuilt included).
    pub(super) fn nodes(&self) -> Vec<u32> {
        match self.nodes.is_empty() {
            true => self.pending.clone(),
            false => self.nodes.clone(),
        }
    }

    /// A flexibility to be rebuilt on a checkpoint's `nodes`, in their order, when first used.
    pub(super) fn resume(nodes: Vec<u32>) -> Flexibility {
        Flexibility {
            pending: nodes,
            ..Flexibility::default()
        }
    }

    /// Node `n`'s place, where it has joined.
    pub(super) fn slot(&self, n: u32) -> Option<usize> {
        self.slot.get(&n).copied()
    }

    /// $H$'s entry between dof a of the node in place p and dof b of the node in place q.
    pub(super) fn entry(&self, (p, a): (usize, usize), (q, b): (usize, usize)) -> f64 {
        self.columns[3 * p + a][3 * q + b]
    }

    /// Adds the `nodes` not held yet, in their order; false (and nothing added) where that
    /// would exceed [`MAX_NODES`].
    pub(super) fn ensure(&mut self, nodes: &[u32], asm: &Assembled, solver: &SpdSolver) -> bool {
        for n in std::mem::take(&mut self.pending) {
            self.add(n, asm, solver);
        }
        let mut new: Vec<u32> = Vec::new();
        for &n in nodes {
            if !self.slot.contains_key(&n) && !new.contains(&n) {
                new.push(n);
            }
        }
        if self.nodes.len() + new.len() > MAX_NODES {
            return false;
        }
        for n in new {
            self.add(n, asm, solver);
        }
        true
    }

    /// Node `n`'s three columns: a unit force on each of its free dofs solved for, read at
    /// every node held (a fixed dof's column and row are zero).
    fn add(&mut self, n: u32, asm: &Assembled, solver: &SpdSolver) {
        let p = self.nodes.len();
        self.slot.insert(n, p);
        self.nodes.push(n);
        let equation = |node: u32, a: usize| asm.equation[3 * node as usize + a];
        let space = solver.contact_space().map(|s| {
            let mut place = vec![u32::MAX; asm.dof_of.len()];
            for (k, &e) in s.equations().iter().enumerate() {
                place[e] = k as u32;
            }
            (s.equations(), place)
        });
        // the first node decides; a node outside the contact space turns it off for good
        let node_in = |m: u32, place: &[u32]| {
            (0..3).all(|a| equation(m, a) == u32::MAX || place[equation(m, a) as usize] != u32::MAX)
        };
        self.in_space =
            (p == 0 || self.in_space) && space.as_ref().is_some_and(|(_, place)| node_in(n, place));
        let mut x = vec![0.0; asm.dof_of.len()];
        for a in 0..3 {
            let e = equation(n, a);
            let mut column = vec![0.0; 3 * (p + 1)];
            if e != u32::MAX {
                match (&space, self.in_space) {
                    (Some((equations, place)), true) => {
                        let mut y = vec![0.0; equations.len()];
                        y[place[e as usize] as usize] = 1.0;
                        solver.contact_solve_in_place(&mut y);
                        for (&v, &f) in y.iter().zip(equations.iter()) {
                            x[f] = v;
                        }
                    }
                    _ => {
                        x.fill(0.0);
                        x[e as usize] = 1.0;
                        solver.solve_in_place(&mut x);
                    }
                }
                for (q, &m) in self.nodes.iter().enumerate() {
                    for b in 0..3 {
                        let f = equation(m, b);
                        if f != u32::MAX {
                            column[3 * q + b] = x[f as usize];
                        }
                    }
                }
            }
            self.columns.push(column);
        }
        // the earlier nodes' columns take their entries at n from n's columns (symmetry)
        debug_assert!(self.columns.len() == 3 * (p + 1));
        for q in 0..p {
            for b in 0..3 {
                for a in 0..3 {
                    let value = self.columns[3 * p + a][3 * q + b];
                    self.columns[3 * q + b].push(value);
                }
            }
        }
    }
}
