//! External loads as data: each `[[load]]` (a deck's `*CLOAD` or pressure `*DLOAD`) as the
//! nodal forces it applies at full amplitude, and its amplitude over time.
//!
//! A pressure p on a face acts against the face's outward normal in the reference
//! configuration; its consistent nodal forces are $f_k = -p \int N_k\, n\, dA$ (2 x 2 Gauss
//! points on a quad, exact for its bilinear geometry; a third of $-p\,n A$ on each corner of
//! a triangle). The loads do not follow the deformation (small displacements).

use crate::error::{ImpactError, Result};
use crate::geometry::face::{Face, FaceKind};
use crate::geometry::vector::{cross, V3};
use crate::mesh::Mesh;
use crate::scene::{LoadKind, NodeSelection, Scene};

/// The scene's `[[load]]`s on the model's mesh, and how many of each load's nodal forces
/// fell on components a `[[fix]]` holds: those go to the support (its reaction takes them,
/// as in CalculiX and Abaqus) and are left out here. One that selects no node is an error
/// naming it.
pub(super) fn loads(scene: &Scene, mesh: &Mesh, fixed: &[bool]) -> Result<(Vec<Load>, Vec<usize>)> {
    let mut out = Vec::with_capacity(scene.loads.len());
    let mut held = Vec::with_capacity(scene.loads.len());
    for (i, l) in scene.loads.iter().enumerate() {
        let err = |message: String| ImpactError::SceneValue {
            path: scene.path.clone(),
            key: format!("load[{i}]"),
            message,
        };
        let amplitude = Amplitude {
            points: l.amplitude.clone(),
        };
        let mut load = match (l.kind, &l.nodes) {
            (LoadKind::Pressure(p), NodeSelection::Surface(s)) => {
                let faces = &mesh.bodies[l.body].surfaces[*s].faces;
                Load::pressure(mesh, faces, p, amplitude)
            }
            (LoadKind::Force(f), nodes) => {
                Load::nodal(&super::selection(mesh, l.body, nodes), f, amplitude)
            }
            (LoadKind::Pressure(_), _) => unreachable!("the scene checks a pressure's face"),
        };
        let body = &scene.bodies[l.body].name;
        if super::selection(mesh, l.body, &l.nodes).is_empty() {
            return Err(err(format!("selects no node of body `{body}`")));
        }
        let before = load.dofs.len();
        let kept: Vec<(u32, f64)> = (load.dofs.iter().zip(&load.force))
            .filter(|(&d, _)| !fixed[d as usize])
            .map(|(&d, &f)| (d, f))
            .collect();
        (load.dofs, load.force) = kept.into_iter().unzip();
        held.push(before - load.dofs.len());
        out.push(load);
    }
    Ok((out, held))
}

/// A piecewise linear amplitude through (time, value) points, held at its first and last
/// values outside them; no point is the constant 1.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Amplitude {
    pub points: Vec<[f64; 2]>,
}

impl Amplitude {
    /// The amplitude at time `t`.
    pub fn at(&self, t: f64) -> f64 {
        let p = &self.points;
        match (p.first(), p.last()) {
            (None, _) | (_, None) => 1.0,
            (Some(first), _) if t <= first[0] => first[1],
            (_, Some(last)) if t >= last[0] => last[1],
            _ => {
                let j = p.partition_point(|q| q[0] <= t);
                let ([t0, a0], [t1, a1]) = (p[j - 1], p[j]);
                a0 + (a1 - a0) * (t - t0) / (t1 - t0)
            }
        }
    }
}

/// One load: the nodal force of each dof it pushes at full amplitude, by increasing dof.
#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    pub dofs: Vec<u32>,
    pub force: Vec<f64>,
    pub amplitude: Amplitude,
}

impl Load {
    /// The same force `f` on each of `nodes`.
    pub fn nodal(nodes: &[u32], f: [f64; 3], amplitude: Amplitude) -> Load {
        let mut forces = std::collections::BTreeMap::new();
        for &n in nodes {
            for a in (0..3).filter(|&a| f[a] != 0.0) {
                forces.insert(3 * n + a as u32, f[a]);
            }
        }
        Self::of(forces, amplitude)
    }

    /// Pressure `p` on `faces` (outward normals), as consistent nodal forces.
    pub fn pressure(mesh: &Mesh, faces: &[Face], p: f64, amplitude: Amplitude) -> Load {
        let mut forces = std::collections::BTreeMap::new();
        for f in faces {
            let x = f.slots().map(|n| mesh.nodes[n as usize]);
            for (k, w) in face_weights(f.kind(), &x).into_iter().enumerate() {
                let Some(&n) = f.corners().get(k) else {
                    continue;
                };
                for (a, wa) in (0u32..).zip(w) {
                    *forces.entry(3 * n + a).or_insert(0.0) -= p * wa;
                }
            }
        }
        Self::of(forces, amplitude)
    }

    fn of(forces: std::collections::BTreeMap<u32, f64>, amplitude: Amplitude) -> Load {
        let (dofs, force) = forces.into_iter().filter(|(_, f)| *f != 0.0).unzip();
        Load {
            dofs,
            force,
            amplitude,
        }
    }

    /// The load's total force at full amplitude.
    pub fn resultant(&self) -> [f64; 3] {
        let mut r = [0.0; 3];
        for (&d, f) in self.dofs.iter().zip(&self.force) {
            r[d as usize % 3] += f;
        }
        r
    }
}

/// $\int N_k\, n\, dA$ of each of a face's four slots (a triangle's fourth is zero).
fn face_weights(kind: FaceKind, x: &[V3; 4]) -> [V3; 4] {
    let mut w = [[0.0; 3]; 4];
    match kind {
        FaceKind::Triangle => {
            let na = cross(
                crate::geometry::vector::sub(x[1], x[0]),
                crate::geometry::vector::sub(x[2], x[0]),
            );
            for wk in w.iter_mut().take(3) {
                *wk = na.map(|c| c / 6.0);
            }
        }
        FaceKind::Quad => {
            let g = 1.0 / 3f64.sqrt();
            for xi in [[-g, -g], [g, -g], [g, g], [-g, g]] {
                let (_, t1, t2, _) = kind.geometry(x, xi);
                // n dA = t1 x t2 dxi1 dxi2, unit weights
                let nda = cross(t1, t2);
                for (k, s) in kind.shape(xi).into_iter().enumerate() {
                    for a in 0..3 {
                        w[k][a] += s * nda[a];
                    }
                }
            }
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_amplitude_interpolates_and_holds_its_ends() {
        let a = Amplitude {
            points: vec![[0.0, 0.0], [1.0, 2.0], [3.0, 2.0], [4.0, 0.0]],
        };
        assert_eq!(a.at(-1.0), 0.0);
        assert_eq!(a.at(0.5), 1.0);
        assert_eq!(a.at(2.0), 2.0);
        assert_eq!(a.at(3.5), 1.0);
        assert_eq!(a.at(9.0), 0.0);
        assert_eq!(Amplitude::default().at(7.0), 1.0);
    }

    #[test]
    fn a_pressure_on_a_warped_quad_sums_to_p_times_its_vector_area() {
        let mut mesh = Mesh {
            nodes: vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.1, 0.3],
                [2.2, 1.5, -0.2],
                [-0.1, 1.2, 0.1],
            ],
            ..Mesh::default()
        };
        let face = Face::Quad([0, 1, 2, 3]);
        let load = Load::pressure(&mesh, &[face], 3.0, Amplitude::default());
        // the vector area of a quad is half the cross product of its diagonals
        let x = &mesh.nodes;
        let d1 = crate::geometry::vector::sub(x[2], x[0]);
        let d2 = crate::geometry::vector::sub(x[3], x[1]);
        let area = cross(d1, d2).map(|c| 0.5 * c);
        let r = load.resultant();
        for a in 0..3 {
            assert!((r[a] + 3.0 * area[a]).abs() < 1e-12, "{r:?} {area:?}");
        }
        // a flat rectangle: a quarter on each corner
        mesh.nodes = vec![
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let load = Load::pressure(&mesh, &[face], 3.0, Amplitude::default());
        assert_eq!(load.dofs, vec![2, 5, 8, 11]);
        for f in &load.force {
            assert!((f + 1.5).abs() < 1e-14, "{f}");
        }
    }
}
