//! Element shapes: every element must have distinct corners and a positive Jacobian
//! determinant at its Gauss points and corners, and every body a finite, positive volume.

use rayon::prelude::*;

use crate::element::ElementKind;
use crate::error::{ImpactError, Result};
use crate::mesh::Mesh;
use crate::scene::Scene;

/// Below this fraction of the element's mean determinant a positive determinant counts as
/// degenerate (a corner angle near 180 degrees, or an edge collapsed to a point).
pub(crate) const DEGENERATE_RATIO: f64 = 1e-8;

pub use crate::element::Sample;

/// What is wrong with one element.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Fault {
    RepeatedNode(u32),
    /// The determinant `det` at a sample point (a Gauss point or a corner) is not positive,
    /// or not finite.
    Inverted {
        at: Sample,
        det: f64,
    },
    /// Positive everywhere but vanishing at one point against the mean.
    Degenerate {
        at: Sample,
        det: f64,
        mean: f64,
    },
}

impl std::fmt::Display for Fault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Fault::RepeatedNode(n) => write!(f, "repeats node {n}"),
            Fault::Inverted { at, det } => write!(
                f,
                "is inverted or folded: the Jacobian determinant at {at} is {det:.4e} (it must be > 0; check the corner order and the node coordinates)"
            ),
            Fault::Degenerate { at, det, mean } => write!(
                f,
                "is degenerate: the Jacobian determinant at {at} is {det:.4e}, {:.1e} of its mean {mean:.4e}",
                det / mean
            ),
        }
    }
}

/// The fault of an element of a kind with nodes `nodes` and corners `x`, if any.
pub(crate) fn fault(kind: ElementKind, nodes: &[u32], x: &[[f64; 3]]) -> Option<Fault> {
    if let Some(n) = repeated(nodes) {
        return Some(Fault::RepeatedNode(n));
    }
    let (dets, scale) = kind.jacobian_samples(x);
    worst(&dets, scale)
}

fn repeated(nodes: &[u32]) -> Option<u32> {
    (1..nodes.len()).find_map(|i| nodes[..i].contains(&nodes[i]).then_some(nodes[i]))
}

/// The most negative determinant, or one too small against `mean`.
fn worst(dets: &[(Sample, f64)], mean: f64) -> Option<Fault> {
    let &(at, det) = dets.iter().min_by(|a, b| a.1.total_cmp(&b.1))?;
    if !(det > 0.0 && det.is_finite() && mean.is_finite()) {
        Some(Fault::Inverted { at, det })
    } else if det < DEGENERATE_RATIO * mean {
        Some(Fault::Degenerate { at, det, mean })
    } else {
        None
    }
}

/// Checks every element of every body; the first faulty element (in body, then element
/// order) is the error, named by its body, kind and index within the body.
pub fn check(scene: &Scene, mesh: &Mesh) -> Result<()> {
    for (b, body) in mesh.bodies.iter().enumerate() {
        let bad = ElementKind::ALL.into_iter().find_map(|kind| {
            let (block, range) = (mesh.elements.block(kind), body.of_kind(kind));
            (range.clone().into_par_iter()).find_map_first(|e| {
                let nodes = block.element(e);
                let x = mesh.corners(nodes);
                fault(kind, nodes, &x).map(|f| (e - range.start, kind, nodes.to_vec(), f))
            })
        });
        if let Some((k, kind, nodes, fault)) = bad {
            let local: Vec<u32> = nodes.iter().map(|&n| n - body.nodes.start as u32).collect();
            return Err(ImpactError::SceneValue {
                path: scene.path.clone(),
                key: format!("body[{b}] (body `{}`)", scene.bodies[b].name),
                message: format!(
                    "{kind} element {k} (0-based, in the body's order; nodes {local:?} of the body, 0-based) {}",
                    fault_local(fault, body.nodes.start as u32)
                ),
            });
        }
    }
    Ok(())
}

fn fault_local(f: Fault, first: u32) -> Fault {
    match f {
        Fault::RepeatedNode(n) => Fault::RepeatedNode(n - first),
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::hex8;

    fn hex8_fault(nodes: &[u32; 8], x: &[[f64; 3]; 8]) -> Option<Fault> {
        fault(ElementKind::Hex8, nodes, x)
    }

    fn tet4_fault(nodes: &[u32; 4], x: &[[f64; 3]; 4]) -> Option<Fault> {
        fault(ElementKind::Tet4, nodes, x)
    }

    fn unit_hex() -> [[f64; 3]; 8] {
        hex8::CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0)))
    }

    #[test]
    fn a_unit_cube_is_sound() {
        assert_eq!(hex8_fault(&[0, 1, 2, 3, 4, 5, 6, 7], &unit_hex()), None);
    }

    #[test]
    fn a_mirrored_hex_is_inverted() {
        let mut x = unit_hex();
        x.swap(0, 4);
        x.swap(1, 5);
        x.swap(2, 6);
        x.swap(3, 7);
        assert!(matches!(
            hex8_fault(&[0, 1, 2, 3, 4, 5, 6, 7], &x),
            Some(Fault::Inverted { .. })
        ));
    }

    #[test]
    fn a_concave_corner_is_caught_at_the_corner() {
        // corner 6 pushed through the opposite diagonal: the Gauss points may stay positive
        let mut x = unit_hex();
        x[6] = [0.2, 0.2, 0.2];
        match hex8_fault(&[0, 1, 2, 3, 4, 5, 6, 7], &x) {
            Some(Fault::Inverted { at, det }) => {
                assert!(det <= 0.0, "{det}");
                assert!(
                    matches!(at, Sample::Corner(_) | Sample::GaussPoint(_)),
                    "{at}"
                );
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_repeated_node_is_named() {
        let mut x = unit_hex();
        x[7] = x[3];
        assert_eq!(
            hex8_fault(&[0, 1, 2, 3, 4, 5, 6, 3], &x),
            Some(Fault::RepeatedNode(3))
        );
    }

    #[test]
    fn a_flat_tet_is_inverted_and_a_good_one_is_not() {
        let good = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        assert_eq!(tet4_fault(&[0, 1, 2, 3], &good), None);
        let flat = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        assert!(matches!(
            tet4_fault(&[0, 1, 2, 3], &flat),
            Some(Fault::Inverted { .. })
        ));
        let mut swapped = good;
        swapped.swap(1, 2);
        assert!(matches!(
            tet4_fault(&[0, 1, 2, 3], &swapped),
            Some(Fault::Inverted { .. })
        ));
    }
}
