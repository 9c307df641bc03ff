//! Geometry below every kernel: vectors, the primary faces (bilinear quads and linear
//! triangles) and their closest-point projections, and the contact point a projection gives.

pub mod face;
pub mod point;
pub mod quad;
pub mod triangle;
pub mod vector;
