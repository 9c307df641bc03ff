//! Contact surfaces that look the same way: a `[[contact]]` whose secondary and primary
//! surfaces are both mostly flat and whose outward normals agree (a wrong face name, the
//! classic `z-` against `z-`) can never touch as declared.

use crate::error::{ImpactError, Result};
use crate::geometry::face::Face;
use crate::geometry::vector::{cross, dot, norm, sub, V3};
use crate::model::Model;
use crate::model::Primary;
use crate::scene::Scene;

/// A surface counts as mostly flat when its summed area vector is at least this fraction of
/// its area.
pub(crate) const FLAT: f64 = 0.5;

/// Surfaces look the same way when the cosine of their mean normals exceeds this.
pub(crate) const SAME_WAY: f64 = 0.5;

/// The summed area vector (outward) of some faces given by their kernel slots
/// ([`crate::mesh::Face::slots`]), and their total area.
pub(crate) fn area_vector(x: &[[f64; 3]], faces: impl IntoIterator<Item = [u32; 4]>) -> (V3, f64) {
    let mut sum = [0.0; 3];
    let mut area = 0.0;
    for f in faces {
        let p = f.map(|n| x[n as usize]);
        // half the cross product of the diagonals: the area vector of a (warped) quad, and
        // of a triangle's slots (its last corner twice)
        let c = cross(sub(p[2], p[0]), sub(p[3], p[1]));
        let a = c.map(|v| 0.5 * v);
        for k in 0..3 {
            sum[k] += a[k];
        }
        area += norm(a);
    }
    (sum, area)
}

/// Refuses surface interfaces with an empty side, or whose flat secondary and primary
/// surfaces face the same way.
pub fn check(scene: &Scene, model: &Model) -> Result<()> {
    let x = &model.mesh.nodes;
    for (k, itf) in model.interfaces.iter().enumerate() {
        let Primary::Surface { faces, .. } = &itf.primary else {
            continue;
        };
        for (side, empty) in [
            ("secondary", itf.secondary_faces.is_empty()),
            ("primary", faces.is_empty()),
        ] {
            if empty {
                return Err(ImpactError::SceneValue {
                    path: scene.path.clone(),
                    key: scene.interface_key(k),
                    message: format!("the {side} surface has no faces (an empty surface or set in the mesh file)"),
                });
            }
        }
        let (s, sa) = area_vector(x, itf.secondary_faces.iter().map(Face::slots));
        let (p, pa) = area_vector(x, model.queries.faces[faces.clone()].iter().copied());
        let (ls, lp) = (norm(s), norm(p));
        if ls < FLAT * sa || lp < FLAT * pa {
            continue;
        }
        let cos = dot(s, p) / (ls * lp);
        if cos > SAME_WAY {
            let unit = |v: V3, l: f64| v.map(|c| (c / l * 1e3).round() / 1e3);
            return Err(ImpactError::SceneValue {
                path: scene.path.clone(),
                key: scene.interface_key(k),
                message: format!(
                    "the secondary and primary surfaces face the same way (mean outward normals {:?} and {:?}): they can never touch as declared; contact needs surfaces that face each other (check the face or surface names)",
                    unit(s, ls),
                    unit(p, lp)
                ),
            });
        }
    }
    Ok(())
}
