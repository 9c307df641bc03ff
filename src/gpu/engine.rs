//! [`GpuKernels`]: the [`Kernels`] interface on a wgpu device. Mesh data (split reference
//! coordinates, connectivity, materials, the node incidence table) is uploaded once;
//! each call uploads the displacements (as split f32 pairs) and the f32 velocities,
//! dispatches, and reads back.

use std::time::{Duration, Instant};

use super::buffer::{staging, submit_and_read, Storage};
use super::context::GpuContext;
use super::kernel::Launch;
use super::search::GpuSearch;
use super::types::{self, ContactQuery, Material, Quad, Split3};
use super::{ContactGap, Hex8Forces, NodeGather, SlipRate, Tet4Forces};
use crate::backend::Kernels;
use crate::contact::search;
use crate::error::{ImpactError, Result};
use crate::kernels::{ContactPoint, ContactQueries, ElementData, Incidence, SearchGrid};
use crate::model::Model;

/// The kernels of the engine, for timing them one by one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KernelId {
    Hex8Forces,
    Tet4Forces,
    NodeGather,
    ContactGap,
    SlipRate,
}

/// Contact data as last uploaded (re-uploaded only when it changes).
#[derive(Default)]
struct UploadedQueries {
    secondary: Vec<u32>,
    offsets: Vec<u32>,
    candidates: Vec<u32>,
    faces: Vec<[u32; 4]>,
}

pub struct GpuKernels {
    pub(super) ctx: GpuContext,
    pub(super) nodes: usize,
    /// Hex8 elements.
    elements: usize,
    tets_count: usize,
    hex8_forces: Hex8Forces,
    tet4_forces: Tet4Forces,
    node_gather: NodeGather,
    contact_gap: ContactGap,
    slip_rate: SlipRate,
    pub(super) reference: Storage,
    /// Connectivity column by column (see [`ElementColumns`]).
    hex_nodes: Storage,
    hex_material: Storage,
    tet_nodes: Storage,
    tet_material: Storage,
    materials: Storage,
    offsets: Storage,
    incidence: Storage,
    pub(super) u: Storage,
    pub(super) v: Storage,
    corners: Storage,
    pub(super) forces: Storage,
    queries: Storage,
    candidates: Storage,
    faces: Storage,
    points: Storage,
    slips: Storage,
    pub(super) staging: Storage,
    uploaded: UploadedQueries,
    query_count: usize,
    hex8_launch: Launch,
    tet4_launch: Launch,
    gather_launch: Launch,
    contact_binds: Option<(wgpu::BindGroup, wgpu::BindGroup)>,
    /// The device contact search, built at its first use.
    search: Option<GpuSearch>,
    scratch: Vec<f32>,
    scratch_split: Vec<Split3>,
    /// Fill every output with NaN before each dispatch (tests: an unwritten entry fails).
    pub fill_nan: bool,
}

/// The reference coordinates as split pairs (on all threads).
pub(super) fn split_reference(data: &ElementData) -> Vec<Split3> {
    use rayon::prelude::*;
    data.reference
        .par_iter()
        .map(|&x| Split3::split(x))
        .collect()
}

/// The materials as the kernels' type.
pub(super) fn device_materials(data: &ElementData) -> Vec<Material> {
    data.materials
        .iter()
        .map(|m| Material {
            lambda: m.lambda as f32,
            mu: m.mu as f32,
            density: m.density as f32,
        })
        .collect()
}

pub(super) fn at_least_one<T: Default>(mut v: Vec<T>) -> Vec<T> {
    if v.is_empty() {
        v.push(T::default());
    }
    v
}

/// The element kernels' layouts, chosen so that neighbouring invocations (elements, nodes)
/// read and write neighbouring words:
/// - connectivity column by column: node k of hex e at `hex_nodes[k E + e]`, of tet t at
///   `tet_nodes[k T + t]`;
/// - corner forces component-major: component a of corner slot s at `a C + s`, where hex
///   corner k of element e has slot `k E + e` and tet corner k of tet t has slot
///   `8 E + k T + t` (C = 8 E + 4 T slots);
/// - the gather's incidence lists hold those slots, in the order of the twin's corner ids
///   (`8 e + k`, then `8 E + 4 t + k`), so the sums run in the twin's order.
pub struct ElementColumns {
    pub hex_nodes: Vec<u32>,
    pub hex_material: Vec<u32>,
    pub tet_nodes: Vec<u32>,
    pub tet_material: Vec<u32>,
    /// The incidence table with slots in place of corner ids.
    pub incidence: Incidence,
}

impl ElementColumns {
    pub fn new(data: &ElementData) -> Self {
        use rayon::prelude::*;
        let (e, t) = (data.hexes.len(), data.tets.len());
        let hex_nodes = (0..8 * e)
            .into_par_iter()
            .map(|i| data.hexes[i % e][i / e])
            .collect();
        let tet_nodes = (0..4 * t)
            .into_par_iter()
            .map(|i| data.tets[i % t][i / t])
            .collect();
        let mut incidence = Incidence::new(&data.hexes, &data.tets, data.reference.len());
        incidence
            .corners
            .par_iter_mut()
            .for_each(|c| *c = corner_slot(*c as usize, e, t) as u32);
        ElementColumns {
            hex_nodes,
            hex_material: data.hex_material.clone(),
            tet_nodes,
            tet_material: data.tet_material.clone(),
            incidence,
        }
    }
}

/// The slot of the twin's corner id `c` (`8 e + k` for hexes, then `8 E + 4 t + k`) in the
/// device's corner-force layout, for `hexes` hexes and `tets` tets (see [`ElementColumns`]).
pub fn corner_slot(c: usize, hexes: usize, tets: usize) -> usize {
    if c < 8 * hexes {
        (c % 8) * hexes + c / 8
    } else {
        let c = c - 8 * hexes;
        8 * hexes + (c % 4) * tets + c / 4
    }
}

fn bytes_of<T>(n: usize) -> u64 {
    (n * std::mem::size_of::<T>()) as u64
}

impl GpuKernels {
    pub fn new(ctx: GpuContext, data: &ElementData) -> Result<Self> {
        let nodes = data.reference.len();
        let elements = data.hexes.len();
        let tets_count = data.tets.len();
        let corner_count = data.corner_count();
        if corner_count > u32::MAX as usize / 3 {
            return Err(ImpactError::Gpu(format!(
                "{} elements exceed the GPU kernels' 32-bit indexing",
                elements + tets_count
            )));
        }
        let (reference, materials) = (split_reference(data), device_materials(data));
        let columns = ElementColumns::new(data);
        let reference = Storage::with_data(&ctx, "reference", &reference)?;
        // a binding holds at least one word: a mesh without hexes (or tets) binds one
        // unused placeholder, never dispatched
        let hex_nodes = Storage::with_data(&ctx, "hex_nodes", &at_least_one(columns.hex_nodes))?;
        let hex_material =
            Storage::with_data(&ctx, "hex_material", &at_least_one(columns.hex_material))?;
        let tet_nodes = Storage::with_data(&ctx, "tet_nodes", &at_least_one(columns.tet_nodes))?;
        let tet_material =
            Storage::with_data(&ctx, "tet_material", &at_least_one(columns.tet_material))?;
        let materials = Storage::with_data(&ctx, "materials", &materials)?;
        let offsets = Storage::with_data(&ctx, "incidence.offsets", &columns.incidence.offsets)?;
        let incidence = Storage::with_data(&ctx, "incidence", &columns.incidence.corners)?;
        let u = Storage::new(&ctx, "displacement", bytes_of::<Split3>(nodes))?;
        let v = Storage::new(&ctx, "velocity", bytes_of::<f32>(3 * nodes))?;
        let corners = Storage::new(&ctx, "corner_forces", bytes_of::<f32>(3 * corner_count))?;
        let forces = Storage::new(&ctx, "forces", bytes_of::<f32>(3 * nodes))?;
        let queries = Storage::new(&ctx, "contact.queries", 0)?;
        let candidates = Storage::new(&ctx, "contact.candidates", 0)?;
        let faces = Storage::new(&ctx, "contact.faces", 0)?;
        let points = Storage::new(&ctx, "contact.points", 0)?;
        let slips = Storage::new(&ctx, "contact.slip", 0)?;
        let staging = staging(&ctx)?;
        let hex8_forces = Hex8Forces::new(&ctx);
        let tet4_forces = Tet4Forces::new(&ctx);
        let node_gather = NodeGather::new(&ctx);
        let contact_gap = ContactGap::new(&ctx);
        let slip_rate = SlipRate::new(&ctx);
        let slots = corner_count as u32;
        let hex8_launch = hex8_forces.launch(
            &ctx,
            elements as u32,
            slots,
            0,
            &reference.buffer,
            &u.buffer,
            &hex_nodes.buffer,
            &hex_material.buffer,
            &materials.buffer,
            &corners.buffer,
        );
        let tet4_launch = tet4_forces.launch(
            &ctx,
            tets_count as u32,
            slots,
            8 * elements as u32,
            &reference.buffer,
            &u.buffer,
            &tet_nodes.buffer,
            &tet_material.buffer,
            &materials.buffer,
            &corners.buffer,
        );
        let gather_launch = node_gather.launch(
            &ctx,
            nodes as u32,
            slots,
            0,
            &offsets.buffer,
            &incidence.buffer,
            &corners.buffer,
            &forces.buffer,
        );
        Ok(GpuKernels {
            ctx,
            nodes,
            elements,
            tets_count,
            hex8_forces,
            tet4_forces,
            node_gather,
            contact_gap,
            slip_rate,
            reference,
            hex_nodes,
            hex_material,
            tet_nodes,
            tet_material,
            materials,
            offsets,
            incidence,
            u,
            v,
            corners,
            forces,
            queries,
            candidates,
            faces,
            points,
            slips,
            staging,
            uploaded: UploadedQueries::default(),
            query_count: 0,
            hex8_launch,
            tet4_launch,
            gather_launch,
            contact_binds: None,
            search: None,
            scratch: Vec::new(),
            scratch_split: Vec::new(),
            fill_nan: false,
        })
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// The device contact search (after the first `contact_search_into`) and the context,
    /// for the kernel tests.
    pub fn search_parts(&mut self) -> Option<(&GpuContext, &mut GpuSearch)> {
        self.search.as_mut().map(|s| (&self.ctx, s))
    }

    /// Bytes held on the device by the mesh and the per-call buffers.
    pub fn device_bytes(&self) -> u64 {
        [
            &self.reference,
            &self.hex_nodes,
            &self.hex_material,
            &self.tet_nodes,
            &self.tet_material,
            &self.materials,
            &self.offsets,
            &self.incidence,
            &self.u,
            &self.v,
            &self.corners,
            &self.forces,
            &self.queries,
            &self.candidates,
            &self.faces,
            &self.points,
            &self.slips,
            &self.staging,
        ]
        .iter()
        .map(|s| s.capacity)
        .sum()
    }

    fn upload_nodal(&mut self, velocity: bool, x: &[f64]) -> Result<()> {
        if x.len() != 3 * self.nodes {
            return Err(ImpactError::Gpu(format!(
                "nodal vector of length {} for {} nodes",
                x.len(),
                self.nodes
            )));
        }
        use rayon::prelude::*;
        if velocity {
            self.scratch.clear();
            x.par_iter()
                .map(|&a| a as f32)
                .collect_into_vec(&mut self.scratch);
            self.v.upload(&self.ctx, &self.scratch)?;
        } else {
            // displacements as split pairs (see `Split3`)
            self.scratch_split.clear();
            x.par_chunks_exact(3)
                .map(|c| Split3::split([c[0], c[1], c[2]]))
                .collect_into_vec(&mut self.scratch_split);
            self.u.upload(&self.ctx, &self.scratch_split)?;
        }
        Ok(())
    }

    pub(super) fn encoder(&self, label: &str) -> wgpu::CommandEncoder {
        self.ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) })
    }

    fn corner_floats(&self) -> usize {
        24 * self.elements + 12 * self.tets_count
    }

    /// Records the element kernels (hex8 then tet4, each only if the mesh has such elements)
    /// that fill the corner forces, each in a pass of its own.
    fn record_elements(&self, enc: &mut wgpu::CommandEncoder) {
        if self.elements > 0 {
            self.hex8_forces.0.record_launch(enc, &self.hex8_launch);
        }
        if self.tets_count > 0 {
            self.tet4_forces.0.record_launch(enc, &self.tet4_launch);
        }
    }

    /// Dispatches the element kernels and the gather in an open pass: the internal forces at
    /// the device's displacement into the forces buffer.
    pub(super) fn dispatch_internal_forces(&self, pass: &mut wgpu::ComputePass) {
        if self.elements > 0 {
            self.hex8_forces.0.dispatch(pass, &self.hex8_launch);
        }
        if self.tets_count > 0 {
            self.tet4_forces.0.dispatch(pass, &self.tet4_launch);
        }
        self.node_gather.0.dispatch(pass, &self.gather_launch);
    }

    /// Records the element kernels and the gather in one pass (see
    /// [`Self::dispatch_internal_forces`]).
    pub(super) fn record_internal_forces(&self, enc: &mut wgpu::CommandEncoder) {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("internal_forces"),
            timestamp_writes: None,
        });
        self.dispatch_internal_forces(&mut pass);
    }

    /// Uploads the velocities alone.
    pub(super) fn upload_velocity(&mut self, v: &[f64]) -> Result<()> {
        self.upload_nodal(true, v)
    }

    /// Uploads displacements (split pairs) and velocities.
    pub(super) fn upload_state(&mut self, u: &[f64], v: &[f64]) -> Result<()> {
        self.upload_nodal(false, u)?;
        self.upload_nodal(true, v)
    }

    /// The device's corner slot of each of the twin's corner ids, in twin order.
    fn slot_of(&self, c: usize) -> usize {
        corner_slot(c, self.elements, self.tets_count)
    }

    /// Runs the element kernels alone: corner forces `[8 e + k]` of the hexes, then
    /// `[8 hexes + 4 t + k]` of the tets (the twin's order), for the displacement `u`.
    pub fn corner_forces(&mut self, u: &[f64]) -> Result<Vec<[f64; 3]>> {
        self.upload_nodal(false, u)?;
        if self.fill_nan {
            self.corners
                .fill_nan(&self.ctx, bytes_of::<f32>(self.corner_floats()));
        }
        let mut enc = self.encoder("element_forces");
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

    /// Runs `node_gather` alone on the given corner forces (the twin's order).
    pub fn gather(&mut self, corners: &[[f64; 3]]) -> Result<Vec<[f64; 3]>> {
        let slots = corners.len();
        let mut c = vec![0f32; 3 * slots];
        for (i, f) in corners.iter().enumerate() {
            let s = self.slot_of(i);
            for a in 0..3 {
                c[a * slots + s] = f[a] as f32;
            }
        }
        self.corners.upload(&self.ctx, &c)?;
        if self.fill_nan {
            self.forces
                .fill_nan(&self.ctx, bytes_of::<f32>(3 * self.nodes));
        }
        let mut enc = self.encoder("node_gather");
        self.node_gather
            .0
            .record_launch(&mut enc, &self.gather_launch);
        let out: Vec<[f32; 3]> = submit_and_read(
            &self.ctx,
            &mut self.staging,
            enc,
            &self.forces.buffer,
            self.nodes,
        )?;
        Ok(out.into_iter().map(|f| f.map(f64::from)).collect())
    }

    /// Uploads the contact queries if they differ from the last ones.
    fn sync_queries(&mut self, q: &ContactQueries) -> Result<()> {
        let mut grew = false;
        // compared in the caller's CSR form, so an unchanged set costs no conversion
        if q.secondary != self.uploaded.secondary || q.offsets != self.uploaded.offsets {
            let queries: Vec<ContactQuery> = (0..q.len())
                .map(|i| ContactQuery {
                    secondary: q.secondary[i],
                    first: q.offsets[i],
                    end: q.offsets[i + 1],
                })
                .collect();
            grew |= self.queries.upload(&self.ctx, &queries)?;
            grew |= self
                .points
                .ensure(&self.ctx, bytes_of::<types::ContactPoint>(q.len()))?;
            grew |= self
                .slips
                .ensure(&self.ctx, bytes_of::<[f32; 2]>(q.len()))?;
            self.uploaded.secondary.clone_from(&q.secondary);
            self.uploaded.offsets.clone_from(&q.offsets);
        }
        if q.candidates != self.uploaded.candidates {
            grew |= self.candidates.upload(&self.ctx, &q.candidates)?;
            self.uploaded.candidates.clone_from(&q.candidates);
        }
        if q.faces != self.uploaded.faces {
            // `Quad` is `[u32; 4]` with the WGSL struct's layout
            let faces: Vec<Quad> = q.faces.iter().map(|&nodes| Quad { nodes }).collect();
            grew |= self.faces.upload(&self.ctx, &faces)?;
            self.uploaded.faces.clone_from(&q.faces);
        }
        self.query_count = q.len();
        if grew || self.contact_binds.is_none() {
            let gap = self.contact_gap.bind(
                &self.ctx,
                &self.reference.buffer,
                &self.u.buffer,
                &self.v.buffer,
                &self.queries.buffer,
                &self.candidates.buffer,
                &self.faces.buffer,
                &self.points.buffer,
            );
            let slip = self.slip_rate.bind(
                &self.ctx,
                &self.reference.buffer,
                &self.u.buffer,
                &self.v.buffer,
                &self.queries.buffer,
                &self.faces.buffer,
                &self.points.buffer,
                &self.slips.buffer,
            );
            self.contact_binds = Some((gap, slip));
        }
        Ok(())
    }

    /// Records `reps` dispatches of one kernel on the current data in one pass, waits, and
    /// returns the elapsed wall time (for the benchmarks; contact kernels use the last
    /// queries).
    pub fn time_kernel(&mut self, kernel: KernelId, reps: usize) -> Result<Duration> {
        let mut enc = self.encoder("timing");
        // the element kernels' launches are fixed; the contact kernels' counts follow the
        // last queries
        let (k, bind, grid) = match kernel {
            KernelId::Hex8Forces => (
                &self.hex8_forces.0,
                &self.hex8_launch.bind,
                self.hex8_launch.grid,
            ),
            KernelId::Tet4Forces => (
                &self.tet4_forces.0,
                &self.tet4_launch.bind,
                self.tet4_launch.grid,
            ),
            KernelId::NodeGather => (
                &self.node_gather.0,
                &self.gather_launch.bind,
                self.gather_launch.grid,
            ),
            KernelId::ContactGap | KernelId::SlipRate => {
                let Some((gap, slip)) = &self.contact_binds else {
                    return Err(ImpactError::Gpu("no contact queries uploaded".into()));
                };
                let (k, bind) = if kernel == KernelId::ContactGap {
                    (&self.contact_gap.0, gap)
                } else {
                    (&self.slip_rate.0, slip)
                };
                (k, bind, k.set_count(&self.ctx, self.query_count as u32))
            }
        };
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("timing"),
                timestamp_writes: None,
            });
            for _ in 0..reps {
                k.dispatch_with(&mut pass, bind, grid);
            }
        }
        // settle earlier work (the params write) before timing
        self.ctx.wait()?;
        let start = Instant::now();
        self.ctx.queue.submit([enc.finish()]);
        self.ctx.wait()?;
        Ok(start.elapsed())
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
        let mut enc = self.encoder("copy");
        enc.copy_buffer_to_buffer(&a, 0, &b, 0, bytes);
        self.ctx.queue.submit([enc.finish()]);
        self.ctx.wait()?;
        let mut enc = self.encoder("copy");
        for _ in 0..reps {
            enc.copy_buffer_to_buffer(&a, 0, &b, 0, bytes);
        }
        let start = Instant::now();
        self.ctx.queue.submit([enc.finish()]);
        self.ctx.wait()?;
        // a copy reads and writes every byte
        Ok(2.0 * bytes as f64 * reps as f64 / start.elapsed().as_secs_f64())
    }
}

impl Kernels for GpuKernels {
    fn device_name(&self) -> String {
        self.ctx.adapter.name.clone()
    }

    fn unit_roundoff(&self) -> f64 {
        f32::EPSILON as f64
    }

    fn internal_forces_into(&mut self, u: &[f64], f: &mut [f64]) -> Result<()> {
        self.upload_nodal(false, u)?;
        if self.fill_nan {
            self.corners
                .fill_nan(&self.ctx, bytes_of::<f32>(self.corner_floats()));
            self.forces
                .fill_nan(&self.ctx, bytes_of::<f32>(3 * self.nodes));
        }
        let mut enc = self.encoder("internal_forces");
        self.record_internal_forces(&mut enc);
        let out: Vec<f32> = submit_and_read(
            &self.ctx,
            &mut self.staging,
            enc,
            &self.forces.buffer,
            3 * self.nodes,
        )?;
        for (d, x) in f.iter_mut().zip(out) {
            *d = x as f64;
        }
        Ok(())
    }

    fn contact_gap_into(
        &mut self,
        u: &[f64],
        v: &[f64],
        queries: &ContactQueries,
        out: &mut [ContactPoint],
    ) -> Result<()> {
        if queries.is_empty() {
            return Ok(());
        }
        self.upload_nodal(false, u)?;
        self.upload_nodal(true, v)?;
        self.sync_queries(queries)?;
        let n = queries.len();
        if self.fill_nan {
            self.points
                .fill_nan(&self.ctx, bytes_of::<types::ContactPoint>(n));
        }
        let mut enc = self.encoder("contact_gap");
        let grid = self.contact_gap.0.set_count(&self.ctx, n as u32);
        let (gap, _) = self.contact_binds.as_ref().expect("bound by sync_queries");
        self.contact_gap.0.record(&mut enc, gap, grid);
        let pts: Vec<types::ContactPoint> =
            submit_and_read(&self.ctx, &mut self.staging, enc, &self.points.buffer, n)?;
        for (o, p) in out.iter_mut().zip(pts) {
            *o = p.into();
        }
        Ok(())
    }

    fn contact_search_into(
        &mut self,
        model: &Model,
        u: &[f64],
        v: &[f64],
        margin: f64,
        queries: &mut ContactQueries,
        _lists: &mut [Vec<u32>],
        out: &mut [ContactPoint],
    ) -> Result<()> {
        if queries.is_empty() {
            return Ok(());
        }
        self.upload_nodal(false, u)?;
        self.upload_nodal(true, v)?;
        if self.search.is_none() {
            let (face_first, q) = search::search_layout(model);
            self.search = Some(GpuSearch::new(
                &self.ctx,
                &self.reference.buffer,
                &self.u.buffer,
                &self.v.buffer,
                &queries.faces,
                &face_first,
                &q,
            )?);
        }
        let enc = self.encoder("contact_search");
        let search = self.search.as_mut().expect("built above");
        let grid = SearchGrid {
            cell: search::search_cell(&model.mesh.nodes, u, &queries.faces, margin),
            margin,
            mask: search.mask(),
        };
        let pts = search.run(&self.ctx, enc, grid)?;
        out[..pts.len()].copy_from_slice(&pts);
        Ok(())
    }

    fn slip_rate_into(
        &mut self,
        u: &[f64],
        v: &[f64],
        queries: &ContactQueries,
        points: &[ContactPoint],
        out: &mut [[f64; 2]],
    ) -> Result<()> {
        if queries.is_empty() {
            return Ok(());
        }
        self.upload_nodal(false, u)?;
        self.upload_nodal(true, v)?;
        self.sync_queries(queries)?;
        let n = queries.len();
        let pts: Vec<types::ContactPoint> =
            points[..n].iter().map(types::ContactPoint::from).collect();
        self.points.upload(&self.ctx, &pts)?;
        if self.fill_nan {
            self.slips.fill_nan(&self.ctx, bytes_of::<[f32; 2]>(n));
        }
        let mut enc = self.encoder("slip_rate");
        let grid = self.slip_rate.0.set_count(&self.ctx, n as u32);
        let (_, slip) = self.contact_binds.as_ref().expect("bound by sync_queries");
        self.slip_rate.0.record(&mut enc, slip, grid);
        let s: Vec<[f32; 2]> =
            submit_and_read(&self.ctx, &mut self.staging, enc, &self.slips.buffer, n)?;
        for (o, x) in out.iter_mut().zip(s) {
            *o = x.map(f64::from);
        }
        Ok(())
    }
}
