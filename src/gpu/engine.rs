//! [`GpuKernels`]: the [`Kernels`] interface on a wgpu device. Mesh data (split reference
//! coordinates, connectivity, materials, the node incidence table) is uploaded once;
//! each call uploads the displacements (as split f32 pairs) and the f32 velocities,
//! dispatches, and reads back.

use super::buffer::{staging, submit_and_read, Storage};
use super::context::GpuContext;
use super::damage_stage::{DamageStage, DamageTarget};
use super::kernel::{Kernel, Launch};
use super::search::GpuSearch;
use super::types::{self, to_device, ContactQuery, GpuMaterial, Quad, Split3};
use super::{ContactGap, CornerSelect, Hex8Forces, Hex8iForces, NodeGather, SlipRate, Tet4Forces};
use crate::backend::Kernels;
use crate::element::{CornerLayout, ElementKind};
use crate::error::{ImpactError, Result};
use crate::kernels::damage_data::{DamageData, DamageState, DamagedPoint};
use crate::kernels::{ContactPoint, ContactQueries, ElementData, Incidence, KeptData, SearchGrid};
use crate::material::damage::Dissipation;
use crate::model::Model;
use crate::search;

/// Contact data as last uploaded (re-uploaded only when it changes).
#[derive(Default)]
struct UploadedQueries {
    secondary: Vec<u32>,
    offsets: Vec<u32>,
    candidates: Vec<u32>,
    faces: Vec<[u32; 4]>,
}

/// The engine's kernels' pipelines, built once.
pub(super) struct EngineKernels {
    pub(super) hex8_forces: Hex8Forces,
    pub(super) tet4_forces: Tet4Forces,
    pub(super) hex8i_forces: Hex8iForces,
    pub(super) node_gather: NodeGather,
    pub(super) corner_select: CornerSelect,
    pub(super) contact_gap: ContactGap,
    pub(super) slip_rate: SlipRate,
}

impl EngineKernels {
    /// The force kernel of a kind's block (the device's force dispatch, with
    /// [`Self::block_launch`]).
    pub(super) fn forces(&self, kind: ElementKind) -> &Kernel {
        match kind {
            ElementKind::Hex8 => &self.hex8_forces.0,
            ElementKind::Tet4 => &self.tet4_forces.0,
            ElementKind::Hex8i => &self.hex8i_forces.0,
        }
    }

    /// The launch of a kind's force kernel over its block.
    #[allow(clippy::too_many_arguments)]
    fn block_launch(
        &self,
        ctx: &GpuContext,
        block: &BlockBuffers,
        (slots, first_slot): (u32, u32),
        m: &MeshBuffers,
        u: &Storage,
        corners: &Storage,
    ) -> Launch {
        let count = block.count as u32;
        let (nodes, material) = (&block.nodes.buffer, &block.material.buffer);
        let (x, u, c, mats) = (
            &m.reference.buffer,
            &u.buffer,
            &corners.buffer,
            &m.materials.buffer,
        );
        match block.kind {
            ElementKind::Hex8 => (self.hex8_forces).launch(
                ctx, count, slots, first_slot, x, u, nodes, material, mats, c,
            ),
            ElementKind::Tet4 => (self.tet4_forces).launch(
                ctx, count, slots, first_slot, x, u, nodes, material, mats, c,
            ),
            ElementKind::Hex8i => (self.hex8i_forces).launch(
                ctx,
                count,
                slots,
                first_slot,
                x,
                u,
                nodes,
                &block.kept.buffer,
                c,
            ),
        }
    }

    fn new(ctx: &GpuContext) -> Self {
        EngineKernels {
            hex8_forces: Hex8Forces::new(ctx),
            tet4_forces: Tet4Forces::new(ctx),
            hex8i_forces: Hex8iForces::new(ctx),
            node_gather: NodeGather::new(ctx),
            corner_select: CornerSelect::new(ctx),
            contact_gap: ContactGap::new(ctx),
            slip_rate: SlipRate::new(ctx),
        }
    }
}

/// One element block on the device: its connectivity column by column and its materials
/// (see [`ElementColumns`]).
pub(super) struct BlockBuffers {
    kind: ElementKind,
    count: usize,
    nodes: Storage,
    material: Storage,
    /// What the kind's force kernel keeps per element (one unused word where it keeps none).
    kept: Storage,
}

/// The mesh on the device, uploaded once: the split reference coordinates, each non-empty
/// element block, the materials and the node incidence table.
pub(super) struct MeshBuffers {
    pub(super) reference: Storage,
    blocks: Vec<BlockBuffers>,
    materials: Storage,
    pub(super) offsets: Storage,
    pub(super) incidence: Storage,
}

impl MeshBuffers {
    fn upload(ctx: &GpuContext, data: &ElementData) -> Result<Self> {
        let columns = ElementColumns::new(data);
        let blocks = (columns.blocks.into_iter())
            .filter(|b| b.count > 0)
            .map(|b| {
                Ok(BlockBuffers {
                    kind: b.kind,
                    count: b.count,
                    nodes: Storage::with_data(ctx, b.kind.name(), &b.nodes)?,
                    material: Storage::with_data(ctx, "block_material", &b.material)?,
                    kept: Storage::with_data(ctx, "block_kept", &at_least_one(b.kept))?,
                })
            })
            .collect::<Result<_>>()?;
        Ok(MeshBuffers {
            reference: Storage::with_data(ctx, "reference", &split_reference(data))?,
            blocks,
            materials: Storage::with_data(ctx, "materials", &device_materials(data))?,
            offsets: Storage::with_data(ctx, "incidence.offsets", &columns.incidence.offsets)?,
            incidence: Storage::with_data(ctx, "incidence", &columns.incidence.corners)?,
        })
    }

    fn all(&self) -> Vec<&Storage> {
        let blocks = (self.blocks.iter()).flat_map(|b| [&b.nodes, &b.material, &b.kept]);
        [
            &self.reference,
            &self.materials,
            &self.offsets,
            &self.incidence,
        ]
        .into_iter()
        .chain(blocks)
        .collect()
    }
}

/// The contact kernels' buffers, grown to the queries of each call.
struct ContactBuffers {
    queries: Storage,
    candidates: Storage,
    faces: Storage,
    points: Storage,
    slips: Storage,
}

impl ContactBuffers {
    fn new(ctx: &GpuContext) -> Result<Self> {
        Ok(ContactBuffers {
            queries: Storage::new(ctx, "contact.queries", 0)?,
            candidates: Storage::new(ctx, "contact.candidates", 0)?,
            faces: Storage::new(ctx, "contact.faces", 0)?,
            points: Storage::new(ctx, "contact.points", 0)?,
            slips: Storage::new(ctx, "contact.slip", 0)?,
        })
    }

    fn all(&self) -> [&Storage; 5] {
        [
            &self.queries,
            &self.candidates,
            &self.faces,
            &self.points,
            &self.slips,
        ]
    }
}

/// The element kernels' launches, fixed for the mesh: each non-empty block's force kernel
/// into the corner forces, then the gather into the nodal forces.
pub(super) struct ElementLaunches {
    pub(super) blocks: Vec<(ElementKind, Launch)>,
    pub(super) gather: Launch,
}

impl ElementLaunches {
    /// The launch of a kind's block, if the mesh has such elements.
    pub(super) fn block(&self, kind: ElementKind) -> Option<&Launch> {
        self.blocks.iter().find(|b| b.0 == kind).map(|b| &b.1)
    }
}

pub struct GpuKernels {
    pub(super) ctx: GpuContext,
    pub(super) nodes: usize,
    /// Where each element corner's force lives on the device.
    pub(super) layout: CornerLayout,
    pub(super) kernels: EngineKernels,
    pub(super) mesh: MeshBuffers,
    pub(super) u: Storage,
    pub(super) v: Storage,
    pub(super) corners: Storage,
    pub(super) forces: Storage,
    contact: ContactBuffers,
    pub(super) staging: Storage,
    uploaded: UploadedQueries,
    query_count: usize,
    pub(super) launches: ElementLaunches,
    contact_binds: Option<(wgpu::BindGroup, wgpu::BindGroup)>,
    /// The device contact search, built at its first use.
    pub(super) search: Option<GpuSearch>,
    scratch: Vec<f32>,
    scratch_split: Vec<Split3>,
    /// Fill every output with NaN before each dispatch (tests: an unwritten entry fails).
    pub fill_nan: bool,
    /// The plies' damage, where any element damages.
    pub(super) damage: Option<(DamageStage, DamageData)>,
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
pub(super) fn device_materials(data: &ElementData) -> Vec<GpuMaterial> {
    data.materials.iter().map(GpuMaterial::of).collect()
}

pub(super) fn at_least_one<T: Default>(mut v: Vec<T>) -> Vec<T> {
    if v.is_empty() {
        v.push(T::default());
    }
    v
}

/// The element kernels' layouts, chosen so that neighbouring invocations (elements, nodes)
/// read and write neighbouring words:
/// - connectivity column by column: node k of element e of a block of E at `nodes[k E + e]`;
/// - corner forces component-major: component a of slot s at `a C + s` (C slots in all),
///   the slots a device's of [`CornerLayout`];
/// - the gather's incidence lists hold those slots, in the order of the twin's corner ids,
///   so the sums run in the twin's order.
pub(crate) struct ElementColumns {
    pub blocks: Vec<BlockColumns>,
    /// The incidence table with slots in place of corner ids.
    pub incidence: Incidence,
}

/// One block's connectivity column by column, its materials, and what its force kernel
/// keeps, in f32 entry by entry (entry i of element e at `i E + e`).
pub(crate) struct BlockColumns {
    pub kind: ElementKind,
    pub count: usize,
    pub nodes: Vec<u32>,
    pub material: Vec<u32>,
    pub kept: Vec<f32>,
}

impl ElementColumns {
    pub fn new(data: &ElementData) -> Self {
        use rayon::prelude::*;
        let kept = KeptData::of(data);
        let blocks = (data.elements.blocks.iter())
            .map(|b| {
                let e = b.len();
                let (k, values) = (b.kind.kept_per_element(), kept.of_kind(b.kind));
                BlockColumns {
                    kind: b.kind,
                    count: e,
                    nodes: column_nodes(b),
                    material: b.material.clone(),
                    kept: (0..k * e)
                        .into_par_iter()
                        .map(|i| values[k * (i % e) + i / e] as f32)
                        .collect(),
                }
            })
            .collect();
        let layout = data.layout();
        let mut incidence = Incidence::new(&data.elements, data.reference.len());
        incidence
            .corners
            .par_iter_mut()
            .for_each(|c| *c = layout.to_device(*c as usize) as u32);
        ElementColumns { blocks, incidence }
    }
}

/// A block's connectivity column by column: corner k of element e at `k E + e` (E elements).
pub(crate) fn column_nodes(b: &crate::element::ElementBlock) -> Vec<u32> {
    use rayon::prelude::*;
    let (e, n) = (b.len(), b.kind.corners());
    (0..n * e)
        .into_par_iter()
        .map(|i| b.nodes[n * (i % e) + i / e])
        .collect()
}

pub(super) fn bytes_of<T>(n: usize) -> u64 {
    (n * std::mem::size_of::<T>()) as u64
}

impl ElementLaunches {
    /// The launches over the mesh's elements and nodes, on the device's displacement.
    fn new(
        ctx: &GpuContext,
        k: &EngineKernels,
        mesh: &MeshBuffers,
        data: &ElementData,
        u: &Storage,
        corners: &Storage,
        forces: &Storage,
    ) -> Self {
        let layout = data.layout();
        let slots = layout.count() as u32;
        let blocks = (mesh.blocks.iter())
            .map(|b| {
                let first = layout.offset(b.kind) as u32;
                (
                    b.kind,
                    k.block_launch(ctx, b, (slots, first), mesh, u, corners),
                )
            })
            .collect();
        let m = mesh;
        ElementLaunches {
            blocks,
            gather: k.node_gather.launch(
                ctx,
                data.reference.len() as u32,
                slots,
                0,
                &m.offsets.buffer,
                &m.incidence.buffer,
                &corners.buffer,
                &forces.buffer,
            ),
        }
    }
}

/// Refuses a mesh whose corner-force entries do not fit the kernels' 32-bit indices.
fn check_indexing(data: &ElementData) -> Result<()> {
    if data.corner_count() > u32::MAX as usize / 3 {
        return Err(ImpactError::Gpu(format!(
            "{} elements exceed the GPU kernels' 32-bit indexing",
            data.elements.count()
        )));
    }
    Ok(())
}

impl GpuKernels {
    pub fn new(ctx: GpuContext, data: &ElementData) -> Result<Self> {
        check_indexing(data)?;
        let nodes = data.reference.len();
        let mesh = MeshBuffers::upload(&ctx, data)?;
        let u = Storage::new(&ctx, "displacement", bytes_of::<Split3>(nodes))?;
        let v = Storage::new(&ctx, "velocity", bytes_of::<f32>(3 * nodes))?;
        let corner_floats = 3 * data.corner_count();
        let corners = Storage::new(&ctx, "corner_forces", bytes_of::<f32>(corner_floats))?;
        let forces = Storage::new(&ctx, "forces", bytes_of::<f32>(3 * nodes))?;
        let kernels = EngineKernels::new(&ctx);
        let launches = ElementLaunches::new(&ctx, &kernels, &mesh, data, &u, &corners, &forces);
        Ok(GpuKernels {
            nodes,
            layout: data.layout(),
            kernels,
            mesh,
            u,
            v,
            corners,
            forces,
            contact: ContactBuffers::new(&ctx)?,
            staging: staging(&ctx)?,
            uploaded: UploadedQueries::default(),
            query_count: 0,
            launches,
            contact_binds: None,
            search: None,
            scratch: Vec::new(),
            scratch_split: Vec::new(),
            fill_nan: false,
            damage: None,
            ctx,
        })
    }

    /// With the plies' damage (none where no element damages): its stage after the force
    /// kernels.
    pub fn with_damage(mut self, damage: Option<DamageData>) -> Result<Self> {
        let Some(data) = damage.filter(DamageData::any) else {
            return Ok(self);
        };
        let target = DamageTarget {
            reference: &self.mesh.reference.buffer,
            displacement: &self.u.buffer,
            velocity: &self.v.buffer,
            corner_forces: &self.corners.buffer,
            layout: &self.layout,
            block_nodes: (self.mesh.blocks.iter())
                .map(|b| (b.kind, &b.nodes.buffer, b.count))
                .collect(),
        };
        let stage = DamageStage::new(&self.ctx, &data, &target)?;
        self.damage = Some((stage, data));
        Ok(self)
    }

    /// Each block's element count, in [`ElementKind::ALL`] order.
    pub(super) fn block_counts(&self) -> Vec<usize> {
        ElementKind::ALL
            .map(|k| {
                (self.mesh.blocks.iter())
                    .find(|b| b.kind == k)
                    .map_or(0, |b| b.count)
            })
            .to_vec()
    }

    /// The damage state on the device (where any element damages).
    pub(super) fn read_damage(&mut self) -> Result<Option<DamageState>> {
        let Some((stage, data)) = &self.damage else {
            return Ok(None);
        };
        stage
            .read_state(&self.ctx, &mut self.staging, data)
            .map(Some)
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// Bytes held on the device by the mesh and the per-call buffers.
    pub fn device_bytes(&self) -> u64 {
        let state = [&self.u, &self.v, &self.corners, &self.forces, &self.staging];
        let damage = self.damage.as_ref().map_or(0, |(d, _)| d.device_bytes());
        self.mesh
            .all()
            .into_iter()
            .chain(state)
            .chain(self.contact.all())
            .map(|s| s.capacity)
            .sum::<u64>()
            + damage
    }

    /// Uploads a nodal vector (3 per node): the velocities in f32, or the displacements as
    /// split pairs.
    pub(super) fn upload_nodal(&mut self, velocity: bool, x: &[f64]) -> Result<()> {
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

    /// Floats of the corner forces: 3 per element corner.
    pub(super) fn corner_floats(&self) -> usize {
        3 * self.layout.count()
    }

    /// Dispatches the element kernels and the gather in an open pass: the internal forces at
    /// the device's displacement into the forces buffer.
    pub(super) fn dispatch_internal_forces(&self, pass: &mut wgpu::ComputePass) {
        self.dispatch_element_kernels(pass);
        (self.kernels.node_gather.0).dispatch(pass, &self.launches.gather);
    }

    /// Dispatches the element kernels in an open pass: the corner forces at the device's
    /// displacement (a gather sums them per node).
    pub(super) fn dispatch_element_kernels(&self, pass: &mut wgpu::ComputePass) {
        let (k, l) = (&self.kernels, &self.launches);
        for (kind, launch) in &l.blocks {
            k.forces(*kind).dispatch(pass, launch);
        }
        if let Some((d, _)) = &self.damage {
            d.dispatch(pass);
        }
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

    /// Records the element kernels alone in one pass.
    pub(super) fn record_element_kernels(&self, enc: &mut wgpu::CommandEncoder) {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("element_kernels"),
            timestamp_writes: None,
        });
        self.dispatch_element_kernels(&mut pass);
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

    /// Uploads (u, v) and the contact queries for a contact kernel: the number of queries,
    /// or `None` (and nothing uploaded) where there are none.
    fn upload_contact(
        &mut self,
        u: &[f64],
        v: &[f64],
        queries: &ContactQueries,
    ) -> Result<Option<usize>> {
        if queries.is_empty() {
            return Ok(None);
        }
        self.upload_state(u, v)?;
        self.sync_queries(queries)?;
        Ok(Some(queries.len()))
    }

    /// Uploads the contact queries if they differ from the last ones, and binds the contact
    /// kernels to the buffers where any was replaced.
    fn sync_queries(&mut self, q: &ContactQueries) -> Result<()> {
        let (ctx, c, up) = (&self.ctx, &mut self.contact, &mut self.uploaded);
        let mut grew = false;
        // compared in the caller's CSR form, so an unchanged set costs no conversion
        if q.secondary != up.secondary || q.offsets != up.offsets {
            let queries: Vec<ContactQuery> = (0..q.len())
                .map(|i| ContactQuery {
                    secondary: q.secondary[i],
                    first: q.offsets[i],
                    end: q.offsets[i + 1],
                })
                .collect();
            grew |= c.queries.upload(ctx, &queries)?;
            grew |= c
                .points
                .ensure(ctx, bytes_of::<types::GpuContactPoint>(q.len()))?;
            grew |= c.slips.ensure(ctx, bytes_of::<[f32; 2]>(q.len()))?;
            up.secondary.clone_from(&q.secondary);
            up.offsets.clone_from(&q.offsets);
        }
        if q.candidates != up.candidates {
            grew |= c.candidates.upload(ctx, &q.candidates)?;
            up.candidates.clone_from(&q.candidates);
        }
        if q.faces != up.faces {
            // `Quad` is `[u32; 4]` with the WGSL struct's layout
            grew |= c.faces.upload(ctx, &to_device::<_, Quad>(&q.faces))?;
            up.faces.clone_from(&q.faces);
        }
        self.query_count = q.len();
        if grew || self.contact_binds.is_none() {
            self.contact_binds = Some(self.bind_contact());
        }
        Ok(())
    }

    /// The bind groups of `contact_gap` and `slip_rate` on the current buffers.
    fn bind_contact(&self) -> (wgpu::BindGroup, wgpu::BindGroup) {
        let (ctx, k, c) = (&self.ctx, &self.kernels, &self.contact);
        let reference = &self.mesh.reference.buffer;
        let gap = k.contact_gap.bind(
            ctx,
            reference,
            &self.u.buffer,
            &self.v.buffer,
            &c.queries.buffer,
            &c.candidates.buffer,
            &c.faces.buffer,
            &c.points.buffer,
        );
        let slip = k.slip_rate.bind(
            ctx,
            reference,
            &self.u.buffer,
            &self.v.buffer,
            &c.queries.buffer,
            &c.faces.buffer,
            &c.points.buffer,
            &c.slips.buffer,
        );
        (gap, slip)
    }

    /// The device contact search of the model's surface interfaces on `faces`.
    fn new_search(&self, model: &Model, faces: &[[u32; 4]]) -> Result<GpuSearch> {
        let (face_first, queries) = search::search_layout(model);
        GpuSearch::new(
            &self.ctx,
            (&self.mesh.reference.buffer, &self.u.buffer, &self.v.buffer),
            faces,
            &face_first,
            &queries,
            0.0,
            None,
        )
    }

    /// The bind group of `contact_gap` (`gap`) or of `slip_rate`, and the grid of the last
    /// queries (their count set in the kernel's params).
    pub(super) fn contact_dispatch(
        &self,
        gap: bool,
    ) -> Result<(&Kernel, &wgpu::BindGroup, [u32; 2])> {
        let Some((gap_bind, slip_bind)) = &self.contact_binds else {
            return Err(ImpactError::Gpu("no contact queries uploaded".into()));
        };
        let (k, bind) = if gap {
            (&self.kernels.contact_gap.0, gap_bind)
        } else {
            (&self.kernels.slip_rate.0, slip_bind)
        };
        Ok((k, bind, k.set_count(&self.ctx, self.query_count as u32)))
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
        if let Some((d, _)) = &mut self.damage {
            d.set_step(&self.ctx, 0.0, false);
        }
        if self.fill_nan {
            self.corners
                .fill_nan(&self.ctx, bytes_of::<f32>(self.corner_floats()));
            self.forces
                .fill_nan(&self.ctx, bytes_of::<f32>(3 * self.nodes));
        }
        let mut enc = self.ctx.encoder("internal_forces");
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
        let Some(n) = self.upload_contact(u, v, queries)? else {
            return Ok(());
        };
        let points = &self.contact.points;
        if self.fill_nan {
            points.fill_nan(&self.ctx, bytes_of::<types::GpuContactPoint>(n));
        }
        let mut enc = self.ctx.encoder("contact_gap");
        let (k, bind, grid) = self.contact_dispatch(true)?;
        k.record(&mut enc, bind, grid);
        let pts: Vec<types::GpuContactPoint> =
            submit_and_read(&self.ctx, &mut self.staging, enc, &points.buffer, n)?;
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
        self.upload_state(u, v)?;
        if self.search.is_none() {
            self.search = Some(self.new_search(model, &queries.faces)?);
        }
        let enc = self.ctx.encoder("contact_search");
        let search = self.search.as_mut().expect("built above");
        let grid = SearchGrid::at(
            search::search_cell(&model.mesh.nodes, u, &queries.faces, margin),
            margin,
            search.mask(),
        );
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
        let Some(n) = self.upload_contact(u, v, queries)? else {
            return Ok(());
        };
        let c = &mut self.contact;
        c.points.upload(
            &self.ctx,
            &to_device::<_, types::GpuContactPoint>(&points[..n]),
        )?;
        if self.fill_nan {
            c.slips.fill_nan(&self.ctx, bytes_of::<[f32; 2]>(n));
        }
        let mut enc = self.ctx.encoder("slip_rate");
        let (k, bind, grid) = self.contact_dispatch(false)?;
        k.record(&mut enc, bind, grid);
        let s: Vec<[f32; 2]> = submit_and_read(
            &self.ctx,
            &mut self.staging,
            enc,
            &self.contact.slips.buffer,
            n,
        )?;
        for (o, x) in out.iter_mut().zip(s) {
            *o = x.map(f64::from);
        }
        Ok(())
    }

    fn step_forces_into(
        &mut self,
        (u, v): (&[f64], &[f64]),
        dt: f64,
        f: &mut [f64],
    ) -> Result<Dissipation> {
        if self.damage.is_none() {
            return (self.internal_forces_into(u, f)).map(|_| Dissipation::default());
        }
        self.upload_state(u, v)?;
        let mut enc = self.ctx.encoder("step_forces");
        if let Some((d, _)) = &mut self.damage {
            d.set_step(&self.ctx, dt, true);
        }
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("step_forces"),
                timestamp_writes: None,
            });
            self.dispatch_internal_forces(&mut pass);
            if let Some((d, _)) = &self.damage {
                d.dispatch_total(&mut pass);
            }
        }
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
        let (d, _) = self.damage.as_ref().expect("damage");
        d.read_dissipation(&self.ctx, &mut self.staging)
    }

    fn damage_values(&self) -> Result<Vec<f64>> {
        // a read-back needs the staging buffer: a copy of the state's path
        let Some((stage, data)) = &self.damage else {
            return Ok(Vec::new());
        };
        let mut staging = super::buffer::staging(&self.ctx)?;
        Ok(stage.read_state(&self.ctx, &mut staging, data)?.flat())
    }

    fn restore_damage(&mut self, values: &[f64]) -> std::result::Result<(), String> {
        let Some((stage, data)) = &self.damage else {
            return match values.is_empty() {
                true => Ok(()),
                false => Err("the checkpoint holds ply damage and this model has none".into()),
            };
        };
        let mut state = DamageState::new(data);
        state.restore(data, values)?;
        stage.write_state(&self.ctx, data, &state);
        Ok(())
    }

    fn damage_cells(&self) -> Option<(Vec<[f64; 4]>, Option<DamagedPoint>)> {
        let (stage, data) = self.damage.as_ref()?;
        let mut staging = super::buffer::staging(&self.ctx).ok()?;
        let state = stage.read_state(&self.ctx, &mut staging, data).ok()?;
        let blocks = self.block_counts();
        Some((
            state.cells(data, &blocks),
            state.first_damaged(data, &blocks),
        ))
    }
}
