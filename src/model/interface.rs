//! Contact interfaces as data: the secondary nodes with their tributary areas, and the
//! primary side (another body's faces, a rigid plane or a rigid body's surface).

use std::ops::Range;

use crate::contact::law::ContactLaw;
use crate::geometry::{face::Face, quad::quad_area};
use crate::mesh::Mesh;

/// What the secondary nodes of an interface press against.
#[derive(Debug, Clone)]
pub enum Primary {
    /// Faces (quads, triangles) of another body: `faces` indexes `ContactQueries::faces`, `queries` the queries
    /// of this interface's secondary nodes (in order).
    Surface {
        body: usize,
        faces: Range<usize>,
        queries: Range<usize>,
    },
    /// An analytic immovable plane: `point`, unit `normal` into the free side.
    Plane { point: [f64; 3], normal: [f64; 3] },
    /// The surface of a rigid body (`body` indexes [`super::Model::rigid`]), placed by its
    /// `node`: a constraint acts on that node with the shape's normal, as a face of one node.
    Rigid {
        body: usize,
        node: u32,
        shape: crate::geometry::rigid_shape::RigidShape,
    },
}

/// One `[[contact]]` or `[[rigid_plane]]` of the scene.
#[derive(Debug, Clone)]
pub struct Interface {
    pub name: String,
    /// What tangential force a pressed secondary node may carry.
    pub law: ContactLaw,
    /// Secondary nodes (global numbers).
    pub nodes: Vec<u32>,
    /// Tributary area of each secondary node (a quarter of each adjacent quad's area).
    pub area: Vec<f64>,
    /// The secondary faces the nodes and areas come from.
    pub secondary_faces: Vec<Face>,
    /// The secondary side is a node set: `nodes` are its nodes alone, and their areas come
    /// from `secondary_faces` by [`node_set_areas`].
    pub node_based: bool,
    pub primary: Primary,
    /// A soft pressure-overclosure law (none: hard contact).
    pub pressure_law: Option<crate::scene::PressureLaw>,
    /// A static step's friction stick slope (none: the node's own penalty).
    pub stick_slope: Option<f64>,
}

impl Interface {
    pub fn is_plane(&self) -> bool {
        matches!(self.primary, Primary::Plane { .. })
    }

    pub fn is_rigid(&self) -> bool {
        matches!(self.primary, Primary::Rigid { .. })
    }
}

/// Secondary nodes of a set of faces with their tributary areas (reference configuration):
/// a quad gives a quarter of its area to each corner, a triangle a third.
pub fn tributary_areas(mesh: &Mesh, faces: &[Face]) -> (Vec<u32>, Vec<f64>) {
    let nodes = Mesh::face_nodes(faces);
    let mut area = vec![0.0; nodes.len()];
    for f in faces {
        // a triangle's area is that of the quad of its slots (its last corner twice)
        let a = quad_area(&f.slots().map(|n| mesh.nodes[n as usize]));
        let corners = f.corners();
        let share = a / corners.len() as f64;
        for n in corners {
            let i = nodes
                .binary_search(n)
                .expect("quad node in its own node list");
            area[i] += share;
        }
    }
    (nodes, area)
}

/// The tributary areas of a node set's nodes as a contact's secondary side: a node takes a
/// quarter of each of `faces` at it whose corners the set holds all (a third of a triangle);
/// a node on no such face takes that share of every one of `faces` at it.
pub fn node_set_areas(mesh: &Mesh, nodes: &[u32], faces: &[Face]) -> Vec<f64> {
    let held = |n: &u32| nodes.binary_search(n).is_ok();
    let mut covered = vec![0.0; nodes.len()];
    let mut any = vec![0.0; nodes.len()];
    for f in faces {
        let a = quad_area(&f.slots().map(|n| mesh.nodes[n as usize]));
        let corners = f.corners();
        let share = a / corners.len() as f64;
        let whole = corners.iter().all(held);
        for n in corners {
            if let Ok(i) = nodes.binary_search(n) {
                any[i] += share;
                if whole {
                    covered[i] += share;
                }
            }
        }
    }
    (covered.into_iter().zip(any))
        .map(|(c, a)| if c > 0.0 { c } else { a })
        .collect()
}
