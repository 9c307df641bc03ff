//! [`DamageStage`]: the plies' damage on the device. After the element force kernels, each
//! block with damageable elements runs its damage kernel (`hex8_damage`, `hex8i_damage`,
//! `tet4_damage`; twins in [`crate::kernels`]), which replaces the corner forces of the
//! elements that damage; `damage_reduce` then sums the step's dissipation into a history
//! row (or a word the host reads) and counts the step.
//!
//! The state lives on the device: each block's points' values (f32), and one records
//! buffer with the step counter and each damageable element's flag, first damage and
//! dissipation ([`crate::kernels::damage_data::DAMAGE_RECORD`] words).

use super::buffer::{read_back, Storage};
use super::context::GpuContext;
use super::engine::at_least_one;
use super::kernel::Launch;
use super::kernels::{DamageReduce, Hex8Damage, Hex8iDamage, Tet4Damage};
use super::types::{self, to_device, DamageElementRecord, DamageParams};
use crate::element::{CornerLayout, ElementKind};
use crate::error::Result;
use crate::kernels::damage_data::{DamageBlock, DamageData, DamageState, DAMAGE_RECORD};
use crate::material::damage::{Dissipation, POINT_STATE};

/// One block's damage on the device.
struct BlockStage {
    kind: ElementKind,
    params: DamageParams,
    uniform: wgpu::Buffer,
    launch: Launch,
    /// The points of its damageable elements.
    points: usize,
    /// Kept alive for the launch's bind group: the element records, plies, condensation
    /// (hex8i) and the points' states.
    buffers: Vec<Storage>,
}

/// The damage kernels' pipelines.
struct DamageKernels {
    hex8: Hex8Damage,
    hex8i: Hex8iDamage,
    tet4: Tet4Damage,
    reduce: DamageReduce,
}

pub(crate) struct DamageStage {
    kernels: DamageKernels,
    blocks: Vec<BlockStage>,
    /// The step counter, then every block's element records.
    records: Storage,
    /// The laws and the entries (kept for the bind groups).
    tables: [Storage; 2],
    /// Damageable elements of every block.
    elements: usize,
    /// The host path's reduce: the step's dissipation into `total`.
    total: Storage,
    reduce_total: Launch,
    /// The resident path's reduces, one per row of a submission.
    reduce_rows: Vec<Launch>,
}

/// What the damage kernels read of the engine: the split reference coordinates and
/// displacements, the velocities, and the corner forces with their layout.
pub(super) struct DamageTarget<'a> {
    pub reference: &'a wgpu::Buffer,
    pub displacement: &'a wgpu::Buffer,
    pub velocity: &'a wgpu::Buffer,
    pub corner_forces: &'a wgpu::Buffer,
    pub layout: &'a CornerLayout,
    /// Each kind's block connectivity (column by column) and element count.
    pub block_nodes: Vec<(ElementKind, &'a wgpu::Buffer, usize)>,
}

/// A block's element records for the device.
fn element_records(b: &DamageBlock) -> Vec<DamageElementRecord> {
    (0..b.len())
        .map(|i| DamageElementRecord {
            element: b.elements[i],
            first_ply: b.first_ply[i],
            plies: b.first_ply[i + 1] - b.first_ply[i],
            first_point: b.first_point[i],
            axis: b.axis[i],
            sieve: b.sieve[i] as f32,
        })
        .collect()
}

/// A hex8i block's condensations column by column: entry (r, j) of element i at
/// `(24 r + j) D + i`.
fn condensation_columns(b: &DamageBlock) -> Vec<f32> {
    let d = b.len();
    (0..216 * d)
        .map(|k| b.condensation[216 * (k % d) + k / d] as f32)
        .collect()
}

impl DamageStage {
    /// The stage of `data` over the engine's buffers (`t`).
    pub(super) fn new(ctx: &GpuContext, data: &DamageData, t: &DamageTarget) -> Result<Self> {
        let kernels = DamageKernels {
            hex8: Hex8Damage::new(ctx),
            hex8i: Hex8iDamage::new(ctx),
            tet4: Tet4Damage::new(ctx),
            reduce: DamageReduce::new(ctx),
        };
        let laws: Vec<types::DamageLaw> = to_device(&data.laws);
        let entries: Vec<types::DamageEntry> = (data.law_of.iter().zip(&data.axes))
            .map(|(&law, r)| {
                let a = r.axes.map(|row| row.map(|x| x as f32));
                types::DamageEntry {
                    law,
                    a11: a[0][0],
                    a12: a[0][1],
                    a13: a[0][2],
                    a21: a[1][0],
                    a22: a[1][1],
                    a23: a[1][2],
                    a31: a[2][0],
                    a32: a[2][1],
                    a33: a[2][2],
                }
            })
            .collect();
        let tables = [
            Storage::with_data(ctx, "damage.laws", &at_least_one(laws))?,
            Storage::with_data(ctx, "damage.entries", &at_least_one(entries))?,
        ];
        let elements: usize = data.blocks.iter().map(DamageBlock::len).sum();
        let records = Storage::new(
            ctx,
            "damage.records",
            (4 * (1 + DAMAGE_RECORD * elements)) as u64,
        )?;
        let mut blocks = Vec::new();
        let mut first_record = 1;
        for (k, b) in data.blocks.iter().enumerate() {
            if b.is_empty() {
                continue;
            }
            let kind = ElementKind::ALL[k];
            let stage = BlockStage::new(
                ctx,
                &kernels,
                (kind, b),
                t,
                (&tables, &records),
                first_record,
            )?;
            first_record += DAMAGE_RECORD * b.len();
            blocks.push(stage);
        }
        // the step's dissipation and its fibre share
        let total = Storage::new(ctx, "damage.total", 8)?;
        let reduce_total =
            (kernels.reduce).launch(ctx, elements as u32, 0, 0, &records.buffer, &total.buffer);
        Ok(DamageStage {
            kernels,
            blocks,
            records,
            tables,
            elements,
            total,
            reduce_total,
            reduce_rows: Vec::new(),
        })
    }

    /// The reduces of the resident path: the step's dissipation and its fibre share into
    /// columns `column` and `column + 1` of each of `chunk_capacity` rows of `row_len` in
    /// `rows`.
    pub(super) fn reduce_into_rows(
        &mut self,
        ctx: &GpuContext,
        rows: &wgpu::Buffer,
        (row_len, column, chunk_capacity): (usize, usize, usize),
    ) {
        let reduce = &self.kernels.reduce;
        self.reduce_rows = (0..chunk_capacity)
            .map(|j| {
                let at = (j * row_len + column) as u32;
                reduce.launch(ctx, self.elements as u32, at, 0, &self.records.buffer, rows)
            })
            .collect();
    }

    /// Sets the step and whether the state advances, for the next submission.
    pub(super) fn set_step(&mut self, ctx: &GpuContext, dt: f64, advance: bool) {
        for b in &mut self.blocks {
            b.params.dt = dt as f32;
            b.params.advance = u32::from(advance);
            ctx.queue
                .write_buffer(&b.uniform, 0, bytemuck::bytes_of(&b.params));
        }
    }

    /// Dispatches the blocks' damage kernels (after the force kernels).
    pub(super) fn dispatch(&self, pass: &mut wgpu::ComputePass) {
        for b in &self.blocks {
            let k = match b.kind {
                ElementKind::Hex8 => &self.kernels.hex8.0,
                ElementKind::Tet4 => &self.kernels.tet4.0,
                ElementKind::Hex8i => &self.kernels.hex8i.0,
            };
            k.dispatch(pass, &b.launch);
        }
    }

    /// Dispatches the reduce of the host path, which counts the step (the host reads each
    /// element's dissipation, [`Self::read_dissipation`]).
    pub(super) fn dispatch_total(&self, pass: &mut wgpu::ComputePass) {
        (self.kernels.reduce.0).dispatch_with(pass, &self.reduce_total.bind, [1, 1]);
    }

    /// Dispatches the reduce of the resident path's row `j`.
    pub(super) fn dispatch_row(&self, pass: &mut wgpu::ComputePass, j: usize) {
        let l = &self.reduce_rows[j];
        (self.kernels.reduce.0).dispatch_with(pass, &l.bind, [1, 1]);
    }

    /// The last step's dissipation and its fibre share, each element's read back and summed
    /// in f64 in element order (the host path's: its sum does not depend on how the elements
    /// are shared out over ranks).
    pub(super) fn read_dissipation(
        &self,
        ctx: &GpuContext,
        staging: &mut Storage,
    ) -> Result<Dissipation> {
        let words = 1 + DAMAGE_RECORD * self.elements;
        let records: Vec<u32> =
            read_back(ctx, staging, "damage.records", &self.records.buffer, words)?;
        let value = |w: u32| f64::from(f32::from_bits(w));
        Ok((records[1..].chunks_exact(DAMAGE_RECORD))
            .map(|r| Dissipation {
                total: value(r[3]),
                fibre: value(r[4]),
            })
            .sum())
    }

    /// The buffers that carry the state from one step to the next: the records, then each
    /// block's points.
    pub(super) fn state_buffers(&self) -> Vec<&wgpu::Buffer> {
        std::iter::once(&self.records.buffer)
            .chain(
                self.blocks
                    .iter()
                    .map(|b| &b.buffers[b.buffers.len() - 1].buffer),
            )
            .collect()
    }

    /// The state on the device, as the CPU kernels keep it (`data`'s blocks).
    pub(super) fn read_state(
        &self,
        ctx: &GpuContext,
        staging: &mut Storage,
        data: &DamageData,
    ) -> Result<DamageState> {
        let words = 1 + DAMAGE_RECORD * self.elements;
        let records: Vec<u32> =
            read_back(ctx, staging, "damage.records", &self.records.buffer, words)?;
        let mut state = DamageState::new(data);
        state.steps = records[0];
        let mut at = 1;
        let mut stages = self.blocks.iter();
        for (k, b) in data.blocks.iter().enumerate() {
            if b.is_empty() {
                continue;
            }
            let stage = stages.next().expect("a stage per non-empty block");
            let points: Vec<f32> = read_back(
                ctx,
                staging,
                "damage.state",
                &stage.buffers[stage.buffers.len() - 1].buffer,
                POINT_STATE * stage.points,
            )?;
            state.points[k] = points.into_iter().map(f64::from).collect();
            for i in 0..b.len() {
                let r = &records[at + DAMAGE_RECORD * i..][..DAMAGE_RECORD];
                state.damaged[k][i] = r[0] != 0;
                state.first[k][i] = if r[0] != 0 { [r[1], r[2]] } else { [0, 0] };
            }
            at += DAMAGE_RECORD * b.len();
        }
        Ok(state)
    }

    /// Writes a state (as [`Self::read_state`] reads it) to the device.
    pub(super) fn write_state(&self, ctx: &GpuContext, data: &DamageData, state: &DamageState) {
        let mut records = vec![state.steps];
        let mut stages = self.blocks.iter();
        for (k, b) in data.blocks.iter().enumerate() {
            if b.is_empty() {
                continue;
            }
            let stage = stages.next().expect("a stage per non-empty block");
            for i in 0..b.len() {
                let [step, at] = state.first[k][i];
                records.extend([u32::from(state.damaged[k][i]), step, at, 0, 0]);
            }
            let points: Vec<f32> = state.points[k].iter().map(|&x| x as f32).collect();
            let buffer = &stage.buffers[stage.buffers.len() - 1].buffer;
            ctx.queue
                .write_buffer(buffer, 0, bytemuck::cast_slice(&points));
        }
        ctx.queue
            .write_buffer(&self.records.buffer, 0, bytemuck::cast_slice(&records));
    }

    /// Bytes held on the device.
    pub(super) fn device_bytes(&self) -> u64 {
        let blocks = self.blocks.iter().flat_map(|b| b.buffers.iter());
        (blocks
            .chain(&self.tables)
            .chain([&self.records, &self.total]))
        .map(|s| s.capacity)
        .sum()
    }
}

impl BlockStage {
    /// Block `kind`'s stage: its buffers, its uniform (records from word `first_record`)
    /// and its launch.
    fn new(
        ctx: &GpuContext,
        kernels: &DamageKernels,
        (kind, b): (ElementKind, &DamageBlock),
        t: &DamageTarget,
        (tables, records): (&[Storage; 2], &Storage),
        first_record: usize,
    ) -> Result<Self> {
        let (_, nodes, count) = *t
            .block_nodes
            .iter()
            .find(|(k, _, _)| *k == kind)
            .expect("the block of a damageable element");
        let params = DamageParams {
            dt: 0.0,
            advance: 0,
            elements: count as u32,
            records: first_record as u32,
        };
        let uniform = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("damage.params"),
            size: std::mem::size_of::<DamageParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        ctx.queue
            .write_buffer(&uniform, 0, bytemuck::bytes_of(&params));
        let plies: Vec<types::DamagePlyRecord> = to_device(&b.plies);
        let mut buffers = vec![
            Storage::with_data(ctx, "damage.elements", &element_records(b))?,
            Storage::with_data(ctx, "damage.plies", &plies)?,
        ];
        if kind == ElementKind::Hex8i {
            buffers.push(Storage::with_data(
                ctx,
                "damage.condensation",
                &condensation_columns(b),
            )?);
        }
        buffers.push(Storage::new(
            ctx,
            "damage.state",
            (4 * POINT_STATE * b.points()) as u64,
        )?);
        let slots = (t.layout.count() as u32, t.layout.offset(kind) as u32);
        let (laws, entries) = (&tables[0].buffer, &tables[1].buffer);
        let (elements, ply, state) = (
            &buffers[0].buffer,
            &buffers[1].buffer,
            &buffers[buffers.len() - 1].buffer,
        );
        let common = (t.reference, t.displacement, t.velocity, nodes);
        let launch = match kind {
            ElementKind::Hex8 => kernels.hex8.launch(
                ctx,
                b.len() as u32,
                slots.0,
                slots.1,
                &uniform,
                common.0,
                common.1,
                common.2,
                common.3,
                elements,
                ply,
                entries,
                laws,
                state,
                &records.buffer,
                t.corner_forces,
            ),
            ElementKind::Tet4 => kernels.tet4.launch(
                ctx,
                b.len() as u32,
                slots.0,
                slots.1,
                &uniform,
                common.0,
                common.1,
                common.2,
                common.3,
                elements,
                ply,
                entries,
                laws,
                state,
                &records.buffer,
                t.corner_forces,
            ),
            ElementKind::Hex8i => kernels.hex8i.launch(
                ctx,
                b.len() as u32,
                slots.0,
                slots.1,
                &uniform,
                common.0,
                common.1,
                common.2,
                common.3,
                elements,
                ply,
                entries,
                laws,
                &buffers[2].buffer,
                state,
                &records.buffer,
                t.corner_forces,
            ),
        };
        Ok(BlockStage {
            kind,
            params,
            uniform,
            launch,
            points: b.points(),
            buffers,
        })
    }
}
