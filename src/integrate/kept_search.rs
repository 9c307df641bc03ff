//! [`KeptSearch`]: how many steps the resident step keeps the contact search's sort of the
//! faces into its grid, and the run's tally (`search_rebuilds`, `search_stale_steps` in
//! `summary.json`).
//!
//! The grid's cells have a skin (`kernels::SEARCH_SKIN`), so the faces may move a little
//! before a sort no longer holds; each step that keeps it measures how much of a cell it
//! needed (the grid's `fill`, at most 1 while it holds), and a step for which it no longer
//! holds tests every face of the interface (a stale step: right, but slower). A sort's own
//! fill is 1 / (1 + skin); the room the skin leaves is the rest. The interval follows the
//! last submission: halved after a stale step or a fill within 15% of the room from 1,
//! doubled (up to [`MAX_INTERVAL`]) while the kept steps used less than half the room. The
//! results do not depend on it.

use crate::gpu::resident_step::SearchRecord;
use crate::kernels::SEARCH_SKIN;

/// Steps between sorts before any submission has been collected.
pub(crate) const FIRST_INTERVAL: usize = 4;
/// The most steps between sorts.
pub(crate) const MAX_INTERVAL: usize = 64;

/// The share of a cell the skin leaves to the faces' drift.
fn room() -> f64 {
    SEARCH_SKIN / (1.0 + SEARCH_SKIN)
}

/// A fill above this halves the interval.
fn halve_above() -> f64 {
    1.0 - 0.15 * room()
}

/// A fill below this doubles it: the kept steps used less than half the room.
fn double_below() -> f64 {
    1.0 - 0.5 * room()
}

/// The interval rule and the run's tally.
#[derive(Debug, Clone, Default)]
pub struct KeptSearch {
    /// An interval fixed by the caller (benchmarks, tests) instead of the rule.
    fixed: Option<usize>,
    /// Sorts recorded by each read-back slot's submission.
    per_slot: [u64; 2],
    /// Sorts of the faces over the steps collected, and the stale steps among them.
    pub rebuilds: u64,
    pub stale_steps: u64,
}

impl KeptSearch {
    /// Fixes the interval (from the next submission on).
    pub fn fix(&mut self, interval: usize) {
        self.fixed = Some(interval.max(1));
    }

    /// Notes that the submission in `slot` records `sorts` sorts.
    pub fn submitted(&mut self, slot: usize, sorts: usize) {
        self.per_slot[slot] = sorts as u64;
    }

    /// Counts the submission collected from `slot`, whose steps kept the grid at
    /// `interval` and left `record`, and returns the interval for the next submission.
    pub fn collected(&mut self, slot: usize, interval: usize, record: SearchRecord) -> usize {
        self.rebuilds += self.per_slot[slot];
        let stale = record.stale_steps.saturating_sub(self.stale_steps);
        self.stale_steps = self.stale_steps.max(record.stale_steps);
        self.fixed
            .unwrap_or_else(|| rule(interval, record.fill, stale))
    }
}

/// The next interval after a submission kept at `interval` reached `fill` with `stale` stale
/// steps.
fn rule(interval: usize, fill: f64, stale: u64) -> usize {
    if stale > 0 || fill > halve_above() {
        (interval / 2).max(1)
    } else if fill < double_below() {
        (2 * interval).min(MAX_INTERVAL)
    } else {
        interval
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(fill: f64, stale_steps: u64) -> SearchRecord {
        SearchRecord { fill, stale_steps }
    }

    /// The fill after a sort and a drift of `share` of the room.
    fn fill(share: f64) -> f64 {
        1.0 - (1.0 - share) * room()
    }

    #[test]
    fn the_rule_halves_on_a_stale_step_and_doubles_on_room() {
        assert!((fill(0.0) - 1.0 / (1.0 + SEARCH_SKIN)).abs() < 1e-12);
        assert_eq!(rule(8, fill(0.3), 0), 16);
        assert_eq!(rule(64, fill(0.3), 0), MAX_INTERVAL);
        assert_eq!(rule(8, fill(0.7), 0), 8);
        assert_eq!(rule(8, fill(0.9), 0), 4);
        assert_eq!(rule(8, 0.5, 1), 4);
        assert_eq!(rule(1, 2.0, 3), 1);
        // a submission that never kept the grid has no fill: room to keep it
        assert_eq!(rule(1, 0.0, 0), 2);
    }

    #[test]
    fn the_tally_counts_sorts_by_slot_and_stale_steps_once() {
        let mut k = KeptSearch::default();
        k.submitted(0, 3);
        k.submitted(1, 2);
        assert_eq!(k.collected(0, 8, record(fill(0.3), 0)), 16);
        assert_eq!(k.collected(1, 16, record(fill(0.9), 2)), 8);
        assert_eq!(k.collected(0, 8, record(fill(0.3), 2)), 16);
        assert_eq!((k.rebuilds, k.stale_steps), (3 + 2 + 3, 2));
        k.fix(1);
        assert_eq!(k.collected(1, 16, record(0.5, 2)), 1);
    }
}
