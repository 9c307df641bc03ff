//! The materials of the elements: each scene material in its own axes, then, for every body
//! with an `orientation` or `plies`, its material turned to the body's (or each ply's) axes,
//! and for every body whose mesh file gives its elements axes (Abaqus `*ORIENTATION`), its
//! material turned to each of those.

use crate::element::ElementKind;
use crate::material::{Elastic, Layup, LayupPly, Rotation};
use crate::mesh::orientation::ElementAxes;
use crate::mesh::Mesh;
use crate::scene::{BodyShape, BodySpec, Plies, Scene};

/// What the mesh's material indices point to.
#[derive(Debug, Clone, Default)]
pub struct MaterialTable {
    /// The law in the global axes.
    pub elastic: Vec<Elastic>,
    /// The material axes (for stresses in the ply axes).
    pub axes: Vec<Rotation>,
    /// The scene material (`[[material]]` index) of each entry.
    pub source: Vec<usize>,
    /// The plies of each entry that is a layered section (its `elastic` is their mean).
    pub layups: Vec<Option<Layup>>,
    /// The ply (of its body's plies, from the lowest) of each entry that is one ply's.
    pub ply: Vec<Option<usize>>,
}

impl MaterialTable {
    fn push(&mut self, m: &Elastic, axes: Rotation, source: usize) -> u32 {
        self.elastic.push(m.rotated(&axes));
        self.axes.push(axes);
        self.source.push(source);
        self.layups.push(None);
        self.ply.push(None);
        (self.elastic.len() - 1) as u32
    }

    /// The entry of a layered section (one per distinct layup), with the axes of the ply at
    /// its centre.
    fn push_layup(&mut self, layup: Layup, source: usize) -> u32 {
        if let Some(k) = self.layups.iter().position(|l| l.as_ref() == Some(&layup)) {
            return k as u32;
        }
        self.elastic.push(layup.average());
        self.axes
            .push(self.axes[layup.ply_at(0.0).material as usize]);
        self.source.push(source);
        self.layups.push(Some(layup));
        self.ply.push(None);
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
        if let Some(plies) = &spec.plies {
            layer_hex8i(&mut table, mesh, b, (plies, spec.material), first);
        }
    }
    table
}

/// Body `b`'s hex8i elements that span several plies pointed at layered sections: each ply
/// integrated over its own part of the element's thickness. An element whose faces across
/// the stacking axis do not lie on planes of constant stacking coordinate keeps the ply at its
/// centroid.
fn layer_hex8i(
    table: &mut MaterialTable,
    mesh: &mut Mesh,
    b: usize,
    (plies, source): (&Plies, usize),
    first: u32,
) {
    let range = mesh.bodies[b].elements[ElementKind::Hex8i.index()].clone();
    let nodes = &mesh.nodes;
    let block = mesh.elements.block_mut(ElementKind::Hex8i);
    for e in range {
        let t: Vec<f64> = (block.element(e).iter())
            .map(|&n| nodes[n as usize][plies.axis])
            .collect();
        if let Some(layup) = layup_of(&t, plies, table, first) {
            block.material[e] = table.push_layup(layup, source);
        }
    }
}

/// The layup of a hex whose corners lie at stacking coordinates `t`, where it spans more than
/// one ply and its faces across the stacking axis are flat in it (the ply entries from
/// `first` on).
fn layup_of(t: &[f64], plies: &Plies, table: &MaterialTable, first: u32) -> Option<Layup> {
    use crate::element::hex8::CORNERS;
    let face_mean = |a: usize, side: f64| -> f64 {
        (0..8)
            .filter(|&k| CORNERS[k][a] == side)
            .map(|k| t[k])
            .sum::<f64>()
            / 4.0
    };
    let rise = |a: usize| face_mean(a, 1.0) - face_mean(a, -1.0);
    let axis = (0..3).max_by(|&a, &c| rise(a).abs().total_cmp(&rise(c).abs()))?;
    let (delta, mid) = (
        rise(axis),
        0.5 * (face_mean(axis, 1.0) + face_mean(axis, -1.0)),
    );
    let flat = (0..8).all(|k| {
        let on_plane = mid + 0.5 * CORNERS[k][axis] * delta;
        (t[k] - on_plane).abs() <= 1e-9 * delta.abs()
    });
    if !flat || delta == 0.0 {
        return None;
    }
    let (lo, hi) = (mid - 0.5 * delta.abs(), mid + 0.5 * delta.abs());
    // each ply's part of lo..hi in the natural coordinate along `axis`
    let natural = |x: f64| 2.0 * (x - mid) / delta;
    let mut out = Vec::new();
    let mut bottom = plies.start;
    for (k, ply) in plies.layers.iter().enumerate() {
        let top = bottom + ply.thickness;
        let (a, c) = (bottom.max(lo), top.min(hi));
        bottom = top;
        // a sliver of a ply within rounding of the element's face is no ply of it
        if c - a <= 1e-9 * delta.abs() {
            continue;
        }
        let (s0, s1) = (natural(a), natural(c));
        let material = first + k as u32;
        out.push(LayupPly {
            lo: s0.min(s1),
            hi: s0.max(s1),
            elastic: table.elastic[material as usize],
            material,
        });
    }
    if out.len() < 2 {
        return None;
    }
    out.sort_by(|p, q| p.lo.total_cmp(&q.lo));
    let n = out.len();
    (out[0].lo, out[n - 1].hi) = (-1.0, 1.0);
    for i in 1..n {
        // neighbours meet exactly
        out[i].lo = out[i - 1].hi;
    }
    Some(Layup { axis, plies: out })
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
            for k in 0..p.layers.len() {
                table.ply[first as usize + k] = Some(k);
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
