//! Finite elements: shape functions, quadrature, element matrices.
//!
//! A mesh holds its elements in blocks, one per [`ElementKind`] ([`block`]); the kind owns
//! what an element computes once (assembly, mass lumping, stable step, stresses for output),
//! and [`corners`] where each corner's force lives.

pub mod block;
#[cfg(test)]
pub(crate) mod checks;
pub mod corners;
pub mod corotation;
pub mod damage;
pub mod hex8;
pub mod hex8i;
pub mod kind;
pub mod mass_moments;
pub mod section;
pub mod stable_step;
pub mod tet4;

use crate::material::Elastic;

pub use block::{ElementBlock, ElementRef, Elements};
pub use corners::CornerLayout;
pub use kind::{ElementKind, Sample};
pub use mass_moments::MassMoments;
pub use section::Section;

/// Cauchy stress $\sigma = \lambda\, \mathrm{tr}(\varepsilon) I + 2\mu\varepsilon$ of the linear
/// strain $\varepsilon = \mathrm{sym} H$, $H = \sum_k u_k \otimes \nabla N_k$, from the shape
/// function gradients at a point and the corner displacements (either element kind).
pub fn stress(grads: &[[f64; 3]], u: &[[f64; 3]], m: &Elastic) -> [[f64; 3]; 3] {
    let mut h = [[0.0; 3]; 3];
    for (g, uk) in grads.iter().zip(u) {
        for a in 0..3 {
            for b in 0..3 {
                h[a][b] += uk[a] * g[b];
            }
        }
    }
    m.stress(&h)
}

/// The stiffness block of a node pair per unit volume, for shape-function gradients gi and
/// gj: $k_{ab} = \sum_{pq} (g_i)_p C_{apbq} (g_j)_q$, for an isotropic material
/// $\lambda\, (g_i)_a (g_j)_b + \mu (g_j)_a (g_i)_b + \mu\, g_i \cdot g_j\, \delta_{ab}$.
pub fn stiffness_block(gi: &[f64; 3], gj: &[f64; 3], m: &Elastic) -> [[f64; 3]; 3] {
    match &m.c {
        None => {
            let dot = gi[0] * gj[0] + gi[1] * gj[1] + gi[2] * gj[2];
            std::array::from_fn(|a| {
                std::array::from_fn(|b| {
                    let v = m.lambda * gi[a] * gj[b] + m.mu * gj[a] * gi[b];
                    if a == b {
                        v + m.mu * dot
                    } else {
                        v
                    }
                })
            })
        }
        Some(c) => {
            let v = |i: usize, j: usize| crate::material::voigt_index(i, j);
            std::array::from_fn(|a| {
                std::array::from_fn(|b| {
                    let mut s = 0.0;
                    for p in 0..3 {
                        for q in 0..3 {
                            s += gi[p] * c[v(a, p)][v(b, q)] * gj[q];
                        }
                    }
                    s
                })
            })
        }
    }
}

/// The longest side of the bounding box of an element's corners (a size for tolerances).
pub fn extent(x: &[[f64; 3]]) -> f64 {
    (0..3)
        .map(|a| {
            let (lo, hi) = x.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |m, p| {
                (m.0.min(p[a]), m.1.max(p[a]))
            });
            hi - lo
        })
        .fold(0.0, f64::max)
}
