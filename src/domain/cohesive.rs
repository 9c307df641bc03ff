//! [`RankCohesive`]: a rank's cohesive pairs. The rank holds both nodes of every pair at a
//! node it holds ([`super::subdomain::pair_groups`]), and steps each such pair after its
//! shared nodes' element forces are summed, in the single process's order (interface by
//! interface, pair by pair, after the elements' gather): every rank holding a node gives it
//! the single process's bits. The owner of a pair's first node counts its areas and its
//! dissipation, so that the sums over the ranks count each pair once.

use super::ranks::Timed;
use super::subdomain::Subdomain;
use crate::kernels::cohesive_forces::{
    cohesive_forces_counting, CohesivePairs, CohesiveReport, CohesiveState,
};
use crate::model::Model;

pub(super) struct RankCohesive {
    /// The rank's pairs of every interface, on local node numbers.
    pairs: Vec<CohesivePairs>,
    /// Each of them's number among its interface's pairs.
    global: Vec<Vec<u32>>,
    /// Whether the rank counts it (it owns the pair's first node).
    counted: Vec<Vec<bool>>,
    state: CohesiveState,
}

impl RankCohesive {
    /// The pairs of `model`'s interfaces at `sub`'s nodes (none without interfaces).
    pub fn new(model: &Model, sub: &Subdomain) -> Option<Self> {
        if model.cohesive.is_empty() {
            return None;
        }
        let local = |n: u32| sub.nodes.binary_search(&n).ok().map(|i| i as u32);
        let (mut pairs, mut global, mut counted) = (Vec::new(), Vec::new(), Vec::new());
        for c in &model.cohesive {
            let p = &c.pairs;
            let mut mine = CohesivePairs::new(p.law);
            let (mut numbers, mut counts) = (Vec::new(), Vec::new());
            for k in 0..p.area.len() {
                let (Some(a), Some(b)) = (local(p.upper[k]), local(p.lower[k])) else {
                    continue;
                };
                mine.push((a, b), p.area[k], p.normal[k]);
                numbers.push(k as u32);
                counts.push(sub.owned[a as usize]);
            }
            pairs.push(mine);
            global.push(numbers);
            counted.push(counts);
        }
        let state = CohesiveState::new(pairs.iter());
        Some(RankCohesive {
            pairs,
            global,
            counted,
            state,
        })
    }

    /// Adds the pairs' forces at the rank's displacement `u` to `f_int`, advances their
    /// damage, and adds the counted pairs' dissipation to their interfaces' energy.
    pub fn forces(&mut self, u: &[f64], f_int: &mut [f64]) {
        let counted = &self.counted;
        let counts = |k: usize, p: usize| counted[k][p];
        cohesive_forces_counting(self.pairs.iter(), u, (&mut self.state, f_int), &counts);
    }

    /// The energy the rank's counted pairs dissipated so far.
    pub fn energy(&self) -> f64 {
        self.state.energy.iter().sum()
    }

    /// The rank's counted pairs' stored-energy offset at the last step.
    pub fn stored_offset(&self) -> f64 {
        self.state.stored_offset()
    }

    /// Each interface's report over every rank (a collective): the counted pairs' areas and
    /// dissipation summed.
    pub fn reports(&self, talk: &Timed) -> Vec<CohesiveReport> {
        let counted = &self.counted;
        let counts = |k: usize, p: usize| counted[k][p];
        let local: Vec<f64> = (self.state.reports_counting(self.pairs.iter(), &counts))
            .iter()
            .flat_map(|r| [r.delaminated_area, r.damaged_area, r.energy])
            .collect();
        let all = talk.talk(|r| r.sum(&local));
        (all.chunks_exact(3))
            .map(|c| CohesiveReport {
                delaminated_area: c[0] + 0.0,
                damaged_area: c[1] + 0.0,
                energy: c[2],
            })
            .collect()
    }

    /// The whole model's state on every rank (a collective): each pair's damage from a rank
    /// that counts it, each interface's energy summed over the ranks.
    pub fn gather(&self, model: &Model, talk: &Timed) -> CohesiveState {
        let offsets: Vec<usize> = (model.cohesive.iter())
            .scan(0, |o, c| {
                let at = *o;
                *o += c.pairs.area.len();
                Some(at)
            })
            .collect();
        // each counted pair's damage and slip (zero without friction)
        let mut places = Vec::new();
        let mut values = Vec::new();
        for (k, (numbers, counted)) in self.global.iter().zip(&self.counted).enumerate() {
            for (i, (&p, &n)) in numbers.iter().zip(counted).enumerate() {
                if n {
                    places.push((offsets[k] + p as usize) as f64);
                    let slip = self.state.slip[k].get(i).copied().unwrap_or_default();
                    values.extend([self.state.damage[k][i], slip[0], slip[1], slip[2]]);
                }
            }
        }
        let (_, places) = talk.talk(|r| r.gather_varied(&places));
        let (_, values) = talk.talk(|r| r.gather_varied(&values));
        let energy = talk.talk(|r| r.sum(&self.state.energy));
        let stored_offset = talk.talk(|r| r.sum(&self.state.stored_offset));
        let mut state = CohesiveState::new(model.cohesive.iter().map(|c| &c.pairs));
        let at = |flat: usize| {
            let k = offsets.partition_point(|&o| o <= flat) - 1;
            (k, flat - offsets[k])
        };
        for (&place, v) in places.iter().zip(values.chunks_exact(4)) {
            let (k, p) = at(place as usize);
            state.damage[k][p] = v[0];
            if let Some(slip) = state.slip[k].get_mut(p) {
                *slip = [v[1], v[2], v[3]];
            }
        }
        state.energy = energy;
        state.stored_offset = stored_offset;
        state
    }

    /// Takes the rank's pairs' damage from the whole model's `state` (a checkpoint's), and
    /// its energy on the first rank alone (`first`), so that the sums count it once.
    pub fn restore(&mut self, state: &CohesiveState, first: bool) {
        for (k, numbers) in self.global.iter().enumerate() {
            for (i, &p) in numbers.iter().enumerate() {
                self.state.damage[k][i] = state.damage[k][p as usize];
                if let Some(slip) = self.state.slip[k].get_mut(i) {
                    *slip = state.slip[k][p as usize];
                }
            }
        }
        for (e, &all) in self.state.energy.iter_mut().zip(&state.energy) {
            *e = if first { all } else { 0.0 };
        }
        // the offset is the counted pairs' own: the next step forms it afresh; until then
        // the first rank carries it whole
        for (o, &all) in self
            .state
            .stored_offset
            .iter_mut()
            .zip(&state.stored_offset)
        {
            *o = if first { all } else { 0.0 };
        }
    }
}
