//! Element quality that does not stop a run but makes its result doubtful or its cost absurd:
//!
//! - **Slivers**: an element whose stable step is far below its body's median (a flattened
//!   tetrahedron from two swapped node tags, a crushed hex) sets the explicit step of the
//!   whole model; the warning names the worst elements, their bodies and their aspect.
//! - **Volumetric locking**: fully integrated hex8 and tet4 lock near incompressibility, so
//!   a Poisson's ratio above [`LOCKING_NU`] gives forces that are too stiff (and, explicit,
//!   a step cut by the dilatational wave speed).

use super::Warning;
use crate::element::ElementKind;
use crate::geometry::vector::{norm, sub};
use crate::mesh::Mesh;
use crate::scene::Scene;

/// An element whose stable step is below this fraction of its body's median is a sliver.
pub(crate) const SLIVER_RATIO: f64 = 0.01;

/// A Poisson's ratio above this on hex8 or tet4 is a locking warning.
pub(crate) const LOCKING_NU: f64 = 0.49;

/// The slivers named in the warning, worst first.
const NAMED: usize = 5;

/// A warning per body holding elements whose step (`steps`, one per element in
/// [`Mesh::elements`] order) is below [`SLIVER_RATIO`] of the body's median.
pub(crate) fn slivers(scene: &Scene, mesh: &Mesh, steps: &[f32]) -> Vec<Warning> {
    let mut out = Vec::new();
    for (b, body) in mesh.bodies.iter().enumerate() {
        let elements: Vec<usize> = body.element_numbers(&mesh.elements).collect();
        if elements.is_empty() {
            continue;
        }
        let mut sorted: Vec<f32> = elements.iter().map(|&e| steps[e]).collect();
        let mid = sorted.len() / 2;
        let median = *sorted.select_nth_unstable_by(mid, f32::total_cmp).1;
        let mut thin: Vec<(f64, usize)> = elements
            .iter()
            .map(|&e| (f64::from(steps[e]) / f64::from(median), e))
            .filter(|&(r, _)| r < SLIVER_RATIO)
            .collect();
        if thin.is_empty() {
            continue;
        }
        thin.sort_by(|a, b| a.0.total_cmp(&b.0));
        let named: Vec<String> = thin
            .iter()
            .take(NAMED)
            .map(|&(r, e)| {
                let el = mesh.element(e);
                format!(
                    "element {e} (step {r:.1e} of the median, aspect {:.0})",
                    aspect(el.kind, &mesh.corners(el.nodes))
                )
            })
            .collect();
        out.push(Warning::new(
            "element_quality",
            format!(
                "body `{}`: {} element(s) have a stable step below {SLIVER_RATIO} of the body's median {median:.3e} (flattened or crushed: check the node order and coordinates); they set the explicit step: {}",
                scene.bodies[b].name,
                thin.len(),
                named.join(", ")
            ),
        ));
    }
    out
}

/// The longest edge over the shortest of an element of a kind at corners `x`.
pub fn aspect(kind: ElementKind, x: &[[f64; 3]]) -> f64 {
    let (lo, hi) = (kind.edges().iter()).fold((f64::INFINITY, 0.0_f64), |(lo, hi), &(i, j)| {
        let d = norm(sub(x[i], x[j]));
        (lo.min(d), hi.max(d))
    });
    hi / lo
}

/// A warning per isotropic material of Poisson's ratio above [`LOCKING_NU`].
pub fn locking(scene: &Scene) -> Vec<Warning> {
    scene
        .materials
        .iter()
        .filter(|m| m.elastic.c.is_none())
        .filter_map(|m| {
            let (lambda, mu) = (m.elastic.lambda, m.elastic.mu);
            let nu = lambda / (2.0 * (lambda + mu));
            (nu > LOCKING_NU).then(|| {
                Warning::new(
                    "volumetric_locking",
                    format!(
                        "material `{}`: Poisson's ratio {nu} is above {LOCKING_NU}: fully integrated hex8 and tet4 lock volumetrically near incompressibility, so forces come out too stiff, and an explicit step shrinks with the dilatational wave speed",
                        m.name
                    ),
                )
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element;

    #[test]
    fn aspect_of_a_box_and_a_flat_tet() {
        let cube = element::hex8::CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0)));
        assert!((aspect(ElementKind::Hex8, &cube) - 1.0).abs() < 1e-12);
        let stretched = cube.map(|p| [4.0 * p[0], p[1], p[2]]);
        assert!((aspect(ElementKind::Hex8, &stretched) - 4.0).abs() < 1e-12);
        let tet = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 1e-3],
        ];
        assert!((aspect(ElementKind::Tet4, &tet) - 2f64.sqrt() / 0.5f64.sqrt()).abs() < 1e-3);
    }
}
