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

/// The whole model's node arrays (`node_count` nodes) from every rank's owned nodes of its
/// local `fields`, on rank 0 (`None` on the others): the owned nodes' numbers, then each
/// field, one gather each (`MPI_Gatherv`, whose counts are 32-bit: a field of more than
/// 715 million nodes is refused, alike on every rank).
pub(crate) fn gather_fields(
    talk: &Timed,
    sub: &Subdomain,
    fields: [&[f64]; FIELDS],
    node_count: usize,
) -> Result<Option<[Vec<f64>; FIELDS]>, String> {
    if 3 * node_count > i32::MAX as usize {
        return Err(format!(
            "a checkpoint of {node_count} nodes is more than one MPI gather holds ({} million)",
            i32::MAX as usize / 3_000_000
        ));
    }
    let owned: Vec<usize> = (0..sub.nodes.len()).filter(|&l| sub.owned[l]).collect();
    let numbers: Vec<f64> = owned.iter().map(|&l| f64::from(sub.nodes[l])).collect();
    let numbers = talk.talk(|r| r.gather_varied_to_first(&numbers));
    let mut global: [Vec<f64>; FIELDS] = Default::default();
    for (f, g) in fields.iter().zip(&mut global) {
        let mine: Vec<f64> = (owned.iter())
            .flat_map(|&l| f[3 * l..3 * l + 3].iter().copied())
            .collect();
        let all = talk.talk(|r| r.gather_varied_to_first(&mine));
        if let (Some(numbers), Some(all)) = (&numbers, all) {
            *g = vec![0.0; 3 * node_count];
            for (&n, x) in numbers.iter().zip(all.chunks_exact(3)) {
                let n = 3 * n as usize;
                g[n..n + 3].copy_from_slice(x);
            }
        }
    }
    Ok(numbers.map(|_| global))
}

/// The rank's part of the whole model's arrays: the values of every node it holds (its
/// shared nodes included: every rank holding one steps it with the same bits).
pub(crate) fn restrict_fields(sub: &Subdomain, global: [&[f64]; FIELDS]) -> [Vec<f64>; FIELDS] {
    global.map(|g| sub.restrict(g))
}

/// The whole model's records (`count` of `width` values each, zero where no rank gives one)
/// from every rank's owned records `records` at their places `places`, on rank 0 (`None` on
/// the others): two gathers.
pub(crate) fn gather_records(
    talk: &Timed,
    places: &[usize],
    records: &[f64],
    (width, count): (usize, usize),
) -> Option<Vec<f64>> {
    debug_assert_eq!(records.len(), width * places.len());
    let places: Vec<f64> = places.iter().map(|&p| p as f64).collect();
    let places = talk.talk(|r| r.gather_varied_to_first(&places));
    let all = talk.talk(|r| r.gather_varied_to_first(records));
    let (places, all) = (places?, all?);
    let mut out = vec![0.0; width * count];
    for (&p, x) in places.iter().zip(all.chunks_exact(width.max(1))) {
        let p = width * p as usize;
        out[p..p + width].copy_from_slice(x);
    }
    Some(out)
}
