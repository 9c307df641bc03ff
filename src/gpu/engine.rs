//! [`GpuKernels`]: the [`Kernels`] interface on a wgpu device. Mesh data (split reference
//! coordinates, connectivity, materials, the node incidence table) is uploaded once;
//! each call uploads the displacements (as split f32 pairs) and the f32 velocities,
//! dispatches, and reads back.

use super::buffer::{staging, submit_and_read, Storage};
use super::context::GpuContext;
use super::kernel::{Kernel, Launch};
use super::search::GpuSearch;
use super::types::{self, to_device, ContactQuery, Material, Quad, Split3};
use super::{ContactGap, CornerSelect, Hex8Forces, NodeGather, SlipRate, Tet4Forces};
use crate::backend::Kernels;
use crate::contact::search;
use crate::error::{ImpactError, Result};
use crate::kernels::{ContactPoint, ContactQueries, ElementData, Incidence, SearchGrid};
use crate::model::Model;

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
    pub(super) node_gather: NodeGather,
    pub(super) corner_select: CornerSelect,
    pub(super) contact_gap: ContactGap,
    pub(super) slip_rate: SlipRate,
}

impl EngineKernels {
    fn new(ctx: &GpuContext) -> Self {
        EngineKernels {
            hex8_forces: Hex8Forces::new(ctx),
            tet4_forces: Tet4Forces::new(ctx),
            node_gather: NodeGather::new(ctx),
            corner_select: CornerSelect::new(ctx),
            contact_gap: ContactGap::new(ctx),
            slip_rate: SlipRate::new(ctx),
        }
    }
}

/// The mesh on the device, uploaded once: the split reference coordinates, the connectivity
/// column by column (see [`ElementColumns`]), the materials and the node incidence table.
pub(super) struct MeshBuffers {
    pub(super) reference: Storage,
    hex_nodes: Storage,
    hex_material: Storage,
    tet_nodes: Storage,
    tet_material: Storage,
    materials: Storage,
    offsets: Storage,
    incidence: Storage,
}

impl MeshBuffers {
    fn upload(ctx: &GpuContext, data: &ElementData) -> Result<Self> {
        let columns = ElementColumns::new(data);
        // a binding holds at least one word: a mesh without hexes (or tets) binds one
        // unused placeholder, never dispatched
        let column =
            |label: &'static str, c: Vec<u32>| Storage::with_data(ctx, label, &at_least_one(c));
        Ok(MeshBuffers {
            reference: Storage::with_data(ctx, "reference", &split_reference(data))?,
            hex_nodes: column("hex_nodes", columns.hex_nodes)?,
            hex_material: column("hex_material", columns.hex_material)?,
            tet_nodes: column("tet_nodes", columns.tet_nodes)?,
            tet_material: column("tet_material", columns.tet_material)?,
            materials: Storage::with_data(ctx, "materials", &device_materials(data))?,
            offsets: Storage::with_data(ctx, "incidence.offsets", &columns.incidence.offsets)?,
            incidence: Storage::with_data(ctx, "incidence", &columns.incidence.corners)?,
        })
    }

    fn all(&self) -> [&Storage; 8] {
        [
            &self.reference,
            &self.hex_nodes,
            &self.hex_material,
            &self.tet_nodes,
            &self.tet_material,
            &self.materials,
            &self.offsets,
            &self.incidence,
        ]
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

/// The element kernels' launches, fixed for the mesh: hex8 and tet4 into the corner forces,
/// then the gather into the nodal forces.
pub(super) struct ElementLaunches {
    pub(super) hex8: Launch,
    pub(super) tet4: Launch,
    pub(super) gather: Launch,
}

pub struct GpuKernels {
    pub(super) ctx: GpuContext,
    pub(super) nodes: usize,
    /// Hex8 elements.
    pub(super) elements: usize,
    pub(super) tets_count: usize,
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
    data.materials.iter().map(Material::of).collect()
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
        let (hexes, tets) = (data.hexes.len() as u32, data.tets.len() as u32);
        let slots = data.corner_count() as u32;
        let m = mesh;
        ElementLaunches {
            hex8: k.hex8_forces.launch(
                ctx,
                hexes,
                slots,
                0,
                &m.reference.buffer,
                &u.buffer,
                &m.hex_nodes.buffer,
                &m.hex_material.buffer,
                &m.materials.buffer,
                &corners.buffer,
            ),
            // the tets' corner slots follow the hexes' 8 per hex
            tet4: k.tet4_forces.launch(
                ctx,
                tets,
                slots,
                8 * hexes,
                &m.reference.buffer,
                &u.buffer,
                &m.tet_nodes.buffer,
                &m.tet_material.buffer,
                &m.materials.buffer,
                &corners.buffer,
            ),
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
            data.hexes.len() + data.tets.len()
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
            elements: data.hexes.len(),
            tets_count: data.tets.len(),
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
            ctx,
        })
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// Bytes held on the device by the mesh and the per-call buffers.
    pub fn device_bytes(&self) -> u64 {
        let state = [&self.u, &self.v, &self.corners, &self.forces, &self.staging];
        self.mesh
            .all()
            .into_iter()
            .chain(state)
            .chain(self.contact.all())
            .map(|s| s.capacity)
            .sum()
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

    /// Floats of the corner forces: 3 per hex8 corner and per tet4 corner.
    pub(super) fn corner_floats(&self) -> usize {
        24 * self.elements + 12 * self.tets_count
    }

    /// Dispatches the element kernels and the gather in an open pass: the internal forces at
    /// the device's displacement into the forces buffer.
    pub(super) fn dispatch_internal_forces(&self, pass: &mut wgpu::ComputePass) {
        let (k, l) = (&self.kernels, &self.launches);
        if self.elements > 0 {
            k.hex8_forces.0.dispatch(pass, &l.hex8);
        }
        if self.tets_count > 0 {
            k.tet4_forces.0.dispatch(pass, &l.tet4);
        }
        k.node_gather.0.dispatch(pass, &l.gather);
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
                .ensure(ctx, bytes_of::<types::ContactPoint>(q.len()))?;
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
            &self.mesh.reference.buffer,
            &self.u.buffer,
            &self.v.buffer,
            faces,
            &face_first,
            &queries,
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
            points.fill_nan(&self.ctx, bytes_of::<types::ContactPoint>(n));
        }
        let mut enc = self.ctx.encoder("contact_gap");
        let (k, bind, grid) = self.contact_dispatch(true)?;
        k.record(&mut enc, bind, grid);
        let pts: Vec<types::ContactPoint> =
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
        let Some(n) = self.upload_contact(u, v, queries)? else {
            return Ok(());
        };
        let c = &mut self.contact;
        c.points.upload(
            &self.ctx,
            &to_device::<_, types::ContactPoint>(&points[..n]),
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
}
