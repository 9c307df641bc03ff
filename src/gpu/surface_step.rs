//! [`SurfaceStep`]: the contact iteration of an explicit step on the contact surfaces
//! alone, on a device of its own state: the surface model of a decomposed run
//! (`domain::surface`), which every rank holds whole. Each step it takes the surface nodes'
//! state after the predictor (gathered from their owners) and the model's fastest speed,
//! runs the single GPU's iteration ([`ImpulseSweeps`]) and its report, and reduces the
//! interfaces' history columns as the single GPU's step does, in a rank's submission on the
//! same device: the rank takes the velocities of its surface nodes from it there.

use super::buffer::{read_back, Storage};
use super::contact_form::ContactForm;
use super::context::GpuContext;
use super::engine::{at_least_one, bytes_of};
use super::impulse_sweeps::{ContactSetup, ImpulseSweeps, StepBuffers};
use super::kernel::Launch;
use super::rank_surface::SurfaceState;
use super::resident_step::{pair_slots, row_columns};
use super::types::{self, to_device, Split3, WORKGROUP};
use super::HistoryReduce;
use crate::error::{ImpactError, Result};
use crate::kernels::plane_contact::{slot, SLOT};
use crate::kernels::{LumpedNode, SearchMode};

pub struct SurfaceStep {
    ctx: GpuContext,
    nodes: usize,
    u: Storage,
    v: Storage,
    a: Storage,
    step: wgpu::Buffer,
    step_consts: types::Step,
    contact: ImpulseSweeps,
    reduce: HistoryReduce,
    reduce_launch: Launch,
    row: Storage,
    row_len: usize,
    staging: Storage,
    /// Sweeps recorded as dispatches of their own (the last step's need and two more; the
    /// results do not depend on it).
    sweeps: u32,
    /// The run's tally: sweeps recorded and needed, and the search's sorts of the faces.
    pub recorded: u64,
    pub needed: u64,
    pub sorts: u64,
    // kept alive for the bindings
    _buffers: Vec<Storage>,
}

impl SurfaceStep {
    /// The surface model's nodes (`reference`, `lumped`, in its node order) and contact
    /// (`setup`), with the step's `dt`, tolerance and sweep limit.
    pub fn new(
        ctx: GpuContext,
        (reference, lumped): (&[[f64; 3]], &[LumpedNode]),
        setup: &ContactSetup,
        (dt, tolerance, max_iterations): (f64, f64, u32),
    ) -> Result<Self> {
        let nodes = reference.len();
        let split: Vec<Split3> = reference.iter().map(|&x| Split3::split(x)).collect();
        let reference = Storage::with_data(&ctx, "surface.reference", &at_least_one(split))?;
        let u = Storage::new(&ctx, "surface.displacement", bytes_of::<Split3>(nodes))?;
        let v = Storage::new(&ctx, "surface.velocity", bytes_of::<f32>(3 * nodes))?;
        let a = Storage::new(&ctx, "surface.acceleration", bytes_of::<f32>(3 * nodes))?;
        let lumped: Vec<types::Lumped> = to_device(lumped);
        let lumped = Storage::with_data(&ctx, "surface.lumped", &at_least_one(lumped))?;
        let step_consts = types::Step {
            dt: dt as f32,
            tolerance: tolerance as f32,
            max_iterations,
            pad: 0,
        };
        let step = Storage::with_usage(
            &ctx,
            "surface.step",
            std::mem::size_of::<types::Step>() as u64,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        )?
        .buffer;
        ctx.queue
            .write_buffer(&step, 0, bytemuck::bytes_of(&step_consts));
        let buffers = StepBuffers {
            step: &step,
            reference: &reference.buffer,
            displacement: &u.buffer,
            velocity: &v.buffer,
            acceleration: &a.buffer,
            lumped: &lumped.buffer,
        };
        // the rank's run times the forms (`ResidentStep::step_surface_forces`)
        let contact = ImpulseSweeps::new(&ctx, &buffers, setup, (nodes, max_iterations), true)?;
        // the interfaces' columns of the history row, as the single GPU's step reduces them
        let columns = row_columns(&[], &pair_slots(&setup.interfaces), &[]);
        let row_len = columns.len();
        let cols: Vec<types::GpuReduceColumn> = to_device(&columns);
        let columns = Storage::with_data(&ctx, "surface.columns", &at_least_one(cols))?;
        let row = Storage::new(&ctx, "surface.row", bytes_of::<f32>(row_len))?;
        let none = Storage::new(&ctx, "surface.partials", 64)?;
        let reduce = HistoryReduce::new(&ctx);
        let mut reduce_launch = reduce.launch(
            &ctx,
            row_len as u32 * WORKGROUP,
            0,
            0,
            &columns.buffer,
            &none.buffer,
            contact.results_buffer(),
            &u.buffer,
            &v.buffer,
            &none.buffer,
            &none.buffer,
            &row.buffer,
        );
        reduce_launch.set_count(&ctx, row_len as u32, 0);
        let staging = super::buffer::staging(&ctx)?;
        Ok(SurfaceStep {
            nodes,
            u,
            v,
            a,
            step,
            step_consts,
            contact,
            reduce,
            reduce_launch,
            row,
            row_len,
            staging,
            sweeps: max_iterations.min(8),
            recorded: 0,
            needed: 0,
            sorts: 0,
            _buffers: vec![reference, lumped, columns, none],
            ctx,
        })
    }

    /// Takes the surface nodes' state after the predictor (`state`, in the surface model's
    /// node order, with the model's fastest speed) for the next [`Self::dispatch`].
    pub fn take_state(&mut self, state: &SurfaceState) -> Result<()> {
        let n = self.nodes;
        if state.u.len() != n || state.v.len() != n || state.a.len() != n {
            return Err(ImpactError::Gpu(format!(
                "the state of {} surface nodes for {n}",
                state.u.len()
            )));
        }
        let q = &self.ctx.queue;
        q.write_buffer(&self.u.buffer, 0, bytemuck::cast_slice(&state.u));
        q.write_buffer(&self.v.buffer, 0, bytemuck::cast_slice(&state.v));
        q.write_buffer(&self.a.buffer, 0, bytemuck::cast_slice(&state.a));
        self.contact.set_speed_floor(&self.ctx, state.speed);
        Ok(())
    }

    /// Dispatches the step's contact iteration with its report and the interfaces' history
    /// columns, after [`Self::take_state`]; the surface nodes' velocities are then in
    /// [`Self::velocity_buffer`] and the columns in [`Self::row_part`].
    pub fn dispatch(&self, pass: &mut wgpu::ComputePass) {
        self.contact.dispatch(pass, self.sweeps, SearchMode::First);
        self.reduce.0.dispatch(pass, &self.reduce_launch);
    }

    /// The surface nodes' velocities (3 per node, in the surface model's order).
    pub fn velocity_buffer(&self) -> &wgpu::Buffer {
        &self.v.buffer
    }

    /// Whether the iteration runs in one workgroup ([`ImpulseSweeps::set_zone`]).
    pub fn runs_zone(&self) -> bool {
        self.contact.runs_zone()
    }

    /// The form the iteration is recorded in from the next step on.
    pub fn form(&self) -> ContactForm {
        self.contact.form()
    }

    /// Records the iteration in `form` from the next step on, where it runs here
    /// ([`ImpulseSweeps::set_form`]); the results do not depend on it.
    pub fn set_form(&mut self, form: ContactForm) -> ContactForm {
        self.contact.set_form(form)
    }

    /// The forms of the iteration worth timing here ([`ImpulseSweeps::forms`]).
    pub fn forms(&self) -> Vec<ContactForm> {
        self.contact.forms()
    }

    /// The interfaces' history columns of the last [`Self::dispatch`], for a read-back.
    pub fn row_part(&self) -> (&wgpu::Buffer, usize) {
        (&self.row.buffer, self.row_len)
    }

    /// Counts a step whose columns (read back from [`Self::row_part`]) are `row`: the sweeps
    /// recorded and needed, and the next step records the sweeps this one needed (the
    /// largest of the interfaces') and two more (none recorded where the iteration runs in
    /// one workgroup).
    pub fn tally(&mut self, row: &[f32]) {
        let needed = (row.chunks_exact(SLOT))
            .map(|q| q[slot::SWEEPS] as u32)
            .max()
            .unwrap_or(0);
        if !self.contact.runs_zone() {
            self.recorded += u64::from(self.sweeps);
        }
        self.needed += u64::from(needed);
        self.sorts += u64::from(self.contact.search.is_some());
        self.sweeps = (needed + 2).min(self.step_consts.max_iterations);
    }

    /// The contact results ([`SLOT`] per pair) as words: a step's state.
    pub fn read_results(&mut self) -> Result<Vec<u32>> {
        let b = self.contact.results_buffer();
        let words = (b.size() / 4) as usize;
        read_back(&self.ctx, &mut self.staging, "surface_results", b, words)
    }

    /// Writes back what [`Self::read_results`] read.
    pub fn write_results(&self, words: &[u32]) -> Result<()> {
        let b = self.contact.results_buffer();
        if (words.len() * 4) as u64 != b.size() {
            return Err(ImpactError::Gpu(
                "the contact results are of another model".into(),
            ));
        }
        (self.ctx.queue).write_buffer(b, 0, bytemuck::cast_slice(words));
        Ok(())
    }

    /// Whether an interface has a primary surface (the iteration searches).
    pub fn has_search(&self) -> bool {
        self.contact.search.is_some()
    }

    /// Sets the step length from the next step on (a shortened last step).
    pub fn set_dt(&mut self, dt: f64) {
        self.step_consts.dt = dt as f32;
        (self.ctx.queue).write_buffer(&self.step, 0, bytemuck::bytes_of(&self.step_consts));
    }
}
