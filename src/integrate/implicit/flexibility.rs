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
//!
//! Where the factor has no contact space, a column solved on the whole model can also be
//! kept at the equations of every contact node ([`Flexibility::respond_at`]): then a change
//! of the contact forces on the nodes held moves the contact nodes, all the kinematics read,
//! by a product with those rows, without a solve ([`Flexibility::respond`]).

use std::collections::HashMap;

use crate::linalg::{Assembled, SpdSolver};

/// The most nodes a flexibility holds: 9 n^2 values, 450 MB at this size (counted in the
/// memory check, [`super::factors::FactorPlan`]).
pub(super) const MAX_NODES: usize = 2500;
/// Nodes whose columns one block solve takes (48 right-hand sides).
const BLOCK_NODES: usize = 16;
/// The most values the columns' rows at the contact nodes may take (128 MB); past it they
/// are dropped, and the iterations go back to solves (counted in the memory check).
pub(super) const RESPONSE_MAX_VALUES: usize = 16 << 20;

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
    /// Each equation's place in the factor's contact space (`u32::MAX` outside it), made at
    /// the first node where the factor has one (the factor does not change).
    place: Vec<u32>,
    /// The equations every column is also read at ([`Flexibility::respond_at`]; empty where
    /// the columns are not kept there), and column 3 p + a's values at them, in their order.
    respond: Vec<u32>,
    response: Vec<Vec<f64>>,
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

    /// Keeps every column's values at `equations` too (the contact nodes' free equations),
    /// from a flexibility's first node on: where it holds nodes already, or their columns
    /// come from the contact space, or the values would pass [`RESPONSE_MAX_VALUES`], they
    /// are not kept.
    pub(super) fn respond_at(&mut self, equations: &[u32]) {
        if self.nodes.is_empty() && self.respond.is_empty() {
            self.respond = equations.to_vec();
        }
    }

    /// The equations the columns are kept at (empty where they are not).
    pub(super) fn response_equations(&self) -> &[u32] {
        &self.respond
    }

    /// Adds $H x$ at the [`Self::response_equations`] to `out`, x given as (place p, dof a,
    /// value) of nodes held; false (`out` untouched) where a node is not held or the columns
    /// are not kept there.
    pub(super) fn respond(&self, x: &[(u32, usize, f64)], out: &mut [f64]) -> bool {
        if self.respond.is_empty() || x.iter().any(|&(n, ..)| !self.slot.contains_key(&n)) {
            return false;
        }
        for &(n, a, value) in x {
            let column = &self.response[3 * self.slot[&n] + a];
            for (o, &h) in out.iter_mut().zip(column) {
                *o += h * value;
            }
        }
        true
    }

    /// Adds the `nodes` not held yet, in their order; false (and nothing added) where that
    /// would exceed [`MAX_NODES`]. Where nodes join, the first of the nodes `ahead` gives
    /// (those likely to be needed next; asked for only then) fill the last block solve's
    /// free columns: a block costs about as much however many of its 16 nodes are new.
    pub(super) fn ensure(
        &mut self,
        nodes: &[u32],
        ahead: impl FnOnce() -> Vec<u32>,
        asm: &Assembled,
        solver: &SpdSolver,
    ) -> bool {
        let pending = std::mem::take(&mut self.pending);
        self.add_all(&pending, asm, solver);
        let mut new: Vec<u32> = Vec::new();
        for &n in nodes {
            if !self.slot.contains_key(&n) && !new.contains(&n) {
                new.push(n);
            }
        }
        if self.nodes.len() + new.len() > MAX_NODES {
            return false;
        }
        if new.is_empty() {
            return true;
        }
        let whole = new.len().div_ceil(BLOCK_NODES) * BLOCK_NODES;
        let room = whole.min(MAX_NODES - self.nodes.len());
        for n in ahead() {
            if new.len() >= room {
                break;
            }
            if !self.slot.contains_key(&n) && !new.contains(&n) {
                new.push(n);
            }
        }
        self.add_all(&new, asm, solver);
        true
    }

    /// Adds `nodes` in their order, their columns solved in blocks of [`BLOCK_NODES`]
    /// nodes' right-hand sides (on the contact space, or on the whole model), zero columns
    /// filling a block: a column's bits depend on the block's width alone, so a checkpoint's
    /// nodes rebuild the same bits however they were grouped when they joined.
    fn add_all(&mut self, nodes: &[u32], asm: &Assembled, solver: &SpdSolver) {
        self.make_places(asm, solver);
        for group in nodes.chunks(BLOCK_NODES) {
            // the first node decides; a node outside the contact space turns it off for good
            let mut on_space = Vec::with_capacity(group.len());
            let mut in_space = self.in_space;
            for (j, &n) in group.iter().enumerate() {
                let first = self.nodes.is_empty() && j == 0;
                in_space =
                    (first || in_space) && solver.contact_space().is_some() && self.node_in(n, asm);
                on_space.push(in_space);
            }
            let space: Vec<u32> = (group.iter().zip(&on_space))
                .filter_map(|(&n, &s)| s.then_some(n))
                .collect();
            let full: Vec<u32> = (group.iter().zip(&on_space))
                .filter_map(|(&n, &s)| (!s).then_some(n))
                .collect();
            let space_columns = self.solve_block(&space, asm, solver, true);
            let full_columns = self.solve_block(&full, asm, solver, false);
            let (mut i_space, mut i_full) = (0, 0);
            for (&n, &s) in group.iter().zip(&on_space) {
                let (columns, i) = match s {
                    true => (&space_columns, &mut i_space),
                    false => (&full_columns, &mut i_full),
                };
                let rows = columns.len() / (3 * BLOCK_NODES);
                self.add(n, asm, &columns[3 * *i * rows..3 * (*i + 1) * rows], s);
                self.in_space = s;
                *i += 1;
            }
        }
    }

    /// The three columns of each of `nodes` (at most [`BLOCK_NODES`]) in one block solve:
    /// on the contact space (`space`, rows in its order) or on the whole model (rows in
    /// equation order); a fixed dof's column is zero.
    fn solve_block(
        &self,
        nodes: &[u32],
        asm: &Assembled,
        solver: &SpdSolver,
        space: bool,
    ) -> Vec<f64> {
        if nodes.is_empty() {
            return Vec::new();
        }
        let rows = match (space, solver.contact_space()) {
            (true, Some(s)) => s.equations().len(),
            _ => asm.dof_of.len(),
        };
        let mut b = vec![0.0; 3 * BLOCK_NODES * rows];
        for (j, &n) in nodes.iter().enumerate() {
            for a in 0..3 {
                let e = asm.equation[3 * n as usize + a];
                if e != u32::MAX {
                    let row = match space {
                        true => self.place[e as usize] as usize,
                        false => e as usize,
                    };
                    b[(3 * j + a) * rows + row] = 1.0;
                }
            }
        }
        if !(space && solver.contact_solve_block_in_place(&mut b)) {
            solver.solve_block_in_place(&mut b);
        }
        b
    }

    /// Each equation's place in the factor's contact space, the first time a factor with
    /// one is seen.
    fn make_places(&mut self, asm: &Assembled, solver: &SpdSolver) {
        if let (Some(space), true) = (solver.contact_space(), self.place.is_empty()) {
            self.place = vec![u32::MAX; asm.dof_of.len()];
            for (k, &e) in space.equations().iter().enumerate() {
                self.place[e] = k as u32;
            }
        }
    }

    /// Whether node `m`'s free equations are all in the factor's contact space.
    fn node_in(&self, m: u32, asm: &Assembled) -> bool {
        (0..3).all(|a| {
            let e = asm.equation[3 * m as usize + a];
            e == u32::MAX || self.place.get(e as usize).is_some_and(|&p| p != u32::MAX)
        })
    }

    /// The three columns' values at the response equations, or none from now on (columns
    /// on the contact space, or too many values).
    fn keep_response(&mut self, solved: &[f64], space: bool) {
        let rows = solved.len() / 3;
        let fits = (self.response.len() + 3) * self.respond.len() <= RESPONSE_MAX_VALUES;
        if space || !fits {
            self.respond = Vec::new();
            self.response = Vec::new();
        }
        if self.respond.is_empty() {
            return;
        }
        for a in 0..3 {
            let x = &solved[a * rows..(a + 1) * rows];
            let column = self.respond.iter().map(|&e| x[e as usize]).collect();
            self.response.push(column);
        }
    }

    /// Node `n`'s three columns, solved already (`solved`: three columns, on the contact
    /// space where `space`, else on the whole model), read at every node held (a fixed
    /// dof's column and row are zero).
    fn add(&mut self, n: u32, asm: &Assembled, solved: &[f64], space: bool) {
        let p = self.nodes.len();
        self.slot.insert(n, p);
        self.nodes.push(n);
        let rows = solved.len() / 3;
        self.keep_response(solved, space);
        let equation = |node: u32, a: usize| asm.equation[3 * node as usize + a];
        for a in 0..3 {
            let x = &solved[a * rows..(a + 1) * rows];
            let mut column = vec![0.0; 3 * (p + 1)];
            if equation(n, a) != u32::MAX {
                for (q, &m) in self.nodes.iter().enumerate() {
                    for b in 0..3 {
                        let f = equation(m, b);
                        if f != u32::MAX {
                            let row = match space {
                                true => self.place[f as usize] as usize,
                                false => f as usize,
                            };
                            column[3 * q + b] = x[row];
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

#[cfg(test)]
mod tests {
    use nalgebra::{DMatrix, Matrix3};

    use super::*;
    use crate::linalg::{Csc, Ordering};

    /// A stiffness on a grid of n^3 nodes: each edge couples its two nodes' dofs through a
    /// random SPD 3 x 3 block, plus a mass shift on the diagonal. Node 0 is held, and node
    /// 1 in x. Returns the assembled system and the dense K on all dofs (held rows unit).
    fn grid(n: usize) -> (Assembled, DMatrix<f64>) {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut random = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let nodes = n * n * n;
        let id = |i: usize, j: usize, k: usize| (i * n + j) * n + k;
        let mut k_full = DMatrix::<f64>::identity(3 * nodes, 3 * nodes) * 0.3;
        for (i, j, k) in
            (0..n).flat_map(|i| (0..n).flat_map(move |j| (0..n).map(move |k| (i, j, k))))
        {
            for (di, dj, dk) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                if i + di >= n || j + dj >= n || k + dk >= n {
                    continue;
                }
                let a = Matrix3::from_fn(|_, _| random());
                let b = a * a.transpose() + Matrix3::identity();
                let (p, q) = (id(i, j, k), id(i + di, j + dj, k + dk));
                for (r, c, s) in [(p, p, 1.0), (q, q, 1.0), (p, q, -1.0), (q, p, -1.0)] {
                    for x in 0..3 {
                        for y in 0..3 {
                            k_full[(3 * r + x, 3 * c + y)] += s * b[(x, y)];
                        }
                    }
                }
            }
        }
        // node 0 held, and node 1 in x
        let held = |d: usize| d <= 3;
        let mut equation = vec![u32::MAX; 3 * nodes];
        let mut dof_of = Vec::new();
        for (d, e) in equation.iter_mut().enumerate() {
            if !held(d) {
                *e = dof_of.len() as u32;
                dof_of.push(d as u32);
            }
        }
        let mut t = Vec::new();
        for (r, &dr) in dof_of.iter().enumerate() {
            for (c, &dc) in dof_of.iter().enumerate() {
                let v = k_full[(dr as usize, dc as usize)];
                if v != 0.0 {
                    t.push((r as u32, c as u32, v));
                }
            }
        }
        let effective = Csc::from_triplets(dof_of.len(), t);
        let asm = Assembled {
            equation,
            dof_of,
            effective,
            consistent_mass: None,
            nodal_mass: vec![1.0; nodes],
            impulse_mass: vec![1.0; nodes],
        };
        (asm, k_full)
    }

    /// K^-1 on the free dofs, zero on the held ones.
    fn inverse(asm: &Assembled, k: &DMatrix<f64>) -> DMatrix<f64> {
        let free = &asm.dof_of;
        let kf = DMatrix::from_fn(free.len(), free.len(), |r, c| {
            k[(free[r] as usize, free[c] as usize)]
        });
        let inv = kf.try_inverse().expect("SPD");
        let mut out = DMatrix::zeros(k.nrows(), k.ncols());
        for (r, &dr) in free.iter().enumerate() {
            for (c, &dc) in free.iter().enumerate() {
                out[(dr as usize, dc as usize)] = inv[(r, c)];
            }
        }
        out
    }

    /// The largest difference between `f`'s entries and `exact`'s (of node dofs m, l),
    /// relative to the largest of `exact`.
    fn largest_error(f: &Flexibility, exact: impl Fn(u32, usize, u32, usize) -> f64) -> f64 {
        let (mut worst, mut scale) = (0.0f64, 0.0f64);
        for (p, &m) in f.nodes.iter().enumerate() {
            for (q, &l) in f.nodes.iter().enumerate() {
                for a in 0..3 {
                    for b in 0..3 {
                        let x = exact(m, a, l, b);
                        worst = worst.max((f.entry((p, a), (q, b)) - x).abs());
                        scale = scale.max(x.abs());
                    }
                }
            }
        }
        worst / scale
    }

    /// Node `n`'s place in `f`.
    fn at(f: &Flexibility, n: u32) -> usize {
        f.slot(n).expect("held")
    }

    /// The flexibility is K^-1 on its nodes' dofs (held dofs zero), grown in any order; a
    /// checkpoint's order rebuilds the same bits; it refuses to grow past its size.
    #[test]
    fn the_flexibility_is_the_inverse_on_its_nodes_and_resumes_to_the_same_bits() {
        let (asm, k) = grid(6);
        let exact = inverse(&asm, &k);
        let first: Vec<u32> = vec![40, 1, 7, 41];
        let later: Vec<u32> = vec![100, 7, 0, 150];
        let full = SpdSolver::new(&asm.effective, Ordering::NestedDissection).unwrap();
        let mut f = Flexibility::default();
        assert!(f.ensure(&first, Vec::new, &asm, &full));
        assert!(f.ensure(&later, Vec::new, &asm, &full));
        assert_eq!(f.nodes(), vec![40, 1, 7, 41, 100, 0, 150]);
        let e = largest_error(&f, |m, a, l, b| {
            exact[(3 * m as usize + a, 3 * l as usize + b)]
        });
        assert!(e < 1e-12, "full solves: {e:.2e}");
        // a resumed flexibility rebuilds the same entries, bit for bit
        let mut r = Flexibility::resume(f.nodes());
        assert!(r.ensure(&[150], Vec::new, &asm, &full));
        assert_eq!(r.nodes(), f.nodes());
        for c in 0..f.columns.len() {
            let (a, b) = (&f.columns[c], &r.columns[c]);
            assert!(a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()));
        }
        // more nodes than it may hold: refused, nothing added
        let many: Vec<u32> = (0..MAX_NODES as u32 + 1).collect();
        assert!(!f.ensure(&many, Vec::new, &asm, &full));
        assert_eq!(f.nodes().len(), 7);
    }

    /// On a factor with the nodes' equations numbered last, the columns are solves on that
    /// contact space alone, and equal the full solves' to rounding.
    #[test]
    fn the_flexibility_on_the_contact_space_is_the_full_solves() {
        let (asm, _) = grid(14);
        let first: Vec<u32> = vec![400, 1, 7, 401, 1500];
        let later: Vec<u32> = vec![1000, 7, 0, 2700];
        let full = SpdSolver::new(&asm.effective, Ordering::NestedDissection).unwrap();
        let mut f = Flexibility::default();
        assert!(f.ensure(&first, Vec::new, &asm, &full) && f.ensure(&later, Vec::new, &asm, &full));
        assert!(!f.in_space);
        let mut last = vec![false; asm.dof_of.len()];
        for &n in first.iter().chain(&later) {
            for a in 0..3 {
                let q = asm.equation[3 * n as usize + a];
                if q != u32::MAX {
                    last[q as usize] = true;
                }
            }
        }
        let space = SpdSolver::with_last(&asm.effective, &last).unwrap();
        assert!(space.contact_space().is_some(), "a supernodal factor");
        let mut g = Flexibility::default();
        assert!(
            g.ensure(&first, Vec::new, &asm, &space) && g.ensure(&later, Vec::new, &asm, &space)
        );
        assert!(g.in_space);
        let (solves, contact_solves) = (space.stats().solves, space.stats().contact_solves);
        // two blocks of right-hand sides, one per ensure with new nodes
        assert_eq!((solves, contact_solves), (0, 2 * 3 * BLOCK_NODES));
        let e = largest_error(&g, |m, a, l, b| f.entry((at(&f, m), a), (at(&f, l), b)));
        assert!(e < 1e-12, "contact-space solves: {e:.2e}");
        // resumed, its nodes join in one block: the same bits
        let mut r = Flexibility::resume(g.nodes());
        assert!(r.ensure(&[], Vec::new, &asm, &space));
        assert_eq!(r.nodes(), g.nodes());
        for c in 0..g.columns.len() {
            let (a, b) = (&g.columns[c], &r.columns[c]);
            assert!(a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()));
        }
    }

    /// Kept at a set of equations, the columns move those equations by K^-1 x for a load x
    /// on the nodes held (and refuse a load on a node not held); the nodes ahead fill the
    /// block's free columns; on a contact space the columns are not kept.
    #[test]
    fn the_columns_at_the_contact_equations_are_the_response_to_a_load() {
        let (asm, k) = grid(6);
        let exact = inverse(&asm, &k);
        let full = SpdSolver::new(&asm.effective, Ordering::NestedDissection).unwrap();
        // the equations of every node in the top layer (z = 5), and some of their nodes
        let top: Vec<u32> = (0..216u32).filter(|n| n % 6 == 5).collect();
        let equation = &asm.equation;
        let equations: Vec<u32> = (top.iter())
            .flat_map(|&n| (0..3).map(move |a| equation[3 * n as usize + a]))
            .filter(|&e| e != u32::MAX)
            .collect();
        let mut f = Flexibility::default();
        f.respond_at(&equations);
        let ahead = || top.iter().rev().copied().collect();
        assert!(f.ensure(&[5, 11, 17], ahead, &asm, &full));
        assert_eq!(
            f.nodes().len(),
            BLOCK_NODES,
            "the block filled from the nodes ahead"
        );
        assert_eq!(&f.nodes()[..4], &[5, 11, 17, 215]);
        let load = [(11u32, 2usize, 1.5), (215, 0, -0.5), (5, 1, 2.0)];
        let mut moved = vec![0.0; equations.len()];
        assert!(f.respond(&load, &mut moved));
        let (mut worst, mut scale) = (0.0f64, 0.0f64);
        for (&e, &m) in equations.iter().zip(&moved) {
            let d = asm.dof_of[e as usize] as usize;
            let want: f64 = (load.iter())
                .map(|&(n, a, x)| exact[(d, 3 * n as usize + a)] * x)
                .sum();
            worst = worst.max((m - want).abs());
            scale = scale.max(want.abs());
        }
        assert!(worst <= 1e-12 * scale, "{worst:e} of {scale:e}");
        // a node not held: refused, nothing moved
        let mut untouched = vec![0.0; equations.len()];
        assert!(!f.respond(&[(100, 0, 1.0)], &mut untouched));
        assert!(untouched.iter().all(|&x| x == 0.0));
        // on a contact space the columns are solved there alone: not kept
        let mut last = vec![false; asm.dof_of.len()];
        for &e in &equations {
            last[e as usize] = true;
        }
        let space = SpdSolver::with_last(&asm.effective, &last).unwrap();
        let mut g = Flexibility::default();
        g.respond_at(&equations);
        assert!(g.ensure(&[5, 11], Vec::new, &asm, &space));
        assert!(g.response_equations().is_empty());
        assert!(!g.respond(&[(5, 0, 1.0)], &mut moved));
    }
}
