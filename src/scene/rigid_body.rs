//! `[[rigid_body]]`: a body that moves without deforming, with an analytic surface that
//! contacts name as their primary side.

use crate::geometry::rigid_shape::RigidShape;

/// How a rigid body moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RigidMotion {
    /// Under its contact forces and gravity, with its mass.
    Free,
    /// Held where it is.
    Fixed,
    /// At its `velocity` whatever the forces (the contacts report the reaction).
    Prescribed,
}

option_names!(RigidMotion { Free = "free", Fixed = "fixed", Prescribed = "prescribed" });

/// A checked `[[rigid_body]]`.
#[derive(Debug, Clone)]
pub struct RigidBodySpec {
    pub name: String,
    /// Its mass (0 where a held or prescribed body gives none).
    pub mass: f64,
    /// Its reference point, which places the shape.
    pub position: [f64; 3],
    pub velocity: [f64; 3],
    /// Its inertia tensor about `position` (a free body that rotates), symmetric and
    /// positive definite.
    pub inertia: Option<[[f64; 3]; 3]>,
    /// Its initial angular velocity (the one it keeps when prescribed).
    pub angular_velocity: [f64; 3],
    pub shape: RigidShape,
    pub motion: RigidMotion,
}

impl RigidBodySpec {
    /// Whether it rotates ([`rotates`]).
    pub fn rotates(&self) -> bool {
        rotates(self.inertia.is_some(), self.motion, self.angular_velocity)
    }
}

/// Whether a rigid body rotates: a free body with an inertia, or a prescribed one spinning.
pub fn rotates(inertia: bool, motion: RigidMotion, angular_velocity: [f64; 3]) -> bool {
    inertia || (motion == RigidMotion::Prescribed && angular_velocity != [0.0; 3])
}

/// The primary side of a `[[contact]]`: a surface of a meshed body or a rigid body.
#[derive(Debug, Clone, Copy)]
pub enum PrimarySide {
    Surface(super::SurfaceRef),
    /// An index into [`super::Scene::rigid_bodies`].
    RigidBody(usize),
}
