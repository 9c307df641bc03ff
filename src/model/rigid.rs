//! Rigid bodies in the model: each is one node of its own (its reference point, after every
//! meshed body's nodes) that carries the body's mass and translation, so that every path
//! integrates it with the other nodes; its analytic surface is placed at that node.

use crate::geometry::rigid_shape::RigidShape;
use crate::scene::{RigidMotion, Scene};

/// A rigid body of the model.
#[derive(Debug, Clone)]
pub struct RigidBody {
    pub name: String,
    /// The node that carries it (its reference point).
    pub node: u32,
    pub mass: f64,
    pub shape: RigidShape,
    pub motion: RigidMotion,
    /// Its initial velocity (the velocity it keeps when prescribed).
    pub velocity: [f64; 3],
    /// Its inertia tensor about its reference point, where it is free to rotate.
    pub inertia: Option<[[f64; 3]; 3]>,
    /// Its initial angular velocity (the one it keeps when prescribed).
    pub angular_velocity: [f64; 3],
}

impl RigidBody {
    /// The scene's rigid bodies, carried by the nodes from `first_node` on.
    pub fn from_scene(scene: &Scene, first_node: usize) -> Vec<RigidBody> {
        (scene.rigid_bodies.iter().enumerate())
            .map(|(i, b)| RigidBody {
                name: b.name.clone(),
                node: (first_node + i) as u32,
                mass: b.mass,
                shape: b.shape.clone(),
                motion: b.motion,
                velocity: b.velocity,
                inertia: b.inertia,
                angular_velocity: b.angular_velocity,
            })
            .collect()
    }

    /// Whether its degrees of freedom are prescribed (held or moved at its velocity).
    pub fn is_prescribed(&self) -> bool {
        self.motion != RigidMotion::Free
    }

    /// Whether it rotates: free with an inertia, or prescribed with an angular velocity.
    pub fn rotates(&self) -> bool {
        crate::scene::rigid_body::rotates(
            self.inertia.is_some(),
            self.motion,
            self.angular_velocity,
        )
    }

    /// The distance of the point `x` from its surface when its node is displaced by `u`
    /// from `reference`, positive outside, and the outward normal.
    pub fn distance(&self, reference: [f64; 3], u: [f64; 3], x: [f64; 3]) -> (f64, [f64; 3]) {
        let r = std::array::from_fn(|a| x[a] - reference[a] - u[a]);
        self.shape.distance(r)
    }

    /// [`Self::distance`] with the body turned by `rotation` (body to world) about its
    /// reference point: the shape's distance at the point in the body's axes, the normal
    /// turned back.
    pub fn distance_turned(
        &self,
        (reference, u): ([f64; 3], [f64; 3]),
        rotation: &[[f64; 3]; 3],
        x: [f64; 3],
    ) -> (f64, [f64; 3]) {
        let r: [f64; 3] = std::array::from_fn(|a| x[a] - reference[a] - u[a]);
        // R^T r
        let body = std::array::from_fn(|k| (0..3).map(|a| rotation[a][k] * r[a]).sum());
        let (d, n) = self.shape.distance(body);
        let n = std::array::from_fn(|a| (0..3).map(|k| rotation[a][k] * n[k]).sum());
        (d, n)
    }
}
