//! The materials of the elements: each scene material in its own axes, then, for every body
//! with an `orientation` or `plies`, its material turned to the body's (or each ply's) axes,
//! and for every body whose mesh file gives its elements axes (Abaqus `*ORIENTATION`), its
//! material turned to each of those.

use crate::element::ElementKind;
use crate::material::{Elastic, Rotation};
use crate::mesh::orientation::ElementAxes;
use crate::mesh::Mesh;
use crate::scene::{BodyShape, BodySpec, Scene};

/// What the mesh's material indices point to.
#[derive(Debug, Clone, Default)]
pub struct MaterialTable {
    /// The law in the global axes.
    pub elastic: Vec<Elastic>,
    /// The material axes (for stresses in the ply axes).
    pub axes: Vec<Rotation>,
    /// The scene material (`[[material]]` index) of each entry.
    pub source: Vec<usize>,
}

impl MaterialTable {
    fn push(&mut self, m: &Elastic, axes: Rotation, source: usize) -> u32 {
        self.elastic.push(m.rotated(&axes));
        self.axes.push(axes);
        self.source.push(source);
        (self.elastic.len() - 1) as u32
    }
}

/// The table, and each oriented body's elements pointed at their own entries (their ply's
/// by the centroid's coordinate along the stacking axis).
pub(crate) fn element_materials(scene: &Scene, mesh: &mut Mesh) -> MaterialTable {
    let mut table = MaterialTable::default();
    for (i, m) in scene.materials.iter().enumerate() {
        table.push(&m.elastic, Rotation::IDENTITY, i);
    }
    for (b, spec) in scene.bodies.iter().enumerate() {
        if let BodyShape::Imported { parts, .. } = &spec.shape {
            if !parts.axes.is_empty() {
                let m = &scene.materials[spec.material].elastic;
                file_axes(&mut table, m, spec.material, &parts.axes, mesh, b);
                continue;
            }
        }
        if spec.plies.is_none() && spec.orientation == Rotation::IDENTITY {
            continue;
        }
        let first = entries(&mut table, scene, spec);
        orient_elements(mesh, b, spec, first);
    }
    table
}

/// Body `b`'s elements that its mesh file gives axes pointed at entries of its material in
/// those axes (one per distinct axes); the others keep the material's own.
fn file_axes(
    table: &mut MaterialTable,
    m: &Elastic,
    source: usize,
    axes: &ElementAxes,
    mesh: &mut Mesh,
    b: usize,
) {
    let mut seen: Vec<(Rotation, u32)> = Vec::new();
    let mut entry = |r: &Rotation| match seen.iter().find(|(s, _)| s == r) {
        Some(&(_, k)) => k,
        None => {
            let k = table.push(m, *r, source);
            seen.push((*r, k));
            k
        }
    };
    let ranges = mesh.bodies[b].elements.clone();
    for kind in ElementKind::ALL {
        let block = mesh.elements.block_mut(kind);
        let range = ranges[kind.index()].clone();
        for (m, a) in block.material[range].iter_mut().zip(axes.of_kind(kind)) {
            if let Some(r) = a {
                *m = entry(r);
            }
        }
    }
}

/// The body's entries, one per ply (one without plies); returns the first's index.
fn entries(table: &mut MaterialTable, scene: &Scene, spec: &BodySpec) -> u32 {
    let m = &scene.materials[spec.material].elastic;
    match &spec.plies {
        None => table.push(m, spec.orientation, spec.material),
        Some(p) => {
            let turned = |angle| spec.orientation.turned(p.normal(), angle);
            let first = table.push(m, turned(p.layers[0].angle), spec.material);
            for ply in &p.layers[1..] {
                table.push(m, turned(ply.angle), spec.material);
            }
            first
        }
    }
}

/// Points body `b`'s elements at the entries from `first` on.
fn orient_elements(mesh: &mut Mesh, b: usize, spec: &BodySpec, first: u32) {
    let ranges = mesh.bodies[b].elements.clone();
    let nodes = &mesh.nodes;
    let ply = |corners: &[u32]| -> u32 {
        let Some(p) = &spec.plies else { return 0 };
        let t = corners
            .iter()
            .map(|&n| nodes[n as usize][p.axis])
            .sum::<f64>()
            / corners.len() as f64;
        p.ply_at(t) as u32
    };
    for block in &mut mesh.elements.blocks {
        let range = ranges[block.kind.index()].clone();
        let plies: Vec<u32> = (range.clone()).map(|e| ply(block.element(e))).collect();
        for (m, k) in block.material[range].iter_mut().zip(plies) {
            *m = first + k;
        }
    }
}
