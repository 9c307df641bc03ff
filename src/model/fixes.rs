//! What the `[[fix]]`es in force hold: the run's own, and from each `[[step]]` on, the
//! step's, over those it releases or takes dofs from.

use std::collections::HashMap;

use super::loads::Amplitude;
use super::prescribed::{FixPath, PathShape};
use super::{body_box, selection, Reaction};
use crate::error::{ImpactError, Result};
use crate::mesh::Mesh;
use crate::scene::{FixSpec, NodeSelection, Release, Scene};

/// A fix in force: its scene key (`fix[0]`, `step[1].fix[0]`), what it says, the step it
/// belongs to (0: the run's own) and the end of its first ramp (the end of its step).
pub(super) struct InForce<'a> {
    key: String,
    /// Its index among the run's own `[[fix]]`es (`None`: a step's).
    own: Option<usize>,
    spec: &'a FixSpec,
    layer: usize,
    ramp_end: f64,
}

/// The fixes in force in step `step` (`None`: the first step, the `[run]`'s): the run's own
/// less those released, then each step's up to it, in order.
pub(super) fn in_force(scene: &Scene, step: Option<usize>) -> Vec<InForce<'_>> {
    let end_of = |k: usize| scene.steps.get(k).map_or(scene.run.end_time, |s| s.start);
    let mut out: Vec<InForce> = (scene.fixes.iter().enumerate())
        .map(|(i, spec)| InForce {
            key: format!("fix[{i}]"),
            own: Some(i),
            spec,
            layer: 0,
            ramp_end: end_of(0),
        })
        .collect();
    for (k, s) in scene
        .steps
        .iter()
        .enumerate()
        .take(step.map_or(0, |k| k + 1))
    {
        match &s.release_fixes {
            Release::None => {}
            Release::All => out.clear(),
            Release::Fixes(ids) => out.retain(|f| f.own.is_none_or(|i| !ids.contains(&i))),
        }
        let ramp_end = s.end.unwrap_or_else(|| end_of(k + 1));
        out.extend(s.fixes.iter().enumerate().map(|(i, spec)| InForce {
            key: format!("step[{k}].fix[{i}]"),
            own: None,
            spec,
            layer: k + 1,
            ramp_end,
        }));
    }
    out
}

/// What the fixes hold: every held dof, the nodes each fix holds, the held dofs that move
/// (with their velocities), the paths of those moved by a displacement and each named
/// fix's held dofs.
pub(super) struct Fixes {
    pub fixed: Vec<bool>,
    pub counts: Vec<usize>,
    pub moving: Vec<(usize, f64)>,
    pub paths: Vec<FixPath>,
    pub reactions: Vec<Reaction>,
}

/// What the fixes `list` hold (a fix that holds no node is an error naming it). Two fixes
/// of one step that move a dof differently are an error; a later step's fix takes the dof
/// over from an earlier one's.
pub(super) fn fixes(scene: &Scene, mesh: &Mesh, list: &[InForce]) -> Result<Fixes> {
    let mut fixed = vec![false; 3 * mesh.node_count()];
    // the velocity each held dof is given (NaN: along a displacement), and by which fix
    let mut owner: HashMap<usize, (f64, usize)> = HashMap::new();
    let mut counts = Vec::with_capacity(list.len());
    let mut reactions = Vec::new();
    // each fix's held dofs with their components
    let mut held_by: Vec<Vec<(usize, usize)>> = Vec::with_capacity(list.len());
    let first_rigid = mesh.node_count() - scene.rigid_bodies.len();
    for (i, f) in list.iter().enumerate() {
        let nodes = match f.spec.nodes {
            NodeSelection::RigidBody => vec![(first_rigid + f.spec.body) as u32],
            _ => selection(mesh, f.spec.body, &f.spec.nodes),
        };
        if nodes.is_empty() {
            return Err(empty_fix(scene, mesh, f));
        }
        counts.push(nodes.len());
        let mut held: [Vec<u32>; 3] = Default::default();
        let mut dofs = Vec::with_capacity(3 * nodes.len());
        for &n in &nodes {
            for a in (0..3).filter(|&a| f.spec.components[a]) {
                let d = 3 * n as usize + a;
                fixed[d] = true;
                held[a].push(d as u32);
                dofs.push((d, a));
                let w = match f.spec.displacement {
                    Some(_) => f64::NAN,
                    None => f.spec.velocity[a],
                };
                if let Some((w0, j)) = owner.insert(d, (w, i)) {
                    if list[j].layer == f.layer && (w0 != w || w.is_nan()) {
                        return Err(two_motions(scene, (f, &list[j]), n, a));
                    }
                }
            }
        }
        held_by.push(dofs);
        if let Some(name) = &f.spec.name {
            reactions.push(Reaction {
                name: name.clone(),
                dofs: held,
            });
        }
    }
    let paths = (list.iter().zip(&held_by).enumerate())
        .filter_map(|(i, (f, dofs))| {
            let (value, table) = f.spec.displacement.as_ref()?;
            let own: Vec<(u32, f64)> = (dofs.iter())
                .filter(|(d, _)| owner[d].1 == i)
                .map(|&(d, a)| (d as u32, value[a]))
                .collect();
            Some(FixPath::new(own, shape(f, table)))
        })
        .collect();
    let mut moving: Vec<(usize, f64)> = (owner.into_iter())
        .filter(|(_, (w, _))| *w != 0.0 && !w.is_nan())
        .map(|(d, (w, _))| (d, w))
        .collect();
    moving.sort_by_key(|m| m.0);
    Ok(Fixes {
        fixed,
        counts,
        moving,
        paths,
        reactions,
    })
}

/// Marks the dofs of every prescribed (or fixed) rigid body held in `fixed`.
pub(super) fn hold_prescribed(fixed: &mut [bool], rigid: &[super::RigidBody]) {
    hold_rigid(fixed, rigid, super::RigidBody::is_prescribed);
}

/// Marks the dofs of the rigid bodies `which` picks held in `fixed`.
pub(crate) fn hold_rigid(
    fixed: &mut [bool],
    rigid: &[super::RigidBody],
    which: impl Fn(&super::RigidBody) -> bool,
) {
    for b in rigid.iter().filter(|b| which(b)) {
        fixed[3 * b.node as usize..3 * b.node as usize + 3].fill(true);
    }
}

/// How a displaced fix reaches its displacement: along its amplitude table; without one,
/// the run's own fixes ramp from 0 at t = 0 over the first step, a step's straight from where
/// its nodes are at the step's start over the step.
fn shape(f: &InForce, table: &[[f64; 2]]) -> PathShape {
    match (table.is_empty(), f.layer) {
        (false, _) => PathShape::Scaled(Amplitude {
            points: table.to_vec(),
        }),
        (true, 0) => PathShape::Scaled(Amplitude {
            points: vec![[0.0, 0.0], [f.ramp_end, 1.0]],
        }),
        (true, _) => PathShape::RampTo { end: f.ramp_end },
    }
}

/// A fix that holds no node.
fn empty_fix(scene: &Scene, mesh: &Mesh, f: &InForce) -> ImpactError {
    ImpactError::SceneValue {
        path: scene.path.clone(),
        key: f.key.clone(),
        message: format!(
            "holds no node of body `{}`{}",
            scene.bodies[f.spec.body].name,
            match &f.spec.nodes {
                NodeSelection::Region { min, max } => format!(
                    " (region.min {min:?}, region.max {max:?}; the body's nodes span {:?} to {:?})",
                    body_box(mesh, f.spec.body).0,
                    body_box(mesh, f.spec.body).1
                ),
                _ => String::new(),
            }
        ),
    }
}

/// Two fixes of one step that move one node's component differently.
fn two_motions(scene: &Scene, (fi, fj): (&InForce, &InForce), n: u32, a: usize) -> ImpactError {
    let axis = ["x", "y", "z"][a];
    let (key, message) = match (&fi.spec.displacement, &fj.spec.displacement) {
        (None, None) => (
            format!("{}.velocity", fi.key),
            format!(
                "{} holds node {n}'s {axis} at {} and this fix at {}: a node's component moves at one velocity",
                fj.key, fj.spec.velocity[a], fi.spec.velocity[a]
            ),
        ),
        _ => (
            format!("{}.displacement", fi.key),
            format!("{} holds node {n}'s {axis} too: a component a fix moves by a displacement is that fix's alone", fj.key),
        ),
    };
    ImpactError::SceneValue {
        path: scene.path.clone(),
        key,
        message,
    }
}
