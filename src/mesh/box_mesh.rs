//! Structured hex8 grids of boxes.

use super::{BodyParts, Surface};

/// The six faces of a structured box, named by their outward normal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BoxFace {
    XMinus,
    XPlus,
    YMinus,
    YPlus,
    ZMinus,
    ZPlus,
}

impl BoxFace {
    pub const ALL: [BoxFace; 6] = [
        BoxFace::XMinus,
        BoxFace::XPlus,
        BoxFace::YMinus,
        BoxFace::YPlus,
        BoxFace::ZMinus,
        BoxFace::ZPlus,
    ];
    pub const NAMES: [&'static str; 6] = ["x-", "x+", "y-", "y+", "z-", "z+"];

    pub fn parse(s: &str) -> Option<BoxFace> {
        Self::NAMES
            .iter()
            .position(|&n| n == s)
            .map(|i| Self::ALL[i])
    }
    /// Axis of the outward normal (0, 1, 2).
    pub fn axis(self) -> usize {
        self as usize / 2
    }
    /// True for the face on the positive side of its axis.
    pub fn positive(self) -> bool {
        self as usize % 2 == 1
    }
}

/// A structured box: its corners and the elements along each axis.
#[derive(Debug, Clone)]
pub struct BoxSpec {
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub divisions: [usize; 3],
}

/// Meshes a box as `divisions[0] x divisions[1] x divisions[2]` hex8 elements.
///
/// Returns local node coordinates, connectivity, and the six faces as surfaces named
/// `x-`, `x+`, `y-`, `y+`, `z-`, `z+` (in [`BoxFace::ALL`] order, so surface `f as usize` is
/// face `f`), each quad ordered so that its first two edges span the face with
/// `tau_1 x tau_2` along the outward normal. The boundary is the six faces together.
pub fn box_mesh(spec: &BoxSpec) -> BodyParts {
    let [nx, ny, nz] = spec.divisions;
    let (px, py) = (nx + 1, ny + 1);
    let id = |i: usize, j: usize, k: usize| (i + px * (j + py * k)) as u32;
    let mut nodes = Vec::with_capacity(px * py * (nz + 1));
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let t = [
                    i as f64 / nx as f64,
                    j as f64 / ny as f64,
                    k as f64 / nz as f64,
                ];
                nodes.push(std::array::from_fn(|a| {
                    // exact end points, so faces of touching boxes coincide bit for bit
                    if t[a] == 1.0 {
                        spec.max[a]
                    } else {
                        spec.min[a] + t[a] * (spec.max[a] - spec.min[a])
                    }
                }));
            }
        }
    }
    let mut hexes = Vec::with_capacity(nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                hexes.push([
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ]);
            }
        }
    }
    let n = [nx, ny, nz];
    let faces = BoxFace::ALL.map(|face| {
        let a = face.axis();
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        let fixed = if face.positive() { n[a] } else { 0 };
        let at = |ib: usize, ic: usize| {
            let mut ijk = [0usize; 3];
            ijk[a] = fixed;
            ijk[b] = ib;
            ijk[c] = ic;
            id(ijk[0], ijk[1], ijk[2])
        };
        let mut quads = Vec::with_capacity(n[b] * n[c]);
        for ic in 0..n[c] {
            for ib in 0..n[b] {
                let (p00, p10, p11, p01) = (
                    at(ib, ic),
                    at(ib + 1, ic),
                    at(ib + 1, ic + 1),
                    at(ib, ic + 1),
                );
                // b x c = +a: counter-clockwise in (b, c) faces +a, the reverse faces -a
                quads.push(if face.positive() {
                    [p00, p10, p11, p01]
                } else {
                    [p00, p01, p11, p10]
                });
            }
        }
        quads
    });
    let boundary = faces.iter().flatten().copied().collect();
    let surfaces = BoxFace::ALL
        .iter()
        .zip(faces)
        .map(|(f, faces)| Surface {
            name: BoxFace::NAMES[*f as usize].to_string(),
            faces,
        })
        .collect();
    BodyParts {
        nodes,
        hexes,
        tets: Vec::new(),
        boundary,
        surfaces,
        node_sets: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    #[test]
    fn face_quads_point_outwards_and_tile_the_face() {
        let spec = BoxSpec {
            min: [0.0, -1.0, 2.0],
            max: [3.0, 1.0, 2.5],
            divisions: [3, 2, 4],
        };
        let parts = box_mesh(&spec);
        let nodes = &parts.nodes;
        assert_eq!(nodes.len(), 4 * 3 * 5);
        assert_eq!(parts.hexes.len(), 24);
        for face in BoxFace::ALL {
            let quads = &parts.surfaces[face as usize].faces;
            let a = face.axis();
            let mut area = 0.0;
            for q in quads {
                let p: Vec<[f64; 3]> = q.iter().map(|&i| nodes[i as usize]).collect();
                let nrm = cross(sub(p[1], p[0]), sub(p[3], p[0]));
                let sign = if face.positive() { 1.0 } else { -1.0 };
                assert!(nrm[a] * sign > 0.0, "{face:?} quad points inwards");
                area += nrm[a].abs();
                for pt in &p {
                    let want = if face.positive() {
                        spec.max[a]
                    } else {
                        spec.min[a]
                    };
                    assert_eq!(pt[a], want);
                }
            }
            let ext = sub(spec.max, spec.min);
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            assert!((area - ext[b] * ext[c]).abs() < 1e-12);
        }
    }
}
