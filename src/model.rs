//! The discrete model built from a scene: mesh, materials, constraints, contact interfaces,
//! probes. Reading and checking (the scene) is kept apart from the time loop (integrate).

use crate::contact::{tributary_areas, Interface, Primary};
use crate::kernels::{ContactQueries, ElementData};
use crate::material::Elastic;
use crate::mesh::Mesh;
use crate::scene::{NodeSelection, Scene};

#[derive(Debug, Clone)]
pub struct Probe {
    pub name: String,
    pub node: u32,
}

#[derive(Debug, Clone)]
pub struct Model {
    pub mesh: Mesh,
    pub materials: Vec<Elastic>,
    pub body_names: Vec<String>,
    /// True for each prescribed (zero) degree of freedom, 3 per node.
    pub fixed: Vec<bool>,
    pub interfaces: Vec<Interface>,
    /// Contact queries of all surface interfaces; candidates are filled by the broad phase.
    pub queries: ContactQueries,
    pub probes: Vec<Probe>,
    /// Initial velocity, 3 per node.
    pub initial_velocity: Vec<f64>,
    pub gravity: [f64; 3],
}

impl Model {
    pub fn from_scene(scene: &Scene) -> Model {
        let mut mesh = Mesh::default();
        let materials: Vec<Elastic> = scene
            .materials
            .iter()
            .map(|m| Elastic::from_engineering(m.youngs_modulus, m.poissons_ratio, m.density))
            .collect();
        let mut initial_velocity = Vec::new();
        for b in &scene.bodies {
            let parts = b.parts();
            for _ in 0..parts.nodes.len() {
                initial_velocity.extend_from_slice(&b.velocity);
            }
            mesh.push_body(parts, b.material);
        }

        let mut fixed = vec![false; 3 * mesh.node_count()];
        for f in &scene.fixes {
            let body = &mesh.bodies[f.body];
            let nodes: Vec<u32> = match &f.nodes {
                NodeSelection::Surface(s) => Mesh::quad_nodes(&body.surfaces[*s].faces),
                NodeSelection::Set(s) => body.node_sets[*s].nodes.clone(),
                NodeSelection::Region { min, max } => body
                    .nodes
                    .clone()
                    .filter(|&n| {
                        let p = mesh.nodes[n];
                        (0..3).all(|a| p[a] >= min[a] - 1e-12 && p[a] <= max[a] + 1e-12)
                    })
                    .map(|n| n as u32)
                    .collect(),
            };
            for n in nodes {
                for a in 0..3 {
                    if f.components[a] {
                        fixed[3 * n as usize + a] = true;
                    }
                }
            }
        }

        let mut queries = ContactQueries::default();
        let mut interfaces = Vec::new();
        for c in &scene.contacts {
            let sec = &mesh.bodies[c.secondary.body].surfaces[c.secondary.surface].faces;
            let (nodes, area) = tributary_areas(&mesh, sec);
            let f0 = queries.faces.len();
            queries
                .faces
                .extend_from_slice(&mesh.bodies[c.primary.body].surfaces[c.primary.surface].faces);
            let q0 = queries.secondary.len();
            queries.secondary.extend_from_slice(&nodes);
            interfaces.push(Interface {
                name: c.name.clone(),
                friction: c.friction,
                nodes,
                area,
                primary: Primary::Surface {
                    body: c.primary.body,
                    faces: f0..queries.faces.len(),
                    queries: q0..queries.secondary.len(),
                },
            });
        }
        queries.offsets = vec![0; queries.secondary.len() + 1];
        for p in &scene.planes {
            let quads: Vec<[u32; 4]> = p
                .bodies
                .iter()
                .flat_map(|&b| mesh.bodies[b].boundary.iter().copied())
                .collect();
            let (nodes, area) = tributary_areas(&mesh, &quads);
            interfaces.push(Interface {
                name: p.name.clone(),
                friction: p.friction,
                nodes,
                area,
                primary: Primary::Plane {
                    point: p.point,
                    normal: p.normal,
                },
            });
        }

        let probes = scene
            .probes
            .iter()
            .map(|p| {
                let body = &mesh.bodies[p.body];
                let node = body
                    .nodes
                    .clone()
                    .min_by(|&a, &b| {
                        let d = |n: usize| {
                            let x = mesh.nodes[n];
                            (0..3).map(|k| (x[k] - p.point[k]).powi(2)).sum::<f64>()
                        };
                        d(a).total_cmp(&d(b))
                    })
                    .expect("a body has nodes");
                Probe {
                    name: p.name.clone(),
                    node: node as u32,
                }
            })
            .collect();

        Model {
            body_names: scene.bodies.iter().map(|b| b.name.clone()).collect(),
            mesh,
            materials,
            fixed,
            interfaces,
            queries,
            probes,
            initial_velocity,
            gravity: scene.gravity,
        }
    }

    pub fn dofs(&self) -> usize {
        3 * self.mesh.node_count()
    }

    pub fn element_data(&self) -> ElementData {
        ElementData {
            reference: self.mesh.nodes.clone(),
            hexes: self.mesh.hexes.clone(),
            hex_material: self.mesh.hex_material.clone(),
            tets: self.mesh.tets.clone(),
            tet_material: self.mesh.tet_material.clone(),
            materials: self.materials.clone(),
        }
    }
}
