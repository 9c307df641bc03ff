//! Fill-reducing orderings of the implicit matrix: nested dissection (METIS) or faer's
//! approximate minimum degree.
//!
//! Nested dissection splits the mesh's graph by small separators and numbers the separators
//! last, which on 3D meshes gives far less fill than minimum degree. METIS is run on the
//! graph of the matrix's supervariables (runs of neighbouring columns with the same pattern:
//! the three free dofs of a node), which is a third of the size and gives the same
//! separators. METIS seeds its generator with a fixed value, so the ordering is the same on
//! every run and every thread count.

use crate::error::{ImpactError, Result};

use super::Csc;
pub use crate::scene::Ordering;

/// A permutation as faer takes it: `forward[new] = old`, `inverse[old] = new`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Permutation {
    pub forward: Vec<usize>,
    pub inverse: Vec<usize>,
}

/// The columns where each supervariable starts (runs of neighbouring columns with the same
/// row pattern), closed by `n`.
pub(crate) fn supervariables(a: &Csc) -> Vec<usize> {
    let column = |j: usize| &a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]];
    let mut starts = Vec::new();
    for j in 0..a.n {
        if j == 0 || column(j) != column(j - 1) {
            starts.push(j);
        }
    }
    starts.push(a.n);
    starts
}

/// The graph of the supervariables in METIS's form (`xadj`, `adjncy`; no self loops).
fn quotient_graph(a: &Csc, starts: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut owner = vec![0usize; a.n];
    for (s, w) in starts.windows(2).enumerate() {
        owner[w[0]..w[1]].fill(s);
    }
    let mut xadj = Vec::with_capacity(starts.len());
    let mut adjncy = Vec::new();
    xadj.push(0);
    for (s, w) in starts.windows(2).enumerate() {
        let j = w[0];
        let mut last = usize::MAX;
        for &i in &a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]] {
            let t = owner[i];
            if t != s && t != last {
                adjncy.push(t);
                last = t;
            }
        }
        xadj.push(adjncy.len());
    }
    (xadj, adjncy)
}

/// GKlib, under METIS's API, traps SIGTERM and SIGABRT with `signal()` for the length of a
/// call and puts back what `signal()` returned. Calls are serialised so that no call puts
/// back another call's trap, and the handlers in place before (the command line's interrupt
/// handler) are restored whole with `sigaction` afterwards.
static METIS_CALL: std::sync::Mutex<()> = std::sync::Mutex::new(());

#[cfg(unix)]
const TRAPPED: [libc::c_int; 2] = [libc::SIGTERM, libc::SIGABRT];

/// The handlers METIS replaces during a call.
#[cfg(unix)]
fn save_handlers() -> [libc::sigaction; 2] {
    TRAPPED.map(|sig| {
        // SAFETY: a zeroed sigaction is a valid out-parameter; a null new action only reads.
        unsafe {
            let mut old: libc::sigaction = std::mem::zeroed();
            libc::sigaction(sig, std::ptr::null(), &mut old);
            old
        }
    })
}

#[cfg(unix)]
fn restore_handlers(saved: &[libc::sigaction; 2]) {
    for (sig, action) in TRAPPED.iter().zip(saved) {
        // SAFETY: `action` was read by sigaction for the same signal.
        unsafe {
            libc::sigaction(*sig, action, std::ptr::null_mut());
        }
    }
}

/// METIS_NodeND on a graph; returns `forward[new] = old`.
fn metis_node_nd(xadj: &[usize], adjncy: &[usize]) -> Result<Vec<usize>> {
    let too_big = |what: &str| {
        ImpactError::Solver(format!(
            "nested dissection: the matrix graph has more {what} than METIS's 32-bit indices hold; choose implicit.ordering = \"amd\""
        ))
    };
    let to_idx = |v: &[usize], what: &str| -> Result<Vec<metis_sys::idx_t>> {
        v.iter()
            .map(|&x| metis_sys::idx_t::try_from(x).map_err(|_| too_big(what)))
            .collect()
    };
    let mut xadj_m = to_idx(xadj, "edges")?;
    let mut adjncy_m = to_idx(adjncy, "edges")?;
    let n = xadj.len() - 1;
    let mut nvtxs = metis_sys::idx_t::try_from(n).map_err(|_| too_big("vertices"))?;
    let mut options = [0 as metis_sys::idx_t; metis_sys::METIS_NOPTIONS as usize];
    let mut perm = vec![0 as metis_sys::idx_t; n];
    let mut iperm = vec![0 as metis_sys::idx_t; n];
    // SAFETY: every array has the length METIS reads or writes (xadj: n + 1, adjncy:
    // xadj[n], options: METIS_NOPTIONS, perm and iperm: n) and outlives the call; METIS keeps
    // no pointer after it returns.
    let _serial = METIS_CALL.lock().unwrap_or_else(|e| e.into_inner());
    #[cfg(unix)]
    let saved = save_handlers();
    let status = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        metis_sys::METIS_NodeND(
            &mut nvtxs,
            xadj_m.as_mut_ptr(),
            adjncy_m.as_mut_ptr(),
            std::ptr::null_mut(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    #[cfg(unix)]
    restore_handlers(&saved);
    if status != metis_sys::rstatus_et_METIS_OK {
        return Err(ImpactError::Solver(format!(
            "nested dissection: METIS_NodeND failed with status {status} (out of memory, an internal error, or SIGTERM during the ordering); choose implicit.ordering = \"amd\" to avoid it"
        )));
    }
    // METIS's perm[new] = old, as faer's forward array
    Ok(perm.into_iter().map(|p| p as usize).collect())
}

/// The supervariables of `a` ([`supervariables`]), also split where `last` changes, so that
/// each lies wholly among the equations `last` marks or wholly outside them.
fn split_supervariables(a: &Csc, last: &[bool]) -> Vec<usize> {
    let mut starts = Vec::new();
    for w in supervariables(a).windows(2) {
        starts.push(w[0]);
        starts.extend((w[0] + 1..w[1]).filter(|&j| last[j] != last[j - 1]));
    }
    starts.push(a.n);
    starts
}

/// The connected component of each equation in the graph of `a` (numbered by their first
/// equation's order).
fn components(a: &Csc) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..a.n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for j in 0..a.n {
        for &i in &a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]] {
            let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
            if ri != rj {
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    let mut number = vec![usize::MAX; a.n];
    let mut count = 0;
    (0..a.n)
        .map(|j| {
            let r = root(&mut parent, j);
            if number[r] == usize::MAX {
                number[r] = count;
                count += 1;
            }
            number[r]
        })
        .collect()
}

/// The nested-dissection permutation of a symmetric matrix that numbers the equations
/// `last` marks after all the others: the trailing block of the Cholesky factor is then the
/// factor of the Schur complement on them (the contact space). They keep their own order
/// within each connected component of the matrix's graph, one component after the other
/// (the consistent mass couples x dofs with x dofs only: its trailing block is three dense
/// blocks, each then contiguous, whose supernodes are whole rather than one column wide).
/// The other equations are ordered by nested dissection of their own graph.
pub fn nested_dissection_last(a: &Csc, last: &[bool]) -> Result<Permutation> {
    debug_assert_eq!(last.len(), a.n);
    let starts = split_supervariables(a, last);
    let count = starts.len() - 1;
    let (xadj, adjncy) = quotient_graph(a, &starts);
    // the interior supervariables, renumbered, and their graph without the last ones
    let mut index = vec![usize::MAX; count];
    let interior: Vec<usize> = (0..count).filter(|&s| !last[starts[s]]).collect();
    for (k, &s) in interior.iter().enumerate() {
        index[s] = k;
    }
    let (mut sub_xadj, mut sub_adjncy) = (vec![0], Vec::new());
    for &s in &interior {
        let kept = adjncy[xadj[s]..xadj[s + 1]].iter().map(|&t| index[t]);
        sub_adjncy.extend(kept.filter(|&t| t != usize::MAX));
        sub_xadj.push(sub_adjncy.len());
    }
    let order = match interior.len() {
        0 | 1 => (0..interior.len()).collect(),
        _ => metis_node_nd(&sub_xadj, &sub_adjncy)?,
    };
    let mut forward = Vec::with_capacity(a.n);
    for k in order {
        let s = interior[k];
        forward.extend(starts[s]..starts[s + 1]);
    }
    let component = components(a);
    let mut trailing: Vec<usize> = (0..a.n).filter(|&j| last[j]).collect();
    trailing.sort_by_key(|&j| component[j]);
    forward.extend(trailing);
    Ok(from_forward(forward))
}

/// The permutation of `forward[new] = old`.
fn from_forward(forward: Vec<usize>) -> Permutation {
    let mut inverse = vec![0; forward.len()];
    for (new, &old) in forward.iter().enumerate() {
        inverse[old] = new;
    }
    Permutation { forward, inverse }
}

/// The nested-dissection permutation of a symmetric matrix given with full storage.
pub fn nested_dissection(a: &Csc) -> Result<Permutation> {
    let starts = supervariables(a);
    let forward = if starts.len() <= 2 {
        (0..a.n).collect()
    } else {
        let (xadj, adjncy) = quotient_graph(a, &starts);
        let order = metis_node_nd(&xadj, &adjncy)?;
        let mut forward = Vec::with_capacity(a.n);
        for s in order {
            forward.extend(starts[s]..starts[s + 1]);
        }
        forward
    };
    Ok(from_forward(forward))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stiffness pattern of a chain of `nodes` nodes with `dofs` dofs each, every node
    /// coupled to its neighbours.
    fn chain(nodes: usize, dofs: usize) -> Csc {
        let mut t = Vec::new();
        for n in 0..nodes {
            for m in n.saturating_sub(1)..(n + 2).min(nodes) {
                for a in 0..dofs {
                    for b in 0..dofs {
                        let v = if n == m && a == b { 4.0 } else { -0.1 };
                        t.push(((dofs * n + a) as u32, (dofs * m + b) as u32, v));
                    }
                }
            }
        }
        Csc::from_triplets(nodes * dofs, t)
    }

    #[test]
    fn the_dofs_of_a_node_form_one_supervariable() {
        let a = chain(7, 3);
        let starts = supervariables(&a);
        assert_eq!(starts, (0..=7).map(|n| 3 * n).collect::<Vec<_>>());
    }

    /// The permutation is a bijection, keeps each node's dofs together and in order, and is
    /// the same when computed again.
    #[test]
    fn nested_dissection_is_a_repeatable_node_wise_permutation() {
        let a = chain(50, 3);
        let p = nested_dissection(&a).unwrap();
        let mut seen = vec![false; a.n];
        for (new, &old) in p.forward.iter().enumerate() {
            assert!(!seen[old]);
            seen[old] = true;
            assert_eq!(p.inverse[old], new);
        }
        for k in (0..a.n).step_by(3) {
            let node = p.forward[k] / 3;
            assert_eq!(p.forward[k..k + 3], [3 * node, 3 * node + 1, 3 * node + 2]);
        }
        assert_eq!(nested_dissection(&a).unwrap(), p);
    }

    /// The equations marked last come last, in their order; the rest keep each node's dofs
    /// together; the permutation is a repeatable bijection.
    #[test]
    fn marked_equations_are_numbered_last() {
        let a = chain(60, 3);
        // a node's dofs marked, and one node's dofs split (its first dof only)
        let mut last = vec![false; a.n];
        for n in [3, 17, 40, 41, 59] {
            last[3 * n..3 * n + 3].fill(true);
        }
        last[3 * 25] = true;
        let p = nested_dissection_last(&a, &last).unwrap();
        let marked: Vec<usize> = (0..a.n).filter(|&j| last[j]).collect();
        assert_eq!(p.forward[a.n - marked.len()..], marked[..]);
        let mut seen = vec![false; a.n];
        for (new, &old) in p.forward.iter().enumerate() {
            assert!(!seen[old]);
            seen[old] = true;
            assert_eq!(p.inverse[old], new);
        }
        for k in (0..a.n - marked.len()).filter(|&k| p.forward[k] % 3 == 0) {
            let n = p.forward[k];
            if n != 75 {
                assert_eq!(p.forward[k..k + 3], [n, n + 1, n + 2]);
            }
        }
        assert_eq!(nested_dissection_last(&a, &last).unwrap(), p);
        // nothing marked: an ordering of everything; everything marked: the identity
        let none = nested_dissection_last(&a, &vec![false; a.n]).unwrap();
        assert_eq!(none.forward.len(), a.n);
        let all = nested_dissection_last(&a, &vec![true; a.n]).unwrap();
        assert_eq!(all.forward, (0..a.n).collect::<Vec<_>>());
    }

    /// A matrix whose dofs decouple by component (a mass: x with x only) numbers its marked
    /// equations one component after the other, each in its own order.
    #[test]
    fn marked_equations_of_decoupled_components_are_grouped() {
        let nodes: usize = 30;
        let mut t = Vec::new();
        for n in 0..nodes {
            for m in n.saturating_sub(1)..(n + 2).min(nodes) {
                for a in 0..3 {
                    let v = if n == m { 4.0 } else { -0.1 };
                    t.push(((3 * n + a) as u32, (3 * m + a) as u32, v));
                }
            }
        }
        let a = Csc::from_triplets(3 * nodes, t);
        let mut last = vec![false; a.n];
        for n in [2, 11, 12, 29] {
            last[3 * n..3 * n + 3].fill(true);
        }
        let p = nested_dissection_last(&a, &last).unwrap();
        let tail = &p.forward[a.n - 12..];
        let by_component: Vec<usize> = (0..3)
            .flat_map(|c| [2, 11, 12, 29].map(|n| 3 * n + c))
            .collect();
        assert_eq!(tail, &by_component[..]);
    }

    #[test]
    fn ordering_names_round_trip() {
        for (name, o) in Ordering::CHOICES {
            assert_eq!(o.name(), *name);
        }
    }
}
