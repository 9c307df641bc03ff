//! Cohesive interfaces as data: the pairs of coincident nodes that bond two bodies' faces,
//! each with its tributary area and the interface's normal there.
//!
//! A pair is the lumped (nodal, Newton-Cotes) form of a zero-thickness cohesive element:
//! each face's quarter of its area (a triangle's third) goes to its corners, as a contact
//! interface's areas do, and the traction acts between the two nodes of a corner. Lumped
//! integration keeps the pairs apart, so the tractions do not oscillate along a steep
//! cohesive zone the way Gauss points of a stiff interface do (Schellekens and de Borst,
//! 1993), and a pair is one kernel thread.

use std::collections::HashMap;

use super::interface::tributary_areas;
use crate::error::{ImpactError, Result};
use crate::geometry::vector::norm;
use crate::kernels::cohesive_forces::CohesivePairs;
use crate::mesh::{Face, Mesh};
use crate::scene::{CohesiveSides, CohesiveSpec, Scene, SurfaceRef};

/// Coincident nodes pair within this fraction of the sides' smallest face size.
pub const PAIR_TOLERANCE: f64 = 1e-6;

/// One `[[cohesive]]` of the scene.
#[derive(Debug, Clone)]
pub struct CohesiveInterface {
    pub name: String,
    pub pairs: CohesivePairs,
    /// The second side's faces, whose corners' shares of area are the pairs' (the
    /// delamination map draws them).
    pub faces: Vec<Face>,
}

/// The pairs of every interface, in the scene's order.
pub fn all_pairs(
    interfaces: &[CohesiveInterface],
) -> impl ExactSizeIterator<Item = &CohesivePairs> {
    interfaces.iter().map(|c| &c.pairs)
}

/// A side's nodes with their tributary areas and area-weighted unit normals.
struct Side {
    nodes: Vec<u32>,
    area: Vec<f64>,
    normal: Vec<[f64; 3]>,
}

impl Side {
    fn of(mesh: &Mesh, faces: &[Face]) -> Side {
        let (nodes, area) = tributary_areas(mesh, faces);
        let mut normal = vec![[0.0; 3]; nodes.len()];
        for f in faces {
            let p = f.slots().map(|n| mesh.nodes[n as usize]);
            let n = crate::geometry::quad::normal(&p, [0.0, 0.0]);
            let a = crate::geometry::quad::quad_area(&p) / f.corners().len() as f64;
            for c in f.corners() {
                let i = nodes
                    .binary_search(c)
                    .expect("a face's corner is its side's");
                (0..3).for_each(|k| normal[i][k] += a * n[k]);
            }
        }
        for n in &mut normal {
            let l = norm(*n);
            *n = n.map(|x| x / l);
        }
        Side {
            nodes,
            area,
            normal,
        }
    }
}

/// A laminate body split at its ply changes for `[[cohesive]]` `spec`: its pairs (the twin
/// above, the original below) and the interface's faces, in the mesh's numbers once
/// [`LaminateSplit::offset`] by the body's first node.
#[derive(Debug, Clone)]
pub(crate) struct LaminateSplit {
    spec: usize,
    pairs: Vec<(u32, u32)>,
    faces: Vec<Face>,
}

impl LaminateSplit {
    pub(crate) fn offset(mut self, first: u32) -> Self {
        self.pairs
            .iter_mut()
            .for_each(|p| *p = (p.0 + first, p.1 + first));
        self.faces = self.faces.iter().map(|f| f.map(|n| n + first)).collect();
        self
    }
}

/// Body `b`'s parts, split at its ply changes where a `[[cohesive]]` asks for it.
pub(crate) fn split_body(
    scene: &Scene,
    b: usize,
    parts: crate::mesh::BodyParts,
) -> (crate::mesh::BodyParts, Option<LaminateSplit>) {
    let asked = (scene.cohesive.iter().enumerate()).find_map(|(i, c)| match &c.sides {
        CohesiveSides::Laminate { body, axis, planes } if *body == b => Some((i, *axis, planes)),
        _ => None,
    });
    let Some((spec, axis, planes)) = asked else {
        return (parts, None);
    };
    let extent = (parts.nodes.iter())
        .map(|x| x[axis])
        .fold(f64::NEG_INFINITY, f64::max)
        - (parts.nodes.iter())
            .map(|x| x[axis])
            .fold(f64::INFINITY, f64::min);
    let s = crate::mesh::split::split_layers(parts, axis, planes, 1e-9 * extent);
    let split = LaminateSplit {
        spec,
        pairs: s.pairs,
        faces: s.faces,
    };
    (s.parts, Some(split))
}

/// Every `[[cohesive]]` of the scene as pairs (`splits`: the laminates' own); a bonded node
/// without a partner is an error naming it.
pub(crate) fn cohesive_interfaces(
    scene: &Scene,
    mesh: &Mesh,
    splits: &[LaminateSplit],
) -> Result<Vec<CohesiveInterface>> {
    (scene.cohesive.iter().enumerate())
        .map(|(i, c)| match &c.sides {
            CohesiveSides::Between(sides) => pair(scene, mesh, (i, c), sides),
            CohesiveSides::Laminate { .. } => {
                let s = splits
                    .iter()
                    .find(|s| s.spec == i)
                    .expect("a laminate's split");
                laminate(scene, mesh, (i, c), s)
            }
        })
        .collect()
}

/// The pairs of a split laminate: each twin with its original, their area and normal from
/// the interface's faces (the layer's below).
fn laminate(
    scene: &Scene,
    mesh: &Mesh,
    (i, c): (usize, &CohesiveSpec),
    split: &LaminateSplit,
) -> Result<CohesiveInterface> {
    let low = Side::of(mesh, &split.faces);
    let inside = |n: u32| in_region(mesh, c, n);
    let mut out = CohesivePairs::new(c.law);
    for &(up, n) in split.pairs.iter().filter(|p| inside(p.1)) {
        // a node of the plane on no face below it (none: the planes are whole layers)
        let Ok(k) = low.nodes.binary_search(&n) else {
            continue;
        };
        out.push((up, n), low.area[k], low.normal[k]);
    }
    if out.upper.is_empty() {
        return Err(nothing_bonded(scene, i, c));
    }
    Ok(CohesiveInterface {
        name: c.name.clone(),
        pairs: out,
        faces: split.faces.clone(),
    })
}

/// Whether node `n` lies in the interface's `region` (everywhere without one).
fn in_region(mesh: &Mesh, c: &CohesiveSpec, n: u32) -> bool {
    (c.region).is_none_or(|r| super::in_region(mesh.nodes[n as usize], r))
}

/// An interface whose `region` holds none of its nodes.
fn nothing_bonded(scene: &Scene, i: usize, c: &CohesiveSpec) -> ImpactError {
    ImpactError::SceneValue {
        path: scene.path.clone(),
        key: format!("cohesive[{i}].region (cohesive `{}`)", c.name),
        message: "holds no node of the interface's faces: nothing is bonded".into(),
    }
}

fn pair(
    scene: &Scene,
    mesh: &Mesh,
    (i, c): (usize, &CohesiveSpec),
    sides: &[SurfaceRef; 2],
) -> Result<CohesiveInterface> {
    let faces = sides.map(|s| &mesh.bodies[s.body].surfaces[s.surface].faces);
    let [up, low] = faces.map(|f| Side::of(mesh, f));
    let size = (faces.iter().flat_map(|f| f.iter()))
        .map(|f| crate::geometry::quad::quad_area(&f.slots().map(|n| mesh.nodes[n as usize])))
        .fold(f64::INFINITY, f64::min)
        .sqrt();
    let tol = PAIR_TOLERANCE * size;
    let inside = |n: u32| in_region(mesh, c, n);
    let grid = Grid::of(mesh, &up.nodes, tol);
    let mut out = CohesivePairs::new(c.law);
    let mut partnered = vec![false; up.nodes.len()];
    for (k, &n) in low.nodes.iter().enumerate().filter(|&(_, &n)| inside(n)) {
        let Some(j) = grid.find(mesh, n) else {
            return Err(unpaired(scene, mesh, (i, sides), (1, 0), n));
        };
        partnered[j] = true;
        let area = 0.5 * (low.area[k] + up.area[j]);
        out.push((up.nodes[j], n), area, low.normal[k]);
    }
    let lone = (up.nodes.iter().zip(&partnered)).find(|&(&n, &p)| !p && inside(n));
    if let Some((&n, _)) = lone {
        return Err(unpaired(scene, mesh, (i, sides), (0, 1), n));
    }
    if out.upper.is_empty() {
        return Err(nothing_bonded(scene, i, c));
    }
    Ok(CohesiveInterface {
        name: c.name.clone(),
        pairs: out,
        faces: faces[1].clone(),
    })
}

/// A bonded node of side `sides.0` without a node of side `sides.1` at its place.
fn unpaired(
    scene: &Scene,
    mesh: &Mesh,
    (i, refs): (usize, &[SurfaceRef; 2]),
    sides: (usize, usize),
    n: u32,
) -> ImpactError {
    let c = &scene.cohesive[i];
    let body = |s: usize| &scene.bodies[refs[s].body].name;
    ImpactError::SceneValue {
        path: scene.path.clone(),
        key: format!("cohesive[{i}].between (cohesive `{}`)", c.name),
        message: format!(
            "node {n} of body `{}` at {:?} has no node of body `{}`'s side within {PAIR_TOLERANCE:e} of the face size: the two sides must be meshed alike where they are bonded (or leave the node out of `region`)",
            body(sides.0),
            mesh.nodes[n as usize],
            body(sides.1),
        ),
    }
}

/// The nodes of one side by cells of the pairing tolerance.
struct Grid {
    cells: HashMap<[i64; 3], Vec<usize>>,
    nodes: Vec<u32>,
    tol: f64,
}

impl Grid {
    fn of(mesh: &Mesh, nodes: &[u32], tol: f64) -> Grid {
        let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (j, &n) in nodes.iter().enumerate() {
            cells
                .entry(cell(mesh.nodes[n as usize], tol))
                .or_default()
                .push(j);
        }
        Grid {
            cells,
            nodes: nodes.to_vec(),
            tol,
        }
    }

    /// The index of the node within the tolerance of node `n`'s place, if any.
    fn find(&self, mesh: &Mesh, n: u32) -> Option<usize> {
        let p = mesh.nodes[n as usize];
        let c = cell(p, self.tol);
        let near = |j: &usize| {
            let q = mesh.nodes[self.nodes[*j] as usize];
            (0..3).all(|a| (p[a] - q[a]).abs() <= self.tol)
        };
        (0..27)
            .map(|k| [k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1])
            .filter_map(|d| self.cells.get(&[c[0] + d[0], c[1] + d[1], c[2] + d[2]]))
            .flat_map(|js| js.iter())
            .find(|j| near(j))
            .copied()
    }
}

fn cell(p: [f64; 3], tol: f64) -> [i64; 3] {
    p.map(|x| (x / tol).floor() as i64)
}
