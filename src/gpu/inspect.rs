//! The read-back and single-stage hooks that tests and benches use to compare device buffers
//! with the CPU twins: a stage or a kernel run alone on inputs the caller uploads
//! ([`ResidentStep::run_stage`], [`GpuKernels::corner_forces`], [`ImpulseSweeps::run`]),
//! the buffers it wrote read back in f64 (`read_*`), and the timings of the benchmarks
//! ([`ResidentStep::time_stage`], [`GpuKernels::time_kernel`], `copy_bandwidth`). The
//! `tests/gpu_*.rs` twin tests and `benches/` call them; the solver never does.

use std::time::{Duration, Instant};

use super::buffer::{
    read_back, read_floats, staging, submit_and_read, submit_and_read_parts, Storage,
};
use super::captured;
use super::context::GpuContext;
use super::corner_select::CornerSelection;
use super::engine::{bytes_of, GpuKernels};
use super::rank_exchange::RankExchange;
use super::rank_surface::RankSurface;
use super::resident_step::{to_f32, ResidentStep};
use super::scan::Scan;
use super::search::GpuSearch;
use super::types;
use super::{FillWords, ImpulseSweeps};
use crate::element::ElementKind;
use crate::error::{ImpactError, Result};
use crate::kernels::plane_contact::SLOT;
use crate::kernels::sweep_control::word;
use crate::kernels::{Constraint, ContactPoint, ReduceColumn, Relaxation, SearchMode, SweepState};

/// One kernel's share of a step on the device ([`ResidentStep::profile_dispatches`]).
#[derive(Debug, Clone, PartialEq)]
pub struct KernelTime {
    pub name: &'static str,
    /// Dispatches per step (a sort every few steps adds a fraction).
    pub dispatches: f64,
    /// Microseconds per step, its dispatches' barriers and launches included.
    pub us: f64,
}

/// Wall time of `enc`'s commands alone: the writes queued before them (a state restored)
/// are submitted and the device left idle first, then they are submitted and waited for.
fn time_submission(ctx: &GpuContext, enc: wgpu::CommandEncoder) -> Result<Duration> {
    let commands = enc.finish();
    ctx.queue.submit([]);
    ctx.wait()?;
    let start = Instant::now();
    ctx.queue.submit([commands]);
    ctx.wait()?;
    Ok(start.elapsed())
}

/// Runs `fill_words` alone on a buffer holding `words` (its first `count` set to `value`)
/// and reads the buffer back.
pub fn run_fill_words(ctx: &GpuContext, words: &[u32], count: u32, value: u32) -> Result<Vec<u32>> {
    let kernel = FillWords::new(ctx);
    let buffer = Storage::with_data(ctx, "fill_words", words)?;
    let launch = kernel.launch(ctx, count, value, 0, &buffer.buffer);
    let mut enc = ctx.encoder("fill_words");
    kernel.0.record_launch(&mut enc, &launch);
    submit_and_read(ctx, &mut staging(ctx)?, enc, &buffer.buffer, words.len())
}

/// Runs the failure survey alone (`failure_survey`, then `failure_reduce` into a row of its
/// own) at the displacement `u` (3 per node) and reads back the workgroups' records and the
/// merged record.
pub fn run_failure_survey(
    ctx: &GpuContext,
    setup: &crate::kernels::SurveySetup,
    u: &[f64],
) -> Result<(Vec<f64>, Vec<f64>)> {
    use super::failure_stage::{FailureStage, StageTarget};
    use crate::kernels::FAILURE_FIELDS;
    let split: Vec<types::Split3> = (u.chunks_exact(3))
        .map(|d| types::Split3::split([d[0], d[1], d[2]]))
        .collect();
    let displacement = Storage::with_data(ctx, "survey.u", &split)?;
    let rows = Storage::new(ctx, "survey.row", (FAILURE_FIELDS * 4) as u64)?;
    let target = StageTarget {
        displacement: &displacement.buffer,
        rows: &rows.buffer,
        row_len: FAILURE_FIELDS,
        column: 0,
        chunk_capacity: 1,
    };
    let stage = FailureStage::new(ctx, setup, &target)?;
    let mut enc = ctx.encoder("failure_survey");
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("failure_survey"),
            timestamp_writes: None,
        });
        stage.dispatch(&mut pass, 0);
    }
    let groups = stage.groups();
    let parts = [
        (stage.partials(), groups * FAILURE_FIELDS),
        (&rows.buffer, FAILURE_FIELDS),
    ];
    let got: Vec<f32> = submit_and_read_parts(ctx, &mut staging(ctx)?, enc, &parts)?;
    let got: Vec<f64> = got.into_iter().map(f64::from).collect();
    let (partials, record) = got.split_at(groups * FAILURE_FIELDS);
    Ok((partials.to_vec(), record.to_vec()))
}

/// What [`run_cohesive`] reads back: each pair's output and state, the corner forces (one
/// per slot) and each interface's reduced values.
pub type CohesiveRun = (
    Vec<crate::kernels::cohesive_pairs::PairOutput>,
    Vec<crate::kernels::cohesive_pairs::PairState>,
    Vec<[f64; 3]>,
    Vec<[f64; crate::kernels::cohesive_reduce::COHESIVE_COLUMNS]>,
);

/// The cohesive stage alone, on its own displacement (`u`, 3 per node) and corner forces
/// (`corners`, one per slot), with the pairs' states `state`: the stage and its two
/// buffers.
fn cohesive_alone(
    ctx: &GpuContext,
    setup: &crate::kernels::cohesive_pairs::CohesiveSetup,
    bonded: &crate::kernels::cohesive_scatter::BondedNodes,
    (u, state, corners): CohesiveInputs,
) -> Result<(super::cohesive_stage::CohesiveStage, [Storage; 2])> {
    use super::cohesive_stage::{CohesiveStage, CohesiveTarget};
    let split: Vec<types::Split3> = (u.chunks_exact(3))
        .map(|d| types::Split3::split([d[0], d[1], d[2]]))
        .collect();
    let displacement = Storage::with_data(ctx, "cohesive.u", &split)?;
    let c = corners.len();
    let columns: Vec<f32> = (0..3 * c).map(|i| corners[i % c][i / c] as f32).collect();
    let corner_forces = Storage::with_data(ctx, "cohesive.corners", &columns)?;
    let target = CohesiveTarget {
        displacement: &displacement.buffer,
        corner_forces: &corner_forces.buffer,
        slots: c as u32,
    };
    let stage = CohesiveStage::new(ctx, setup, bonded, &target)?;
    stage.write_state(ctx, state);
    Ok((stage, [displacement, corner_forces]))
}

/// The inputs of [`run_cohesive`] and [`time_cohesive`]: the displacement (3 per node), the
/// pairs' states and the corner forces (one per slot, the bonded nodes' corners among them).
pub type CohesiveInputs<'a> = (
    &'a [f64],
    &'a [crate::kernels::cohesive_pairs::PairState],
    &'a [[f64; 3]],
);

/// Runs the cohesive stage alone (`cohesive_pairs`, `cohesive_scatter` and
/// `cohesive_reduce` into a row of its own) on `inputs`.
pub fn run_cohesive(
    ctx: &GpuContext,
    setup: &crate::kernels::cohesive_pairs::CohesiveSetup,
    bonded: &crate::kernels::cohesive_scatter::BondedNodes,
    inputs: CohesiveInputs,
) -> Result<CohesiveRun> {
    use crate::kernels::cohesive_reduce::COHESIVE_COLUMNS;
    let (mut stage, [_u, corner_forces]) = cohesive_alone(ctx, setup, bonded, inputs)?;
    let c = inputs.2.len();
    let values = COHESIVE_COLUMNS * setup.interfaces.len();
    let rows = Storage::new(ctx, "cohesive.row", (values * 4) as u64)?;
    stage.reduce_into_rows(ctx, &rows.buffer, (values, 0, 1));
    let mut enc = ctx.encoder("cohesive");
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("cohesive"),
            timestamp_writes: None,
        });
        stage.dispatch(&mut pass);
        stage.dispatch_row(&mut pass, 0);
    }
    let parts = [(&corner_forces.buffer, 3 * c), (&rows.buffer, values)];
    let mut staging = staging(ctx)?;
    let got: Vec<f32> = submit_and_read_parts(ctx, &mut staging, enc, &parts)?;
    let (forces, row) = got.split_at(3 * c);
    let forces = (0..c)
        .map(|s| std::array::from_fn(|a| f64::from(forces[a * c + s])))
        .collect();
    let row = (row.chunks_exact(COHESIVE_COLUMNS))
        .map(|v| std::array::from_fn(|k| f64::from(v[k])))
        .collect();
    let outputs = stage.read_outputs(ctx, &mut staging)?;
    let state = stage.read_state(ctx, &mut staging)?;
    Ok((outputs, state, forces, row))
}

/// Wall time of `reps` steps of the cohesive stage alone (`cohesive_pairs` and
/// `cohesive_scatter`, the state advancing) on `inputs`, in one submission.
pub fn time_cohesive(
    ctx: &GpuContext,
    setup: &crate::kernels::cohesive_pairs::CohesiveSetup,
    bonded: &crate::kernels::cohesive_scatter::BondedNodes,
    inputs: CohesiveInputs,
    reps: usize,
) -> Result<Duration> {
    let (stage, _buffers) = cohesive_alone(ctx, setup, bonded, inputs)?;
    let mut enc = ctx.encoder("timing");
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("timing"),
            timestamp_writes: None,
        });
        for _ in 0..reps {
            stage.dispatch(&mut pass);
        }
    }
    time_submission(ctx, enc)
}

/// Runs the device's prefix sum ([`Scan`]: `scan_totals`, then `prefix_sum`) alone on
/// `values` and reads the starts back (one more than the values), with the block totals.
pub fn run_prefix_sum(ctx: &GpuContext, values: &[u32]) -> Result<(Vec<u32>, Vec<u32>)> {
    let input = Storage::with_data(ctx, "prefix_sum.values", values)?;
    let starts = Storage::new(ctx, "prefix_sum.starts", 4 * (values.len() as u64 + 1))?;
    let scan = Scan::new(ctx, &input.buffer, &starts.buffer, values.len())?;
    let mut enc = ctx.encoder("prefix_sum");
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("prefix_sum"),
            timestamp_writes: None,
        });
        scan.dispatch(&mut pass);
    }
    let got = submit_and_read(
        ctx,
        &mut staging(ctx)?,
        enc,
        &starts.buffer,
        values.len() + 1,
    )?;
    Ok((got, scan.read_totals(ctx)?))
}

impl Scan {
    /// The block totals of the last scan (written where there is more than one block).
    pub fn read_totals(&self, ctx: &GpuContext) -> Result<Vec<u32>> {
        let source = &self.block_totals.buffer;
        read_back(
            ctx,
            &mut staging(ctx)?,
            "scan.totals",
            source,
            self.blocks as usize,
        )
    }
}

/// The kernels of [`GpuKernels`], for timing them one by one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KernelId {
    /// The force kernel of a kind's block.
    Forces(ElementKind),
    NodeGather,
    ContactGap,
    SlipRate,
}

impl GpuKernels {
    /// The device contact search (after the first `contact_search_into`) and the context.
    pub fn search_parts(&mut self) -> Option<(&GpuContext, &mut GpuSearch)> {
        self.search.as_mut().map(|s| (&self.ctx, s))
    }

    /// The device's corner slot of each of the twin's corner ids, in twin order.
    fn slot_of(&self, c: usize) -> usize {
        self.layout.to_device(c)
    }

    /// Records the element kernels (each non-empty block's) that fill the corner forces,
    /// each in a pass of its own.
    fn record_elements(&self, enc: &mut wgpu::CommandEncoder) {
        for (kind, launch) in &self.launches.blocks {
            self.kernels.forces(*kind).record_launch(enc, launch);
        }
    }

    /// Runs the element kernels alone: the corner forces in the twin's order (by corner id,
    /// [`crate::element::CornerLayout`]), for the displacement `u`.
    pub fn corner_forces(&mut self, u: &[f64]) -> Result<Vec<[f64; 3]>> {
        self.upload_nodal(false, u)?;
        if self.fill_nan {
            self.corners
                .fill_nan(&self.ctx, bytes_of::<f32>(self.corner_floats()));
        }
        let mut enc = self.ctx.encoder("element_forces");
        self.record_elements(&mut enc);
        let slots = self.corner_floats() / 3;
        let out: Vec<f32> = submit_and_read(
            &self.ctx,
            &mut self.staging,
            enc,
            &self.corners.buffer,
            3 * slots,
        )?;
        Ok((0..slots)
            .map(|c| {
                let s = self.slot_of(c);
                [0, 1, 2].map(|a| out[a * slots + s] as f64)
            })
            .collect())
    }

    /// Uploads corner forces given in the twin's order into the device's layout.
    pub(super) fn upload_corners(&mut self, corners: &[[f64; 3]]) -> Result<()> {
        let slots = corners.len();
        let mut c = vec![0f32; 3 * slots];
        for (i, f) in corners.iter().enumerate() {
            let s = self.slot_of(i);
            for a in 0..3 {
                c[a * slots + s] = f[a] as f32;
            }
        }
        self.corners.upload(&self.ctx, &c)?;
        Ok(())
    }

    /// Runs `corner_select` alone on the given corner forces (the twin's order).
    pub fn select(
        &mut self,
        corners: &[[f64; 3]],
        selection: &CornerSelection,
    ) -> Result<Vec<[f64; 3]>> {
        self.upload_corners(corners)?;
        let chosen = selection.run_alone(self)?;
        Ok(chosen.into_iter().map(|f| f.map(f64::from)).collect())
    }

    /// Runs `node_scatter` of `exchange` (built on these kernels) alone over the nodal
    /// forces `forces` with the shared nodes' `sums`: every node's forces after it.
    pub fn node_scatter(
        &mut self,
        exchange: &RankExchange,
        forces: &[f64],
        sums: &[[f64; 3]],
    ) -> Result<Vec<f64>> {
        let f: Vec<f32> = forces.iter().map(|&x| x as f32).collect();
        self.forces.upload(&self.ctx, &f)?;
        let sums: Vec<[f32; 3]> = sums.iter().map(|s| s.map(|x| x as f32)).collect();
        let out = exchange.run_alone(self, &sums)?;
        Ok(out.into_iter().map(f64::from).collect())
    }

    /// Runs `node_select` alone (a rank's surface read-back, [`RankSurface`]) on the
    /// displacements `u` and velocities `v`: the packed displacements (hi + lo) and
    /// velocities of the nodes `owned`, in order.
    pub fn node_select(
        &mut self,
        owned: &[u32],
        u: &[f64],
        v: &[f64],
    ) -> Result<(Vec<f64>, Vec<f64>)> {
        self.upload_nodal(false, u)?;
        self.upload_velocity(v)?;
        let none = (&self.forces.buffer, &[][..]);
        let surface = RankSurface::new(self, &self.forces.buffer, (owned, &[]), none)?;
        for s in &surface.selected {
            s.fill_nan(&self.ctx, s.capacity);
        }
        let mut enc = self.ctx.encoder("node_select");
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("node_select"),
                timestamp_writes: None,
            });
            surface.dispatch_select(&mut pass);
        }
        let c = owned.len();
        let parts = [
            (&surface.selected[0].buffer, 6 * c),
            (&surface.selected[1].buffer, 3 * c),
        ];
        let out: Vec<f32> = submit_and_read_parts(&self.ctx, &mut self.staging, enc, &parts)?;
        let (split, vel) = out.split_at(6 * c);
        let u = (split.chunks_exact(6))
            .flat_map(|w| (0..3).map(move |a| f64::from(w[a]) + f64::from(w[3 + a])))
            .collect();
        Ok((u, vel.iter().map(|&x| f64::from(x)).collect()))
    }

    /// Runs `node_gather` alone on the given corner forces (the twin's order).
    pub fn gather(&mut self, corners: &[[f64; 3]]) -> Result<Vec<[f64; 3]>> {
        self.upload_corners(corners)?;
        if self.fill_nan {
            self.forces
                .fill_nan(&self.ctx, bytes_of::<f32>(3 * self.nodes));
        }
        let mut enc = self.ctx.encoder("node_gather");
        let gather = &self.launches.gather;
        self.kernels.node_gather.0.record_launch(&mut enc, gather);
        let out: Vec<[f32; 3]> = submit_and_read(
            &self.ctx,
            &mut self.staging,
            enc,
            &self.forces.buffer,
            self.nodes,
        )?;
        Ok(out.into_iter().map(|f| f.map(f64::from)).collect())
    }

    /// Records `reps` dispatches of one kernel on the current data in one pass, waits, and
    /// returns the elapsed wall time (contact kernels use the last queries).
    pub fn time_kernel(&mut self, kernel: KernelId, reps: usize) -> Result<Duration> {
        let mut enc = self.ctx.encoder("timing");
        let (k, l) = (&self.kernels, &self.launches);
        // the element kernels' launches are fixed; the contact kernels' counts follow the
        // last queries
        let (kernel, bind, grid) = match kernel {
            KernelId::Forces(kind) => {
                let launch = l.block(kind).ok_or_else(|| {
                    ImpactError::Gpu(format!("the mesh has no {kind} elements to time"))
                })?;
                (k.forces(kind), &launch.bind, launch.grid)
            }
            KernelId::NodeGather => (&k.node_gather.0, &l.gather.bind, l.gather.grid),
            KernelId::ContactGap => self.contact_dispatch(true)?,
            KernelId::SlipRate => self.contact_dispatch(false)?,
        };
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("timing"),
                timestamp_writes: None,
            });
            for _ in 0..reps {
                kernel.dispatch_with(&mut pass, bind, grid);
            }
        }
        // the idle wait first also settles earlier work (the params write)
        time_submission(&self.ctx, enc)
    }

    /// Copy bandwidth of the device in bytes per second: a buffer-to-buffer copy of `bytes`
    /// (the reference for the kernels' effective bandwidth).
    pub fn copy_bandwidth(&self, bytes: u64, reps: usize) -> Result<f64> {
        let bytes = bytes.min(self.ctx.max_binding()).next_multiple_of(4);
        let make = |label| {
            self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let (a, b) = (make("copy.a"), make("copy.b"));
        // warm up (first touch allocates on software adapters)
        let mut enc = self.ctx.encoder("copy");
        enc.copy_buffer_to_buffer(&a, 0, &b, 0, bytes);
        self.ctx.submit_and_wait(enc)?;
        let mut enc = self.ctx.encoder("copy");
        for _ in 0..reps {
            enc.copy_buffer_to_buffer(&a, 0, &b, 0, bytes);
        }
        let elapsed = time_submission(&self.ctx, enc)?;
        // a copy reads and writes every byte
        Ok(2.0 * bytes as f64 * reps as f64 / elapsed.as_secs_f64())
    }
}

impl GpuSearch {
    /// The last search's sort: each face's key and rank, the bucket sizes, the bucket starts
    /// (one more than buckets) and the sorted faces.
    pub fn read_sort(&mut self, ctx: &GpuContext) -> Result<[Vec<u32>; 5]> {
        let (f, t, b) = (self.faces, self.table, &self.buffers);
        let mut read =
            |s: &Storage, n| read_back(ctx, &mut self.staging, "search.read", &s.buffer, n);
        Ok([
            read(&b.sort.keys, f)?,
            read(&b.sort.ranks, f)?,
            read(&b.sort.counts, t)?,
            read(&b.sort.starts, t + 1)?,
            read(&b.sort.sorted, f)?,
        ])
    }
}

/// One stage of the resident step, for running it alone ([`ResidentStep::run_stage`]):
/// the kernel tests compare each with its CPU twin, the benchmarks time each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    Predict,
    PlaneContact,
    /// The predictor in the search's bounds and the contact iteration, which drifts every
    /// node, as a step records them where the iteration [`ResidentStep::predicts`].
    PredictContact,
    Drift,
    /// The element kernels and the gather.
    InternalForces,
    /// The element kernels alone (the corner forces).
    ElementForces,
    Correct,
    /// `gather_correct`: the gather and the corrector in one dispatch, from the corner
    /// forces the last `InternalForces` left.
    GatherCorrect,
    Reduce,
}

impl ResidentStep {
    /// The device contact iteration, if the step has one, with the context (to run its
    /// stages alone).
    pub fn impulse_sweeps(&mut self) -> Option<(&GpuContext, &mut ImpulseSweeps)> {
        let ctx = &self.k.ctx;
        self.contact.as_mut().map(|c| (ctx, c))
    }

    /// The history row's columns (the inputs of `history_reduce`).
    pub fn columns(&self) -> &[ReduceColumn] {
        &self.history.column_list
    }

    /// Records one stage of the step (the contact iteration whole, its sweeps recorded as
    /// the step records them).
    fn record_stage(&self, enc: &mut wgpu::CommandEncoder, stage: Stage) {
        let (k, l) = (&self.kernels, &self.launches);
        match stage {
            Stage::Predict => k.predict.0.record_launch(enc, &l.predict),
            Stage::PlaneContact => {
                if let Some(p) = &l.plane {
                    k.plane.0.record_launch(enc, p);
                }
                if let Some(c) = &self.contact {
                    c.record(enc, |c, p| c.dispatch(p, self.sweeps(), SearchMode::Build));
                }
            }
            Stage::PredictContact => {
                if let Some(c) = &self.contact {
                    c.record(enc, |c, p| {
                        c.dispatch_predicting(p, self.sweeps(), SearchMode::Build)
                    });
                }
            }
            Stage::Drift => k.drift.0.record_launch(enc, &l.drift),
            Stage::InternalForces => self.k.record_internal_forces(enc),
            Stage::ElementForces => self.k.record_element_kernels(enc),
            Stage::Correct => k.correct.0.record_launch(enc, &l.correct),
            Stage::GatherCorrect => k.gather_correct.0.record_launch(enc, &l.gather_correct),
            Stage::Reduce => k.reduce.0.record_launch(enc, &l.reduce[0]),
        }
    }

    /// Runs `gather_correct` alone on the corner forces `corners` (the twin's order) and the
    /// device's state.
    pub fn run_gather_correct(&mut self, corners: &[[f64; 3]]) -> Result<()> {
        self.k.upload_corners(corners)?;
        self.run_stage(Stage::GatherCorrect)
    }

    /// Runs one stage alone on the device's current buffers and waits for it.
    pub fn run_stage(&mut self, stage: Stage) -> Result<()> {
        let mut enc = self.k.ctx.encoder("explicit_stage");
        self.record_stage(&mut enc, stage);
        self.k.ctx.submit_and_wait(enc)
    }

    /// Wall time of `reps` runs of one stage in one submission, after the device is idle
    /// (the benchmarks' per-stage figures; the state moves on as the stage runs).
    pub fn time_stage(&mut self, stage: Stage, reps: usize) -> Result<Duration> {
        let mut enc = self.k.ctx.encoder("stage_timing");
        for _ in 0..reps {
            self.record_stage(&mut enc, stage);
        }
        time_submission(&self.k.ctx, enc)
    }

    /// The contact iteration's parts alone, each repeated `reps` times in one submission
    /// from the step state the engine holds (restored before each part; the repetitions of
    /// a part change it, as the stages' do: the sweeps after the first repetition's start
    /// from velocities that already meet the constraints): its setup (search
    /// with the faces' sort, constraints, sort, compliance); the setup keeping the faces'
    /// sort (after one sort); the setup and every sweep in `contact_finish`; the setup,
    /// `sweeps` recorded sweeps and `contact_finish`; and the report. None without a contact
    /// iteration.
    pub fn time_contact_parts(
        &mut self,
        reps: usize,
        sweeps: u32,
    ) -> Result<Option<[Duration; 5]>> {
        if self.contact.is_none() {
            return Ok(None);
        }
        let state = self.read_step_state()?;
        let Some(c) = &self.contact else {
            return Ok(None);
        };
        let ctx = &self.k.ctx;
        let time = |part: &dyn Fn(&mut wgpu::CommandEncoder)| {
            self.write_step_state(&state)?;
            let mut enc = ctx.encoder("contact_part_timing");
            for _ in 0..reps {
                part(&mut enc);
            }
            time_submission(ctx, enc)
        };
        let build = SearchMode::Build;
        Ok(Some([
            time(&|enc| c.record(enc, |c, p| c.dispatch_setup(p, build)))?,
            time(&|enc| c.record(enc, |c, p| c.dispatch_setup(p, SearchMode::Keep)))?,
            time(&|enc| {
                c.record(enc, |c, p| {
                    c.dispatch_setup(p, build);
                    c.dispatch_finish(p);
                })
            })?,
            time(&|enc| {
                c.record(enc, |c, p| {
                    c.dispatch_setup(p, build);
                    c.dispatch_sweeps(p, sweeps);
                    c.dispatch_finish(p);
                })
            })?,
            time(&|enc| c.record(enc, |c, p| c.dispatch_report(p)))?,
        ]))
        .and_then(|parts| self.write_step_state(&state).map(|_| parts))
    }

    /// The search and the whole iteration in one workgroup (`contact_zone`) repeated `reps`
    /// times in one submission from the step state (left as found), where the model has
    /// contact between meshed bodies and the adapter runs the kernel.
    pub fn time_zone(&mut self, reps: usize) -> Result<Option<Duration>> {
        let state = self.read_step_state()?;
        let Some(c) = self.contact.as_ref().filter(|c| c.zone_available()) else {
            return Ok(None);
        };
        let ctx = &self.k.ctx;
        let mut enc = ctx.encoder("contact_zone_timing");
        for _ in 0..reps {
            c.record(&mut enc, |c, p| {
                c.dispatch_search(p, SearchMode::Build, false);
                c.dispatch_zone(p);
            });
        }
        let t = time_submission(ctx, enc)?;
        self.write_step_state(&state)?;
        Ok(Some(t))
    }

    /// Waits for the submissions in flight and drops their rows (the caller steps no more:
    /// a benchmark about to time parts of the step from the state the steps left).
    pub fn drain(&mut self) -> Result<()> {
        for slot in 0..2 {
            if self.is_pending(slot) {
                self.collect(slot)?;
            }
        }
        Ok(())
    }

    /// Each kernel of a submission timed on the device: a submission of `steps` steps
    /// (fewer where the adapter's query set is too small) is recorded as the run records it
    /// (the faces' sort at its first step and where the search interval says), in one
    /// compute pass with a timestamp before the first dispatch and after each, from the
    /// state the caller's steps left. A dispatch's time runs from the timestamp before it
    /// to the one after it, so it includes its wait for the dispatch before (the barrier)
    /// and its launch. Per kernel, in the order of its first dispatch: its name, its
    /// dispatches and microseconds per step ([`KernelTime`]). `None` where the adapter has no
    /// timestamps inside passes ([`super::context::PROFILING`]). Submissions in flight are
    /// waited for first (their rows dropped: the caller steps no more); the state is left as
    /// it was found.
    pub fn profile_dispatches(&mut self, steps: usize) -> Result<Option<Vec<KernelTime>>> {
        if !self
            .k
            .ctx
            .device
            .features()
            .contains(super::context::PROFILING)
        {
            return Ok(None);
        }
        self.drain()?;
        let state = self.read_step_state()?;
        let ctx = self.k.ctx.clone();
        let record = |steps| {
            // recorded only to be captured: never submitted
            let mut enc = ctx.encoder("dispatch_capture");
            captured::capture(|| self.record_steps(&mut enc, steps, None))
        };
        let most = wgpu::QUERY_SET_MAX_QUERIES as usize - 1;
        let mut steps = steps.clamp(1, self.chunk_capacity);
        let mut list = record(steps);
        // one timestamp per dispatch and one before them all
        while list.len() > most && steps > 1 {
            steps = (steps * most / list.len()).clamp(1, steps - 1);
            list = record(steps);
        }
        if list.len() > most {
            return Err(ImpactError::Gpu(format!(
                "a step records {} dispatches, more than the {most} timestamps a query set holds",
                list.len()
            )));
        }
        let queries = (1 + list.len()) as u32;
        let set = ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("dispatch_profile"),
            ty: wgpu::QueryType::Timestamp,
            count: queries,
        });
        let resolved = Storage::with_usage(
            &ctx,
            "dispatch_profile",
            8 * queries as u64,
            wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        )?;
        let mut enc = ctx.encoder("dispatch_profile");
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("dispatch_profile"),
                timestamp_writes: None,
            });
            pass.write_timestamp(&set, 0);
            for (q, d) in list.iter().enumerate() {
                d.dispatch(&mut pass);
                pass.write_timestamp(&set, q as u32 + 1);
            }
        }
        enc.resolve_query_set(&set, 0..queries, &resolved.buffer, 0);
        let words: Vec<u32> = submit_and_read(
            &ctx,
            &mut self.k.staging,
            enc,
            &resolved.buffer,
            2 * queries as usize,
        )?;
        self.write_step_state(&state)?;
        let stamps: Vec<u64> = (words.chunks(2))
            .map(|w| w[0] as u64 | (w[1] as u64) << 32)
            .collect();
        let us = ctx.queue.get_timestamp_period() as f64 * 1e-3;
        let mut kernels: Vec<KernelTime> = Vec::new();
        for (q, d) in list.iter().enumerate() {
            let t = stamps[q + 1].saturating_sub(stamps[q]) as f64 * us / steps as f64;
            let k = match kernels.iter().position(|k| k.name == d.name) {
                Some(i) => &mut kernels[i],
                None => {
                    kernels.push(KernelTime {
                        name: d.name,
                        dispatches: 0.0,
                        us: 0.0,
                    });
                    kernels.last_mut().expect("just pushed")
                }
            };
            k.dispatches += 1.0 / steps as f64;
            k.us += t;
        }
        Ok(Some(kernels))
    }

    /// The host's time to record and submit `steps` steps (without waiting for the device,
    /// which then runs them; the device's time is apart): the benchmarks compare it with the
    /// step's time to tell a step bound by the host from one bound by the device.
    pub fn recording_time(&mut self, steps: usize) -> Result<Duration> {
        let steps = steps.clamp(1, self.chunk_capacity);
        let ctx = &self.k.ctx;
        ctx.wait()?;
        let start = Instant::now();
        let mut enc = ctx.encoder("recording_timing");
        self.record_steps(&mut enc, steps, None);
        ctx.queue.submit([enc.finish()]);
        let host = start.elapsed();
        ctx.wait()?;
        Ok(host)
    }

    /// The device's buffer-copy bandwidth in bytes per second (see
    /// [`GpuKernels::copy_bandwidth`]).
    pub fn copy_bandwidth(&self, bytes: u64, reps: usize) -> Result<f64> {
        self.k.copy_bandwidth(bytes, reps)
    }

    /// Overwrites the device state: displacement, velocity, acceleration (3 per node), the
    /// internal forces (3 per node) and the plane contact results.
    pub fn upload(
        &mut self,
        u: &[f64],
        v: &[f64],
        a: &[f64],
        forces: &[f64],
        results: &[f64],
    ) -> Result<()> {
        self.k.upload_state(u, v)?;
        let ctx = &self.k.ctx;
        self.m.a.upload(ctx, &to_f32(a))?;
        self.k.forces.upload(ctx, &to_f32(forces))?;
        self.m.results.upload(ctx, &to_f32(results))?;
        Ok(())
    }

    /// The correctors' workgroup sums, `FIELDS` per workgroup, body after body.
    pub fn read_partials(&mut self) -> Result<Vec<f64>> {
        let n = (self.partials.capacity / 4) as usize;
        let k = &mut self.k;
        read_floats(
            &k.ctx,
            &mut k.staging,
            "read_back",
            &self.partials.buffer,
            n,
        )
    }

    /// The first history row of the rows buffer (the row [`Stage::Reduce`] writes).
    pub fn read_row(&mut self) -> Result<Vec<f64>> {
        let (k, h) = (&mut self.k, &self.history);
        read_floats(
            &k.ctx,
            &mut k.staging,
            "read_back",
            &h.rows.buffer,
            h.row_len,
        )
    }
}

/// The label of the contact iteration's read-backs.
const CONTACT_READ: &str = "contact.read";

impl ImpulseSweeps {
    /// Runs `part` of the iteration (one of its `dispatch_*`) alone, in a compute pass of
    /// its own, and waits.
    pub fn run(
        &self,
        ctx: &GpuContext,
        part: impl FnOnce(&Self, &mut wgpu::ComputePass),
    ) -> Result<()> {
        let mut enc = ctx.encoder("contact_iteration");
        self.record(&mut enc, part);
        ctx.submit_and_wait(enc)
    }

    /// What `contact_relax` carries from sweep to sweep: the state words (with the
    /// violations' ring), both halves of the impulse changes and both slots of the contact
    /// nodes' velocities.
    pub fn read_relaxation(&mut self, ctx: &GpuContext) -> Result<Relaxation> {
        let state = self.read_state(ctx)?;
        let w: Vec<u32> = read_back(
            ctx,
            &mut self.staging,
            CONTACT_READ,
            &self.work.state.buffer,
            8,
        )?;
        let ring = [0, 1, 2].map(|k| f32::from_bits(w[word::RING + k]) as f64);
        let half = 3 * (self.pairs + self.ranges);
        let dj = read_floats(
            ctx,
            &mut self.staging,
            CONTACT_READ,
            &self.work.dj.buffer,
            2 * half,
        )?;
        let carried = read_floats(
            ctx,
            &mut self.staging,
            CONTACT_READ,
            &self.work.carried.buffer,
            6 * self.contact_nodes,
        )?;
        Ok(Relaxation {
            state,
            ring,
            dj,
            carried,
        })
    }

    /// The constraints, in f64.
    pub fn read_constraints(&mut self, ctx: &GpuContext) -> Result<Vec<Constraint>> {
        let source = &self.work.constraints.buffer;
        let c: Vec<types::GpuConstraint> =
            read_back(ctx, &mut self.staging, CONTACT_READ, source, self.pairs)?;
        Ok(c.into_iter().map(Constraint::from).collect())
    }

    /// The bucket keys, the bucket starts (faces + 2), the sorted pairs and the bucket sizes
    /// (faces + 1; `bucket_order` clears them for the next step's count).
    pub fn read_sort(&mut self, ctx: &GpuContext) -> Result<[Vec<u32>; 4]> {
        let (np, nf, w) = (self.pairs, self.faces, &self.work);
        let mut read =
            |s: &Storage, n| read_back(ctx, &mut self.staging, CONTACT_READ, &s.buffer, n);
        Ok([
            read(&w.sort.keys, np)?,
            read(&w.sort.starts, nf + 2)?,
            read(&w.sort.sorted, np)?,
            read(&w.sort.counts, nf + 1)?,
        ])
    }

    /// The touches of every node (entries of nodes outside the iteration are not written).
    pub fn read_touches(&mut self, ctx: &GpuContext, nodes: usize) -> Result<Vec<f64>> {
        let source = &self.work.touches.buffer;
        read_floats(ctx, &mut self.staging, CONTACT_READ, source, nodes)
    }

    /// The impulse changes of the last sweep (3 per pair).
    pub fn read_dj(&mut self, ctx: &GpuContext) -> Result<Vec<f64>> {
        let source = &self.work.dj.buffer;
        let values = 3 * (self.pairs + self.ranges);
        read_floats(ctx, &mut self.staging, CONTACT_READ, source, values)
    }

    /// The iteration's state.
    pub fn read_state(&mut self, ctx: &GpuContext) -> Result<SweepState> {
        let source = &self.work.state.buffer;
        let w: Vec<u32> = read_back(ctx, &mut self.staging, CONTACT_READ, source, 4)?;
        Ok(SweepState {
            violation: f32::from_bits(w[word::VIOLATION]) as f64,
            active: w[word::ACTIVE],
            sweeps: w[word::SWEEPS],
            phase: w[word::PHASE],
        })
    }

    /// The search grid's bounds (speed, side, drift: the copy the last search left) and the
    /// grid of the last search.
    pub fn read_grid(&mut self, ctx: &GpuContext) -> Result<([f64; 3], types::GpuSearchGrid)> {
        let staging = &mut self.staging;
        let b = read_floats(ctx, staging, CONTACT_READ, &self.work.bounds.buffer, 6)?[3..].to_vec();
        let g = match &self.search {
            Some(s) => read_back(ctx, staging, CONTACT_READ, s.grid_buffer(), 1)?[0],
            None => types::GpuSearchGrid::default(),
        };
        Ok(([b[0], b[1], b[2]], g))
    }

    /// The faces' boxes of the last search, as (lo, hi).
    pub fn read_boxes(&mut self, ctx: &GpuContext) -> Result<Vec<[[f64; 3]; 2]>> {
        let Some(s) = &self.search else {
            return Ok(Vec::new());
        };
        let b: Vec<types::FaceBox> = read_back(
            ctx,
            &mut self.staging,
            CONTACT_READ,
            s.boxes_buffer(),
            s.faces,
        )?;
        Ok(b.iter()
            .map(|b| [b.lo.map(f64::from), b.hi.map(f64::from)])
            .collect())
    }

    /// The contact points of the last search.
    pub fn read_points(&mut self, ctx: &GpuContext, queries: usize) -> Result<Vec<ContactPoint>> {
        let p: Vec<types::GpuContactPoint> = match &self.search {
            Some(s) => read_back(
                ctx,
                &mut self.staging,
                CONTACT_READ,
                s.points_buffer(),
                queries,
            )?,
            None => Vec::new(),
        };
        Ok(p.into_iter().map(ContactPoint::from).collect())
    }

    /// The contact results, [`SLOT`] per pair.
    pub fn read_results(&mut self, ctx: &GpuContext) -> Result<Vec<f64>> {
        let source = &self.work.results.buffer;
        read_floats(
            ctx,
            &mut self.staging,
            CONTACT_READ,
            source,
            SLOT * self.pairs,
        )
    }

    /// Overwrites the contact results ([`SLOT`] per pair, in f32): what a last step's report
    /// left, the warm start's impulses among them.
    pub fn upload_results(&mut self, ctx: &GpuContext, results: &[f64]) -> Result<()> {
        let r: Vec<f32> = results.iter().map(|&x| x as f32).collect();
        if r.len() != SLOT * self.pairs {
            return Err(crate::error::ImpactError::Gpu(format!(
                "upload_results: {} values for {} pairs",
                r.len(),
                self.pairs
            )));
        }
        self.work.results.upload(ctx, &r).map(|_| ())
    }

    /// Overwrites the constraints (to feed a stage the same inputs as its twin).
    pub fn upload_constraints(&mut self, ctx: &GpuContext, c: &[Constraint]) -> Result<()> {
        let c: Vec<types::GpuConstraint> = c.iter().map(types::GpuConstraint::from).collect();
        self.work.constraints.upload(ctx, &c)?;
        Ok(())
    }
}
