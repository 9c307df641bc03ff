//! `[[tie]]`s as linear constraints: each secondary node within the tie's tolerance of the
//! primary surface follows the point of it nearest to the node, $u_s = \sum_i N_i(\xi)
//! u_i$ for each component, with $N_i$ the primary face's shape functions at that point (a
//! deck's `*TIE`, as CalculiX's multiple-point constraints). With `adjust` the node is first
//! moved onto that point, so that the two meshes meet without a gap.

use super::equations::Equation;
use crate::error::{ImpactError, Result};
use crate::geometry::face::Face;
use crate::geometry::vector::{norm, sub, V3};
use crate::mesh::Mesh;
use crate::scene::{Scene, SecondarySide, TieSpec};

/// CalculiX's default tolerance: this fraction of the primary faces' mean size.
pub const DEFAULT_TOLERANCE: f64 = 0.025;

/// One tie on the model's mesh: its constraints (three per tied node) and what it found.
#[derive(Debug, Clone, PartialEq)]
pub struct Tie {
    pub name: String,
    pub equations: Vec<Equation>,
    /// Secondary nodes tied.
    pub tied: usize,
    /// Secondary nodes farther than the tolerance from the primary surface, left free.
    pub untied: usize,
    /// Secondary nodes that are nodes of the primary surface too (already one).
    pub shared: usize,
    /// The tolerance used.
    pub tolerance: f64,
    /// The largest distance a tied node was from its point (moved by it with `adjust`).
    pub largest_gap: f64,
}

/// The scene's ties on `mesh`, whose tied nodes are moved where a tie adjusts them. A tie
/// that ties no node is an error naming it.
pub(super) fn ties(scene: &Scene, mesh: &mut Mesh) -> Result<Vec<Tie>> {
    let mut out = Vec::with_capacity(scene.ties.len());
    for (i, t) in scene.ties.iter().enumerate() {
        let tie = tie(mesh, t);
        if tie.tied == 0 {
            return Err(ImpactError::SceneValue {
                path: scene.path.clone(),
                key: format!("tie[{i}] (tie `{}`)", t.name),
                message: format!(
                    "no secondary node lies within {:.4e} of the primary surface ({} nodes farther, {} on it as its own nodes): give a larger `tolerance`, or check the sides",
                    tie.tolerance, tie.untied, tie.shared
                ),
            });
        }
        out.push(tie);
    }
    Ok(out)
}

/// Each tie's name and constraints, as [`super::equations`] takes them.
pub(super) fn views(ties: &[Tie]) -> Vec<super::equations::TieEquations<'_>> {
    (ties.iter())
        .map(|t| (t.name.as_str(), &t.equations[..]))
        .collect()
}

/// The secondary nodes of a tie, in increasing order.
fn secondary_nodes(mesh: &Mesh, side: SecondarySide) -> Vec<u32> {
    match side {
        SecondarySide::Faces(s) => Mesh::face_nodes(&mesh.bodies[s.body].surfaces[s.surface].faces),
        SecondarySide::Nodes { body, set } => {
            let mut nodes = mesh.bodies[body].node_sets[set].nodes.clone();
            nodes.sort_unstable();
            nodes.dedup();
            nodes
        }
    }
}

fn corners_of(mesh: &Mesh, f: &Face) -> [V3; 4] {
    f.slots().map(|n| mesh.nodes[n as usize])
}

/// One tie: each secondary node's nearest point on the primary faces (the first face in
/// order where two are as near, as on a shared edge), its constraints, and the node moved
/// onto it where the tie adjusts.
fn tie(mesh: &mut Mesh, t: &TieSpec) -> Tie {
    let faces = mesh.bodies[t.primary.body].surfaces[t.primary.surface]
        .faces
        .clone();
    let on_primary = Mesh::face_nodes(&faces);
    let sizes: Vec<f64> = (faces.iter())
        .map(|f| f.kind().size(&corners_of(mesh, f)))
        .collect();
    let mean = sizes.iter().sum::<f64>() / sizes.len().max(1) as f64;
    let tolerance = t.tolerance.unwrap_or(DEFAULT_TOLERANCE * mean);
    let boxes: Vec<(V3, V3)> = (faces.iter())
        .map(|f| {
            let p = corners_of(mesh, f);
            let lo = std::array::from_fn(|a| p.iter().map(|q| q[a]).fold(f64::MAX, f64::min));
            let hi = std::array::from_fn(|a| p.iter().map(|q| q[a]).fold(f64::MIN, f64::max));
            (lo, hi)
        })
        .collect();
    let mut out = Tie {
        name: t.name.clone(),
        equations: Vec::new(),
        tied: 0,
        untied: 0,
        shared: 0,
        tolerance,
        largest_gap: 0.0,
    };
    for n in secondary_nodes(mesh, t.secondary) {
        if on_primary.binary_search(&n).is_ok() {
            out.shared += 1;
            continue;
        }
        let x = mesh.nodes[n as usize];
        let near = |(lo, hi): &(V3, V3)| {
            (0..3).all(|a| x[a] >= lo[a] - tolerance && x[a] <= hi[a] + tolerance)
        };
        let mut best: Option<(f64, usize, [f64; 4], V3)> = None;
        for (k, f) in faces.iter().enumerate().filter(|(k, _)| near(&boxes[*k])) {
            let p = corners_of(mesh, f);
            let kind = f.kind();
            let xi = kind.project(&p, x);
            let w = kind.shape(xi);
            let y: V3 = std::array::from_fn(|a| (0..4).map(|c| w[c] * p[c][a]).sum());
            let d = norm(sub(x, y));
            if best.is_none_or(|b| d < b.0) {
                best = Some((d, k, w, y));
            }
        }
        let Some((d, k, w, y)) = best.filter(|b| b.0 <= tolerance) else {
            out.untied += 1;
            continue;
        };
        out.tied += 1;
        out.largest_gap = out.largest_gap.max(d);
        if t.adjust {
            mesh.nodes[n as usize] = y;
        }
        let corners = faces[k].corners();
        for c in 0..3u32 {
            let terms = (corners.iter().zip(&w))
                .filter(|(_, &wi)| wi.abs() > 1e-12)
                .map(|(&m, &wi)| (3 * m + c, wi))
                .collect();
            out.equations.push(Equation {
                dependent: 3 * n + c,
                terms,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A node over a unit quad's point (0.25, 0.5), 1e-3 above it: its weights are the
    /// bilinear ones there, the gap is 1e-3, and with adjust it lands on the face.
    #[test]
    fn a_node_follows_the_point_beneath_it() {
        use crate::scene::SurfaceRef;
        let mut mesh = Mesh {
            nodes: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.25, 0.5, 1e-3],
            ],
            ..Default::default()
        };
        let primary = crate::mesh::Surface {
            name: "p".into(),
            faces: vec![Face::Quad([0, 1, 2, 3])],
        };
        let secondary = crate::mesh::NodeSet {
            name: "s".into(),
            nodes: vec![4],
        };
        mesh.bodies.push(crate::mesh::BodyMesh {
            nodes: 0..5,
            elements: Vec::new(),
            material: 0,
            boundary: Vec::new(),
            surfaces: vec![primary],
            node_sets: vec![secondary],
        });
        let spec = TieSpec {
            name: "t".into(),
            secondary: SecondarySide::Nodes { body: 0, set: 0 },
            primary: SurfaceRef {
                body: 0,
                surface: 0,
            },
            tolerance: Some(2e-3),
            adjust: true,
        };
        let t = tie(&mut mesh, &spec);
        assert_eq!((t.tied, t.untied, t.shared), (1, 0, 0));
        assert!((t.largest_gap - 1e-3).abs() < 1e-15);
        assert_eq!(mesh.nodes[4], [0.25, 0.5, 0.0]);
        // weights (1 - x)(1 - y), x(1 - y), x y, (1 - x) y at (0.25, 0.5)
        let expected = [0.375, 0.125, 0.125, 0.375];
        assert_eq!(t.equations.len(), 3);
        for (c, e) in t.equations.iter().enumerate() {
            assert_eq!(e.dependent, 12 + c as u32);
            for (k, &(dof, w)) in e.terms.iter().enumerate() {
                assert_eq!(dof, 3 * k as u32 + c as u32);
                assert!(
                    (w - expected[k]).abs() < 1e-12,
                    "{w} against {}",
                    expected[k]
                );
            }
        }
        // out of reach: left free
        mesh.nodes[4] = [0.25, 0.5, 1e-2];
        let t = tie(&mut mesh, &spec);
        assert_eq!((t.tied, t.untied), (0, 1));
    }
}
