//! Broad phase: for each secondary node, the primary faces it may touch during the step.
//!
//! A uniform grid of cells as large as the biggest face holds every face whose bounding
//! box, grown by a margin, overlaps the cell; a node's candidates are the faces of its cell
//! whose grown box contains it. Rebuilt at the start of every step from the current
//! configuration, with a margin that covers the step's motion.

use std::collections::HashMap;

use crate::geometry::face::FaceKind;
use crate::kernels::search_bounds::{fastest_speed, largest_face_side};
use crate::kernels::ContactQueries;
use crate::model::Model;
use crate::model::Primary;

/// Fills the candidate list (`out`) of each query in `query_range` with the faces of
/// `face_range` whose box grown by `margin` holds its node. `x` holds current positions.
pub(crate) fn find_candidates(
    queries: &ContactQueries,
    x: &[[f64; 3]],
    query_range: std::ops::Range<usize>,
    face_range: std::ops::Range<usize>,
    margin: f64,
    out: &mut [Vec<u32>],
) {
    let query_ids: Vec<usize> = query_range.collect();
    find_candidates_of(queries, x, &query_ids, face_range, margin, out);
}

/// [`find_candidates`] for the queries `query_ids` alone (increasing) against the faces
/// `faces` (increasing). Each query's list is the faces whose grown box holds it, in face
/// order, whichever other queries and faces are searched with it.
pub(crate) fn find_candidates_of(
    queries: &ContactQueries,
    x: &[[f64; 3]],
    query_ids: &[usize],
    faces: impl Iterator<Item = usize>,
    margin: f64,
    out: &mut [Vec<u32>],
) {
    let reach = query_box(queries, x, query_ids);
    let (boxes, cell) = face_boxes(queries, x, faces, margin, reach);
    let key = |p: [f64; 3]| p.map(|c| (c / cell).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (b, (_, lo, hi)) in boxes.iter().enumerate() {
        let (k0, k1) = (key(*lo), key(*hi));
        for i in k0[0]..=k1[0] {
            for j in k0[1]..=k1[1] {
                for k in k0[2]..=k1[2] {
                    grid.entry([i, j, k]).or_default().push(b);
                }
            }
        }
    }
    // each query fills its own list (in the grid cell's order): any thread count gives the
    // same lists
    use rayon::prelude::*;
    let secondary = &queries.secondary;
    let lists: Vec<Vec<u32>> = query_ids
        .par_iter()
        .with_min_len(256)
        .map(|&qi| {
            let p = x[secondary[qi] as usize];
            let mut list = Vec::new();
            if let Some(cands) = grid.get(&key(p)) {
                for &b in cands {
                    let (fi, lo, hi) = &boxes[b];
                    if (0..3).all(|a| p[a] >= lo[a] && p[a] <= hi[a]) {
                        list.push(*fi);
                    }
                }
            }
            list
        })
        .collect();
    for (&qi, list) in query_ids.iter().zip(lists) {
        out[qi] = list;
    }
}

/// The box of the nodes of `query_ids`.
fn query_box(queries: &ContactQueries, x: &[[f64; 3]], query_ids: &[usize]) -> [[f64; 3]; 2] {
    let mut reach = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
    for &qi in query_ids {
        let p = x[queries.secondary[qi] as usize];
        for a in 0..3 {
            reach[0][a] = reach[0][a].min(p[a]);
            reach[1][a] = reach[1][a].max(p[a]);
        }
    }
    reach
}

/// A face's grown box: the face, its low and its high corner.
type FaceBox = (u32, [f64; 3], [f64; 3]);

/// The boxes of `faces` grown by `margin` that reach the box `reach`, and the largest side
/// among them (the grid's cell).
fn face_boxes(
    queries: &ContactQueries,
    x: &[[f64; 3]],
    faces: impl Iterator<Item = usize>,
    margin: f64,
    reach: [[f64; 3]; 2],
) -> (Vec<FaceBox>, f64) {
    let mut boxes = Vec::new();
    let mut cell = 0.0f64;
    for fi in faces {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for &n in &queries.faces[fi] {
            for a in 0..3 {
                lo[a] = lo[a].min(x[n as usize][a]);
                hi[a] = hi[a].max(x[n as usize][a]);
            }
        }
        for a in 0..3 {
            lo[a] -= margin;
            hi[a] += margin;
        }
        // only faces whose grown box reaches the queries' box can hold one of them
        if (0..3).any(|a| hi[a] < reach[0][a] || lo[a] > reach[1][a]) {
            continue;
        }
        for a in 0..3 {
            cell = cell.max(hi[a] - lo[a]);
        }
        boxes.push((fi as u32, lo, hi));
    }
    (boxes, cell)
}

/// Flattens per-query candidate lists into the CSR arrays of `queries`.
pub fn flatten(queries: &mut ContactQueries, lists: &[Vec<u32>]) {
    queries.offsets.clear();
    queries.candidates.clear();
    queries.offsets.push(0);
    for l in lists {
        queries.candidates.extend_from_slice(l);
        queries.offsets.push(queries.candidates.len() as u32);
    }
}

/// The largest size (a quad's longer diagonal, a triangle's longest edge) of the model's
/// primary faces (reference configuration): the search grid's cell size and the reach of a
/// candidate.
pub(crate) fn largest_face_size(model: &Model) -> f64 {
    model
        .queries
        .faces
        .iter()
        .map(|f| {
            let p = f.map(|n| model.mesh.nodes[n as usize]);
            FaceKind::of(f).size(&p)
        })
        .fold(0.0, f64::max)
}

/// The reach of a step: the largest face size plus four steps of the fastest node's
/// motion. The broad phase grows face boxes by it, so that a node's candidates cover its
/// motion over the step.
pub fn margin(v: &[f64], dt: f64, face_size: f64) -> f64 {
    face_size + 4.0 * dt * fastest_speed(v)
}

/// The broad phase of every surface interface at displacement `u` with face boxes grown by
/// `margin`. Fills `queries`' CSR arrays (through `lists`, one per query).
pub fn surface_candidates(
    model: &Model,
    queries: &mut ContactQueries,
    lists: &mut [Vec<u32>],
    u: &[f64],
    margin: f64,
) {
    let x: Vec<[f64; 3]> = model
        .mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(n, p)| std::array::from_fn(|a| p[a] + u[3 * n + a]))
        .collect();
    for itf in &model.interfaces {
        if let Primary::Surface {
            faces, queries: q, ..
        } = &itf.primary
        {
            find_candidates(queries, &x, q.clone(), faces.clone(), margin, lists);
        }
    }
    flatten(queries, lists);
}

/// The layout of the device search: the first face of each face's interface, and for each
/// query its secondary node and its interface's face range.
pub fn search_layout(model: &Model) -> (Vec<u32>, Vec<(u32, u32, u32)>) {
    let mut face_first = vec![0u32; model.queries.faces.len()];
    let mut queries = vec![(0u32, 0u32, 0u32); model.queries.len()];
    for itf in &model.interfaces {
        if let Primary::Surface {
            faces, queries: q, ..
        } = &itf.primary
        {
            for f in faces.clone() {
                face_first[f] = faces.start as u32;
            }
            for i in q.clone() {
                queries[i] = (
                    model.queries.secondary[i],
                    faces.start as u32,
                    faces.end as u32,
                );
            }
        }
    }
    (face_first, queries)
}

/// The search grid's cell side at displacement `u`: the largest box side of a face plus the
/// margin, and a thousandth more, so that a node inside a face's grown box lies within one
/// cell of the cell of the face's centroid.
pub fn search_cell(reference: &[[f64; 3]], u: &[f64], faces: &[[u32; 4]], margin: f64) -> f64 {
    ((largest_face_side(reference, u, faces) + margin) * 1.001).max(f64::MIN_POSITIVE)
}
