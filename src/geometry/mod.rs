//! Geometry below every kernel: vectors, the primary faces (bilinear quads and linear
//! triangles) and their closest-point projections, the contact point a projection gives, and
//! the analytic surfaces of rigid bodies.

pub mod face;
pub mod point;
pub mod quad;
pub mod rigid_mesh;
pub mod rigid_shape;
pub mod triangle;
pub mod vector;
