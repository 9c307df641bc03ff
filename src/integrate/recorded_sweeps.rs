//! [`RecordedSweeps`]: how many sweeps of the device contact iteration the resident step
//! records per step as dispatches of their own, and the run's tally of sweeps recorded and
//! needed (`sweeps_recorded`, `sweeps_needed` in `summary.json`).
//!
//! A recorded sweep that the iteration needs is a full dispatch pair; one it does not need
//! is a pair of dispatches that exit at once; a sweep needed past the recorded ones runs in
//! `contact_finish`, one workgroup, which is cheap on small contact zones and slow on large
//! ones. The count follows the last submission's needs: the number that covers three steps
//! in four, at most 1.25 times their mean plus one. The results do not depend on it.

/// Sweeps recorded per step before any submission has been collected.
pub(crate) const FIRST_GUESS: u32 = 4;

/// The recorded-sweeps rule and the run's tally.
#[derive(Debug, Clone, Default)]
pub struct RecordedSweeps {
    /// A count fixed by the caller (benchmarks, tests) instead of the rule.
    fixed: Option<u32>,
    /// Sweeps recorded per step in each read-back slot's submission.
    per_slot: [u32; 2],
    /// Sweeps recorded and needed, over the steps collected.
    pub recorded: u64,
    pub needed: u64,
}

impl RecordedSweeps {
    /// Fixes the count recorded per step (from the next submission on).
    pub fn fix(&mut self, sweeps: u32) {
        self.fixed = Some(sweeps);
    }

    /// Notes that the submission in `slot` records `sweeps` per step.
    pub fn submitted(&mut self, slot: usize, sweeps: u32) {
        self.per_slot[slot] = sweeps;
    }

    /// Counts the steps of the submission collected from `slot`, which needed `needs`
    /// sweeps each, and returns the count to record from the next submission on.
    pub fn collected(&mut self, slot: usize, needs: &[u32]) -> u32 {
        self.recorded += self.per_slot[slot] as u64 * needs.len() as u64;
        self.needed += needs.iter().map(|&n| n as u64).sum::<u64>();
        self.fixed.unwrap_or_else(|| rule(needs))
    }
}

/// The count that covers three steps in four of `needs`, at most 1.25 times their mean plus
/// one ([`FIRST_GUESS`] without steps).
fn rule(needs: &[u32]) -> u32 {
    if needs.is_empty() {
        return FIRST_GUESS;
    }
    let mut sorted = needs.to_vec();
    sorted.sort_unstable();
    let covering = sorted[(3 * sorted.len()).div_ceil(4) - 1];
    let mean = needs.iter().map(|&n| n as f64).sum::<f64>() / needs.len() as f64;
    covering.min((1.25 * mean + 1.0).floor() as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rule_covers_three_steps_in_four_within_its_cap() {
        assert_eq!(rule(&[]), FIRST_GUESS);
        assert_eq!(rule(&[5; 8]), 5);
        // three in four need at most 6; the mean (6.25) caps it at 8
        assert_eq!(rule(&[6, 6, 6, 6, 6, 6, 7, 7]), 6);
        // a few steps that need many do not set it: the mean caps it
        assert_eq!(rule(&[2, 2, 2, 2, 2, 2, 40, 40]), 2);
        let needs = [4, 30, 30, 30];
        let mean = 23.5;
        assert_eq!(rule(&needs), 30.min((1.25 * mean + 1.0) as u32));
        assert_eq!(rule(&[0, 0, 0, 0]), 0);
    }

    #[test]
    fn the_tally_counts_each_submission_at_its_own_count() {
        let mut r = RecordedSweeps::default();
        r.submitted(0, 4);
        r.submitted(1, 6);
        assert_eq!(r.collected(0, &[3, 5]), 5);
        assert_eq!(r.collected(1, &[6, 6, 6]), 6);
        assert_eq!((r.recorded, r.needed), (2 * 4 + 3 * 6, 8 + 18));
        r.fix(1);
        assert_eq!(r.collected(0, &[9]), 1);
    }
}
