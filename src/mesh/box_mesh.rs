//! Structured grids of boxes: hex8, or each hex cut into six tet4.

use super::grading::{axis_nodes, AxisZone};
use super::{BodyParts, Surface};
use crate::element::{ElementKind, Elements};
use crate::geometry::face::Face;

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

/// The elements a box is meshed with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BoxElement {
    #[default]
    Hex8,
    /// Each hex cell cut into six tetrahedra around its diagonal from the lowest to the
    /// highest corner (the Kuhn subdivision): every cell face is cut along its diagonal from
    /// its lowest to its highest corner, so neighbouring cells' triangles match.
    Tet4,
    /// One hex8 with incompatible modes per cell ([`crate::element::hex8i`]).
    Hex8i,
}

impl BoxElement {
    /// The kind of element and how many of them fill a cell.
    pub fn per_cell(self) -> (ElementKind, u64) {
        match self {
            BoxElement::Hex8 => (ElementKind::Hex8, 1),
            BoxElement::Tet4 => (ElementKind::Tet4, 6),
            BoxElement::Hex8i => (ElementKind::Hex8i, 1),
        }
    }
}

/// A structured box: its corners, the cells along each axis and the elements of a cell,
/// and where its cells are refined.
#[derive(Debug, Clone)]
pub struct BoxSpec {
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub divisions: [usize; 3],
    pub element: BoxElement,
    pub refine: Option<Refine>,
}

/// A zone of a box whose cells are at most `size` along each axis (`box.refine`); outside
/// it the spacing grows to the one `divisions` gives ([`super::grading`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refine {
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub size: [f64; 3],
}

impl BoxSpec {
    /// The nodes' coordinates along axis `a`, from `min` to `max`.
    pub fn axis_nodes(&self, a: usize) -> Vec<f64> {
        let zone = self.refine.map(|r| AxisZone {
            lo: r.min[a],
            hi: r.max[a],
            size: r.size[a],
        });
        axis_nodes(self.min[a], self.max[a], self.divisions[a], zone)
    }

    /// The cells along each axis (`divisions`, or more where the box is refined).
    pub fn cells(&self) -> [usize; 3] {
        match self.refine {
            None => self.divisions,
            Some(_) => std::array::from_fn(|a| self.axis_nodes(a).len() - 1),
        }
    }
}

/// The six tets of a hex cell (hex8 corner numbers), each around the diagonal 0-6 with
/// positive volume.
pub const KUHN_TETS: [[usize; 4]; 6] = [
    [0, 1, 2, 6],
    [0, 2, 3, 6],
    [0, 3, 7, 6],
    [0, 7, 4, 6],
    [0, 4, 5, 6],
    [0, 5, 1, 6],
];

/// Meshes a box as `divisions[0] x divisions[1] x divisions[2]` cells, each a hex8 or six
/// tet4 ([`BoxElement`]).
///
/// Returns local node coordinates, connectivity, and the six faces as surfaces named
/// `x-`, `x+`, `y-`, `y+`, `z-`, `z+` (in [`BoxFace::ALL`] order, so surface `f as usize` is
/// face `f`), each quad ordered so that its first two edges span the face with
/// `tau_1 x tau_2` along the outward normal; a tet4 box has each quad's two triangles
/// instead, oriented the same way. The boundary is the six faces together.
pub fn box_mesh(spec: &BoxSpec) -> BodyParts {
    let grid = Grid::new(spec);
    let cells = grid.cells();
    let faces = BoxFace::ALL.map(|face| grid.face_quads(face));
    let mut elements = Elements::default();
    let faces = match spec.element {
        BoxElement::Hex8 | BoxElement::Hex8i => {
            let kind = spec.element.per_cell().0;
            cells.iter().for_each(|h| elements.push(kind, h, 0));
            faces
        }
        BoxElement::Tet4 => {
            (kuhn_tets(&cells).iter()).for_each(|t| elements.push(ElementKind::Tet4, t, 0));
            faces.map(|q| halves(&q))
        }
    };
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
        nodes: grid.nodes(),
        elements,
        boundary,
        surfaces,
        node_sets: Vec::new(),
        axes: Default::default(),
    }
}

/// The node numbering of a structured grid of cells: node (i, j, k) is
/// `i + (nx + 1) (j + (ny + 1) k)`, at the axes' coordinates.
struct Grid {
    n: [usize; 3],
    axes: [Vec<f64>; 3],
}

impl Grid {
    fn new(spec: &BoxSpec) -> Self {
        let axes: [Vec<f64>; 3] = std::array::from_fn(|a| spec.axis_nodes(a));
        Grid {
            n: std::array::from_fn(|a| axes[a].len() - 1),
            axes,
        }
    }

    fn id(&self, i: usize, j: usize, k: usize) -> u32 {
        let (px, py) = (self.n[0] + 1, self.n[1] + 1);
        (i + px * (j + py * k)) as u32
    }

    /// The nodes' coordinates (the box's far faces exactly at `max`).
    fn nodes(&self) -> Vec<[f64; 3]> {
        let [nx, ny, nz] = self.n;
        let [x, y, z] = &self.axes;
        let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
        for zk in z {
            for yj in y {
                for xi in x {
                    nodes.push([*xi, *yj, *zk]);
                }
            }
        }
        nodes
    }

    /// One hex8 per cell.
    fn cells(&self) -> Vec<[u32; 8]> {
        let [nx, ny, nz] = self.n;
        let mut cells = Vec::with_capacity(nx * ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    cells.push([
                        self.id(i, j, k),
                        self.id(i + 1, j, k),
                        self.id(i + 1, j + 1, k),
                        self.id(i, j + 1, k),
                        self.id(i, j, k + 1),
                        self.id(i + 1, j, k + 1),
                        self.id(i + 1, j + 1, k + 1),
                        self.id(i, j + 1, k + 1),
                    ]);
                }
            }
        }
        cells
    }

    /// The quads of one box face, outward.
    fn face_quads(&self, face: BoxFace) -> Vec<Face> {
        let n = self.n;
        let a = face.axis();
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        let fixed = if face.positive() { n[a] } else { 0 };
        let at = |ib: usize, ic: usize| {
            let mut ijk = [0usize; 3];
            ijk[a] = fixed;
            ijk[b] = ib;
            ijk[c] = ic;
            self.id(ijk[0], ijk[1], ijk[2])
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
                quads.push(Face::Quad(if face.positive() {
                    [p00, p10, p11, p01]
                } else {
                    [p00, p01, p11, p10]
                }));
            }
        }
        quads
    }
}

/// Each hex cut into its six Kuhn tets.
fn kuhn_tets(cells: &[[u32; 8]]) -> Vec<[u32; 4]> {
    cells
        .iter()
        .flat_map(|h| KUHN_TETS.map(|t| t.map(|k| h[k])))
        .collect()
}

/// Each face quad cut into two triangles along its diagonal from corner 0 to corner 2 (the
/// cell's lowest to its highest node, the Kuhn tets' cut).
fn halves(quads: &[Face]) -> Vec<Face> {
    quads
        .iter()
        .flat_map(|f| {
            let q = f.corners();
            [
                Face::Triangle([q[0], q[1], q[2]]),
                Face::Triangle([q[0], q[2], q[3]]),
            ]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::tet4;
    use crate::geometry::vector::{cross, sub};

    #[test]
    fn face_quads_point_outwards_and_tile_the_face() {
        let spec = BoxSpec {
            min: [0.0, -1.0, 2.0],
            max: [3.0, 1.0, 2.5],
            divisions: [3, 2, 4],
            element: BoxElement::Hex8,
            refine: None,
        };
        let parts = box_mesh(&spec);
        let nodes = &parts.nodes;
        assert_eq!(nodes.len(), 4 * 3 * 5);
        assert_eq!(parts.elements.count_of(ElementKind::Hex8), 24);
        for face in BoxFace::ALL {
            let quads = &parts.surfaces[face as usize].faces;
            let a = face.axis();
            let mut area = 0.0;
            for q in quads {
                let p: Vec<[f64; 3]> = q.corners().iter().map(|&i| nodes[i as usize]).collect();
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

    /// A tet4 box: six positive tets per cell filling the box's volume, and surfaces of
    /// outward triangles that are exactly the element boundary's faces (so the cut is
    /// conforming: an unmatched inner face would show up in the boundary).
    #[test]
    fn tet4_boxes_are_conforming_and_their_triangles_point_outwards() {
        let spec = BoxSpec {
            min: [0.0, -1.0, 2.0],
            max: [3.0, 1.0, 2.5],
            divisions: [3, 2, 4],
            element: BoxElement::Tet4,
            refine: None,
        };
        let parts = box_mesh(&spec);
        let x = |n: u32| parts.nodes[n as usize];
        let els = &parts.elements;
        assert_eq!((els.count_of(ElementKind::Hex8), els.count()), (0, 6 * 24));
        let mut volume = 0.0;
        for t in els.block(ElementKind::Tet4).corners::<4>() {
            let v = tet4::volume(&t.map(x));
            assert!(v > 0.0, "tet {t:?} has volume {v}");
            volume += v;
        }
        assert!((volume - 3.0 * 2.0 * 0.5).abs() < 1e-12, "{volume}");
        let key = |f: &Face| {
            let f = f.corners();
            let mut k = [f[0], f[1], f[2]];
            k.sort();
            k
        };
        let mut from_elements: Vec<[u32; 3]> =
            crate::mesh::boundary::boundary_faces(&parts.elements)
                .iter()
                .map(key)
                .collect();
        let mut from_surfaces: Vec<[u32; 3]> = parts.boundary.iter().map(key).collect();
        from_elements.sort();
        from_surfaces.sort();
        assert_eq!(from_elements, from_surfaces);
        for face in BoxFace::ALL {
            let a = face.axis();
            let sign = if face.positive() { 1.0 } else { -1.0 };
            for f in &parts.surfaces[face as usize].faces {
                let Face::Triangle(f) = f else {
                    panic!("{f:?} is not a triangle")
                };
                let nrm = cross(sub(x(f[1]), x(f[0])), sub(x(f[2]), x(f[0])));
                assert!(
                    nrm[a] * sign > 0.0,
                    "{face:?} triangle {f:?} points inwards"
                );
            }
        }
    }
}
