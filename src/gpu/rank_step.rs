//! A rank's step of a decomposed run on its GPU: [`ResidentStep`] cut in two submissions
//! around the exchange of the shared nodes' corners ([`RankExchange`]).

use super::buffer::{submit_and_read, submit_and_read_parts};
use super::engine::GpuKernels;
use super::rank_exchange::RankExchange;
use super::rank_surface::{RankSurface, SurfaceState};
use super::resident_step::ResidentStep;
use super::surface_step::SurfaceStep;
use crate::error::{ImpactError, Result};

/// What [`ResidentStep::step_surface_forces`] reads back.
pub struct SurfaceForces {
    /// The interfaces' history columns of the step.
    pub row: Vec<f32>,
    /// The exchanged corners' forces.
    pub corners: Vec<[f32; 3]>,
    /// The device's seconds for the submission's pass (none without timestamps).
    pub device: Option<f64>,
    /// The host's seconds to record the submission.
    pub host: f64,
}

impl ResidentStep {
    /// Makes the step a rank's of a decomposed run: [`Self::step_forces`] reads back the
    /// corners `chosen` (by corner id) and [`Self::step_correct`] takes the sums of the nodes
    /// `shared_nodes`. The contact iteration between meshed bodies is not taken (its
    /// sweeps would need the other ranks' surfaces).
    pub fn exchange_with(&mut self, chosen: &[u32], shared_nodes: &[u32]) -> Result<()> {
        if self.contact.is_some() {
            return Err(ImpactError::Gpu(
                "a rank's resident step takes rigid planes alone as contact".into(),
            ));
        }
        self.exchange = Some(RankExchange::new(&self.k, chosen, shared_nodes)?);
        Ok(())
    }

    /// Makes the rank take part in the contact iteration on the surfaces, `surface` on
    /// this step's device: [`Self::step_front`] reads back the state of the surface nodes it
    /// owns (`owned`) and [`Self::step_surface_forces`] takes the velocities of those it
    /// holds (`held`), by the device's node numbers, from their `places` in `surface`.
    pub fn surface_with(
        &mut self,
        (owned, held): (&[u32], &[u32]),
        surface: &SurfaceStep,
        places: &[u32],
    ) -> Result<()> {
        let v = surface.velocity_buffer();
        let s = RankSurface::new(&self.k, &self.m.a.buffer, (owned, held), (v, places))?;
        self.surface = Some(s);
        Ok(())
    }

    /// The predictor of a rank's step, and the state of its owned surface nodes after it
    /// with its nodes' fastest speed (waits for the device).
    pub fn step_front(&mut self) -> Result<SurfaceState> {
        let Some(s) = &self.surface else {
            return Err(ImpactError::Gpu("step_front: no surface".into()));
        };
        let mut enc = self.k.ctx.encoder("rank_step_front");
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("rank_step_front"),
                timestamp_writes: None,
            });
            self.dispatch_front(&mut pass);
            s.dispatch_select(&mut pass);
        }
        let parts = s.state_parts();
        let k = &mut self.k;
        let out: Vec<f32> = submit_and_read_parts(&k.ctx, &mut k.staging, enc, &parts)?;
        Ok(s.state_of(&out))
    }

    /// The rest of a rank's step before the exchange, after [`Self::step_front`] and the
    /// surface step's [`SurfaceStep::take_state`]: the surface step's contact iteration, the
    /// held surface nodes' velocities taken from it, then the drift and the internal forces,
    /// in one submission; returns the interfaces' history columns (counted by the surface
    /// step), the chosen corners' forces, and the device's seconds for the submission's
    /// pass where the device has timestamps, which the rank's trial of the iteration's
    /// forms compares (waits for the device).
    pub fn step_surface_forces(&mut self, surface: &mut SurfaceStep) -> Result<SurfaceForces> {
        let Some(s) = &self.surface else {
            return Err(ImpactError::Gpu("step_surface_forces: no surface".into()));
        };
        let recording = std::time::Instant::now();
        let enc = self.forces_encoder(true, |pass| {
            surface.dispatch(pass);
            s.dispatch_scatter(pass);
        })?;
        let host = recording.elapsed().as_secs_f64();
        let Some(x) = &self.exchange else {
            return Err(ImpactError::Gpu("step_forces: no exchange".into()));
        };
        let row = surface.row_part();
        let stamps = self.clock.as_ref().map(|c| c.first_slot());
        let parts: Vec<_> = [Some(row), stamps].into_iter().flatten().collect();
        let (head, corners) = read_with_corners(&mut self.k, x, enc, &parts)?;
        let (row, stamps) = head.split_at(row.1);
        let words: Vec<u32> = stamps.iter().map(|w| w.to_bits()).collect();
        let device = (self.clock.as_ref()).and_then(|c| c.seconds(&words));
        surface.tally(row);
        Ok(SurfaceForces {
            row: row.to_vec(),
            corners,
            device,
            host,
        })
    }

    /// The first part of a rank's step: the predictor, the rigid planes, the drift and the
    /// internal forces of the rank's elements; returns the chosen corners' forces as the
    /// device computed them (waits for the device).
    pub fn step_forces(&mut self) -> Result<Vec<[f32; 3]>> {
        let enc = self.forces_encoder(false, |pass| self.dispatch_front(pass))?;
        let Some(x) = &self.exchange else {
            return Err(ImpactError::Gpu("step_forces: no exchange".into()));
        };
        Ok(read_with_corners(&mut self.k, x, enc, &[])?.1)
    }

    /// An encoder with what `first` records, then the drift, the internal forces and the
    /// exchanged corners' packing, in one compute pass; `timed`, with the step's clock's
    /// timestamps (slot 0) at the pass's start and end, resolved after it.
    fn forces_encoder(
        &self,
        timed: bool,
        first: impl FnOnce(&mut wgpu::ComputePass),
    ) -> Result<wgpu::CommandEncoder> {
        if self.exchange.is_none() {
            return Err(ImpactError::Gpu("step_forces: no exchange".into()));
        }
        let clock = self.clock.as_ref().filter(|_| timed);
        let mut enc = self.k.ctx.encoder("rank_step_forces");
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("rank_step_forces"),
                timestamp_writes: clock.map(|c| c.writes(0)),
            });
            first(&mut pass);
            self.dispatch_forces_select(&mut pass);
        }
        if let Some(c) = clock {
            c.resolve(&mut enc, 0);
        }
        Ok(enc)
    }

    /// Dispatches the drift, the internal forces and the exchanged corners' packing.
    fn dispatch_forces_select(&self, pass: &mut wgpu::ComputePass) {
        self.dispatch_forces(pass);
        if let Some(x) = &self.exchange {
            x.dispatch_select(&self.k, pass);
        }
    }

    /// The rest of a rank's step: the shared nodes' `sums` over the gathered forces, the
    /// correctors and the history row; returns the row (waits for the device).
    pub fn step_correct(&mut self, sums: &[[f32; 3]]) -> Result<Vec<f32>> {
        let enc = self.correct_encoder(sums, |_, _| {})?;
        let rows = &self.history.rows.buffer;
        let len = self.history.row_len;
        let k = &mut self.k;
        submit_and_read(&k.ctx, &mut k.staging, enc, rows, len)
    }

    /// [`Self::step_correct`], then in the same submission the next step's
    /// [`Self::step_forces`] (rigid planes as the only contacts): returns the row and the
    /// next step's chosen corners (one wait for the device where there were two). The
    /// caller reads no state between the two steps: the device is then past the
    /// predictor of the next one.
    pub fn step_correct_then_forces(
        &mut self,
        sums: &[[f32; 3]],
    ) -> Result<(Vec<f32>, Vec<[f32; 3]>)> {
        let enc = self.correct_encoder(sums, |step, pass| {
            step.dispatch_front(pass);
            step.dispatch_forces_select(pass);
        })?;
        let Some(x) = &self.exchange else {
            return Err(ImpactError::Gpu("step_correct: no exchange".into()));
        };
        let row = (&self.history.rows.buffer, self.history.row_len);
        read_with_corners(&mut self.k, x, enc, &[row])
    }

    /// [`Self::step_correct`], then in the same submission the next step's
    /// [`Self::step_front`] (contact on the surfaces): returns the row and the next step's
    /// surface state (one wait for the device where there were two). The caller reads no
    /// state between the two steps.
    pub fn step_correct_then_front(
        &mut self,
        sums: &[[f32; 3]],
    ) -> Result<(Vec<f32>, SurfaceState)> {
        let enc = self.correct_encoder(sums, |step, pass| {
            step.dispatch_front(pass);
            if let Some(s) = &step.surface {
                s.dispatch_select(pass);
            }
        })?;
        let Some(s) = &self.surface else {
            return Err(ImpactError::Gpu(
                "step_correct_then_front: no surface".into(),
            ));
        };
        let len = self.history.row_len;
        let [a, b, c, d] = s.state_parts();
        let parts = [(&self.history.rows.buffer, len), a, b, c, d];
        let k = &mut self.k;
        let out: Vec<f32> = submit_and_read_parts(&k.ctx, &mut k.staging, enc, &parts)?;
        let (row, state) = out.split_at(len);
        Ok((row.to_vec(), s.state_of(state)))
    }

    /// An encoder with the shared nodes' `sums` written over the gathered forces, the
    /// correctors and the history row, and then whatever `next` records, in one compute pass.
    fn correct_encoder(
        &self,
        sums: &[[f32; 3]],
        next: impl FnOnce(&Self, &mut wgpu::ComputePass),
    ) -> Result<wgpu::CommandEncoder> {
        let Some(x) = &self.exchange else {
            return Err(ImpactError::Gpu("step_correct: no exchange".into()));
        };
        x.write_sums(&self.k, sums)?;
        let mut enc = self.k.ctx.encoder("rank_step_correct");
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("rank_step_correct"),
                timestamp_writes: None,
            });
            x.dispatch_sums(&mut pass);
            self.dispatch_row(&mut pass, 0);
            next(self, &mut pass);
        }
        Ok(enc)
    }
}

/// Submits `enc` on `k`'s device and reads back `head` (the parts in turn), then the corners
/// `x` exchanges (one wait for the device).
fn read_with_corners(
    k: &mut GpuKernels,
    x: &RankExchange,
    enc: wgpu::CommandEncoder,
    head: &[(&wgpu::Buffer, usize)],
) -> Result<(Vec<f32>, Vec<[f32; 3]>)> {
    let corners = (x.selection.chosen_buffer(), 3 * x.selection.count());
    let parts: Vec<_> = head.iter().copied().chain([corners]).collect();
    let len = head.iter().map(|p| p.1).sum();
    let out: Vec<f32> = submit_and_read_parts(&k.ctx, &mut k.staging, enc, &parts)?;
    let (head, corners) = out.split_at(len);
    let corners = corners.chunks_exact(3).map(|c| [c[0], c[1], c[2]]);
    Ok((head.to_vec(), corners.collect()))
}
