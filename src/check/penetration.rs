//! Initial penetration: secondary nodes behind their primary surface at t = 0, measured on
//! every interface, and moved onto it where the scene says `initial_penetration = "adjust"`.
//!
//! A node penetrates when its closest point on the primary surface lies in a face (the normal
//! distance is at least [`ALONG_NORMAL`] of the distance: a node beside an open surface's edge
//! does not count) and it lies behind that face by more than [`TOLERANCE`] of its local face
//! size (the square root of its tributary area). Nodes deeper than a face's reach inside the
//! primary body's bounding box are measured against the face with the nearest centroid.

use rayon::prelude::*;
use serde::Serialize;

use crate::geometry::{
    face::FaceKind,
    vector::{dot, norm, sub, V3},
};
use crate::kernels::ContactQueries;
use crate::model::Model;
use crate::model::{Interface, Primary};
use crate::scene::PenetrationPolicy;
use crate::search::{find_candidates, flatten};

/// Penetration below this fraction of the local face size is rounding (touching faces).
pub(crate) const TOLERANCE: f64 = 1e-6;

/// The closest point counts as "on the face" when the normal part of the distance is at least
/// this fraction of it.
pub(crate) const ALONG_NORMAL: f64 = 0.99;

/// What t = 0 looks like on one interface.
#[derive(Debug, Clone, Serialize, Default)]
pub struct InitialContact {
    pub interface: String,
    /// Secondary nodes with a primary face within reach (all of them for a rigid plane).
    pub nodes_in_reach: usize,
    /// Smallest and largest separation (negative: penetration) of the nodes in reach.
    pub gap_min: Option<f64>,
    pub gap_max: Option<f64>,
    /// Nodes behind the surface by more than the tolerance.
    pub penetrating: usize,
    /// The deepest of them: global node number, its position and its depth.
    pub deepest_node: Option<u32>,
    pub deepest_at: Option<[f64; 3]>,
    pub depth: f64,
    /// "error", "adjust" or "ignore".
    pub policy: String,
    /// Nodes moved onto the surface: the penetrating ones under "adjust", and those in front
    /// of it by at most the contact's `adjust` distance.
    pub moved: usize,
    /// Points of the primary surface (its nodes; a rigid shape's centre, axis ends or
    /// corners) inside the secondary body where no secondary node is behind the surface to
    /// show it ([`super::inside`]), and one of them.
    pub primary_inside: usize,
    pub primary_inside_at: Option<[f64; 3]>,
}

/// A node with no primary face within reach.
const OUT_OF_REACH: Sample = Sample {
    gap: f64::INFINITY,
    normal: [0.0; 3],
    on_face: false,
};

/// One secondary node's closest point: separation (< 0 behind), unit normal, and whether it
/// counts (a face within reach, the point on it).
#[derive(Debug, Clone, Copy)]
struct Sample {
    gap: f64,
    normal: V3,
    on_face: bool,
}

/// Measures every interface at the reference configuration and, where the policy is
/// "adjust", moves the penetrating nodes onto the surface, and with an `adjust` distance the
/// nodes in front of it by at most that (in `model.mesh.nodes`; the interfaces' tributary
/// areas are recomputed). Returns one record per interface.
pub fn resolve(
    model: &mut Model,
    policies: &[PenetrationPolicy],
    adjust: &[f64],
) -> Vec<InitialContact> {
    let mut out = Vec::with_capacity(model.interfaces.len());
    let mut moved_any = false;
    for (k, itf) in model.interfaces.iter().enumerate() {
        let samples = samples(model, itf, adjust[k]);
        let (mut record, mut moves) = summarise(model, itf, &samples, policies[k]);
        if policies[k] != PenetrationPolicy::Adjust {
            moves.clear();
        }
        moves.extend(closing(itf, &samples, adjust[k]));
        // where secondary nodes are behind the surface, they tell the overlap already
        let inside = match record.penetrating {
            0 => primary_inside(model, itf),
            _ => Vec::new(),
        };
        record.primary_inside = inside.len();
        record.primary_inside_at = inside.first().copied();
        for (n, delta) in &moves {
            let p = &mut model.mesh.nodes[*n as usize];
            for a in 0..3 {
                p[a] += delta[a];
            }
        }
        record.moved = moves.len();
        moved_any |= !moves.is_empty();
        out.push(record);
    }
    if moved_any {
        model.refresh_areas();
    }
    out
}

/// The moves that close the gaps of the nodes in front of the surface by at most `adjust`
/// (Abaqus's `ADJUST=`): each onto its closest point.
fn closing(itf: &Interface, samples: &[Sample], adjust: f64) -> Vec<(u32, V3)> {
    if adjust <= 0.0 {
        return Vec::new();
    }
    (samples.iter().zip(&itf.nodes))
        .filter(|(s, _)| s.on_face && s.gap > 0.0 && s.gap <= adjust)
        .map(|(s, &n)| (n, s.normal.map(|c| -c * s.gap)))
        .collect()
}

fn summarise(
    model: &Model,
    itf: &Interface,
    samples: &[Sample],
    policy: PenetrationPolicy,
) -> (InitialContact, Vec<(u32, V3)>) {
    let mut r = InitialContact {
        interface: itf.name.clone(),
        policy: policy.name().into(),
        ..Default::default()
    };
    let mut moves = Vec::new();
    for (i, s) in samples.iter().enumerate() {
        if !s.on_face {
            continue;
        }
        r.nodes_in_reach += 1;
        r.gap_min = Some(r.gap_min.map_or(s.gap, |g: f64| g.min(s.gap)));
        r.gap_max = Some(r.gap_max.map_or(s.gap, |g: f64| g.max(s.gap)));
        let depth = -s.gap;
        if depth > TOLERANCE * itf.area[i].sqrt() {
            r.penetrating += 1;
            let n = itf.nodes[i];
            if depth > r.depth {
                r.depth = depth;
                r.deepest_node = Some(n);
                r.deepest_at = Some(model.mesh.nodes[n as usize]);
            }
            moves.push((n, s.normal.map(|c| c * depth)));
        }
    }
    (r, moves)
}

/// The points of `itf`'s primary surface that lie inside its secondary body by more than a
/// thousandth of the secondary faces' size (touching surfaces do not count).
fn primary_inside(model: &Model, itf: &Interface) -> Vec<V3> {
    let x = &model.mesh.nodes;
    let Some(&first) = itf.nodes.first() else {
        return Vec::new();
    };
    let Some(body) = (model.mesh.bodies.iter()).find(|b| b.nodes.contains(&(first as usize)))
    else {
        return Vec::new();
    };
    let points: Vec<V3> = match &itf.primary {
        Primary::Plane { .. } => return Vec::new(),
        Primary::Surface { faces, .. } => {
            let mut nodes: Vec<u32> = model.queries.faces[faces.clone()]
                .iter()
                .flatten()
                .copied()
                .collect();
            nodes.sort_unstable();
            nodes.dedup();
            nodes.iter().map(|&n| x[n as usize]).collect()
        }
        Primary::Rigid { node, shape, .. } => {
            let at = x[*node as usize];
            let moved = |r: V3| std::array::from_fn(|a| at[a] + r[a]);
            use crate::geometry::rigid_shape::RigidShape;
            match shape {
                RigidShape::Sphere { .. } => vec![at],
                RigidShape::Cylinder { axis, length, .. } => [-0.5, 0.0, 0.5]
                    .map(|s| moved(axis.map(|c| s * length * c)))
                    .to_vec(),
                RigidShape::Mesh(m) => m.corners().map(moved).collect(),
                RigidShape::Plane { .. } | RigidShape::Plate { .. } => return Vec::new(),
            }
        }
    };
    let Some(enclosure) = super::inside::Enclosure::new(x, &body.boundary) else {
        return Vec::new();
    };
    let size = (itf.area.iter().sum::<f64>() / itf.area.len().max(1) as f64).sqrt();
    (points.into_par_iter())
        .filter(|p| enclosure.holds(*p, 1e-3 * size))
        .collect()
}

/// The closest point of every secondary node of `itf` (on a meshed surface, those within
/// its largest face side or within `adjust`, whichever is further).
fn samples(model: &Model, itf: &Interface, adjust: f64) -> Vec<Sample> {
    let x = &model.mesh.nodes;
    match &itf.primary {
        Primary::Plane { point, normal } => itf
            .nodes
            .iter()
            .map(|&n| Sample {
                gap: dot(sub(x[n as usize], *point), *normal),
                normal: *normal,
                on_face: true,
            })
            .collect(),
        Primary::Surface { body, faces, .. } => {
            let faces = &model.queries.faces[faces.clone()];
            surface_samples(model, *body, faces, &itf.nodes, adjust)
        }
        Primary::Rigid { body, node, .. } => {
            let (b, at) = (&model.rigid[*body], x[*node as usize]);
            (itf.nodes.iter())
                .map(|&n| {
                    let (gap, normal) = b.distance(at, [0.0; 3], x[n as usize]);
                    Sample {
                        gap,
                        normal,
                        on_face: true,
                    }
                })
                .collect()
        }
    }
}

fn surface_samples(
    model: &Model,
    body: usize,
    faces: &[[u32; 4]],
    nodes: &[u32],
    adjust: f64,
) -> Vec<Sample> {
    let x = &model.mesh.nodes;
    let side = crate::kernels::search_bounds::largest_face_side(x, &vec![0.0; 3 * x.len()], faces);
    let reach = side.max(adjust);
    let mut q = ContactQueries {
        secondary: nodes.to_vec(),
        faces: faces.to_vec(),
        ..Default::default()
    };
    let mut lists = vec![Vec::new(); nodes.len()];
    find_candidates(&q, x, 0..nodes.len(), 0..faces.len(), reach, &mut lists);
    flatten(&mut q, &lists);
    let (lo, hi) = bounding_box(x, model.mesh.bodies[body].nodes.clone());
    (0..nodes.len())
        .into_par_iter()
        .map(|i| {
            let p = x[nodes[i] as usize];
            let best = q
                .candidates_of(i)
                .iter()
                .map(|&f| closest(x, &faces[f as usize], p))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            match best {
                Some((_, s)) => s,
                None if (0..3).all(|a| p[a] >= lo[a] && p[a] <= hi[a]) => {
                    // deep inside the primary body's box: the face with the nearest centroid
                    let nearest = faces.iter().min_by(|a, b| {
                        centroid_distance(x, a, p).total_cmp(&centroid_distance(x, b, p))
                    });
                    nearest.map_or(OUT_OF_REACH, |f| closest(x, f, p).1)
                }
                None => OUT_OF_REACH,
            }
        })
        .collect()
}

/// Distance to the face's closest point and the sample there.
fn closest(x: &[[f64; 3]], face: &[u32; 4], p: V3) -> (f64, Sample) {
    let c = face.map(|n| x[n as usize]);
    let kind = FaceKind::of(face);
    let xi = kind.project(&c, p);
    let (y, ..) = kind.geometry(&c, xi);
    let n = kind.normal(&c, xi);
    let d = sub(p, y);
    let dist = norm(d);
    let gap = dot(d, n);
    // a node on the face to rounding (touching faces, nodes on shared edges) is on it
    let touching = dist <= TOLERANCE * kind.size(&c);
    (
        dist,
        Sample {
            gap,
            normal: n,
            on_face: touching || gap.abs() >= ALONG_NORMAL * dist,
        },
    )
}

/// Distance from p to the face's centroid (a triangle's of its three corners).
fn centroid_distance(x: &[[f64; 3]], face: &[u32; 4], p: V3) -> f64 {
    let corners = FaceKind::of(face).corners(face);
    let w = 1.0 / corners.len() as f64;
    let mut c = [0.0; 3];
    for &n in corners {
        for a in 0..3 {
            c[a] += w * x[n as usize][a];
        }
    }
    norm(sub(p, c))
}

fn bounding_box(x: &[[f64; 3]], nodes: std::ops::Range<usize>) -> (V3, V3) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &x[nodes] {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
}
