//! A decomposed run's checkpoint is the single process's: the whole model's node arrays,
//! gathered on rank 0 (which writes it) from the nodes each rank owns, and the interfaces'
//! state, which every rank holds whole (every rank works the sweeps on every gathered
//! contact). A rank resuming takes the values of the nodes it holds from those arrays. So a
//! checkpoint written on P ranks resumes on any number of ranks, or on one process, and one
//! written by one process resumes on ranks, each continuing with the bits of the run that
//! was not stopped.

use super::ranks::Timed;
use super::subdomain::Subdomain;

/// The node arrays a checkpoint keeps, in the order of
/// [`crate::integrate::explicit::ExplicitState`]: u, v, a, f_int, u_prev, v_half.
pub const FIELDS: usize = 6;

/// Values per owned node in the gather: its global number and the fields' three each.
const RECORD: usize = 1 + 3 * FIELDS;

/// The whole model's node arrays (`node_count` nodes) from every rank's owned nodes of its
/// local `fields`, on rank 0 (`None` on the others).
pub fn gather_fields(
    talk: &Timed,
    sub: &Subdomain,
    fields: [&[f64]; FIELDS],
    node_count: usize,
) -> Option<[Vec<f64>; FIELDS]> {
    let owned = sub.owned.iter().filter(|&&o| o).count();
    let mut mine = Vec::with_capacity(RECORD * owned);
    for (l, &n) in sub.nodes.iter().enumerate() {
        if sub.owned[l] {
            mine.push(f64::from(n));
            for f in &fields {
                mine.extend_from_slice(&f[3 * l..3 * l + 3]);
            }
        }
    }
    let all = talk.talk(|r| r.gather_varied_to_first(&mine))?;
    let mut global: [Vec<f64>; FIELDS] = std::array::from_fn(|_| vec![0.0; 3 * node_count]);
    for x in all.chunks_exact(RECORD) {
        let n = 3 * x[0] as usize;
        for (k, g) in global.iter_mut().enumerate() {
            g[n..n + 3].copy_from_slice(&x[1 + 3 * k..4 + 3 * k]);
        }
    }
    Some(global)
}

/// The rank's part of the whole model's arrays: the values of every node it holds (its
/// shared nodes included: every rank holding one steps it with the same bits).
pub fn restrict_fields(sub: &Subdomain, global: [&[f64]; FIELDS]) -> [Vec<f64>; FIELDS] {
    global.map(|g| sub.restrict(g))
}
