//! The discrete model built from a scene: mesh, materials, constraints, contact interfaces,
//! probes. Reading and checking (the scene) is kept apart from the time loop (integrate).

pub mod cohesive;
pub mod damage;
mod damage_shapes;
pub mod equations;
pub mod fixes;
pub mod interface;
pub mod loads;
pub mod materials;
pub mod prescribed;
pub mod rigid;
pub mod ties;

pub use interface::{tributary_areas, Interface, Primary};
pub use materials::MaterialTable;
pub use prescribed::{FixPath, PathShape};
pub use rigid::RigidBody;

use crate::contact::law::ContactLaw;
use crate::error::{ImpactError, Result};
use crate::geometry::vector::{bbox_diagonal, norm, sub};
use crate::kernels::{ContactQueries, ElementData};
use crate::material::Elastic;
use crate::mesh::{Face, Mesh};
use crate::scene::{ContactSpec, NodeSelection, PrimarySide, Scene, SecondarySide};

#[derive(Debug, Clone)]
pub struct Probe {
    pub name: String,
    pub node: u32,
}

/// A named `[[fix]]`: its held dofs, by component. Its reaction is the force it applies to
/// them, the sum over each component's dofs of the internal force less the body force.
#[derive(Debug, Clone)]
pub struct Reaction {
    pub name: String,
    pub dofs: [Vec<u32>; 3],
}

#[derive(Debug, Clone)]
pub struct Model {
    pub mesh: Mesh,
    /// The law of each material index of the mesh, in the global axes.
    pub materials: Vec<Elastic>,
    /// The plies of each material index that is a layered section (hex8i elements that span
    /// several plies), else None; `materials` holds its plies' mean law.
    pub layups: Vec<Option<crate::material::Layup>>,
    /// The ply (of its body's plies, from the lowest) of each material index that is one
    /// ply's.
    pub material_ply: Vec<Option<usize>>,
    /// The material axes and the scene material of each material index.
    pub material_axes: Vec<crate::material::Rotation>,
    pub material_source: Vec<usize>,
    /// The ply strengths of each scene material, where it gives them.
    pub strengths: Vec<Option<crate::material::Strength>>,
    /// The damage law of each scene material that damages.
    pub damage_laws: Vec<Option<crate::material::PlyDamage>>,
    pub body_names: Vec<String>,
    /// True for each prescribed (zero) degree of freedom, 3 per node.
    pub fixed: Vec<bool>,
    pub interfaces: Vec<Interface>,
    /// Contact queries of all surface interfaces; candidates are filled by the broad phase.
    pub queries: ContactQueries,
    pub probes: Vec<Probe>,
    /// Nodes held by each `[[fix]]`, in the scene's order.
    pub fix_nodes: Vec<usize>,
    /// The held dofs that a `[[fix]]` moves, with their velocities, by increasing dof.
    pub fix_motion: Vec<(usize, f64)>,
    /// The `[[fix]]`es that move their nodes by a displacement over time.
    pub fix_paths: Vec<FixPath>,
    /// The named `[[fix]]`s, whose reactions the history gives.
    pub reactions: Vec<Reaction>,
    /// Initial velocity, 3 per node.
    pub initial_velocity: Vec<f64>,
    pub gravity: [f64; 3],
    /// The rigid bodies, each carried by a node after the meshed bodies' nodes.
    pub rigid: Vec<RigidBody>,
    /// The `[[cohesive]]` interfaces, as pairs of bonded nodes.
    pub cohesive: Vec<cohesive::CohesiveInterface>,
    /// The `[[load]]`s, as nodal forces with their amplitudes.
    pub loads: Vec<loads::Load>,
    /// Each load's nodal forces on held components, left to the supports.
    pub held_loads: Vec<usize>,
    /// The `[[equation]]`s, then the `[[tie]]`s' constraints: dofs set by others (static
    /// steps, implicit ones without contact).
    pub equations: Vec<equations::Equation>,
    /// The `[[tie]]`s, each with its constraints (the model's `equations` hold those whose
    /// dof no fix holds).
    pub ties: Vec<ties::Tie>,
}

impl Model {
    /// Builds the model; a `[[fix]]` that selects no node is an error (a support that holds
    /// nothing would leave its body free without a word).
    pub fn from_scene(scene: &Scene) -> Result<Model> {
        let mut mesh = Mesh::default();
        let mut initial_velocity = Vec::new();
        // the laminates split at their ply changes, with their pairs in global numbers
        let mut splits = Vec::new();
        for (i, b) in scene.bodies.iter().enumerate() {
            let (parts, split) = cohesive::split_body(scene, i, b.parts());
            for _ in 0..parts.nodes.len() {
                initial_velocity.extend_from_slice(&b.velocity);
            }
            let offset = mesh.node_count() as u32;
            splits.extend(split.map(|s| s.offset(offset)));
            mesh.push_body(parts, b.material);
        }
        let rigid = RigidBody::from_scene(scene, mesh.node_count());
        for b in &scene.rigid_bodies {
            mesh.nodes.push(b.position);
            initial_velocity.extend_from_slice(&b.velocity);
        }
        initial_velocities(scene, &mesh, &mut initial_velocity)?;
        // tied nodes moved onto their surfaces before anything measures the mesh
        let ties = ties::ties(scene, &mut mesh)?;
        let table = materials::element_materials(scene, &mut mesh);
        let fixes::Fixes {
            mut fixed,
            counts: fix_nodes,
            moving: fix_motion,
            paths: fix_paths,
            reactions,
        } = fixes::fixes(scene, &mesh, &fixes::in_force(scene, None))?;
        fixes::hold_prescribed(&mut fixed, &rigid);
        let (loads, held_loads) = loads::loads(scene, &mesh, &fixed)?;
        let equations = equations::equations(scene, &mesh, &fixed, &ties::views(&ties))?;
        let (queries, interfaces) = interfaces(scene, &mesh, &rigid)?;
        let cohesive = cohesive::cohesive_interfaces(scene, &mesh, &splits)?;
        let mut probes = probes(scene, &mesh);
        // a rigid body's history columns are those of a probe on its node
        probes.extend(rigid.iter().map(|b| Probe {
            name: b.name.clone(),
            node: b.node,
        }));
        Ok(Model {
            body_names: scene.bodies.iter().map(|b| b.name.clone()).collect(),
            mesh,
            materials: table.elastic,
            layups: table.layups,
            material_ply: table.ply,
            material_axes: table.axes,
            material_source: table.source,
            strengths: scene.materials.iter().map(|m| m.strength).collect(),
            damage_laws: scene
                .materials
                .iter()
                .map(damage::law_of_material)
                .collect(),
            fixed,
            interfaces,
            queries,
            probes,
            fix_nodes,
            fix_motion,
            fix_paths,
            reactions,
            initial_velocity,
            gravity: scene.gravity,
            rigid,
            cohesive,
            loads,
            held_loads,
            equations,
            ties,
        })
    }

    /// Each rigid body's node and mass.
    pub fn point_masses(&self) -> impl Iterator<Item = (u32, f64)> + '_ {
        self.rigid.iter().map(|b| (b.node, b.mass))
    }

    /// The prescribed dofs that move, with their velocities: the prescribed rigid bodies',
    /// then the `[[fix]]`es' with a velocity.
    pub fn moving_dofs(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (self.rigid.iter())
            .filter(|b| b.motion == crate::scene::RigidMotion::Prescribed)
            .flat_map(|b| (0..3).map(move |a| (3 * b.node as usize + a, b.velocity[a])))
            .chain(self.fix_motion.iter().copied())
    }

    /// The model of each of the scene's `[[step]]`s: this one without the equations the
    /// steps up to it removed.
    pub fn for_steps(&self, scene: &Scene) -> Result<Vec<Model>> {
        (0..scene.steps.len())
            .map(|k| {
                let f = fixes::fixes(scene, &self.mesh, &fixes::in_force(scene, Some(k)))?;
                let mut fixed = f.fixed;
                fixes::hold_prescribed(&mut fixed, &self.rigid);
                let (loads, held_loads) = loads::loads(scene, &self.mesh, &fixed)?;
                let removed = equations::removed_by(scene, &self.mesh, k);
                let equations = equations::equations_kept(
                    scene,
                    &self.mesh,
                    (&fixed, &ties::views(&self.ties)),
                    &removed,
                )?;
                let mut interfaces = self.interfaces.clone();
                for change in scene.steps[..=k].iter().flat_map(|s| &s.contacts) {
                    let itf = &mut interfaces[change.contact];
                    if let Some(mu) = change.friction {
                        itf.law = ContactLaw::of_friction(mu);
                    }
                    if let Some(slope) = change.stick_slope {
                        itf.stick_slope = Some(slope);
                    }
                }
                Ok(Model {
                    fixed,
                    fix_motion: f.moving,
                    fix_paths: f.paths,
                    loads,
                    held_loads,
                    equations,
                    interfaces,
                    ..self.clone()
                })
            })
            .collect()
    }

    /// Recomputes every interface's tributary areas from the current reference coordinates
    /// (after nodes were moved onto a surface at t = 0).
    pub fn refresh_areas(&mut self) {
        for itf in &mut self.interfaces {
            itf.area = match itf.node_based {
                true => interface::node_set_areas(&self.mesh, &itf.nodes, &itf.secondary_faces),
                false => tributary_areas(&self.mesh, &itf.secondary_faces).1,
            };
        }
    }

    /// The bounding box of body `b`'s nodes.
    pub fn body_box(&self, b: usize) -> ([f64; 3], [f64; 3]) {
        body_box(&self.mesh, b)
    }

    pub fn dofs(&self) -> usize {
        3 * self.mesh.node_count()
    }

    pub fn element_data(&self) -> ElementData {
        ElementData {
            reference: self.mesh.nodes.clone(),
            elements: self.mesh.elements.clone(),
            materials: self.materials.clone(),
            layups: self.layups.clone(),
        }
    }

    /// The ply of material index `m`, where it is one ply's.
    pub fn ply_of(&self, m: u32) -> Option<usize> {
        self.material_ply.get(m as usize).copied().flatten()
    }

    /// The section of material index `m`.
    pub fn section(&self, m: u32) -> crate::element::Section<'_> {
        crate::kernels::section_of(&self.materials, &self.layups, m)
    }
}

pub(super) fn body_box(mesh: &Mesh, b: usize) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &mesh.nodes[mesh.bodies[b].nodes.clone()] {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
}

/// The nodes of meshed body `body` that `nodes` selects (a fix's or an initial velocity's;
/// none for a rigid body's, whose fix holds the body's node).
pub(super) fn selection(mesh: &Mesh, body: usize, nodes: &NodeSelection) -> Vec<u32> {
    let body = &mesh.bodies[body];
    match nodes {
        NodeSelection::RigidBody => Vec::new(),
        NodeSelection::Surface(s) => Mesh::face_nodes(&body.surfaces[*s].faces),
        NodeSelection::Set(s) => body.node_sets[*s].nodes.clone(),
        NodeSelection::Region { min, max } => body
            .nodes
            .clone()
            .filter(|&n| in_region(mesh.nodes[n], (*min, *max)))
            .map(|n| n as u32)
            .collect(),
    }
}

/// Each `[[initial_velocity]]`'s velocity on the nodes it selects, over the bodies' own, in
/// the scene's order; one that selects no node is an error naming it.
fn initial_velocities(scene: &Scene, mesh: &Mesh, v: &mut [f64]) -> Result<()> {
    for (i, s) in scene.initial_velocities.iter().enumerate() {
        let nodes = selection(mesh, s.body, &s.nodes);
        if nodes.is_empty() {
            return Err(ImpactError::SceneValue {
                path: scene.path.clone(),
                key: format!("initial_velocity[{i}]"),
                message: format!("selects no node of body `{}`", scene.bodies[s.body].name),
            });
        }
        for n in nodes {
            for a in (0..3).filter(|&a| s.components[a]) {
                v[3 * n as usize + a] = s.velocity[a];
            }
        }
    }
    Ok(())
}

/// The contact queries of the surface interfaces, then every interface: the `[[contact]]`s
/// (secondary nodes against primary faces or a rigid body's surface), then the
/// `[[rigid_plane]]`s.
fn interfaces(
    scene: &Scene,
    mesh: &Mesh,
    rigid: &[RigidBody],
) -> Result<(ContactQueries, Vec<Interface>)> {
    let mut queries = ContactQueries::default();
    let mut interfaces = Vec::new();
    for (i, c) in scene.contacts.iter().enumerate() {
        let (nodes, area, sec) = &secondary_side(scene, mesh, (i, c))?;
        let primary = match c.primary {
            PrimarySide::RigidBody(b) => Primary::Rigid {
                body: b,
                node: rigid[b].node,
                shape: rigid[b].shape.clone(),
            },
            PrimarySide::Surface(p) => {
                let f0 = queries.faces.len();
                let faces = &mesh.bodies[p.body].surfaces[p.surface].faces;
                queries.faces.extend(faces.iter().map(Face::slots));
                let q0 = queries.secondary.len();
                queries.secondary.extend_from_slice(nodes);
                Primary::Surface {
                    body: p.body,
                    faces: f0..queries.faces.len(),
                    queries: q0..queries.secondary.len(),
                }
            }
        };
        interfaces.push(Interface {
            name: c.name.clone(),
            law: ContactLaw::of_friction(c.friction),
            nodes: nodes.clone(),
            area: area.clone(),
            secondary_faces: sec.clone(),
            node_based: matches!(c.secondary, SecondarySide::Nodes { .. }),
            primary,
            pressure_law: c.pressure_law,
            stick_slope: c.stick_slope,
        });
    }
    queries.offsets = vec![0; queries.secondary.len() + 1];
    for p in &scene.planes {
        let quads: Vec<Face> = p
            .bodies
            .iter()
            .flat_map(|&b| mesh.bodies[b].boundary.iter().copied())
            .collect();
        let (nodes, area) = tributary_areas(mesh, &quads);
        interfaces.push(Interface {
            name: p.name.clone(),
            law: ContactLaw::of_friction(p.friction),
            nodes,
            area,
            secondary_faces: quads,
            node_based: false,
            primary: Primary::Plane {
                point: p.point,
                normal: p.normal,
            },
            pressure_law: None,
            stick_slope: None,
        });
    }

    Ok((queries, interfaces))
}

/// Whether the point `p` lies in the box `(min, max)` of a scene's `region` (to 1e-12).
pub(crate) fn in_region(p: [f64; 3], (min, max): ([f64; 3], [f64; 3])) -> bool {
    (0..3).all(|a| p[a] >= min[a] - 1e-12 && p[a] <= max[a] + 1e-12)
}

/// A contact's secondary nodes, their tributary areas and the faces those come from.
fn secondary_side(
    scene: &Scene,
    mesh: &Mesh,
    (i, c): (usize, &ContactSpec),
) -> Result<(Vec<u32>, Vec<f64>, Vec<Face>)> {
    let err = |k: &str, message: String| ImpactError::SceneValue {
        path: scene.path.clone(),
        key: format!("contact[{i}].{k} (contact `{}`)", c.name),
        message,
    };
    let SecondarySide::Nodes { body, set } = c.secondary else {
        let faces = secondary_faces(mesh, c).ok_or_else(|| {
            err(
                "region",
                "holds no whole face of the secondary surface: nothing would touch".into(),
            )
        })?;
        let (nodes, area) = tributary_areas(mesh, &faces);
        return Ok((nodes, area, faces));
    };
    let b = &mesh.bodies[body];
    let mut nodes: Vec<u32> = (b.node_sets[set].nodes.iter().copied())
        .filter(|&n| {
            c.region
                .is_none_or(|r| in_region(mesh.nodes[n as usize], r))
        })
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    let faces: Vec<Face> = (b.boundary.iter())
        .filter(|f| f.corners().iter().any(|n| nodes.binary_search(n).is_ok()))
        .copied()
        .collect();
    let on_boundary = Mesh::face_nodes(&faces);
    let inside = nodes
        .iter()
        .filter(|n| on_boundary.binary_search(n).is_err())
        .count();
    if nodes.is_empty() || inside > 0 {
        let what = match nodes.len() {
            0 => "holds no node (inside the region, where one is given)".to_string(),
            _ => format!("holds {inside} node(s) inside the body, off its boundary: a secondary node lies on the surface"),
        };
        return Err(err(
            "secondary.set",
            format!("node set `{}` {what}", b.node_sets[set].name),
        ));
    }
    let area = interface::node_set_areas(mesh, &nodes, &faces);
    Ok((nodes, area, faces))
}

/// A surface secondary side's faces: its surface's, those with every node inside its
/// `region` where it has one (`None` where the region holds none).
fn secondary_faces(mesh: &Mesh, c: &ContactSpec) -> Option<Vec<Face>> {
    let SecondarySide::Faces(s) = c.secondary else {
        return None;
    };
    let faces = &mesh.bodies[s.body].surfaces[s.surface].faces;
    let Some((min, max)) = c.region else {
        return Some(faces.clone());
    };
    let kept: Vec<Face> = (faces.iter())
        .filter(|f| (f.corners().iter()).all(|&n| in_region(mesh.nodes[n as usize], (min, max))))
        .copied()
        .collect();
    (!kept.is_empty()).then_some(kept)
}

/// A probe's point may lie at most this fraction of its body's bounding-box diagonal from
/// the node it records, or (where more) the largest corner-to-corner distance of an element at that node.
pub(crate) const PROBE_REACH: f64 = 0.1;

/// Each probe's node: the body's node nearest its point.
fn probes(scene: &Scene, mesh: &Mesh) -> Vec<Probe> {
    scene
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
        .collect()
}

impl Model {
    /// Refuses a probe whose point lies farther from the node it records than
    /// [`PROBE_REACH`] of its body's size and than the largest corner-to-corner distance of the elements at that
    /// node (a point far outside the body is a mistake, not a probe; a point inside a
    /// coarse element is not).
    pub fn check_probes(&self, scene: &Scene) -> Result<()> {
        let sizes: Vec<f64> = (self.mesh.bodies.iter())
            .map(|b| bbox_diagonal(&self.mesh.nodes[b.nodes.clone()]))
            .collect();
        let edges = self.probe_edges();
        for (i, (spec, probe)) in scene.probes.iter().zip(&self.probes).enumerate() {
            let node = probe.node as usize;
            let x = self.mesh.nodes[node];
            let distance = norm(sub(x, spec.point));
            let size = sizes[spec.body];
            if distance > (PROBE_REACH * size).max(edges[&probe.node]) {
                return Err(ImpactError::SceneValue {
                    path: scene.path.clone(),
                    key: format!("probe[{i}].point (probe `{}`)", spec.name),
                    message: format!(
                        "{:?} is {distance:.4e} from the nearest node of body `{}` (node {node} at {x:?}), more than {PROBE_REACH} of the body's size {size:.4e} and than the largest corner-to-corner distance {:.4e} of the elements at that node: a probe records the node nearest its point, which must lie on or in its body",
                        spec.point, scene.bodies[spec.body].name, edges[&probe.node]
                    ),
                });
            }
        }
        Ok(())
    }
}

impl Model {
    /// The largest corner-to-corner distance of the elements at each probe's node.
    fn probe_edges(&self) -> std::collections::HashMap<u32, f64> {
        let mut edges: std::collections::HashMap<u32, f64> =
            self.probes.iter().map(|p| (p.node, 0.0)).collect();
        for e in self.mesh.elements() {
            let corners = e.nodes;
            if !corners.iter().any(|n| edges.contains_key(n)) {
                continue;
            }
            let x = self.mesh.corners(corners);
            let longest = (0..x.len())
                .flat_map(|i| (i + 1..x.len()).map(move |j| (i, j)))
                .map(|(i, j)| norm(sub(x[i], x[j])))
                .fold(0.0, f64::max);
            for n in corners {
                if let Some(e) = edges.get_mut(n) {
                    *e = e.max(longest);
                }
            }
        }
        edges
    }
}
