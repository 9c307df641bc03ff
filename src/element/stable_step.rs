//! One element's explicit stability limit: Gershgorin's bound on its lumped-mass
//! eigenproblem (cheap, guaranteed) and the exact limit (its eigenvalue).

use super::{ElementKind, Section};

/// $2 / \sqrt{\max_i \sum_j |K_{ij}| / m_i}$ for one element of a kind at coordinates `x`.
pub fn element_stable_step<'a>(
    kind: ElementKind,
    x: &[[f64; 3]],
    section: impl Into<Section<'a>>,
) -> f64 {
    let (k, ml) = stiffness_and_mass(kind, x, section.into());
    let w2 = (0..k.len())
        .map(|i| k[i].iter().map(|v| v.abs()).sum::<f64>() / ml[i / 3])
        .fold(0.0, f64::max);
    2.0 / w2.sqrt()
}

/// $2/\omega_{max}$ of one element from its lumped-mass eigenproblem (a 24 x 24 or 12 x 12
/// symmetric eigenvalue problem; exact, but for the hex8 about 30 times the cost of the
/// Gershgorin bound).
pub fn element_critical_step<'a>(
    kind: ElementKind,
    x: &[[f64; 3]],
    section: impl Into<Section<'a>>,
) -> f64 {
    let (k, ml) = stiffness_and_mass(kind, x, section.into());
    let n = k.len();
    let s = nalgebra::DMatrix::from_fn(n, n, |i, j| k[i][j] / (ml[i / 3] * ml[j / 3]).sqrt());
    let w2 = nalgebra::SymmetricEigen::new(s).eigenvalues.max();
    2.0 / w2.sqrt()
}

/// The element's stiffness and lumped corner masses.
fn stiffness_and_mass(kind: ElementKind, x: &[[f64; 3]], s: Section) -> (Vec<Vec<f64>>, Vec<f64>) {
    (kind.stiffness(x, s), kind.lumped_mass(x, s.density()))
}
