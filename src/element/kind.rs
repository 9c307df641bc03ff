//! [`ElementKind`]: what each kind of element is (its corners, faces, VTK cell type) and what
//! it computes once per element (stiffness, masses, volume, Jacobian samples, centre
//! gradients). This is the one place that matches on the kind, besides the per-step force
//! kernels' dispatch (`kernels` on the CPU, `gpu::engine` on a device).

use super::{hex8, hex8i, tet4, Section};

/// A kind of finite element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ElementKind {
    /// The trilinear hexahedron, 2x2x2 Gauss points ([`hex8`]).
    Hex8,
    /// The linear tetrahedron ([`tet4`]).
    Tet4,
    /// The hex8 with incompatible modes, condensed in the element ([`hex8i`]): no shear
    /// locking in bending.
    Hex8i,
}

/// Where an element's Jacobian determinant was sampled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sample {
    GaussPoint(usize),
    Corner(usize),
    Centre,
}

impl std::fmt::Display for Sample {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Sample::GaussPoint(g) => write!(f, "Gauss point {g}"),
            Sample::Corner(k) => write!(f, "corner {k}"),
            Sample::Centre => write!(f, "its centre"),
        }
    }
}

const HEX8_FACES: [&[usize]; 6] = [
    &hex8::FACES[0],
    &hex8::FACES[1],
    &hex8::FACES[2],
    &hex8::FACES[3],
    &hex8::FACES[4],
    &hex8::FACES[5],
];
const TET4_FACES: [&[usize]; 4] = [
    &tet4::FACES[0],
    &tet4::FACES[1],
    &tet4::FACES[2],
    &tet4::FACES[3],
];

impl ElementKind {
    /// Every kind, in the order of a mesh's blocks: global element numbers run through the
    /// blocks in this order.
    pub const ALL: [ElementKind; 3] = [ElementKind::Hex8, ElementKind::Tet4, ElementKind::Hex8i];

    /// The position of the kind in [`Self::ALL`] (its block).
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Corner nodes per element.
    pub const fn corners(self) -> usize {
        match self {
            ElementKind::Hex8 | ElementKind::Hex8i => 8,
            ElementKind::Tet4 => 4,
        }
    }

    /// The name users see ("hex8", "tet4").
    pub const fn name(self) -> &'static str {
        match self {
            ElementKind::Hex8 => "hex8",
            ElementKind::Tet4 => "tet4",
            ElementKind::Hex8i => "hex8i",
        }
    }

    /// The VTK cell type of the kind.
    pub const fn vtk_cell(self) -> u8 {
        match self {
            ElementKind::Hex8 | ElementKind::Hex8i => 12,
            ElementKind::Tet4 => 10,
        }
    }

    /// The faces as corner numbers, each ordered so that its normal points out of a
    /// positively oriented element (quads for a hex8, triangles for a tet4).
    pub fn faces(self) -> &'static [&'static [usize]] {
        match self {
            ElementKind::Hex8 | ElementKind::Hex8i => &HEX8_FACES,
            ElementKind::Tet4 => &TET4_FACES,
        }
    }

    /// The cost of the exact stable step of one element (its (3 n) x (3 n) eigenproblem)
    /// against a tet4's.
    pub const fn exact_step_cost(self) -> usize {
        match self {
            ElementKind::Hex8 | ElementKind::Hex8i => 5,
            ElementKind::Tet4 => 1,
        }
    }

    /// Values the force kernel keeps per element, computed once ([`Self::kept`]).
    pub const fn kept_per_element(self) -> usize {
        match self {
            ElementKind::Hex8 | ElementKind::Tet4 => 0,
            ElementKind::Hex8i => hex8i::KEPT,
        }
    }

    /// What the force kernel keeps of an element (none for hex8 and tet4, which compute from
    /// the corners and the material at every call; a hex8i's condensed stiffness and centre
    /// gradients, [`hex8i::kept`]).
    pub fn kept(self, x: &[[f64; 3]], section: Section) -> Vec<f64> {
        match self {
            ElementKind::Hex8 | ElementKind::Tet4 => Vec::new(),
            ElementKind::Hex8i => hex8i::kept(as_array(x), section).to_vec(),
        }
    }

    /// The edges as corner pairs.
    pub fn edges(self) -> &'static [(usize, usize)] {
        match self {
            ElementKind::Hex8 | ElementKind::Hex8i => &[
                (0, 1),
                (1, 2),
                (2, 3),
                (3, 0),
                (4, 5),
                (5, 6),
                (6, 7),
                (7, 4),
                (0, 4),
                (1, 5),
                (2, 6),
                (3, 7),
            ],
            ElementKind::Tet4 => &[(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)],
        }
    }

    /// Reorders the corners of an element of negative volume (a mirrored corner order) so
    /// that it has positive volume.
    pub fn mirror(self, nodes: &mut [u32]) {
        match self {
            ElementKind::Hex8 | ElementKind::Hex8i => {
                let (bottom, top) = nodes.split_at_mut(4);
                bottom.swap_with_slice(top);
            }
            ElementKind::Tet4 => nodes.swap(1, 2),
        }
    }

    /// Element volume at corners `x`.
    pub fn volume(self, x: &[[f64; 3]]) -> f64 {
        match self {
            ElementKind::Hex8 | ElementKind::Hex8i => hex8::volume(as_array(x)),
            ElementKind::Tet4 => tet4::volume(as_array(x)),
        }
    }

    /// Element stiffness of the section, (3 n) x (3 n) in (node, component) order; hex8i
    /// integrates a layered section ply by ply, hex8 and tet4 take its mean law.
    pub fn stiffness<'a>(self, x: &[[f64; 3]], section: impl Into<Section<'a>>) -> Vec<Vec<f64>> {
        let section = section.into();
        match self {
            ElementKind::Hex8 => (hex8::stiffness(as_array(x), &section.elastic()).iter())
                .map(|r| r.to_vec())
                .collect(),
            ElementKind::Tet4 => (tet4::stiffness(as_array(x), &section.elastic()).iter())
                .map(|r| r.to_vec())
                .collect(),
            ElementKind::Hex8i => (hex8i::stiffness(as_array(x), section).iter())
                .map(|r| r.to_vec())
                .collect(),
        }
    }

    /// Consistent mass per node pair, n x n.
    pub fn consistent_mass(self, x: &[[f64; 3]], density: f64) -> Vec<Vec<f64>> {
        match self {
            // the incompatible modes carry no mass
            ElementKind::Hex8 | ElementKind::Hex8i => (hex8::consistent_mass(as_array(x), density)
                .iter())
            .map(|r| r.to_vec())
            .collect(),
            ElementKind::Tet4 => (tet4::consistent_mass(as_array(x), density).iter())
                .map(|r| r.to_vec())
                .collect(),
        }
    }

    /// Lumped mass of each corner.
    pub fn lumped_mass(self, x: &[[f64; 3]], density: f64) -> Vec<f64> {
        match self {
            ElementKind::Hex8 | ElementKind::Hex8i => {
                hex8::lumped_mass(as_array(x), density).to_vec()
            }
            ElementKind::Tet4 => tet4::lumped_mass(as_array(x), density).to_vec(),
        }
    }

    /// The shape functions' spatial gradients at the element's centre.
    pub fn centre_gradients(self, x: &[[f64; 3]]) -> Vec<[f64; 3]> {
        match self {
            // the modes' gradients vanish at the centre
            ElementKind::Hex8 | ElementKind::Hex8i => {
                hex8::gradients(as_array(x), [0.0; 3]).0.to_vec()
            }
            ElementKind::Tet4 => tet4::gradients(as_array(x)).0.to_vec(),
        }
    }

    /// The Jacobian determinant where the element's shape is checked, and the scale a
    /// positive determinant is judged degenerate against: a hex8 at its Gauss points (whose
    /// mean is the scale) and corners; a tet4 once (6 V), against its extent cubed.
    pub fn jacobian_samples(self, x: &[[f64; 3]]) -> (Vec<(Sample, f64)>, f64) {
        match self {
            ElementKind::Hex8 | ElementKind::Hex8i => {
                let x = as_array(x);
                let det = |p| hex8::gradients(x, p).1;
                let gauss = hex8::gauss_points().map(det);
                let corners = hex8::CORNERS.map(det);
                let mean = gauss.iter().sum::<f64>() / 8.0;
                let samples = (gauss.iter().enumerate())
                    .map(|(k, &d)| (Sample::GaussPoint(k), d))
                    .chain((corners.iter().enumerate()).map(|(k, &d)| (Sample::Corner(k), d)))
                    .collect();
                (samples, mean)
            }
            ElementKind::Tet4 => {
                let det = 6.0 * tet4::volume(as_array(x));
                (vec![(Sample::Centre, det)], super::extent(x).powi(3))
            }
        }
    }
}

impl std::fmt::Display for ElementKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The corners of one element as the fixed array its kind's functions take.
fn as_array<const N: usize>(x: &[[f64; 3]]) -> &[[f64; 3]; N] {
    x.try_into()
        .expect("an element's corner list has its kind's corner count")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A positive reference element of each kind: the unit cube (hex8 and hex8i), the unit
    /// corner tetrahedron.
    fn reference_elements() -> Vec<(ElementKind, Vec<[f64; 3]>)> {
        let cube = hex8::CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0))).to_vec();
        let tet = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        ElementKind::ALL
            .map(|k| {
                (
                    k,
                    if k.corners() == 8 {
                        cube.clone()
                    } else {
                        tet.clone()
                    },
                )
            })
            .to_vec()
    }

    /// Each face's outward normal points away from the centre of the unit element.
    #[test]
    fn faces_point_out_of_the_reference_elements() {
        use crate::geometry::vector::{cross, dot, sub};
        for (kind, x) in reference_elements() {
            assert_eq!(x.len(), kind.corners());
            assert!(kind.volume(&x) > 0.0);
            let n = x.len() as f64;
            let c: [f64; 3] = std::array::from_fn(|a| x.iter().map(|p| p[a]).sum::<f64>() / n);
            for f in kind.faces() {
                let p = |k: usize| x[f[k]];
                let m = cross(sub(p(1), p(0)), sub(p(2), p(0)));
                assert!(
                    dot(m, sub(p(0), c)) > 0.0,
                    "{kind} face {f:?} points inward"
                );
            }
        }
    }

    /// Mirroring a mirrored element restores a positive volume of the same size.
    #[test]
    fn mirror_turns_a_negative_element_positive() {
        for (kind, x) in reference_elements() {
            let v = kind.volume(&x);
            let mut nodes: Vec<u32> = (0..kind.corners() as u32).collect();
            kind.mirror(&mut nodes);
            let mirrored: Vec<[f64; 3]> = nodes.iter().map(|&n| x[n as usize]).collect();
            assert!((kind.volume(&mirrored) + v).abs() < 1e-14);
            kind.mirror(&mut nodes);
            assert_eq!(nodes, (0..kind.corners() as u32).collect::<Vec<_>>());
        }
    }
}
