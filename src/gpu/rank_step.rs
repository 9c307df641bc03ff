//! A rank's step of a decomposed run on its GPU: [`ResidentStep`] cut in two submissions
//! around the exchange of the shared nodes' corners ([`RankExchange`]).

use super::buffer::submit_and_read;
use super::rank_exchange::RankExchange;
use super::resident_step::ResidentStep;
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

    /// The first part of a rank's step: the predictor, the rigid planes, the drift and the
    /// internal forces of the rank's elements; returns the chosen corners' forces as the
    /// device computed them (waits for the device).
    pub fn step_forces(&mut self) -> Result<Vec<[f32; 3]>> {
        let Some(x) = &self.exchange else {
            return Err(ImpactError::Gpu("step_forces: no exchange".into()));
        };
        let mut enc = self.k.ctx.encoder("rank_step_forces");
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("rank_step_forces"),
                timestamp_writes: None,
            });
            self.dispatch_front(&mut pass);
            self.dispatch_forces(&mut pass);
            x.dispatch_select(&self.k, &mut pass);
        }
        let count = x.selection.count();
        let source = x.selection.chosen_buffer().clone();
        let k = &mut self.k;
        let out: Vec<f32> = submit_and_read(&k.ctx, &mut k.staging, enc, &source, 3 * count)?;
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
        let rows = self.history.rows.buffer.clone();
        let len = self.history.row_len;
        let k = &mut self.k;
        submit_and_read(&k.ctx, &mut k.staging, enc, &rows, len)
    }
}
