//! The triangular solves L y = b and L^T x = y with faer's supernodal Cholesky factor,
//! parallel over the subtrees of the supernodal elimination tree, with results that do not
//! depend on the number of threads.
//!
//! A schedule is made once per symbolic analysis. It cuts the supernodal elimination tree
//! (a supernode's parent is the supernode holding the first row below its diagonal block)
//! from the root down into a fixed set of subtree tasks of balanced factor values and the top
//! supernodes above them; the cut depends on the symbolic factor alone. The solve renumbers
//! the columns so that each task's supernodes occupy one run of columns and the top
//! supernodes the last run (the tail). Forward, each task solves its supernodes in its own
//! run and adds its updates of tail rows into a buffer of its own; the buffers are added to
//! the tail in task order, then the top supernodes are solved. Backward, the top supernodes
//! come first, then the tasks, each reading the tail and writing only its own run.
//!
//! Inside a supernode the forward pass takes each row's updates column by column in
//! increasing order, and the backward pass forms each column's dot products in fixed pieces
//! with fixed running sums. So reading four columns at a time, or cutting a large top
//! supernode's rows (forward) or columns (backward) into one chunk per thread, changes no
//! bit: the solution is the same on any number of threads.

use std::ops::Range;
use std::sync::{Mutex, PoisonError};

use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use rayon::prelude::*;

/// The subtree tasks the tree is cut into (at least, where the tree has enough supernodes).
const TASKS: usize = 16;
/// Columns of a supernode's diagonal block solved together: backward, the columns of a
/// block take their products with the solution after it before its triangle is solved;
/// forward, in a split supernode, a block's triangle is solved before the rows after it.
const BLOCK: usize = 256;
/// Factor values of a top supernode from which its dense work is split into parallel chunks.
const SPLIT_VALUES: usize = 1 << 17;

/// A supernode as the solve sees it.
#[derive(Debug, Clone)]
struct Node {
    /// Offset of its block in the factor values: column-major, `ncols + rows.len()` rows,
    /// the diagonal block first.
    val: usize,
    /// Its first column, as a position in its home run (its task's run, or the tail).
    col: usize,
    ncols: usize,
    /// Its rows below the diagonal block: a range of [`SupernodalSolve::rows`].
    rows: Range<usize>,
    /// How many of those rows (the first ones) lie in its home run; the others lie in the
    /// tail and are positions in it.
    inner: usize,
    /// Whether its dense work is split into chunks that run in parallel.
    split: bool,
}

/// A subtree task: its supernodes (a range of [`SupernodalSolve::nodes`]) and its run of
/// columns.
#[derive(Debug, Clone)]
struct Task {
    nodes: Range<usize>,
    cols: Range<usize>,
}

/// Working vectors of a solve.
#[derive(Debug, Default)]
struct Scratch {
    /// The right-hand side in solve order.
    y: Vec<f64>,
    /// Each task's updates of the tail.
    buffers: Vec<f64>,
    /// A supernode's columns and rows, one per task and one for the top.
    work: Vec<f64>,
}

/// A schedule of the supernodal triangular solves for one symbolic factor, with its working
/// vectors.
#[derive(Debug)]
pub(crate) struct SupernodalSolve {
    /// The right-hand side's row for each solve position (faer's fill-reducing permutation
    /// composed with the renumbering by tasks).
    gather: Vec<usize>,
    /// The supernodes in solve order: each task's, then the top ones.
    nodes: Vec<Node>,
    /// The supernodes' rows below their diagonal blocks, as positions in their home runs or
    /// in the tail.
    rows: Vec<u32>,
    tasks: Vec<Task>,
    /// The top supernodes: a range of `nodes`.
    top: Range<usize>,
    /// The first solve position of the tail.
    tail: usize,
    /// The most rows of a supernode's block.
    front: usize,
    scratch: Mutex<Scratch>,
}

/// The supernodal elimination tree: each supernode's parent, or `None` for a root. `None`
/// overall when a parent does not come after its child (faer's supernodes always do).
fn etree(s: &SymbolicSupernodalCholesky<usize>) -> Option<Vec<Option<usize>>> {
    let n_super = s.n_supernodes();
    let mut super_of = vec![0; s.nrows()];
    for k in 0..n_super {
        super_of[s.supernode_begin()[k]..s.supernode_end()[k]].fill(k);
    }
    let ptr = s.col_ptr_for_row_idx();
    let mut parent = Vec::with_capacity(n_super);
    for k in 0..n_super {
        let p = (ptr[k] < ptr[k + 1]).then(|| super_of[s.row_idx()[ptr[k]]]);
        if p.is_some_and(|p| p <= k) {
            return None;
        }
        parent.push(p);
    }
    Some(parent)
}

/// The factor values of each supernode's subtree.
fn subtree_weights(parent: &[Option<usize>], weight: &[usize]) -> Vec<usize> {
    let mut total = weight.to_vec();
    for k in 0..parent.len() {
        if let Some(p) = parent[k] {
            total[p] += total[k];
        }
    }
    total
}

/// Cuts the tree into subtrees: starting from the roots, the heaviest subtree is replaced by
/// its children (its root moves to the top) while there are fewer than [`TASKS`] subtrees or
/// the heaviest holds more than two shares of the values. Returns the subtrees' roots and
/// which supernodes are top ones.
fn cut(parent: &[Option<usize>], subtree: &[usize]) -> (Vec<usize>, Vec<bool>) {
    let n_super = parent.len();
    let mut children = vec![Vec::new(); n_super];
    let mut heap = std::collections::BinaryHeap::new();
    for k in 0..n_super {
        match parent[k] {
            Some(p) => children[p].push(k),
            None => heap.push((subtree[k], std::cmp::Reverse(k))),
        }
    }
    let total: usize = heap.iter().map(|&(w, _)| w).sum();
    let mut top = vec![false; n_super];
    while let Some(&(w, std::cmp::Reverse(k))) = heap.peek() {
        let enough = heap.len() >= TASKS && w * TASKS <= 2 * total;
        if enough || children[k].is_empty() {
            break;
        }
        heap.pop();
        top[k] = true;
        heap.extend(
            children[k]
                .iter()
                .map(|&c| (subtree[c], std::cmp::Reverse(c))),
        );
    }
    let mut roots: Vec<usize> = heap.into_iter().map(|(_, r)| r.0).collect();
    roots.sort_unstable();
    (roots, top)
}

/// Groups the subtrees (in order of their roots) into tasks: a task is closed once it holds
/// half a share of the subtrees' values. Returns each root's task.
fn group(roots: &[usize], subtree: &[usize]) -> Vec<usize> {
    let total: usize = roots.iter().map(|&r| subtree[r]).sum();
    let mut task_of = Vec::with_capacity(roots.len());
    let (mut task, mut held) = (0, 0);
    for &r in roots {
        if held > 0 && 2 * TASKS * held >= total {
            task += 1;
            held = 0;
        }
        task_of.push(task);
        held += subtree[r];
    }
    task_of
}

/// The supernodes in solve order (each task's in increasing order, then the top ones in
/// increasing order), and each task's range of that order.
fn layout(parent: &[Option<usize>], weight: &[usize]) -> (Vec<usize>, Vec<Range<usize>>) {
    let subtree = subtree_weights(parent, weight);
    let (roots, top) = cut(parent, &subtree);
    let task_of_root = group(&roots, &subtree);
    let n_tasks = task_of_root.last().map_or(0, |t| t + 1);
    let mut label = vec![usize::MAX; parent.len()];
    for (&r, &t) in roots.iter().zip(&task_of_root) {
        label[r] = t;
    }
    for k in (0..parent.len()).rev() {
        if let Some(p) = parent[k].filter(|&p| !top[k] && !top[p]) {
            label[k] = label[p];
        }
    }
    let mut members = vec![Vec::new(); n_tasks + 1];
    for (k, &t) in label.iter().enumerate() {
        members[if top[k] { n_tasks } else { t }].push(k);
    }
    let mut ranges = Vec::with_capacity(n_tasks);
    let mut order = Vec::with_capacity(parent.len());
    for m in &members[..n_tasks] {
        ranges.push(order.len()..order.len() + m.len());
        order.extend_from_slice(m);
    }
    order.extend_from_slice(&members[n_tasks]);
    (order, ranges)
}

impl SupernodalSolve {
    /// The schedule for a supernodal symbolic factor; `None` for a simplicial one (solved by
    /// faer itself).
    pub fn new(symbolic: &SymbolicCholesky<usize>) -> Option<SupernodalSolve> {
        Self::with_split(symbolic, SPLIT_VALUES)
    }

    /// The schedule, splitting the top supernodes of at least `split_values` factor values.
    fn with_split(symbolic: &SymbolicCholesky<usize>, split_values: usize) -> Option<Self> {
        let SymbolicCholeskyRaw::Supernodal(s) = symbolic.raw() else {
            return None;
        };
        let parent = etree(s)?;
        let ptr = s.col_ptr_for_val();
        let weight: Vec<usize> = (0..parent.len()).map(|k| ptr[k + 1] - ptr[k]).collect();
        let (order, ranges) = layout(&parent, &weight);
        let mut position = vec![0; s.nrows()];
        let mut next = 0;
        for &k in &order {
            for p in &mut position[s.supernode_begin()[k]..s.supernode_end()[k]] {
                *p = next;
                next += 1;
            }
        }
        let forward = symbolic.perm().map(|p| p.arrays().0);
        let mut gather = vec![0; s.nrows()];
        for (c, &p) in position.iter().enumerate() {
            gather[p] = forward.map_or(c, |f| f[c]);
        }
        Self::assemble(s, &order, &ranges, &position, gather, split_values)
    }

    /// The tasks, nodes and rows from the solve order and the solve positions.
    fn assemble(
        s: &SymbolicSupernodalCholesky<usize>,
        order: &[usize],
        ranges: &[Range<usize>],
        position: &[usize],
        gather: Vec<usize>,
        split_values: usize,
    ) -> Option<Self> {
        let top = ranges.last().map_or(0, |r| r.end)..order.len();
        let first_col = |i: usize| {
            let k = order.get(i);
            k.map_or(s.nrows(), |&k| position[s.supernode_begin()[k]])
        };
        let tail = first_col(top.start);
        let tasks: Vec<Task> = ranges
            .iter()
            .filter(|r| !r.is_empty())
            .map(|r| Task {
                nodes: r.clone(),
                cols: first_col(r.start)..first_col(r.end),
            })
            .collect();
        let homes = tasks
            .iter()
            .map(|t| (t.nodes.clone(), t.cols.clone(), false));
        let homes = homes.chain(std::iter::once((top.clone(), tail..s.nrows(), true)));
        let places = Places {
            s,
            order,
            position,
            tail,
        };
        let (nodes, rows) = places.nodes(homes, split_values)?;
        let front = nodes.iter().map(|n| n.ncols + n.rows.len()).max();
        let front = front.unwrap_or(0);
        let scratch = Scratch {
            y: vec![0.0; s.nrows()],
            buffers: vec![0.0; tasks.len() * (s.nrows() - tail).max(1)],
            work: vec![0.0; (tasks.len() + 1) * front.max(1)],
        };
        Some(SupernodalSolve {
            gather,
            nodes,
            rows,
            tasks,
            top,
            tail,
            front,
            scratch: Mutex::new(scratch),
        })
    }
}

/// The symbolic factor, the solve order and positions, and where the tail begins: what
/// placing the supernodes' columns and rows needs.
struct Places<'a> {
    s: &'a SymbolicSupernodalCholesky<usize>,
    order: &'a [usize],
    position: &'a [usize],
    tail: usize,
}

impl Places<'_> {
    /// The nodes and their rows, home run by home run (each a range of the solve order, its
    /// run of positions, and whether it is the tail); the top supernodes of at least
    /// `split_values` factor values are split.
    fn nodes(
        &self,
        homes: impl Iterator<Item = (Range<usize>, Range<usize>, bool)>,
        split_values: usize,
    ) -> Option<(Vec<Node>, Vec<u32>)> {
        let s = self.s;
        let mut nodes = Vec::with_capacity(self.order.len());
        let mut rows = Vec::new();
        for (range, home, top) in homes {
            for &k in &self.order[range] {
                let start = rows.len();
                let pattern =
                    &s.row_idx()[s.col_ptr_for_row_idx()[k]..s.col_ptr_for_row_idx()[k + 1]];
                let inner = self.rows(pattern, &home, &mut rows)?;
                let ncols = s.supernode_end()[k] - s.supernode_begin()[k];
                let values = s.col_ptr_for_val()[k + 1] - s.col_ptr_for_val()[k];
                debug_assert_eq!(values, ncols * (ncols + pattern.len()));
                nodes.push(Node {
                    val: s.col_ptr_for_val()[k],
                    col: self.position[s.supernode_begin()[k]] - home.start,
                    ncols,
                    rows: start..rows.len(),
                    inner,
                    split: top && values >= split_values,
                });
            }
        }
        Some((nodes, rows))
    }

    /// Appends a supernode's rows below its diagonal block, as positions in its home run
    /// (the rows that lie in it, which come first) or in the tail; returns how many lie in
    /// the home run. `None` if a row lies in another task's run, a home row follows a tail
    /// row, or a position does not fit in 32 bits.
    fn rows(&self, pattern: &[usize], home: &Range<usize>, rows: &mut Vec<u32>) -> Option<usize> {
        let (mut inner, mut outer) = (0, 0);
        for &r in pattern {
            let p = self.position[r];
            let at = if home.contains(&p) && outer == 0 {
                inner += 1;
                p - home.start
            } else if p >= self.tail {
                outer += 1;
                p - self.tail
            } else {
                return None;
            };
            rows.push(u32::try_from(at).ok()?);
        }
        Some(inner)
    }
}

impl SupernodalSolve {
    /// Solves A x = b in place with the factor's values `l` (L L^T = P A P^T). The solve
    /// runs on a thread of the current pool, so that its parallel parts start there.
    pub fn solve_in_place(&self, l: &[f64], b: &mut [f64]) {
        rayon::scope(|_| self.solve_on_pool(l, b));
    }

    fn solve_on_pool(&self, l: &[f64], b: &mut [f64]) {
        debug_assert_eq!(b.len(), self.gather.len());
        let mut scratch = self.scratch.lock().unwrap_or_else(PoisonError::into_inner);
        let Scratch { y, buffers, work } = &mut *scratch;
        for (yj, &i) in y.iter_mut().zip(&self.gather) {
            *yj = b[i];
        }
        self.forward(l, y, buffers, work);
        self.backward(l, y, work);
        for (&yj, &i) in y.iter().zip(&self.gather) {
            b[i] = yj;
        }
    }

    /// The tasks' runs of `sub` (the positions before the tail).
    fn runs<'a>(&self, mut sub: &'a mut [f64]) -> Vec<&'a mut [f64]> {
        let mut runs = Vec::with_capacity(self.tasks.len());
        for task in &self.tasks {
            let (run, rest) = std::mem::take(&mut sub).split_at_mut(task.cols.len());
            runs.push(run);
            sub = rest;
        }
        runs
    }

    /// L y = b in place: the tasks in parallel, their tail updates added in task order, then
    /// the top supernodes.
    fn forward(&self, l: &[f64], y: &mut [f64], buffers: &mut [f64], work: &mut [f64]) {
        let (sub, tail) = y.split_at_mut(self.tail);
        let len = tail.len();
        let front = self.front.max(1);
        let (work_top, work_tasks) = work.split_at_mut(front);
        self.runs(sub)
            .into_par_iter()
            .zip(buffers.par_chunks_mut(len.max(1)))
            .zip(work_tasks.par_chunks_mut(front))
            .zip(self.tasks.par_iter())
            .for_each(|(((run, buffer), w), task)| {
                let buffer = &mut buffer[..len];
                buffer.fill(0.0);
                for node in &self.nodes[task.nodes.clone()] {
                    self.forward_node(node, l, run, buffer, w);
                }
            });
        for buffer in buffers.chunks(len.max(1)).take(self.tasks.len()) {
            for (t, &u) in tail.iter_mut().zip(buffer) {
                *t += u;
            }
        }
        for node in &self.nodes[self.top.clone()] {
            self.forward_node(node, l, tail, &mut [], work_top);
        }
    }

    /// L^T x = y in place: the top supernodes, then the tasks in parallel.
    fn backward(&self, l: &[f64], y: &mut [f64], work: &mut [f64]) {
        let (sub, tail) = y.split_at_mut(self.tail);
        let front = self.front.max(1);
        let (work_top, work_tasks) = work.split_at_mut(front);
        for node in self.nodes[self.top.clone()].iter().rev() {
            self.backward_node(node, l, tail, &[], work_top);
        }
        let tail = &*tail;
        self.runs(sub)
            .into_par_iter()
            .zip(work_tasks.par_chunks_mut(front))
            .zip(self.tasks.par_iter())
            .for_each(|((run, w), task)| {
                for node in self.nodes[task.nodes.clone()].iter().rev() {
                    self.backward_node(node, l, run, tail, w);
                }
            });
    }

    /// One supernode of L y = b: its columns solved in `home`, the updates of its rows below
    /// added to `home` (its inner rows) and `outer` (its tail rows). A supernode whose
    /// columns hold zeros when it comes is skipped: its solution and updates are zero (so
    /// loads on the contact equations alone, numbered last, cost the forward solve little).
    fn forward_node(
        &self,
        node: &Node,
        l: &[f64],
        home: &mut [f64],
        outer: &mut [f64],
        w: &mut [f64],
    ) {
        let (nc, rows) = (node.ncols, &self.rows[node.rows.clone()]);
        let w = &mut w[..nc + rows.len()];
        let cols = node.col..node.col + nc;
        if home[cols.clone()].iter().all(|&v| v == 0.0) {
            return;
        }
        w[..nc].copy_from_slice(&home[cols.clone()]);
        w[nc..].fill(0.0);
        lower_solve(&l[node.val..node.val + w.len() * nc], w, nc, chunks(node));
        home[cols].copy_from_slice(&w[..nc]);
        let (inner, tail_rows) = rows.split_at(node.inner);
        let (w_inner, w_tail) = w[nc..].split_at(node.inner);
        for (&r, &u) in inner.iter().zip(w_inner) {
            home[r as usize] += u;
        }
        for (&r, &u) in tail_rows.iter().zip(w_tail) {
            outer[r as usize] += u;
        }
    }

    /// One supernode of L^T x = y: its columns solved in `home`, reading its rows below from
    /// `home` (its inner rows) and `outer` (its tail rows).
    fn backward_node(
        &self,
        node: &Node,
        l: &[f64],
        home: &mut [f64],
        outer: &[f64],
        w: &mut [f64],
    ) {
        let (nc, rows) = (node.ncols, &self.rows[node.rows.clone()]);
        let w = &mut w[..nc + rows.len()];
        let cols = node.col..node.col + nc;
        w[..nc].copy_from_slice(&home[cols.clone()]);
        let (inner, tail_rows) = rows.split_at(node.inner);
        let (w_inner, w_tail) = w[nc..].split_at_mut(node.inner);
        for (&r, v) in inner.iter().zip(w_inner) {
            *v = home[r as usize];
        }
        for (&r, v) in tail_rows.iter().zip(w_tail) {
            *v = outer[r as usize];
        }
        upper_solve(&l[node.val..node.val + w.len() * nc], w, nc, chunks(node));
        home[cols].copy_from_slice(&w[..nc]);
    }
}

/// The chunks a supernode's dense work is cut into: one per thread of the pool the solve
/// runs on for a split supernode, else one. The chunks change no bit of the solution.
fn chunks(node: &Node) -> usize {
    if node.split {
        rayon::current_num_threads()
    } else {
        1
    }
}

/// w -= a x
fn axpy(w: &mut [f64], a: &[f64], x: f64) {
    for (wi, &ai) in w.iter_mut().zip(a) {
        *wi -= ai * x;
    }
}

/// w -= a_0 x_0, then a_1 x_1, a_2 x_2, a_3 x_3: the bits of four [`axpy`] in turn, reading
/// the four columns together.
fn axpy4(w: &mut [f64], a: [&[f64]; 4], x: [f64; 4]) {
    let n = w.len();
    let [a0, a1, a2, a3] = a.map(|c| &c[..n]);
    for i in 0..n {
        w[i] = w[i] - a0[i] * x[0] - a1[i] * x[1] - a2[i] * x[2] - a3[i] * x[3];
    }
}

/// a . b: four running sums over the whole fours (element i in sum i mod 4), added in
/// pairs, then the remaining products in turn.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0; 4];
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (a4.remainder(), b4.remainder());
    for (x, y) in a4.zip(b4) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let mut sum = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for (x, y) in ra.iter().zip(rb) {
        sum += x * y;
    }
    sum
}

/// The dot products of four columns with `b`, each with the bits of [`dot`], reading the
/// four columns together.
fn dot4(a: [&[f64]; 4], b: &[f64]) -> [f64; 4] {
    let n = b.len();
    let whole = n - n % 4;
    let a = a.map(|c| &c[..n]);
    let mut acc = [[0.0; 4]; 4];
    for i in (0..whole).step_by(4) {
        for (q, c) in a.iter().enumerate() {
            for k in 0..4 {
                acc[q][k] += c[i + k] * b[i + k];
            }
        }
    }
    let mut sums = acc.map(|s| (s[0] + s[1]) + (s[2] + s[3]));
    for (q, c) in a.iter().enumerate() {
        for i in whole..n {
            sums[q] += c[i] * b[i];
        }
    }
    sums
}

/// A supernode's block of L y = b: `w` holds its columns' right-hand side, then zeros for
/// its rows below; the columns are solved with the diagonal block and the rows below take
/// minus the below block times them. One chunk sweeps the block column by column; more
/// solve each block of [`BLOCK`] columns' triangle, then update the rows after it in that
/// many chunks in parallel. Each row takes the columns in increasing order either way, so
/// the bits do not depend on `chunks`.
pub(super) fn lower_solve(block: &[f64], w: &mut [f64], nc: usize, chunks: usize) {
    let ld = w.len();
    if chunks <= 1 {
        eliminate(block, ld, w, 0..nc);
        return;
    }
    for p0 in (0..nc).step_by(BLOCK) {
        let p1 = (p0 + BLOCK).min(nc);
        eliminate(block, ld, &mut w[..p1], p0..p1);
        let (done, rest) = w.split_at_mut(p1);
        let x = &done[p0..];
        let len = rest.len().div_ceil(chunks).max(1);
        rest.par_chunks_mut(len).enumerate().for_each(|(k, part)| {
            let column = |j: usize| &block[j * ld + p1 + k * len..];
            let mut j = p0;
            for x4 in x.chunks_exact(4) {
                let a = [column(j), column(j + 1), column(j + 2), column(j + 3)];
                axpy4(part, a, [x4[0], x4[1], x4[2], x4[3]]);
                j += 4;
            }
            for &xj in x.chunks_exact(4).remainder() {
                axpy(part, column(j), xj);
                j += 1;
            }
        });
    }
}

/// Columns `cols` of L y = b on the first rows of the block (columns of `ld` rows), as many
/// as `w` holds (at least to the last of `cols`): each column's entry is divided by its
/// diagonal, then its multiples are taken from the rows after it, four columns at a time
/// where there are four (the bits of one at a time).
pub(super) fn eliminate(block: &[f64], ld: usize, w: &mut [f64], cols: Range<usize>) {
    let end = w.len();
    let column = |j: usize| &block[j * ld..j * ld + end];
    let mut j = cols.start;
    while j + 4 <= cols.end {
        for q in 0..4 {
            let c = column(j + q);
            w[j + q] /= c[j + q];
            let x = w[j + q];
            axpy(&mut w[j + q + 1..j + 4], &c[j + q + 1..j + 4], x);
        }
        let x = [w[j], w[j + 1], w[j + 2], w[j + 3]];
        let a = [0, 1, 2, 3].map(|q| &column(j + q)[j + 4..]);
        axpy4(&mut w[j + 4..], a, x);
        j += 4;
    }
    for j in j..cols.end {
        let c = column(j);
        w[j] /= c[j];
        let x = w[j];
        axpy(&mut w[j + 1..], &c[j + 1..], x);
    }
}

/// A supernode's block of L^T x = y: `w` holds its columns' right-hand side, then the
/// solution at its rows below. The columns are solved in blocks of [`BLOCK`] from the last:
/// each column of a block takes minus its dot product with the solution after the block
/// (in `chunks` of columns in parallel: the same bits), then the block's triangle is solved.
pub(super) fn upper_solve(block: &[f64], w: &mut [f64], nc: usize, chunks: usize) {
    upper_solve_strided(block, w.len(), w, nc, chunks);
}

/// [`upper_solve`] on the trailing part of a block whose columns are `ld` long: `block`
/// starts at the part's first diagonal entry and `w` holds the part's rows.
pub(super) fn upper_solve_strided(
    block: &[f64],
    ld: usize,
    w: &mut [f64],
    nc: usize,
    chunks: usize,
) {
    let rows = w.len();
    for p0 in (0..nc).step_by(BLOCK).rev() {
        let p1 = (p0 + BLOCK).min(nc);
        let (head, solved) = w.split_at_mut(p1);
        let solved = &*solved;
        let take_after = |first: usize, part: &mut [f64]| {
            let column = |j: usize| &block[j * ld + p1..j * ld + rows];
            let mut j = first;
            let mut groups = part.chunks_exact_mut(4);
            for x4 in &mut groups {
                let d = dot4(
                    [column(j), column(j + 1), column(j + 2), column(j + 3)],
                    solved,
                );
                for (xj, dj) in x4.iter_mut().zip(d) {
                    *xj -= dj;
                }
                j += 4;
            }
            for xj in groups.into_remainder() {
                *xj -= dot(column(j), solved);
                j += 1;
            }
        };
        let x = &mut head[p0..];
        if chunks > 1 {
            let len = x.len().div_ceil(chunks);
            let parts = x.par_chunks_mut(len).enumerate();
            parts.for_each(|(k, part)| take_after(p0 + k * len, part));
        } else {
            take_after(p0, x);
        }
        for j in (p0..p1).rev() {
            let c = &block[j * ld..j * ld + p1];
            let s = dot(&c[j + 1..], &head[j + 1..]);
            head[j] = (head[j] - s) / c[j];
        }
    }
}

#[cfg(test)]
mod tests {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::sparse::linalg::cholesky::LltRef;
    use faer::sparse::{SparseColMat, SymbolicSparseColMat};
    use faer::{Conj, MatMut, Par};

    use super::*;
    use crate::linalg::cholesky::{analyse, factorise};
    use crate::linalg::test_matrices::{grid_matrix, Lcg};
    use crate::linalg::{Csc, Ordering};

    /// The symbolic analysis and factor values of `a` with `ordering`.
    fn factor(a: &Csc, ordering: Ordering) -> (std::sync::Arc<SymbolicCholesky<usize>>, Vec<f64>) {
        let pattern =
            SymbolicSparseColMat::new_checked(a.n, a.n, a.col_ptr.clone(), None, a.row_idx.clone());
        let symbolic = analyse(a, &pattern, ordering).unwrap();
        let l = factorise(
            &symbolic,
            SparseColMat::new(pattern, a.values.clone()).as_ref(),
        )
        .unwrap();
        (symbolic, l)
    }

    /// faer's own solve of A x = b in place.
    fn faer_solve(symbolic: &SymbolicCholesky<usize>, l: &[f64], b: &mut [f64]) {
        let n = b.len();
        let mut mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        LltRef::new(symbolic, l).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(b, n, 1),
            Par::Seq,
            MemStack::new(&mut mem),
        );
    }

    fn max_abs(v: impl IntoIterator<Item = f64>) -> f64 {
        v.into_iter().fold(0.0, |m, x| m.max(x.abs()))
    }

    fn right_hand_side(n: usize) -> Vec<f64> {
        let mut rng = Lcg(12345);
        (0..n).map(|_| rng.next() - 0.5).collect()
    }

    /// On a 27-point grid matrix with each ordering the solve has many tasks and top
    /// supernodes, agrees with faer's solve and solves the system.
    #[test]
    fn agrees_with_faer_and_solves_the_system() {
        let a = grid_matrix(20, 7);
        let b = right_hand_side(a.n);
        for &(name, ordering) in Ordering::CHOICES {
            let (symbolic, l) = factor(&a, ordering);
            let tree = SupernodalSolve::new(&symbolic).expect("a supernodal factor");
            assert!(
                tree.tasks.len() >= TASKS / 2 && !tree.top.is_empty(),
                "{name}"
            );
            assert!(tree.nodes.iter().any(|n| n.split), "{name}");
            let mut x = b.clone();
            tree.solve_in_place(&l, &mut x);
            let mut x_faer = b.clone();
            faer_solve(&symbolic, &l, &mut x_faer);
            let diff = max_abs(x.iter().zip(&x_faer).map(|(u, v)| u - v));
            assert!(
                diff <= 1e-12 * max_abs(x_faer.iter().copied()),
                "{name}: {diff}"
            );
            let mut ax = vec![0.0; a.n];
            a.mul_into(&x, &mut ax);
            let residual = max_abs(ax.iter().zip(&b).map(|(u, v)| u - v));
            assert!(
                residual <= 1e-10 * max_abs(b.iter().copied()),
                "{name}: {residual}"
            );
        }
    }

    /// The solution's bits are the same on 1, 2 and 4 threads, and with every top supernode
    /// split into parallel chunks.
    #[test]
    fn is_the_same_on_any_number_of_threads() {
        let a = grid_matrix(20, 8);
        let b = right_hand_side(a.n);
        for &(name, ordering) in Ordering::CHOICES {
            let (symbolic, l) = factor(&a, ordering);
            let schedules = [
                SupernodalSolve::new(&symbolic).unwrap(),
                SupernodalSolve::with_split(&symbolic, 0).unwrap(),
            ];
            let mut solutions = Vec::new();
            for threads in [1, 2, 4] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                for tree in &schedules {
                    let mut x = b.clone();
                    pool.install(|| tree.solve_in_place(&l, &mut x));
                    solutions.push(x.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
                }
            }
            assert!(solutions.iter().all(|x| *x == solutions[0]), "{name}");
        }
    }

    /// Four columns read together give the bits of one column at a time.
    #[test]
    fn four_columns_at_a_time_give_the_bits_of_one() {
        let mut rng = Lcg(3);
        for n in 0..23 {
            let mut column = || (0..n).map(|_| rng.next() - 0.5).collect::<Vec<f64>>();
            let a: Vec<Vec<f64>> = (0..4).map(|_| column()).collect();
            let b = column();
            let a4 = [&a[0][..], &a[1][..], &a[2][..], &a[3][..]];
            let one: Vec<u64> = a.iter().map(|c| dot(c, &b).to_bits()).collect();
            assert_eq!(dot4(a4, &b).map(f64::to_bits).to_vec(), one, "dot, n = {n}");
            let x = [0.3, -1.7, 2.9, 0.011];
            let (mut w1, mut w4) = (b.clone(), b.clone());
            for (c, &xq) in a.iter().zip(&x) {
                axpy(&mut w1, c, xq);
            }
            axpy4(&mut w4, a4, x);
            let bits = |w: &[f64]| w.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&w4), bits(&w1), "axpy, n = {n}");
        }
    }

    /// A small matrix gets a simplicial factor, which faer solves itself.
    #[test]
    fn a_simplicial_factor_has_no_schedule() {
        let a = grid_matrix(3, 1);
        let (symbolic, _) = factor(&a, Ordering::Amd);
        assert!(matches!(symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_)));
        assert!(SupernodalSolve::new(&symbolic).is_none());
    }
}
