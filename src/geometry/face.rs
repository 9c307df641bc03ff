//! A boundary face ([`Face`]) of either kind: a bilinear quad ([`super::quad`], a hex8 face)
//! or a linear triangle ([`super::triangle`], a tet4 face). The contact kernels read a face
//! as four node slots ([`Face::slots`]) and ask its [`FaceKind`] for its shape functions,
//! geometry, normal and closest point without caring which it is (twin:
//! `shaders/shared/face.wgsl`).

use super::{
    quad, triangle,
    vector::{norm, sub, V3},
};

/// A face of an element's boundary, outward: its corner nodes, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Face {
    Quad([u32; 4]),
    Triangle([u32; 3]),
}

impl Face {
    /// The face with these corners (3 or 4, in order).
    pub fn of_corners(corners: &[u32]) -> Face {
        match *corners {
            [a, b, c] => Face::Triangle([a, b, c]),
            [a, b, c, d] => Face::Quad([a, b, c, d]),
            _ => panic!("a face has 3 or 4 corners, not {}", corners.len()),
        }
    }

    pub fn kind(&self) -> FaceKind {
        match self {
            Face::Quad(_) => FaceKind::Quad,
            Face::Triangle(_) => FaceKind::Triangle,
        }
    }

    /// The corner nodes, in order.
    pub fn corners(&self) -> &[u32] {
        match self {
            Face::Quad(q) => q,
            Face::Triangle(t) => t,
        }
    }

    /// The face with each node renumbered by `f`.
    pub fn map(self, f: impl Fn(u32) -> u32) -> Face {
        match self {
            Face::Quad(q) => Face::Quad(q.map(f)),
            Face::Triangle(t) => Face::Triangle(t.map(f)),
        }
    }

    /// The four node slots the contact kernels read (CPU twins and WGSL): a quad's corners;
    /// a triangle's three, its third again in the fourth slot, whose shape function is zero
    /// there ([`FaceKind::of`] reads the kind back).
    pub fn slots(&self) -> [u32; 4] {
        match *self {
            Face::Quad(q) => q,
            Face::Triangle([a, b, c]) => [a, b, c, c],
        }
    }

    /// The face of the kernels' four slots ([`Self::slots`]).
    pub fn from_slots(s: [u32; 4]) -> Face {
        match FaceKind::of(&s) {
            FaceKind::Quad => Face::Quad(s),
            FaceKind::Triangle => Face::Triangle([s[0], s[1], s[2]]),
        }
    }
}

/// Which interpolation a primary face has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaceKind {
    Quad,
    Triangle,
}

impl FaceKind {
    /// The kind of a face given by its kernel slots ([`Face::slots`]): a triangle's fourth
    /// slot repeats its third.
    pub fn of(nodes: &[u32; 4]) -> Self {
        if nodes[2] == nodes[3] {
            FaceKind::Triangle
        } else {
            FaceKind::Quad
        }
    }

    /// Shape functions at xi (one per stored corner).
    pub fn shape(self, xi: [f64; 2]) -> [f64; 4] {
        match self {
            FaceKind::Quad => quad::shape(xi),
            FaceKind::Triangle => triangle::shape(xi),
        }
    }

    /// Point, covariant tangents and mixed second derivative at xi.
    pub fn geometry(self, p: &[V3; 4], xi: [f64; 2]) -> (V3, V3, V3, V3) {
        match self {
            FaceKind::Quad => quad::geometry(p, xi),
            FaceKind::Triangle => triangle::geometry(p, xi),
        }
    }

    /// Unit outward normal at xi.
    pub fn normal(self, p: &[V3; 4], xi: [f64; 2]) -> V3 {
        match self {
            FaceKind::Quad => quad::normal(p, xi),
            FaceKind::Triangle => triangle::normal(p),
        }
    }

    /// Convected coordinates of the face's closest point to x.
    pub fn project(self, p: &[V3; 4], x: V3) -> [f64; 2] {
        match self {
            FaceKind::Quad => quad::project(p, x),
            FaceKind::Triangle => triangle::project(p, x),
        }
    }

    /// The face's distinct corners: a triangle's three, a quad's four.
    pub fn corners(self, nodes: &[u32; 4]) -> &[u32] {
        match self {
            FaceKind::Quad => nodes,
            FaceKind::Triangle => &nodes[..3],
        }
    }

    /// The face's size: a quad's longer diagonal, a triangle's longest edge.
    pub fn size(self, p: &[V3; 4]) -> f64 {
        let d = |a: usize, b: usize| norm(sub(p[a], p[b]));
        match self {
            FaceKind::Quad => d(2, 0).max(d(3, 1)),
            FaceKind::Triangle => d(1, 0).max(d(2, 1)).max(d(2, 0)),
        }
    }
}

/// Shape-function weights of face `nodes` at xi.
pub fn shape(nodes: &[u32; 4], xi: [f64; 2]) -> [f64; 4] {
    FaceKind::of(nodes).shape(xi)
}

/// The value at shape-function weights `w` of a nodal field (`values`, one per node) over
/// face `nodes` (twin of `face_interpolate` in `shaders/shared/face.wgsl`).
pub(crate) fn interpolate(nodes: &[u32; 4], w: [f64; 4], values: &[V3]) -> V3 {
    let mut out = [0.0; 3];
    for k in 0..4 {
        for a in 0..3 {
            out[a] += w[k] * values[nodes[k] as usize][a];
        }
    }
    out
}
