//! The corner forces of chosen corners, read back with the nodal forces
//! (`shaders/corner_select.wgsl`, CPU twin [`crate::kernels::corner_select`]): what a rank of
//! a decomposed run on its own GPU needs of its corners to sum the nodes it shares with its
//! neighbours in the order of the global corners (`domain::forces`).

use super::buffer::{submit_and_read_parts, Storage};
use super::engine::{at_least_one, bytes_of, GpuKernels};
use super::kernel::Launch;
use crate::error::{ImpactError, Result};
use crate::material::damage::Dissipation;

/// A fixed list of corners of a [`GpuKernels`]' mesh and the launch that packs their forces.
pub struct CornerSelection {
    /// Kept alive for the launch's bindings.
    _slots: Storage,
    chosen: Storage,
    launch: Launch,
    count: usize,
}

impl CornerSelection {
    /// The corners `corners` of `k`'s mesh, by corner id (the twin's slot of
    /// [`crate::element::CornerLayout`]).
    pub fn new(k: &GpuKernels, corners: &[u32]) -> Result<Self> {
        let total = k.layout.count();
        if let Some(&c) = corners.iter().find(|&&c| c as usize >= total) {
            return Err(ImpactError::Gpu(format!(
                "corner {c} chosen from a mesh of {total} corners"
            )));
        }
        let slots: Vec<u32> = (corners.iter())
            .map(|&c| k.layout.to_device(c as usize) as u32)
            .collect();
        let ctx = &k.ctx;
        let slots = Storage::with_data(ctx, "chosen_slots", &at_least_one(slots))?;
        let chosen = Storage::new(ctx, "chosen_corners", bytes_of::<f32>(3 * corners.len()))?;
        let launch = k.kernels.corner_select.launch(
            ctx,
            corners.len() as u32,
            total as u32,
            0,
            &slots.buffer,
            &k.corners.buffer,
            &chosen.buffer,
        );
        Ok(CornerSelection {
            _slots: slots,
            chosen,
            launch,
            count: corners.len(),
        })
    }

    /// Corners chosen.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The packed forces of the chosen corners (3 floats each).
    pub(super) fn chosen_buffer(&self) -> &wgpu::Buffer {
        &self.chosen.buffer
    }

    /// Dispatches the selection on `k`'s corner forces in an open pass.
    pub(super) fn dispatch(&self, k: &GpuKernels, pass: &mut wgpu::ComputePass) {
        if self.count > 0 {
            (k.kernels.corner_select.0).dispatch(pass, &self.launch);
        }
    }

    /// The kernel alone on `k`'s corner forces as they are (for the twin test).
    pub(super) fn run_alone(&self, k: &mut GpuKernels) -> Result<Vec<[f32; 3]>> {
        if k.fill_nan {
            (self.chosen).fill_nan(&k.ctx, bytes_of::<f32>(3 * self.count));
        }
        let mut enc = k.ctx.encoder("corner_select");
        k.kernels
            .corner_select
            .0
            .record_launch(&mut enc, &self.launch);
        let parts = [(&self.chosen.buffer, self.count)];
        submit_and_read_parts(&k.ctx, &mut k.staging, enc, &parts)
    }
}

impl GpuKernels {
    /// The internal forces at `u` into `f`, as [`crate::backend::Kernels::internal_forces_into`]
    /// gives them, and the forces of `selection`'s corners into `chosen` in f32 as the device
    /// computed them, from one submission and one read-back.
    pub fn internal_forces_selecting(
        &mut self,
        u: &[f64],
        f: &mut [f64],
        selection: &CornerSelection,
        chosen: &mut Vec<[f32; 3]>,
    ) -> Result<()> {
        if let Some((d, _)) = &mut self.damage {
            d.set_step(&self.ctx, 0.0, false);
        }
        self.forces_selecting(u, f, selection, chosen, false)
    }

    /// [`Self::internal_forces_selecting`] for an explicit step: the damage stepped over `dt`
    /// to `u` (from $u - \Delta t\, v$); returns the energy it dissipated, with the fibre
    /// modes' share.
    pub fn step_forces_selecting(
        &mut self,
        (u, v): (&[f64], &[f64]),
        dt: f64,
        f: &mut [f64],
        (selection, chosen): (&CornerSelection, &mut Vec<[f32; 3]>),
    ) -> Result<Dissipation> {
        if self.damage.is_none() {
            return (self.forces_selecting(u, f, selection, chosen, false))
                .map(|_| Dissipation::default());
        }
        self.upload_nodal(true, v)?;
        if let Some((d, _)) = &mut self.damage {
            d.set_step(&self.ctx, dt, true);
        }
        self.forces_selecting(u, f, selection, chosen, true)?;
        let (d, _) = self.damage.as_ref().expect("damage");
        d.read_dissipation(&self.ctx, &mut self.staging)
    }

    /// The forces and the chosen corners at `u`, with the damage's dissipation summed where
    /// `total`.
    fn forces_selecting(
        &mut self,
        u: &[f64],
        f: &mut [f64],
        selection: &CornerSelection,
        chosen: &mut Vec<[f32; 3]>,
        total: bool,
    ) -> Result<()> {
        self.upload_nodal(false, u)?;
        if self.fill_nan {
            let floats = [self.corner_floats(), 3 * self.nodes, 3 * selection.count];
            let buffers = [&self.corners, &self.forces, &selection.chosen];
            for (b, n) in buffers.into_iter().zip(floats) {
                b.fill_nan(&self.ctx, bytes_of::<f32>(n));
            }
        }
        let mut enc = self.ctx.encoder("internal_forces_selecting");
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("internal_forces_selecting"),
                timestamp_writes: None,
            });
            self.dispatch_internal_forces(&mut pass);
            if selection.count > 0 {
                (self.kernels.corner_select.0).dispatch(&mut pass, &selection.launch);
            }
            if let (true, Some((d, _))) = (total, &self.damage) {
                d.dispatch_total(&mut pass);
            }
        }
        let parts = [
            (&self.forces.buffer, 3 * self.nodes),
            (&selection.chosen.buffer, 3 * selection.count),
        ];
        let out: Vec<f32> = submit_and_read_parts(&self.ctx, &mut self.staging, enc, &parts)?;
        let (nodal, corners) = out.split_at(3 * self.nodes);
        for (d, &x) in f.iter_mut().zip(nodal) {
            *d = f64::from(x);
        }
        chosen.clear();
        chosen.extend(corners.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
        Ok(())
    }
}
