//! The contact surfaces as a model of their own: the nodes every interface reads, no
//! elements, the interfaces and queries renumbered onto those nodes.
//!
//! Every rank of a decomposed run holds this small model and works the contact of a step on
//! it ([`super::contact`]) from the state of the nodes it holds, the primary-face nodes it
//! receives and the contacts gathered from the other ranks.

use super::subdomain::at_nodes;
use crate::mesh::Mesh;
use crate::model::{Interface, Model};

/// `model` restricted to `nodes` (increasing global numbers, holding every node an
/// interface reads): node i of the result is `nodes[i]`.
pub fn surface_model(model: &Model, nodes: &[u32]) -> Model {
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
            ..itf.clone()
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
        material_axes: model.material_axes.clone(),
        material_source: model.material_source.clone(),
        body_names: model.body_names.clone(),
        fixed: at_nodes(nodes, &model.fixed),
        interfaces,
        queries,
        probes: Vec::new(),
        fix_nodes: Vec::new(),
        initial_velocity: at_nodes(nodes, &model.initial_velocity),
        gravity: model.gravity,
    }
}
