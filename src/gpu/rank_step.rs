//! A rank's step of a decomposed run on its GPU: [`ResidentStep`] cut in two submissions
//! around the exchange of the shared nodes' corners ([`RankExchange`]).

use super::buffer::{submit_and_read, submit_and_read_parts};
use super::rank_exchange::RankExchange;
use super::rank_surface::{RankSurface, SurfaceState};
use super::resident_step::ResidentStep;
use super::types::Split3;
use crate::error::{ImpactError, Result};

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

    /// Makes the rank take part in the contact iteration on the surfaces:
    /// [`Self::step_front`] reads back the state of the surface nodes it owns (`owned`) and
    /// [`Self::step_forces_with`] takes the velocities of those it holds (`held`), by the
    /// device's node numbers.
    pub fn surface_with(&mut self, owned: &[u32], held: &[u32]) -> Result<()> {
        self.surface = Some(RankSurface::new(&self.k, &self.m.a.buffer, owned, held)?);
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
        let c = s.owned;
        let parts = [
            (&s.bounds.buffer, 1),
            (&s.selected[0].buffer, 6 * c),
            (&s.selected[1].buffer, 3 * c),
            (&s.selected[2].buffer, 3 * c),
        ];
        let k = &mut self.k;
        let out: Vec<f32> = submit_and_read_parts(&k.ctx, &mut k.staging, enc, &parts)?;
        let (speed, rest) = out.split_at(1);
        let (u, rest) = rest.split_at(6 * c);
        let (v, a) = rest.split_at(3 * c);
        let three = |x: &[f32]| x.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        Ok(SurfaceState {
            speed: speed[0].to_bits(),
            u: (u.chunks_exact(6))
                .map(|c| Split3 {
                    hi: [c[0], c[1], c[2]],
                    lo: [c[3], c[4], c[5]],
                })
                .collect(),
            v: three(v),
            a: three(a),
        })
    }

    /// The rest of a rank's step before the exchange, after [`Self::step_front`]: the held
    /// surface nodes take the velocities `v` the iteration gave them, then the drift and the
    /// internal forces; returns the chosen corners' forces (waits for the device).
    pub fn step_forces_with(&mut self, v: &[[f32; 3]]) -> Result<Vec<[f32; 3]>> {
        let Some(s) = &self.surface else {
            return Err(ImpactError::Gpu("step_forces_with: no surface".into()));
        };
        s.write_velocities(&self.k, v)?;
        self.forces_then_select(true)
    }

    /// The first part of a rank's step: the predictor, the rigid planes, the drift and the
    /// internal forces of the rank's elements; returns the chosen corners' forces as the
    /// device computed them (waits for the device).
    pub fn step_forces(&mut self) -> Result<Vec<[f32; 3]>> {
        self.forces_then_select(false)
    }

    /// The predictor and planes (unless `after_front`: the surface nodes' velocities
    /// instead), the drift, the internal forces and the exchanged corners read back.
    fn forces_then_select(&mut self, after_front: bool) -> Result<Vec<[f32; 3]>> {
        let Some(x) = &self.exchange else {
            return Err(ImpactError::Gpu("step_forces: no exchange".into()));
        };
        let mut enc = self.k.ctx.encoder("rank_step_forces");
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("rank_step_forces"),
                timestamp_writes: None,
            });
            match (after_front, &self.surface) {
                (true, Some(s)) => s.dispatch_scatter(&mut pass),
                _ => self.dispatch_front(&mut pass),
            }
            self.dispatch_forces(&mut pass);
            x.dispatch_select(&self.k, &mut pass);
        }
        let count = x.selection.count();
        let source = x.selection.chosen_buffer();
        let k = &mut self.k;
        let out: Vec<f32> = submit_and_read(&k.ctx, &mut k.staging, enc, source, 3 * count)?;
        Ok(out.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
    }

    /// The rest of a rank's step: the shared nodes' `sums` over the gathered forces, the
    /// correctors and the history row; returns the row (waits for the device).
    pub fn step_correct(&mut self, sums: &[[f32; 3]]) -> Result<Vec<f32>> {
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
        }
        let rows = &self.history.rows.buffer;
        let len = self.history.row_len;
        let k = &mut self.k;
        submit_and_read(&k.ctx, &mut k.staging, enc, rows, len)
    }
}
