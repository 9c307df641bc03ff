//! The contact between meshed bodies of ranks resident on their GPUs: every rank works the
//! single GPU's contact iteration on the whole contact surfaces ([`crate::gpu::SurfaceStep`]
//! on the surface model, [`super::surface`]).
//!
//! Each step, after the predictor, every rank reads back the state of the surface nodes it
//! owns (split displacement, velocity, acceleration) and its nodes' fastest speed; one
//! gather gives every rank every surface node's state, and the fastest speed of the model
//! (the single GPU's search reach). Every rank then runs the iteration on the same values,
//! so each gets the single GPU's impulses, velocities and contact results, and its device
//! takes the velocities of the surface nodes it holds, in the same submission as its
//! element forces.

use std::ops::Range;

use super::ranks::Timed;
use super::subdomain::{surface_nodes, Subdomain};
use super::surface::surface_model;
use crate::error::Result;
use crate::gpu::rank_surface::SurfaceState;
use crate::gpu::resident_step::SubmissionTime;
use crate::gpu::types::Split3;
use crate::gpu::{GpuContext, ResidentSetup, SurfaceStep};
use crate::integrate::form_trial::FormTrial;
use crate::integrate::resident::contact_setup;
use crate::model::Model;

/// Values per surface node in the gather: its surface index, u (hi and lo), v and a.
const RECORD: usize = 13;

/// A rank's part in the contact on the surfaces.
pub(super) struct SurfaceContact {
    pub(super) step: SurfaceStep,
    /// The surface index of each surface node the rank owns (in the order its device
    /// reads them back), and of each it holds (in the order it takes their velocities).
    owned: Vec<usize>,
    held: Vec<usize>,
    /// Every rank's count of owned surface nodes (the gather's counts, in values).
    counts: Vec<usize>,
    nodes: usize,
    /// Each interface's pairs.
    pub(super) pairs: Vec<Range<usize>>,
    /// The rank's trial of the iteration's forms, timed on its steps' submissions (no
    /// rounds without timestamps or with one form). Every form gives the same bits, so the
    /// ranks may choose apart.
    pub(super) forms: FormTrial,
}

impl SurfaceContact {
    /// The surfaces of `model` on `ctx`, with the rank's owned and held surface nodes; and
    /// those nodes' local numbers, owned then held, for the rank's device.
    pub(super) fn new(
        model: &Model,
        sub: &Subdomain,
        global: &ResidentSetup,
        ctx: GpuContext,
        ranks: &Timed,
    ) -> Result<(Self, Vec<u32>, Vec<u32>)> {
        let nodes = surface_nodes(model);
        let surfaces = surface_model(model, &nodes);
        let setup = contact_setup(&surfaces)?;
        let (mut owned, mut held) = (Vec::new(), Vec::new());
        let (mut owned_local, mut held_local) = (Vec::new(), Vec::new());
        for (s, &n) in nodes.iter().enumerate() {
            let Ok(l) = sub.nodes.binary_search(&n) else {
                continue;
            };
            if sub.owned[l] {
                owned.push(s);
                owned_local.push(l as u32);
            }
            held.push(s);
            held_local.push(l as u32);
        }
        // the collective first: a rank whose device step fails below returns after it, and
        // the ranks agree on the outcome
        let counts = (ranks.talk(|r| r.gather_all(&[owned.len() as f64])).iter())
            .map(|c| RECORD * c[0] as usize)
            .collect();
        let lumped: Vec<_> = nodes.iter().map(|&n| global.lumped[n as usize]).collect();
        let reference = &surfaces.mesh.nodes;
        let consts = (global.dt, global.tolerance, global.max_iterations);
        let timed = ctx.has_timestamps();
        let step = SurfaceStep::new(ctx, (reference, &lumped), &setup, consts)?;
        let contact = SurfaceContact {
            forms: FormTrial::new(step.forms(), step.form(), timed),
            step,
            owned,
            held,
            counts,
            nodes: nodes.len(),
            pairs: setup.interfaces.clone(),
        };
        Ok((contact, owned_local, held_local))
    }

    /// Gives the surface step every surface node's state from the rank's owned surface
    /// nodes' (`mine`, as its device read them back) and the other ranks': its iteration
    /// then runs in the rank's submission (`ResidentStep::step_surface_forces`).
    pub(super) fn gather(&mut self, talk: &Timed, mine: &SurfaceState) -> Result<()> {
        let speed = talk.talk(|r| r.max(f64::from(f32::from_bits(mine.speed))));
        let mut records = Vec::with_capacity(RECORD * self.owned.len());
        for (j, &s) in self.owned.iter().enumerate() {
            records.push(s as f64);
            let u = &mine.u[j];
            records.extend(u.hi.iter().chain(&u.lo).map(|&x| f64::from(x)));
            records.extend(mine.v[j].iter().chain(&mine.a[j]).map(|&x| f64::from(x)));
        }
        let mut all = vec![0.0; self.counts.iter().sum()];
        talk.talk(|r| r.all_gather(&records, &self.counts, &mut all));
        let n = self.nodes;
        let mut state = SurfaceState {
            speed: (speed as f32).to_bits(),
            u: vec![Split3::default(); n],
            v: vec![[0.0; 3]; n],
            a: vec![[0.0; 3]; n],
        };
        for r in all.chunks_exact(RECORD) {
            let s = r[0] as usize;
            let f = |k: usize| r[k] as f32;
            state.u[s] = Split3 {
                hi: [f(1), f(2), f(3)],
                lo: [f(4), f(5), f(6)],
            };
            state.v[s] = [f(7), f(8), f(9)];
            state.a[s] = [f(10), f(11), f(12)];
        }
        self.step.take_state(&state)
    }

    /// Records the next step's iteration in the form the trial gives it.
    pub(super) fn submitting(&mut self) {
        let form = self.forms.submitting(0);
        self.step.set_form(form);
    }

    /// Takes the device's seconds for the step's submission (none without timestamps) and
    /// the host's to record it.
    pub(super) fn collected(&mut self, device: Option<f64>, host: f64) {
        let time = SubmissionTime {
            steps: 1,
            // the rank records a submission, then waits for it: the two add up
            device: device.map(|d| d + host),
            host: 0.0,
        };
        self.forms.collected(0, time);
    }

    /// Each held surface node's place in the surface model (the order the rank's device
    /// numbers them in [`Self::new`]'s held list).
    pub(super) fn held_places(&self) -> Vec<u32> {
        self.held.iter().map(|&s| s as u32).collect()
    }
}
