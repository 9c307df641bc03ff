//! [`FormTrial`]: which form of the device contact iteration ([`ContactForm`]) the resident
//! step records, chosen by timing the forms on the run's own steps. Every form computes the
//! same bits, so the choice changes the run's speed and nothing else; which is fastest
//! depends on the adapter (one workgroup's latency against many dispatches') and on the
//! contact zone, which changes as bodies come into contact.
//!
//! After the first submission (the pipelines' first use), a round records submissions in
//! each form in turn, twice in the first round and in mirrored order (A B C C B A, so that a
//! drift of the scene's cost over the round weighs on every form alike), once in later
//! rounds, forwards and backwards in turn. A submission's cost per step is the slower of
//! the device's time for its compute pass and the host's time to record it (the two
//! overlap: the host records a submission while the device runs the one before). At the
//! round's end the run takes the cheapest form, unless the one it has is within
//! [`MARGIN`] of it; a form more than [`KEEP_WITHIN`] times the cheapest is not tried
//! again. The next round starts when the run has collected twice the submissions it had
//! at this round's end, so rounds take a share of the run that shrinks as it goes. Without
//! timestamps on the adapter, or with one form, there are no rounds.

use std::collections::{BTreeMap, VecDeque};

use super::ContactForms;
use crate::gpu::resident_step::SubmissionTime;
use crate::gpu::ContactForm;

/// A form this many times the round's cheapest is not tried again.
pub const KEEP_WITHIN: f64 = 1.5;

/// The share by which a form must beat the run's form to replace it (the rounds' noise).
pub const MARGIN: f64 = 0.03;

/// The forms' trial and the run's tally of the steps each form ran.
#[derive(Debug, Clone)]
pub struct FormTrial {
    /// The forms the rounds still time, in the order they take them.
    candidates: Vec<ContactForm>,
    /// The form submissions record outside the rounds.
    current: ContactForm,
    /// The round's submissions still to submit.
    plan: VecDeque<ContactForm>,
    /// Each read-back slot's submission: its form, and whether the round times it.
    per_slot: [(ContactForm, bool); 2],
    /// The round's submissions submitted and not yet collected.
    outstanding: usize,
    /// The round's seconds and steps per form.
    round: BTreeMap<ContactForm, (f64, usize)>,
    /// Submissions collected.
    collected: usize,
    /// The collected submissions after which the next round starts (none: no more rounds).
    next_round: Option<usize>,
    /// Rounds ended.
    pub rounds: usize,
    /// The last round's seconds per step of each form it timed.
    pub last_round: Vec<(ContactForm, f64)>,
    /// Steps each form ran, over the submissions collected.
    pub steps: BTreeMap<ContactForm, u64>,
}

impl FormTrial {
    /// The trial among `candidates` (at least `current`), starting from `current`; with
    /// `timed` submissions (the adapter has timestamps).
    pub fn new(candidates: Vec<ContactForm>, current: ContactForm, timed: bool) -> Self {
        FormTrial {
            next_round: (timed && candidates.len() > 1).then_some(1),
            candidates,
            current,
            plan: VecDeque::new(),
            per_slot: [(current, false); 2],
            outstanding: 0,
            round: BTreeMap::new(),
            collected: 0,
            rounds: 0,
            last_round: Vec::new(),
            steps: BTreeMap::new(),
        }
    }

    /// Records every submission from the next on in `form`: no more rounds (a round under
    /// way ends without a choice; its submissions in flight are counted, not timed).
    pub fn fix(&mut self, form: ContactForm) {
        self.current = form;
        self.plan.clear();
        self.round.clear();
        self.outstanding = 0;
        for slot in &mut self.per_slot {
            slot.1 = false;
        }
        self.next_round = None;
    }

    /// Whether a round is under way or will start (timestamps, more than one form, not
    /// fixed).
    pub fn trialling(&self) -> bool {
        self.next_round.is_some() || !self.plan.is_empty() || self.outstanding > 0
    }

    /// The form the run records outside the rounds (the last round's choice).
    pub fn current(&self) -> ContactForm {
        self.current
    }

    /// The summary's account: the form chosen, the steps each form ran and the rounds.
    pub fn summary(&self) -> ContactForms {
        ContactForms {
            chosen: self.current.name(),
            steps: (self.steps.iter())
                .map(|(form, &n)| (form.name(), n))
                .collect(),
            rounds: self.rounds,
        }
    }

    /// The form of the next submission, which goes to read-back slot `slot`.
    pub fn submitting(&mut self, slot: usize) -> ContactForm {
        let (form, timed) = match self.plan.pop_front() {
            Some(f) => (f, true),
            None => (self.current, false),
        };
        self.outstanding += usize::from(timed);
        self.per_slot[slot] = (form, timed);
        form
    }

    /// Takes what the submission collected from `slot` took.
    pub fn collected(&mut self, slot: usize, time: SubmissionTime) {
        let (form, timed) = self.per_slot[slot];
        *self.steps.entry(form).or_default() += time.steps as u64;
        self.collected += 1;
        if timed {
            self.outstanding -= 1;
            if let Some(per_step) = time.per_step() {
                let r = self.round.entry(form).or_default();
                r.0 += per_step * time.steps as f64;
                r.1 += time.steps;
            }
            if self.outstanding == 0 && self.plan.is_empty() {
                self.end_round();
            }
        }
        if self.next_round == Some(self.collected) {
            self.start_round();
        }
    }

    /// Plans the round's submissions: each candidate twice, in mirrored order, in the first
    /// round; once in later ones, in the candidates' order and reversed in turn (so that a
    /// cost that drifts over a round does not weigh on the same form in every round).
    fn start_round(&mut self) {
        let forward = self.candidates.iter().copied();
        let reversed = self.candidates.iter().rev().copied();
        match self.rounds {
            0 => self.plan.extend(forward.chain(reversed)),
            r if r % 2 == 1 => self.plan.extend(forward),
            _ => self.plan.extend(reversed),
        }
    }

    /// Takes the round's cheapest form (unless the run's is within [`MARGIN`] of it), drops
    /// the forms over [`KEEP_WITHIN`] times it and sets the next round.
    fn end_round(&mut self) {
        let costs: Vec<(ContactForm, f64)> = (std::mem::take(&mut self.round).into_iter())
            .filter(|(_, (_, steps))| *steps > 0)
            .map(|(f, (seconds, steps))| (f, seconds / steps as f64))
            .collect();
        self.rounds += 1;
        if let Some(&(best, cheapest)) = costs.iter().min_by(|a, b| a.1.total_cmp(&b.1)) {
            let own = costs.iter().find(|(f, _)| *f == self.current);
            if own.is_none_or(|&(_, c)| c > cheapest * (1.0 + MARGIN)) {
                self.current = best;
            }
            let current = self.current;
            self.candidates.retain(|f| {
                *f == current || (costs.iter()).any(|(g, c)| g == f && *c <= KEEP_WITHIN * cheapest)
            });
        }
        self.last_round = costs;
        self.next_round = (self.candidates.len() > 1).then_some(2 * self.collected);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ContactForm::{Relax, Staged};

    const ZONE: ContactForm = ContactForm::Zone(256);

    /// Runs `n` submissions of `steps` steps through the trial, one in flight ahead of the
    /// one collected as the resident solver keeps them, each costing `cost(form)` seconds per
    /// step on the device; returns the forms submitted.
    fn run(
        trial: &mut FormTrial,
        n: usize,
        steps: usize,
        cost: impl Fn(ContactForm) -> f64,
    ) -> Vec<ContactForm> {
        let mut forms = vec![trial.submitting(0)];
        for k in 0..n {
            if k + 1 < n {
                forms.push(trial.submitting((k + 1) % 2));
            }
            let form = forms[k];
            let time = SubmissionTime {
                steps,
                device: Some(cost(form) * steps as f64),
                host: 0.0,
            };
            trial.collected(k % 2, time);
        }
        forms
    }

    fn costs(zone: f64, relax: f64, staged: f64) -> impl Fn(ContactForm) -> f64 {
        move |f| match f {
            ContactForm::Zone(_) => zone,
            Relax => relax,
            Staged => staged,
        }
    }

    #[test]
    fn the_first_round_times_each_form_twice_in_mirrored_order_then_takes_the_cheapest() {
        let mut t = FormTrial::new(vec![ZONE, Relax, Staged], ZONE, true);
        let forms = run(&mut t, 10, 10, costs(3.0, 1.0, 1.2));
        // two submissions before the round (the second was in flight when the first came
        // back), the round, one more in flight when it ended, then the choice
        assert_eq!(
            forms,
            [ZONE, ZONE, ZONE, Relax, Staged, Staged, Relax, ZONE, ZONE, Relax]
        );
        assert_eq!(t.rounds, 1);
        assert_eq!(t.current(), Relax);
        // the zone, three times the cheapest, is not tried again
        assert_eq!(t.candidates, [Relax, Staged]);
        assert_eq!(t.last_round, [(ZONE, 3.0), (Relax, 1.0), (Staged, 1.2)]);
        assert_eq!(t.steps[&ZONE], 50);
        assert_eq!(t.steps[&Relax], 30);
        assert_eq!(t.steps[&Staged], 20);
    }

    #[test]
    fn later_rounds_start_at_twice_the_submissions_and_time_each_form_once() {
        let mut t = FormTrial::new(vec![ZONE, Relax, Staged], ZONE, true);
        // the first round ends with the eighth submission collected: the next starts after
        // the sixteenth
        let forms = run(&mut t, 20, 10, costs(1.1, 1.0, 1.2));
        assert_eq!(t.rounds, 2);
        assert_eq!(&forms[9..17], [Relax; 8]);
        assert_eq!(&forms[17..20], [ZONE, Relax, Staged]);
        assert_eq!(t.current(), Relax);
        // the third round, after the fortieth, takes them in reverse order
        let mut t = FormTrial::new(vec![ZONE, Relax, Staged], ZONE, true);
        let forms = run(&mut t, 44, 10, costs(1.1, 1.0, 1.2));
        assert_eq!(t.rounds, 3);
        assert_eq!(&forms[20..41], [Relax; 21]);
        assert_eq!(&forms[41..44], [Staged, Relax, ZONE]);
    }

    #[test]
    fn the_run_keeps_its_form_within_the_margin() {
        let mut t = FormTrial::new(vec![ZONE, Relax], ZONE, true);
        run(&mut t, 8, 10, costs(1.0, 1.0 - MARGIN / 2.0, 2.0));
        assert_eq!(t.rounds, 1);
        assert_eq!(t.current(), ZONE);
        let mut t = FormTrial::new(vec![ZONE, Relax], ZONE, true);
        run(&mut t, 8, 10, costs(1.0, 1.0 - 2.0 * MARGIN, 2.0));
        assert_eq!(t.current(), Relax);
    }

    #[test]
    fn the_host_bounds_a_submission_it_records_slower_than_the_device_runs_it() {
        let time = SubmissionTime {
            steps: 4,
            device: Some(1.0),
            host: 2.0,
        };
        assert_eq!(time.per_step(), Some(0.5));
        let untimed = SubmissionTime {
            device: None,
            ..time
        };
        assert_eq!(untimed.per_step(), None);
    }

    #[test]
    fn no_rounds_without_timestamps_with_one_form_or_once_fixed() {
        let mut t = FormTrial::new(vec![ZONE, Relax, Staged], Relax, false);
        assert!(run(&mut t, 12, 10, costs(0.1, 1.0, 1.0))
            .iter()
            .all(|&f| f == Relax));
        assert_eq!(t.rounds, 0);
        let mut t = FormTrial::new(vec![Staged], Staged, true);
        assert!(run(&mut t, 12, 10, costs(1.0, 1.0, 1.0))
            .iter()
            .all(|&f| f == Staged));
        assert_eq!(t.rounds, 0);
        let mut t = FormTrial::new(vec![ZONE, Relax, Staged], ZONE, true);
        t.fix(Staged);
        assert!(run(&mut t, 12, 10, costs(0.1, 0.1, 1.0))
            .iter()
            .all(|&f| f == Staged));
        assert_eq!(t.rounds, 0);
    }

    #[test]
    fn a_form_fixed_during_a_round_stays() {
        let mut t = FormTrial::new(vec![ZONE, Relax, Staged], ZONE, true);
        // the round starts with the first submission collected; its first timed one is in
        // flight when the caller fixes the form
        assert_eq!(t.submitting(0), ZONE);
        assert_eq!(t.submitting(1), ZONE);
        let time = SubmissionTime {
            steps: 10,
            device: Some(1.0),
            host: 0.0,
        };
        t.collected(0, time);
        assert_eq!(t.submitting(0), ZONE);
        t.fix(Staged);
        t.collected(1, time);
        t.collected(0, time);
        assert_eq!((t.rounds, t.current()), (0, Staged));
        assert!(!t.trialling());
        assert!((0..6).all(|k| t.submitting(k % 2) == Staged));
    }
}
