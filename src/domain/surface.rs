//! The contact surfaces as a model of their own: the nodes every interface reads (a rigid
//! body's node among them), no elements, the interfaces, queries and rigid bodies renumbered
//! onto those nodes.
//!
//! Every rank of a decomposed run holds this small model and works the contact of a step on
//! it ([`super::contact`]) from the state of the nodes it holds, the primary-face nodes it
//! receives and the contacts gathered from the other ranks.

use super::subdomain::at_nodes;
use crate::mesh::Mesh;
use crate::model::{Interface, Model, Primary, RigidBody};

/// `model` restricted to `nodes` (increasing global numbers, holding every node an
/// interface reads): node i of the result is `nodes[i]`.
pub(crate) fn surface_model(model: &Model, nodes: &[u32]) -> Model {
    let at = |n: u32| -> u32 {
        nodes
            .binary_search(&n)
            .expect("every interface node is a surface node") as u32
    };
    let mut queries = model.queries.clone();
    queries.secondary = queries.secondary.iter().map(|&n| at(n)).collect();
    queries.faces = queries.faces.iter().map(|f| f.map(at)).collect();
    let interfaces = (model.interfaces.iter())
        .map(|itf| Interface {
            nodes: itf.nodes.iter().map(|&n| at(n)).collect(),
            secondary_faces: itf.secondary_faces.iter().map(|f| f.map(at)).collect(),
            primary: match &itf.primary {
                Primary::Rigid { body, node, shape } => Primary::Rigid {
                    body: *body,
                    node: at(*node),
                    shape: shape.clone(),
                },
                other => other.clone(),
            },
            ..itf.clone()
        })
        .collect();
    // a body no contact names is no surface node (and no surface contact reads its node)
    let rigid = (model.rigid.iter())
        .map(|b| RigidBody {
            node: nodes.binary_search(&b.node).map_or(u32::MAX, |i| i as u32),
            ..b.clone()
        })
        .collect();
    Model {
        mesh: Mesh {
            nodes: nodes
                .iter()
                .map(|&n| model.mesh.nodes[n as usize])
                .collect(),
            ..Mesh::default()
        },
        materials: model.materials.clone(),
        layups: model.layups.clone(),
        material_ply: model.material_ply.clone(),
        material_axes: model.material_axes.clone(),
        material_source: model.material_source.clone(),
        strengths: model.strengths.clone(),
        damage_laws: model.damage_laws.clone(),
        body_names: model.body_names.clone(),
        fixed: at_nodes(nodes, &model.fixed),
        interfaces,
        queries,
        probes: Vec::new(),
        fix_nodes: Vec::new(),
        fix_motion: Vec::new(),
        fix_paths: Vec::new(),
        reactions: Vec::new(),
        initial_velocity: at_nodes(nodes, &model.initial_velocity),
        gravity: model.gravity,
        // a decomposed run refuses cohesive interfaces (`run_ranks`)
        cohesive: Vec::new(),
        // the rank's loads are its solver's (`LoadForces`)
        loads: Vec::new(),
        held_loads: Vec::new(),
        equations: Vec::new(),
        ties: Vec::new(),
        rigid,
    }
}

/// What a rank looks up in the surface model each step, so that a step's contact work grows
/// with the rank's share of the surfaces and with the nodes it receives, not with the whole
/// model's surfaces.
pub(crate) struct SurfaceIndex {
    /// Per interface: the secondary nodes the rank owns, in the interface's order.
    pub owned_secondary: Vec<Vec<u32>>,
    /// Per interface: its faces whose nodes the rank holds, increasing (none for a plane).
    pub held_faces: Vec<Vec<usize>>,
    /// Per interface: the nodes of its faces the rank owns, increasing (none for a plane).
    pub owned_face_nodes: Vec<Vec<u32>>,
    /// The (interface, place) of each query.
    pub query_slot: Vec<(u32, u32)>,
    /// The faces of each surface node (CSR).
    faces: Csr<u32>,
    /// The (interface, place) of each surface node that is a secondary node of a rigid plane
    /// or a rigid body.
    plane_slots: Csr<(u32, u32)>,
}

impl SurfaceIndex {
    /// The index of `surface` (the model of [`surface_model`]) for a rank that holds the
    /// surface nodes `held` and owns those `owned` says.
    pub fn new(surface: &Model, held: &[bool], owned: impl Fn(u32) -> bool) -> Self {
        let n = surface.mesh.nodes.len();
        let faces = &surface.queries.faces;
        let mut held_faces = Vec::new();
        let mut query_slot = vec![(0, 0); surface.queries.len()];
        let mut planes = Vec::new();
        for (k, itf) in surface.interfaces.iter().enumerate() {
            let mut mine = Vec::new();
            if let crate::model::Primary::Surface {
                faces: range,
                queries,
                ..
            } = &itf.primary
            {
                let whole = |f: &usize| faces[*f].iter().all(|&s| held[s as usize]);
                mine = range.clone().filter(whole).collect();
                for (i, q) in queries.clone().enumerate() {
                    query_slot[q] = (k as u32, i as u32);
                }
            } else {
                let slots = itf.nodes.iter().enumerate();
                planes.extend(slots.map(|(i, &s)| (s, (k as u32, i as u32))));
            }
            held_faces.push(mine);
        }
        let owned_secondary = (surface.interfaces.iter())
            .map(|itf| itf.nodes.iter().copied().filter(|&s| owned(s)).collect())
            .collect();
        let owned_face_nodes = (surface.interfaces.iter())
            .map(|itf| match &itf.primary {
                crate::model::Primary::Surface { faces: range, .. } => {
                    let all = faces[range.clone()].iter().flatten().copied();
                    let mut n: Vec<u32> = all.filter(|&s| owned(s)).collect();
                    n.sort_unstable();
                    n.dedup();
                    n
                }
                // a rigid body's node goes to every rank with the analytic contacts
                // (`super::contact`)
                crate::model::Primary::Plane { .. } | crate::model::Primary::Rigid { .. } => {
                    Vec::new()
                }
            })
            .collect();
        let corners = faces.iter().enumerate().flat_map(|(f, face)| {
            let mut c = face.to_vec();
            c.dedup(); // a triangle repeats its last corner
            c.into_iter().map(move |s| (s, f as u32))
        });
        SurfaceIndex {
            owned_secondary,
            held_faces,
            owned_face_nodes,
            query_slot,
            faces: Csr::new(n, corners),
            plane_slots: Csr::new(n, planes.into_iter()),
        }
    }

    /// The faces surface node `k` is a corner of, increasing.
    pub fn faces_of(&self, k: u32) -> &[u32] {
        self.faces.of(k)
    }

    /// The (rigid plane or rigid body interface, place) slots of surface node `k`.
    pub fn plane_slots_of(&self, k: u32) -> &[(u32, u32)] {
        self.plane_slots.of(k)
    }
}

/// Values listed per key `0..n`, each key's in the order given.
struct Csr<T> {
    start: Vec<u32>,
    values: Vec<T>,
}

impl<T: Copy + Default> Csr<T> {
    fn new(n: usize, pairs: impl Iterator<Item = (u32, T)> + Clone) -> Self {
        let mut start = vec![0u32; n + 1];
        for (k, _) in pairs.clone() {
            start[k as usize + 1] += 1;
        }
        for k in 0..n {
            start[k + 1] += start[k];
        }
        let mut next = start.clone();
        let mut values = vec![T::default(); start[n] as usize];
        for (k, v) in pairs {
            values[next[k as usize] as usize] = v;
            next[k as usize] += 1;
        }
        Csr { start, values }
    }

    fn of(&self, k: u32) -> &[T] {
        &self.values[self.start[k as usize] as usize..self.start[k as usize + 1] as usize]
    }
}
