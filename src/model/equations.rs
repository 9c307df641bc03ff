//! `[[equation]]`s as data: each a dependent dof and the dofs (with their factors) that set
//! it, $u_d = \sum_j c_j u_j$, chains of equations substituted so that no dof that sets
//! another is itself set by one.

use crate::error::{ImpactError, Result};
use crate::mesh::Mesh;
use crate::scene::{Removal, Scene};

/// A `[[tie]]`'s name and constraints.
pub(super) type TieEquations<'a> = (&'a str, &'a [Equation]);

/// One linear constraint: `dependent` = sum of factor x dof over `terms`.
#[derive(Debug, Clone, PartialEq)]
pub struct Equation {
    pub dependent: u32,
    pub terms: Vec<(u32, f64)>,
}

/// The scene's equations on the model's mesh, then the ties' constraints on the dofs no
/// `[[fix]]` holds (a support wins over a tie). A term whose selection is not one node, a
/// dependent dof a `[[fix]]` holds or another equation sets too, and a cycle of equations
/// are errors naming the equation or the tie.
pub(super) fn equations(
    scene: &Scene,
    mesh: &Mesh,
    fixed: &[bool],
    ties: &[TieEquations],
) -> Result<Vec<Equation>> {
    let kept = vec![false; scene.equations.len()];
    equations_kept(scene, mesh, (fixed, ties), &kept)
}

/// Which of the scene's equations the steps up to step `k` (of `scene.steps`) have removed:
/// all, or those whose first term's dof is a removed one.
pub(super) fn removed_by(scene: &Scene, mesh: &Mesh, k: usize) -> Vec<bool> {
    let dependent = |e: &crate::scene::EquationSpec| {
        let t = &e.terms[0];
        (super::selection(mesh, t.body, &t.nodes).first()).map(|&n| 3 * n as usize + t.component)
    };
    let mut removed = vec![false; scene.equations.len()];
    for step in &scene.steps[..=k] {
        let dofs: Vec<usize> = match &step.remove_equations {
            Removal::None => continue,
            Removal::All => {
                removed.fill(true);
                continue;
            }
            Removal::Dofs(d) => (d.iter())
                .flat_map(|(b, nodes, c)| {
                    let nodes = super::selection(mesh, *b, nodes);
                    nodes.into_iter().map(move |n| 3 * n as usize + c)
                })
                .collect(),
        };
        for (r, e) in removed.iter_mut().zip(&scene.equations) {
            *r |= dependent(e).is_some_and(|d| dofs.contains(&d));
        }
    }
    removed
}

/// [`equations`] without the scene's equations `removed` marks.
pub(super) fn equations_kept(
    scene: &Scene,
    mesh: &Mesh,
    (fixed, ties): (&[bool], &[TieEquations]),
    removed: &[bool],
) -> Result<Vec<Equation>> {
    let err = |i: usize, message: String| ImpactError::SceneValue {
        path: scene.path.clone(),
        key: format!("equation[{i}]"),
        message,
    };
    let mut out: Vec<Equation> = Vec::with_capacity(scene.equations.len());
    // the scene equation each of `out`'s came from (the ties' come after)
    let mut origin: Vec<usize> = Vec::with_capacity(scene.equations.len());
    for (i, e) in scene.equations.iter().enumerate() {
        if removed[i] {
            continue;
        }
        let mut dofs = Vec::with_capacity(e.terms.len());
        for (j, t) in e.terms.iter().enumerate() {
            let nodes = super::selection(mesh, t.body, &t.nodes);
            let [node] = nodes[..] else {
                return Err(err(
                    i,
                    format!(
                        "term {j} selects {} nodes of body `{}`: a term is one node's component",
                        nodes.len(),
                        scene.bodies[t.body].name
                    ),
                ));
            };
            dofs.push((3 * node + t.component as u32, t.coefficient));
        }
        let (dependent, a) = dofs[0];
        if fixed[dependent as usize] {
            return Err(err(i, format!("its first term's dof (node {}, {}) is held by a [[fix]]: put a free dof first, the one the others set", dependent / 3, ["x", "y", "z"][dependent as usize % 3])));
        }
        if out.iter().any(|o| o.dependent == dependent) {
            return Err(err(
                i,
                format!(
                    "its first term's dof (node {}) is set by an earlier equation too",
                    dependent / 3
                ),
            ));
        }
        let terms = dofs[1..].iter().map(|&(d, c)| (d, -c / a)).collect();
        out.push(Equation { dependent, terms });
        origin.push(i);
    }
    for (k, (name, tied)) in ties.iter().enumerate() {
        let tie_err = |message: String| ImpactError::SceneValue {
            path: scene.path.clone(),
            key: format!("tie[{k}] (tie `{name}`)"),
            message,
        };
        for e in tied.iter().filter(|e| !fixed[e.dependent as usize]) {
            if let Some(j) = out.iter().position(|o| o.dependent == e.dependent) {
                let node = e.dependent / 3;
                return Err(tie_err(match origin.get(j) {
                    Some(i) => format!("its secondary node {node} is the dependent of equation[{i}] too: a node follows one constraint"),
                    None => format!("its secondary node {node} is tied by an earlier tie too: a node follows one surface"),
                }));
            }
            out.push(e.clone());
        }
    }
    substitute(&mut out).map_err(|k| match origin.get(k) {
        Some(&i) => err(i, "its dofs set each other through a cycle of equations".into()),
        None => ImpactError::SceneValue {
            path: scene.path.clone(),
            key: "tie".into(),
            message: format!(
                "node {}'s constraints run in a cycle through the ties (a node tied to a surface whose nodes are tied back to it): make one side of each pair of ties the secondary",
                out[k].dependent / 3
            ),
        },
    })?;
    Ok(out)
}

/// Replaces each term on a dependent dof by that dof's own terms until none is left;
/// `Err(k)` for equation k on a cycle.
fn substitute(eqs: &mut [Equation]) -> std::result::Result<(), usize> {
    let index: std::collections::HashMap<u32, usize> = eqs
        .iter()
        .enumerate()
        .map(|(k, e)| (e.dependent, k))
        .collect();
    for k in 0..eqs.len() {
        for _ in 0..=eqs.len() {
            let Some(p) = eqs[k].terms.iter().position(|t| index.contains_key(&t.0)) else {
                break;
            };
            let (d, c) = eqs[k].terms.remove(p);
            let other = index[&d];
            if other == k {
                return Err(k);
            }
            let more: Vec<(u32, f64)> = eqs[other].terms.iter().map(|&(e, f)| (e, c * f)).collect();
            for (e, f) in more {
                match eqs[k].terms.iter_mut().find(|t| t.0 == e) {
                    Some(t) => t.1 += f,
                    None => eqs[k].terms.push((e, f)),
                }
            }
        }
        if eqs[k].terms.iter().any(|t| index.contains_key(&t.0)) {
            return Err(k);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_are_substituted_and_cycles_found() {
        // u0 = 2 u1, u1 = 3 u2 + u3: u0 = 6 u2 + 2 u3
        let mut eqs = vec![
            Equation {
                dependent: 0,
                terms: vec![(1, 2.0)],
            },
            Equation {
                dependent: 1,
                terms: vec![(2, 3.0), (3, 1.0)],
            },
        ];
        substitute(&mut eqs).unwrap();
        assert_eq!(eqs[0].terms, vec![(2, 6.0), (3, 2.0)]);
        let mut cycle = vec![
            Equation {
                dependent: 0,
                terms: vec![(1, 1.0)],
            },
            Equation {
                dependent: 1,
                terms: vec![(0, 1.0)],
            },
        ];
        assert!(substitute(&mut cycle).is_err());
    }
}
