//! Steps that hold a contact event (an impact, a release, the arrival of a wave) are taken
//! again in sub-steps, so that the event is resolved in time.

use crate::error::Result;
use crate::geometry::vector;
use crate::linalg::assemble;

use super::super::state::StepReport;
use super::interface::InterfaceState;
use super::{ImplicitSolver, Snapshot, EVENT_FORCE_FLOOR};

impl ImplicitSolver<'_> {
    /// Whether the step just taken holds a contact event on some interface (`before`: the
    /// interfaces as the step found them).
    /// With F0, F1 its normal force before and after, m = max(F0, F1) and
    /// r = `event_force_change`, an event is either
    /// - a change of the contact state: the nodes that came into contact or left it carry
    ///   more than r m (an impact, a release), or
    /// - a ramp: |F1 - F0| > r m, in the same direction as the step before (the arrival of
    ///   a loading or unloading wave; a force that alternates from step to step, as in a
    ///   stiff body rattling on its support, is not a ramp).
    ///
    /// Forces below [`EVENT_FORCE_FLOOR`] of the interface's peak make no event.
    pub(super) fn contact_event(&self, before: &[InterfaceState]) -> bool {
        let r = self.settings.event_force_change;
        let model = self.model;
        model
            .interfaces
            .iter()
            .zip(self.contact.interfaces.iter().zip(before))
            .any(|(itf, (st, old))| {
                let (f0, f1) = (old.report.normal_force, st.report.normal_force);
                let m = f0.max(f1);
                // no node pressed at the step's start or end: a release inside the last
                // step's sub-steps left an average F0 > 0, but nothing happens in this one
                let pressed = old.lambda.iter().chain(&st.lambda).any(|&l| l > 0.0);
                if !pressed || m <= 0.0 || m < EVENT_FORCE_FLOOR * st.peak_force {
                    return false;
                }
                let switched: f64 = itf
                    .area
                    .iter()
                    .zip(old.lambda.iter().zip(&st.lambda))
                    .filter(|(_, (&l0, &l1))| (l0 > 0.0) != (l1 > 0.0))
                    .map(|(a, (&l0, &l1))| a * l0.max(l1))
                    .sum();
                let d = f1 - f0;
                switched > r * m || (d.abs() > r * m && d * old.last_change > 0.0)
            })
    }

    /// Takes the step again from `saved` in k sub-steps of dt / k and reports each interface's
    /// impulse over the whole step / dt (the other report fields are the last sub-step's).
    pub(super) fn substeps(&mut self, saved: Snapshot, k: usize) -> Result<StepReport> {
        // The penalties adapt to the compliance, which depends on the step: a pressure's
        // effect on the gap rate grows with the step where inertia resists (s ~ h) and
        // shrinks where stiffness does (s ~ 1/h), so no fixed rescaling is right. The
        // sub-steps start from the full step's penalties at the first event and from their
        // own last values after it; eq. 20 adapts them. The steps of dt keep their own.
        let full = self.contact.penalties();
        // the penalty law's counters: the first attempt's changes, then the sub-steps'
        let counts: Vec<[usize; 4]> = self
            .contact
            .interfaces
            .iter()
            .zip(&saved.interfaces)
            .map(|(st, old)| {
                let (now, before) = (st.penalty_counts(), old.penalty_counts());
                [0, 1, 2, 3].map(|i| now[i] - before[i])
            })
            .collect();
        self.u = saved.u;
        self.v = saved.v;
        self.a = saved.a;
        self.contact.interfaces = saved.interfaces;
        self.spins = saved.spins;
        self.load_work = saved.load_work;
        self.clock = self.time;
        for st in &mut self.contact.interfaces {
            if let Some(p) = st.sub_penalties {
                st.set_penalties(p);
            }
        }
        let h = self.dt / k as f64;
        if self.sub_solver.is_none() {
            let asm = assemble(
                self.model,
                self.settings.mass,
                1.0 / (self.settings.beta * h * h),
            );
            self.sub_solver = Some(self.solver.sibling(&asm.effective)?);
        }
        let kf = k as f64;
        let mut total = StepReport {
            iterations: 0,
            converged: true,
        };
        // impulses of the sub-steps, normal, tangential and as the force on the model's
        // side, and each node's
        let mut sums = vec![(0.0, [0.0; 3], [0.0; 3]); self.contact.interfaces.len()];
        for st in &mut self.contact.interfaces {
            st.step_pressure = vec![0.0; st.lambda.len()];
        }
        for _ in 0..k {
            let r = self.advance(h, true)?;
            total.iterations += r.iterations;
            total.converged &= r.converged;
            for (sum, st) in sums.iter_mut().zip(&mut self.contact.interfaces) {
                for (p, l) in st.step_pressure.iter_mut().zip(&st.lambda) {
                    *p += l / kf;
                }
                sum.0 += st.report.normal_force;
                for a in 0..3 {
                    sum.1[a] += st.tangential[a];
                    sum.2[a] += st.report.force[a];
                }
            }
        }
        for (((sum, st), p), c) in sums
            .iter()
            .zip(&mut self.contact.interfaces)
            .zip(full)
            .zip(counts)
        {
            st.sub_penalties = Some(st.penalties());
            st.set_penalties(p);
            let now = st.penalty_counts();
            st.set_penalty_counts([0, 1, 2, 3].map(|i| now[i] + c[i]));
            st.report.normal_force = sum.0 / kf;
            st.tangential = sum.1.map(|x| x / kf);
            st.report.force = sum.2.map(|x| x / kf);
            st.report.tangential_force = vector::norm(st.tangential);
        }
        self.event_steps += 1;
        Ok(total)
    }
}
