//! The delamination a run leaves, as a C-scan shows it: every cohesive interface's separated
//! pairs projected onto the plane across the interfaces, seen from the side of their first
//! bodies (the impacted face), each point of the map coloured by the depth of the shallowest
//! separation above it. The projected area is the map's covered area; `delamination.svg` and
//! `.png` draw it.
//!
//! Each separated pair covers its tributary patches: of each face of the second side at its
//! node, the quadrilateral of the node, the midpoints of the face's two edges there and the
//! face's centre (a quarter of a parallelogram, a third of a triangle), the areas the pairs
//! carry. The map's cells are half the smallest extent of a patch (so a structured face's
//! patches fall on whole cells), at most [`MAX_CELLS`] along an axis; a cell is covered where its
//! centre lies in a separated patch.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use crate::error::Result;
use crate::geometry::vector::{cross, dot, norm};
use crate::kernels::cohesive_forces::CohesiveState;
use crate::model::Model;

/// The map has at most this many cells along each axis.
pub const MAX_CELLS: usize = 1024;

/// `summary.json`'s `delamination`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct DelaminationSummary {
    /// The area of the union of the interfaces' separated regions, projected across them.
    pub projected_area: f64,
    pub interfaces: Vec<InterfaceArea>,
}

/// One interface's separated (fully damaged) area.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct InterfaceArea {
    pub name: String,
    pub area: f64,
}

/// The projected map: cells of size `cell` from `origin` in the plane axes, each with the
/// depth of its shallowest separation (NaN where none).
#[derive(Debug, Clone)]
pub struct DelaminationMap {
    pub origin: [f64; 2],
    pub cell: f64,
    pub size: [usize; 2],
    pub depth: Vec<f64>,
    /// The deepest interface's depth (the colour scale's end).
    pub deepest: f64,
}

impl DelaminationMap {
    /// The map of the pairs of `model`'s cohesive interfaces that `state` has separated.
    pub fn of(model: &Model, state: &CohesiveState) -> DelaminationMap {
        let n = view_normal(model);
        let e1 = plane_axis(n);
        let e2 = cross(n, e1);
        let x = |node: u32| model.mesh.nodes[node as usize];
        // the meshed bodies' top (rigid bodies' nodes, a tup above the coupon, left out)
        let top = (model.mesh.bodies.iter())
            .flat_map(|b| &model.mesh.nodes[b.nodes.clone()])
            .map(|x| dot(*x, n))
            .fold(f64::MIN, f64::max);
        let plane = |p: [f64; 3]| [dot(p, e1), dot(p, e2)];
        // every face's corner patches: its place in the plane, its depth and whether its
        // pair is separated
        let mut patches: Vec<([[f64; 2]; 4], f64, bool)> = Vec::new();
        let mut smallest = f64::INFINITY;
        for (c, d) in model.cohesive.iter().zip(&state.damage) {
            let pair: HashMap<u32, usize> = (c.pairs.lower.iter().enumerate())
                .map(|(k, &n)| (n, k))
                .collect();
            for f in &c.faces {
                let corners: Vec<[f64; 3]> = f.corners().iter().map(|&n| x(n)).collect();
                let m = corners.len();
                let centre = mean(&corners);
                for (k, node) in f.corners().iter().enumerate() {
                    let Some(&p) = pair.get(node) else { continue };
                    let (prev, next) = (corners[(k + m - 1) % m], corners[(k + 1) % m]);
                    let patch = [
                        corners[k],
                        mean(&[corners[k], next]),
                        centre,
                        mean(&[prev, corners[k]]),
                    ]
                    .map(plane);
                    smallest = smallest.min(side(&patch));
                    patches.push((patch, top - dot(corners[k], n), d[p] >= 1.0));
                }
            }
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in patches.iter().flat_map(|p| p.0) {
            for a in 0..2 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        if patches.is_empty() {
            (lo, hi) = ([0.0; 2], [1.0; 2]);
        }
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let cell = (0.5 * smallest).max(span / MAX_CELLS as f64);
        // (less a rounding: a span of whole cells takes no cell more)
        let size = [0, 1].map(|a| (((hi[a] - lo[a]) / cell - 1e-9).ceil() as usize).max(1));
        let mut map = DelaminationMap {
            origin: lo,
            cell,
            size,
            depth: vec![f64::NAN; size[0] * size[1]],
            deepest: patches.iter().map(|p| p.1).fold(0.0, f64::max),
        };
        for (patch, depth, separated) in patches {
            if separated {
                map.cover(&patch, depth);
            }
        }
        map
    }

    /// Marks the cells whose centres lie in the convex quadrilateral `patch` with `depth`,
    /// where no shallower separation marks them.
    fn cover(&mut self, patch: &[[f64; 2]; 4], depth: f64) {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in patch {
            for a in 0..2 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let index = |a: usize, x: f64| ((x - self.origin[a]) / self.cell - 0.5).max(0.0);
        let range = |a: usize| {
            (index(a, lo[a]).ceil() as usize)
                ..=(index(a, hi[a]).floor() as usize).min(self.size[a] - 1)
        };
        let area2 = signed_area2(patch);
        for j in range(1) {
            for i in range(0) {
                let c = [0, 1].map(|a| {
                    self.origin[a] + (if a == 0 { i } else { j } as f64 + 0.5) * self.cell
                });
                let inside = (0..4).all(|k| {
                    let (p, q) = (patch[k], patch[(k + 1) % 4]);
                    let cross = (q[0] - p[0]) * (c[1] - p[1]) - (q[1] - p[1]) * (c[0] - p[0]);
                    cross * area2 >= 0.0
                });
                let d = &mut self.depth[j * self.size[0] + i];
                if inside && (d.is_nan() || depth < *d) {
                    *d = depth;
                }
            }
        }
    }

    /// The covered area.
    pub fn area(&self) -> f64 {
        self.depth.iter().filter(|d| !d.is_nan()).count() as f64 * self.cell * self.cell
    }

    /// The map as an SVG picture: the covered cells coloured by depth, a depth scale and the
    /// projected area.
    pub fn svg(&self, title: &str) -> String {
        let (w, h) = (640.0, 560.0);
        let plot = 440.0;
        let scale = plot / (self.size[0].max(self.size[1]) as f64);
        let mut s = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"DejaVu Sans\" font-size=\"13\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"20\" y=\"28\" font-size=\"16\">{}</text>\n",
            crate::output::file::xml_escape(title)
        );
        let (x0, y0) = (30.0, 60.0);
        let _ = writeln!(
            s,
            "<rect x=\"{x0}\" y=\"{y0}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"#f0f0f0\" stroke=\"#888\"/>",
            self.size[0] as f64 * scale,
            self.size[1] as f64 * scale
        );
        for j in 0..self.size[1] {
            // the map's rows drawn from the top: t grows upwards
            let y = y0 + (self.size[1] - 1 - j) as f64 * scale;
            let mut i = 0;
            while i < self.size[0] {
                let d = self.depth[j * self.size[0] + i];
                if d.is_nan() {
                    i += 1;
                    continue;
                }
                let colour = ramp(d / self.deepest.max(f64::MIN_POSITIVE));
                let start = i;
                while i < self.size[0]
                    && ramp(self.depth[j * self.size[0] + i] / self.deepest.max(f64::MIN_POSITIVE))
                        == colour
                {
                    i += 1;
                }
                let _ = writeln!(
                    s,
                    "<rect x=\"{:.2}\" y=\"{y:.2}\" width=\"{:.2}\" height=\"{scale:.2}\" fill=\"{colour}\"/>",
                    x0 + start as f64 * scale,
                    (i - start) as f64 * scale
                );
            }
        }
        let lx = x0 + plot + 40.0;
        let _ = writeln!(s, "<text x=\"{lx}\" y=\"{}\">depth</text>", y0 - 8.0);
        for k in 0..=8 {
            let f = k as f64 / 8.0;
            let y = y0 + f * 200.0;
            let _ = writeln!(
                s,
                "<rect x=\"{lx}\" y=\"{y:.1}\" width=\"20\" height=\"25\" fill=\"{}\"/><text x=\"{}\" y=\"{:.1}\">{:.3}</text>",
                ramp(f),
                lx + 26.0,
                y + 16.0,
                f * self.deepest
            );
        }
        let _ = writeln!(
            s,
            "<text x=\"{x0}\" y=\"{}\">projected delamination {:.4e} (length^2); the frame is {:.4e} x {:.4e}</text>\n</svg>",
            y0 + plot + 40.0,
            self.area(),
            self.size[0] as f64 * self.cell,
            self.size[1] as f64 * self.cell
        );
        s
    }

    /// Writes `dir/delamination.svg` and `.png`.
    pub fn write(&self, dir: &Path, title: &str) -> Result<()> {
        let svg = self.svg(title);
        crate::output::file::write_whole(&dir.join("delamination.svg"), svg.as_bytes())?;
        let png = crate::output::plot::render_png(&svg, 640, 560);
        crate::output::file::write_whole(&dir.join("delamination.png"), &png)
    }
}

/// The summary's figures: the projected area and each interface's separated area.
pub fn summary(model: &Model, state: &CohesiveState, map: &DelaminationMap) -> DelaminationSummary {
    let interfaces = (model.cohesive.iter().zip(&state.damage))
        .map(|(c, d)| InterfaceArea {
            name: c.name.clone(),
            area: (c.pairs.area.iter().zip(d))
                .filter(|(_, &d)| d >= 1.0)
                .map(|(a, _)| a)
                .sum::<f64>()
                + 0.0,
        })
        .collect();
    DelaminationSummary {
        projected_area: map.area(),
        interfaces,
    }
}

/// The mean of points.
fn mean(p: &[[f64; 3]]) -> [f64; 3] {
    let n = p.len() as f64;
    std::array::from_fn(|a| p.iter().map(|x| x[a]).sum::<f64>() / n)
}

/// Twice the signed area of a polygon in the plane.
fn signed_area2(p: &[[f64; 2]; 4]) -> f64 {
    (0..4)
        .map(|k| {
            let (a, b) = (p[k], p[(k + 1) % 4]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum()
}

/// A patch's size: the smaller extent of its bounding box (a structured face's patches
/// are rectangles whose sides are then whole multiples of half of it).
fn side(p: &[[f64; 2]; 4]) -> f64 {
    let extent = |a: usize| {
        let (lo, hi) = p
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), q| {
                (l.min(q[a]), h.max(q[a]))
            });
        hi - lo
    };
    extent(0).min(extent(1))
}

/// The direction the map looks along: the area-weighted mean of the pairs' normals (from
/// the second sides towards the first), or z where they cancel.
fn view_normal(model: &Model) -> [f64; 3] {
    let mut n = [0.0; 3];
    for c in &model.cohesive {
        for (a, m) in c.pairs.area.iter().zip(&c.pairs.normal) {
            (0..3).for_each(|k| n[k] += a * m[k]);
        }
    }
    let l = norm(n);
    match l > 0.0 {
        true => n.map(|x| x / l),
        false => [0.0, 0.0, 1.0],
    }
}

/// A unit axis of the plane across `n`: the global axis most across it, made normal to it.
fn plane_axis(n: [f64; 3]) -> [f64; 3] {
    let k = (0..3)
        .min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .unwrap_or(0);
    let mut e = [0.0; 3];
    e[k] = 1.0;
    let d = dot(e, n);
    let e = [e[0] - d * n[0], e[1] - d * n[1], e[2] - d * n[2]];
    let l = norm(e);
    e.map(|x| x / l)
}

/// A colour from yellow (shallow, f = 0) through green to dark blue (deep, f = 1), in nine
/// steps.
fn ramp(f: f64) -> &'static str {
    const STEPS: [&str; 9] = [
        "#fde725", "#b5de2b", "#6ece58", "#35b779", "#1f9e89", "#26828e", "#31688e", "#3e4989",
        "#482878",
    ];
    STEPS[((f.clamp(0.0, 1.0) * 8.0).round()) as usize]
}
