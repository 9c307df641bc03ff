//! Geometry below every kernel: vector helpers, bilinear quads and their closest-point
//! projection, and the contact point a projection gives.

pub mod point;
pub mod quad;
