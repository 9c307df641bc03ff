//! VTU frames for ParaView: one XML UnstructuredGrid file per frame with its arrays in a raw
//! binary appended block, and a `.pvd` collection that indexes the frames by time.
//!
//! Points are the reference coordinates (ParaView's "Warp By Vector" on `displacement` shows
//! the deformed shape); cells are the elements in global order, each of its kind's VTK type
//! (hex8: VTK_HEXAHEDRON, tet4: VTK_TETRA, [`ElementKind::vtk_cell`]), both with our corner
//! order. Point data: `displacement`, `velocity`, `contact_pressure` (the normal traction of
//! the step on secondary nodes, summed over interfaces; 0 elsewhere) and `contact_gap` (the
//! gap on secondary nodes, g > 0 penetration; NaN on nodes that are no interface's secondary
//! node, or whose primary surface is out of reach). Cell data: `stress` (xx, yy, zz, xy, yz,
//! xz at the element centre), `von_mises`, and the Int32 `body` and `material` of each cell
//! (their indices in the scene's order of `[[body]]` and `[[material]]`); where some body
//! has an `orientation` or `plies`, also `material_stress`, the stress in each cell's
//! material (ply) axes (11, 22, 33, 12, 23, 13).
//!
//! The `.pvd` is rewritten after every frame, so a run that stops early leaves a valid
//! collection of what it wrote. Point data `node` holds each point's node number; a rank of
//! a decomposed run writes its piece of each frame (its elements and nodes, `node` their
//! numbers in the whole model), and rank 0 the `.pvtu` that joins the pieces.

use std::path::{Path, PathBuf};

use super::file::{write_whole, write_whole_with, xml_escape};
use crate::element::ElementKind;
use crate::error::{ImpactError, Result};
use crate::material::Rotation;
use crate::model::Model;

/// Contact values of one node for a frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NodeContact {
    pub pressure: f64,
    pub gap: f64,
    /// The damage of the cohesive pairs the node is in, the largest (NaN where none).
    pub cohesive_damage: f64,
}

impl Default for NodeContact {
    fn default() -> Self {
        NodeContact {
            pressure: 0.0,
            gap: f64::NAN,
            cohesive_damage: f64::NAN,
        }
    }
}

pub(crate) struct VtuWriter {
    dir: PathBuf,
    stem: String,
    /// (time, file name) of every frame written.
    frames: Vec<(f64, String)>,
    /// A rank's writer in a decomposed run: (rank, ranks). Each rank writes its piece of a
    /// frame, and rank 0 the `.pvtu` that joins them and the `.pvd`.
    piece: Option<(usize, usize)>,
}

/// Writes one UnstructuredGrid file of `model` with the state (u, v, contact); returns the
/// headers of its point and cell data arrays (a `.pvtu` lists them).
/// A frame's displacements, velocities, nodes' contact and cells' damage (where any).
type FrameState<'a> = (
    &'a [f64],
    &'a [f64],
    &'a [NodeContact],
    Option<&'a [[f64; 4]]>,
);

fn write_grid(
    path: &Path,
    (model, nodes): (&Model, &[u32]),
    time: f64,
    (u, v, contact, damage): FrameState,
) -> Result<(String, String)> {
    let mesh = &model.mesh;
    let (n_points, n_cells) = (mesh.node_count(), mesh.element_count());
    let mut app = Appended {
        bytes: Vec::new(),
        headers: String::new(),
    };
    let points: Vec<f64> = mesh.nodes.iter().flatten().copied().collect();
    app.array("Points", "Float64", 3, &f64_bytes(&points));
    let points_xml = app.take_headers();

    cell_arrays(&mut app, mesh);
    let cells_xml = app.take_headers();

    app.array("displacement", "Float64", 3, &f64_bytes(u));
    app.array("velocity", "Float64", 3, &f64_bytes(v));
    let pressure: Vec<f64> = contact.iter().map(|c| c.pressure).collect();
    let gap: Vec<f64> = contact.iter().map(|c| c.gap).collect();
    app.array("contact_pressure", "Float64", 1, &f64_bytes(&pressure));
    app.array("contact_gap", "Float64", 1, &f64_bytes(&gap));
    if !model.cohesive.is_empty() {
        let d: Vec<f64> = contact.iter().map(|c| c.cohesive_damage).collect();
        app.array("cohesive_damage", "Float64", 1, &f64_bytes(&d));
    }
    let numbers: Vec<i64> = nodes.iter().map(|&n| i64::from(n)).collect();
    app.array("node", "Int64", 1, &i64_bytes(&numbers));
    let point_data_xml = app.take_headers();

    cell_data(&mut app, model, u);
    if let Some(d) = damage {
        // each cell's acting damage of each mode, the largest over its plies and points
        let values: Vec<f64> = d.iter().flatten().copied().collect();
        app.array("damage", "Float64", 4, &f64_bytes(&values));
    }
    let cell_data_xml = app.take_headers();

    let head = format!(
        "<?xml version=\"1.0\"?>\n\
<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n\
  <UnstructuredGrid>\n\
    <FieldData>\n\
      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{time:e}</DataArray>\n\
    </FieldData>\n\
    <Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\">\n\
      <PointData Vectors=\"displacement\">\n{point_data_xml}      </PointData>\n\
      <CellData>\n{cell_data_xml}      </CellData>\n\
      <Points>\n{points_xml}      </Points>\n\
      <Cells>\n{cells_xml}      </Cells>\n\
    </Piece>\n\
  </UnstructuredGrid>\n\
  <AppendedData encoding=\"raw\">\n_"
    );
    write_whole_with(path, |out| {
        out.write_all(head.as_bytes())?;
        out.write_all(&app.bytes)?;
        out.write_all(b"\n  </AppendedData>\n</VTKFile>\n")
    })?;
    Ok((point_data_xml, cell_data_xml))
}

/// The `.pvtu` that joins `pieces`, whose point and cell data arrays have the headers
/// `point_data` and `cell_data`.
fn pvtu(point_data: &str, cell_data: &str, pieces: &[String]) -> String {
    // each piece's `<DataArray ... format="appended" offset="N"/>` as a `<PDataArray .../>`
    let declare = |headers: &str| -> String {
        (headers.lines())
            .map(|l| {
                let l = l.trim().replacen("<DataArray", "<PDataArray", 1);
                let l = l.split(" format=").next().unwrap_or_default().to_string();
                format!("      {l}/>\n")
            })
            .collect()
    };
    let mut text = format!(
        "<?xml version=\"1.0\"?>\n\
<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n\
  <PUnstructuredGrid GhostLevel=\"0\">\n\
    <PPointData Vectors=\"displacement\">\n{}    </PPointData>\n\
    <PCellData>\n{}    </PCellData>\n\
    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n    </PPoints>\n",
        declare(point_data),
        declare(cell_data)
    );
    for p in pieces {
        text.push_str(&format!("    <Piece Source=\"{}\"/>\n", xml_escape(p)));
    }
    text.push_str("  </PUnstructuredGrid>\n</VTKFile>\n");
    text
}

/// Stress at the element centre: (xx, yy, zz, xy, yz, xz), from the linear strain of u.
pub fn centre_stress(
    kind: ElementKind,
    x: &[[f64; 3]],
    u: &[[f64; 3]],
    m: &crate::material::Elastic,
) -> [f64; 6] {
    pack(&centre_stress_tensor(kind, x, u, m))
}

/// The stress tensor at the element centre.
fn centre_stress_tensor(
    kind: ElementKind,
    x: &[[f64; 3]],
    u: &[[f64; 3]],
    m: &crate::material::Elastic,
) -> [[f64; 3]; 3] {
    crate::element::stress(&kind.centre_gradients(x), u, m)
}

/// von Mises equivalent stress of (xx, yy, zz, xy, yz, xz).
pub(crate) fn von_mises(s: [f64; 6]) -> f64 {
    let d = (s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2);
    (0.5 * d + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])).sqrt()
}

/// The raw appended block: each array as its byte count (u64) then its bytes.
struct Appended {
    bytes: Vec<u8>,
    headers: String,
}

impl Appended {
    fn array(&mut self, name: &str, kind: &str, components: usize, data: &[u8]) {
        let offset = self.bytes.len();
        self.bytes
            .extend_from_slice(&(data.len() as u64).to_le_bytes());
        self.bytes.extend_from_slice(data);
        let comps = if components > 1 {
            format!(" NumberOfComponents=\"{components}\"")
        } else {
            String::new()
        };
        self.headers.push_str(&format!(
            "        <DataArray type=\"{kind}\" Name=\"{name}\"{comps} format=\"appended\" offset=\"{offset}\"/>\n"
        ));
    }
    fn take_headers(&mut self) -> String {
        std::mem::take(&mut self.headers)
    }
}

/// Little-endian bytes of a slice of numbers (a copy of memory on little-endian machines).
fn le_bytes<T: bytemuck::Pod>(x: &[T], to_le: impl Fn(&T) -> T) -> Vec<u8> {
    if cfg!(target_endian = "little") {
        bytemuck::cast_slice(x).to_vec()
    } else {
        let swapped: Vec<T> = x.iter().map(to_le).collect();
        bytemuck::cast_slice(&swapped).to_vec()
    }
}

fn f64_bytes(x: &[f64]) -> Vec<u8> {
    le_bytes(x, |v| f64::from_bits(v.to_bits().to_le()))
}

fn i32_bytes(x: &[i32]) -> Vec<u8> {
    le_bytes(x, |v| v.to_le())
}

fn i64_bytes(x: &[i64]) -> Vec<u8> {
    le_bytes(x, |v| v.to_le())
}

/// The body (index in the scene's order) and material (index in the scene's order) of each
/// cell, in the cells' order ([`crate::mesh::Mesh::elements`]).
/// Each cell's body and scene material (`source`: the scene material of each material index).
fn cell_body_material(mesh: &crate::mesh::Mesh, source: &[usize]) -> (Vec<i32>, Vec<i32>) {
    let mut body = vec![-1i32; mesh.element_count()];
    for (b, part) in mesh.bodies.iter().enumerate() {
        for e in part.element_numbers(&mesh.elements) {
            body[e] = b as i32;
        }
    }
    let material = mesh
        .elements()
        .map(|e| source[e.material as usize] as i32)
        .collect();
    (body, material)
}

/// The centre stress of every cell (xx, yy, zz, xy, yz, zx), its von Mises stress, and the
/// stress in the cell's material axes (11, 22, 33, 12, 23, 13), computed on all threads in
/// cell order.
fn cell_stresses(model: &Model, u: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    use rayon::prelude::*;
    let mesh = &model.mesh;
    let per_cell: Vec<([f64; 6], [f64; 6])> = (0..mesh.element_count())
        .into_par_iter()
        .map(|c| {
            let element = mesh.element(c);
            let (el, material) = (element.nodes, element.material);
            let x = mesh.corners(el);
            let ue: Vec<[f64; 3]> = el
                .iter()
                .map(|&n| {
                    let d = 3 * n as usize;
                    [u[d], u[d + 1], u[d + 2]]
                })
                .collect();
            let m = material as usize;
            // a layered cell's centre stress is that of the ply at its centre
            let law = match &model.layups[m] {
                Some(l) => l.ply_at(0.0).elastic,
                None => model.materials[m],
            };
            let s = centre_stress_tensor(element.kind, &x, &ue, &law);
            (pack(&s), pack(&model.material_axes[m].to_material(&s)))
        })
        .collect();
    let vm = per_cell.iter().map(|(s, _)| von_mises(*s)).collect();
    let global = per_cell.iter().flat_map(|(s, _)| *s).collect();
    let axes = per_cell.iter().flat_map(|(_, s)| *s).collect();
    (global, vm, axes)
}

/// The failure indices of every cell ([`crate::material::failure::INDICES`], five per cell)
/// from its stress in its material axes; zero for cells of a material without strengths.
fn cell_failure_indices(model: &Model, u: &[f64], material_stress: &[f64]) -> Vec<f64> {
    use rayon::prelude::*;
    let mesh = &model.mesh;
    (0..mesh.element_count())
        .into_par_iter()
        .zip(material_stress.par_chunks_exact(6))
        .flat_map_iter(|(c, s)| {
            let e = mesh.element(c);
            let source = model.material_source[e.material as usize];
            let s: [f64; 6] = s.try_into().expect("six components");
            match (&model.strengths[source], &model.layups[e.material as usize]) {
                (Some(k), Some(layup)) => layered_failure_indices(model, c, u, layup, k),
                (Some(k), None) => crate::material::failure_indices(s, k),
                (None, _) => [0.0; 5],
            }
        })
        .collect()
}

/// The failure indices of a layered hex8i cell: each ply's at its mid-thickness on the
/// cell's axis (the condensed modes included), the largest of each index over the plies.
fn layered_failure_indices(
    model: &Model,
    c: usize,
    u: &[f64],
    layup: &crate::material::Layup,
    strength: &crate::material::Strength,
) -> [f64; 5] {
    let mesh = &model.mesh;
    let e = mesh.element(c);
    let x: [[f64; 3]; 8] = mesh
        .corners(e.nodes)
        .try_into()
        .expect("a hex8i has 8 corners");
    let ue: [[f64; 3]; 8] = std::array::from_fn(|k| {
        let d = 3 * e.nodes[k] as usize;
        [u[d], u[d + 1], u[d + 2]]
    });
    let section = crate::element::Section::Layered(layup);
    let mids: Vec<[f64; 3]> = (layup.plies.iter())
        .map(|ply| {
            let mut p = [0.0; 3];
            p[layup.axis] = 0.5 * (ply.lo + ply.hi);
            p
        })
        .collect();
    let gradients = crate::element::hex8i::gradients_at(&x, section, &ue, &mids);
    let mut worst = [0.0f64; 5];
    for (ply, h) in layup.plies.iter().zip(&gradients) {
        let s = ply.elastic.stress(h);
        let local = pack(&model.material_axes[ply.material as usize].to_material(&s));
        let f = crate::material::failure_indices(local, strength);
        for (w, v) in worst.iter_mut().zip(f) {
            *w = w.max(v);
        }
    }
    worst
}

/// (xx, yy, zz, xy, yz, xz) of a symmetric tensor.
fn pack(s: &[[f64; 3]; 3]) -> [f64; 6] {
    [s[0][0], s[1][1], s[2][2], s[0][1], s[1][2], s[0][2]]
}

/// The cells' connectivity, offsets and VTK types.
fn cell_arrays(app: &mut Appended, mesh: &crate::mesh::Mesh) {
    let conn: Vec<u8> = mesh
        .elements()
        .flat_map(|e| e.nodes.iter())
        .flat_map(|&n| (n as i64).to_le_bytes())
        .collect();
    app.array("connectivity", "Int64", 1, &conn);
    let offsets: Vec<u8> = mesh
        .elements()
        .scan(0i64, |end, e| {
            *end += e.nodes.len() as i64;
            Some(*end)
        })
        .flat_map(|c| c.to_le_bytes())
        .collect();
    app.array("offsets", "Int64", 1, &offsets);
    let types: Vec<u8> = mesh.elements().map(|e| e.kind.vtk_cell()).collect();
    app.array("types", "UInt8", 1, &types);
}

/// The cells' stresses, von Mises stress, material-axes stress (where some body has axes),
/// body and material.
fn cell_data(app: &mut Appended, model: &Model, u: &[f64]) {
    let mesh = &model.mesh;
    let (stress, vm, material_stress) = cell_stresses(model, u);
    app.array("stress", "Float64", 6, &f64_bytes(&stress));
    app.array("von_mises", "Float64", 1, &f64_bytes(&vm));
    if model.material_axes.iter().any(|r| *r != Rotation::IDENTITY) {
        app.array(
            "material_stress",
            "Float64",
            6,
            &f64_bytes(&material_stress),
        );
    }
    if model.strengths.iter().any(Option::is_some) {
        let indices = cell_failure_indices(model, u, &material_stress);
        app.array("failure_index", "Float64", 5, &f64_bytes(&indices));
    }
    let (body, material) = cell_body_material(mesh, &model.material_source);
    app.array("body", "Int32", 1, &i32_bytes(&body));
    app.array("material", "Int32", 1, &i32_bytes(&material));
}

impl VtuWriter {
    /// Frames go to `dir/<stem>_NNNNNN.vtu`, the collection to `dir/<stem>.pvd`.
    pub fn new(dir: &Path, stem: &str) -> VtuWriter {
        VtuWriter {
            dir: dir.to_path_buf(),
            stem: stem.to_string(),
            frames: Vec::new(),
            piece: None,
        }
    }

    /// The writer of rank `rank` of `ranks`: frames go to `dir/<stem>_NNNNNN_RRRR.vtu`, one
    /// piece per rank (its elements and the nodes they touch), joined by
    /// `dir/<stem>_NNNNNN.pvtu`, which the `.pvd` indexes.
    pub fn pieces(dir: &Path, stem: &str, rank: usize, ranks: usize) -> VtuWriter {
        VtuWriter {
            piece: Some((rank, ranks)),
            ..VtuWriter::new(dir, stem)
        }
    }

    /// Continues a collection whose frames up to a checkpoint are `written` (time, file
    /// name), as the writer of the whole model (`piece` `None`) or of rank `r` of `P`
    /// (`Some((r, P))`); frames written after the checkpoint are left out of the collection
    /// (and overwritten as the run reaches them again). The frames kept are those the
    /// checkpoint names, whatever process wrote them: a run resumed on another number of
    /// ranks indexes its earlier frames as they were written.
    pub fn resume(
        dir: &Path,
        stem: &str,
        written: &[(f64, String)],
        piece: Option<(usize, usize)>,
    ) -> VtuWriter {
        VtuWriter {
            frames: written.to_vec(),
            piece,
            ..VtuWriter::new(dir, stem)
        }
    }

    /// The frames written so far: (time, file name).
    pub fn written(&self) -> &[(f64, String)] {
        &self.frames
    }

    fn frame_name(stem: &str, step: usize) -> String {
        format!("{stem}_{step:06}.vtu")
    }

    /// Writes one frame of the state (u, v) with the contact values of each node: the whole
    /// model's, or a rank's piece (`model` its part, on its own node numbers, and `nodes`
    /// their global numbers).
    pub fn frame(
        &mut self,
        (model, nodes): (&Model, Option<&[u32]>),
        step: usize,
        time: f64,
        u: &[f64],
        v: &[f64],
        (contact, damage): (&[NodeContact], Option<&[[f64; 4]]>),
    ) -> Result<()> {
        let state = (u, v, contact, damage);
        let Some((rank, ranks)) = self.piece else {
            let name = Self::frame_name(&self.stem, step);
            let nodes: Vec<u32> = (0..model.mesh.node_count() as u32).collect();
            write_grid(&self.dir.join(&name), (model, &nodes), time, state)?;
            self.frames.push((time, name));
            return self.write_collection();
        };
        let piece = |r: usize| format!("{}_{step:06}_{r:04}.vtu", self.stem);
        let nodes = nodes.ok_or_else(|| {
            ImpactError::Ranks("a piece of a frame needs its nodes' global numbers".into())
        })?;
        let path = self.dir.join(piece(rank));
        let (point_data, cell_data) = write_grid(&path, (model, nodes), time, state)?;
        if rank != 0 {
            return Ok(());
        }
        let name = format!("{}_{step:06}.pvtu", self.stem);
        let pieces: Vec<String> = (0..ranks).map(piece).collect();
        let path = self.dir.join(&name);
        let text = pvtu(&point_data, &cell_data, &pieces);
        write_whole(&path, text.as_bytes())?;
        self.frames.push((time, name));
        self.write_collection()
    }

    /// Rewrites `<stem>.pvd` with every frame so far.
    fn write_collection(&self) -> Result<()> {
        let path = self.dir.join(format!("{}.pvd", self.stem));
        let mut text = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, name) in &self.frames {
            text.push_str(&format!(
                "    <DataSet timestep=\"{t:e}\" part=\"0\" file=\"{}\"/>\n",
                xml_escape(name)
            ));
        }
        text.push_str("  </Collection>\n</VTKFile>\n");
        write_whole(&path, text.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Elastic;

    /// A unit cube stretched by 1% along x with nu = 0: sigma_xx = E 0.01, the rest 0, and von
    /// Mises equals |sigma_xx|; a simple shear gives sqrt(3) |tau|.
    #[test]
    fn centre_stress_of_uniform_states() {
        let m = Elastic::from_engineering(200.0, 0.0, 1.0);
        let x = crate::element::hex8::CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0)));
        let stretch = x.map(|p| [0.01 * p[0], 0.0, 0.0]);
        let s = centre_stress(ElementKind::Hex8, &x, &stretch, &m);
        assert!((s[0] - 2.0).abs() < 1e-12 && s[1..].iter().all(|v| v.abs() < 1e-12));
        assert!((von_mises(s) - 2.0).abs() < 1e-12);
        let shear = x.map(|p| [0.01 * p[1], 0.0, 0.0]);
        let s = centre_stress(ElementKind::Hex8, &x, &shear, &m);
        // tau_xy = mu gamma = 100 * 0.01
        assert!((s[3] - 1.0).abs() < 1e-12);
        assert!((von_mises(s) - 3f64.sqrt()).abs() < 1e-12);
    }

    /// Bodies hex, tet, hex: the cells are both hex bodies' hexes, then the tets, and each
    /// carries its body's index and material.
    #[test]
    fn cells_carry_their_body_and_material() {
        let hexes = |n| crate::mesh::BodyParts {
            nodes: vec![[0.0; 3]; 8],
            elements: {
                let mut els = crate::element::Elements::default();
                (0..n).for_each(|_| els.push(ElementKind::Hex8, &[0, 1, 2, 3, 4, 5, 6, 7], 0));
                els
            },
            ..Default::default()
        };
        let tets = crate::mesh::BodyParts {
            nodes: vec![[0.0; 3]; 4],
            elements: {
                let mut els = crate::element::Elements::default();
                (0..3).for_each(|_| els.push(ElementKind::Tet4, &[0, 1, 2, 3], 0));
                els
            },
            ..Default::default()
        };
        let mut mesh = crate::mesh::Mesh::default();
        mesh.push_body(hexes(2), 1);
        mesh.push_body(tets, 0);
        mesh.push_body(hexes(1), 2);
        let (body, material) = cell_body_material(&mesh, &[0, 1, 2]);
        assert_eq!(body, [0, 0, 2, 1, 1, 1]);
        assert_eq!(material, [1, 1, 2, 0, 0, 0]);
    }
}
