//! Finite elements: shape functions, quadrature, element matrices.

pub mod hex8;
