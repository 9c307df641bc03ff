//! `impact check`: what an engineer checks first about a model, as text, without running it.

use std::fmt::Write as _;

use crate::check::memory;
use crate::error::{bytes, Result};
use crate::integrate::explicit::lumped_mass;
use crate::integrate::implicit::FactorPlan;
use crate::integrate::stable_step::stable_step_on;
use crate::linalg::assemble;
use crate::scene::{Method, Scene};
use crate::setup::{choose_method, Setup};

/// The report of a prepared scene; an implicit model's factors are analysed for it, and
/// refused as a run would refuse them when they do not fit the memory.
pub fn model_report(scene: &Scene, setup: &Setup) -> Result<String> {
    let mut out = String::new();
    let _ = writeln!(out, "scene {}", scene.path.display());
    let _ = writeln!(out, "bodies:");
    bodies(&mut out, scene, setup);
    stable_step(&mut out, scene, setup);
    method(&mut out, scene, setup);
    let _ = writeln!(out, "contact interfaces:");
    interfaces(&mut out, setup);
    if !setup.model.cohesive.is_empty() {
        let _ = writeln!(out, "cohesive interfaces:");
        cohesive(&mut out, setup);
    }
    let _ = writeln!(out, "fixes:");
    fixes(&mut out, scene, setup);
    let _ = writeln!(out, "memory: {}", memory::describe(&setup.estimate));
    if setup.method == Method::Implicit {
        let _ = writeln!(out, "implicit factors: {}", implicit_factors(scene, setup)?);
    }
    let lowered = (setup.damage.as_ref())
        .map(|d| crate::check::crack_band::lowered(scene, &setup.model, d))
        .unwrap_or_default();
    if !lowered.is_empty() {
        let _ = writeln!(out, "ply damage:");
        for line in &lowered {
            let _ = writeln!(out, "  {line}");
        }
    }
    let bands = (setup.damage.as_ref())
        .map(|d| crate::check::crack_band::crack_band(scene, &setup.model, d))
        .unwrap_or_default();
    for w in setup.warnings.iter().chain(&bands) {
        let _ = writeln!(out, "warning: {}: {}", w.kind, w.message);
    }
    Ok(out)
}

/// The implicit run's factors from their symbolic analysis (as the run plans them), checked
/// against the memory.
fn implicit_factors(scene: &Scene, setup: &Setup) -> Result<String> {
    let settings = &scene.implicit;
    let c_m = 1.0 / (settings.beta * setup.dt * setup.dt);
    let asm = assemble(&setup.model, settings.mass, c_m);
    // the GPU's kernels compute in f32, which keeps the iteration on the whole model
    let exact = setup.ctx.is_none();
    let plan = FactorPlan::new(&setup.model, settings, &asm, exact)?;
    plan.check().map_err(|e| e.at_scene(&scene.path))?;
    let space = match plan.effective.contact_equations() {
        0 => "the contact iteration solves on the whole model".to_string(),
        n => format!("the contact iteration solves on {n} contact equations"),
    };
    Ok(format!(
        "{}; {} with their workspace (from the symbolic analysis); {space}",
        plan.describe(),
        bytes(plan.bytes())
    ))
}

/// Each body: elements, nodes, dofs, mass, centre of mass and material.
fn bodies(out: &mut String, scene: &Scene, setup: &Setup) {
    let model = &setup.model;
    let mass = lumped_mass(model);
    for (b, body) in model.mesh.bodies.iter().enumerate() {
        let (mut m, mut c) = (0.0, [0.0; 3]);
        for n in body.nodes.clone() {
            m += mass[n];
            for (ca, x) in c.iter_mut().zip(model.mesh.nodes[n]) {
                *ca += mass[n] * x;
            }
        }
        let c = c.map(|v| v / m);
        let _ = writeln!(
            out,
            "  {}: {} elements ({}), {} nodes, {} dofs ({} free); mass {m:.6e}, centre of mass [{:.6e}, {:.6e}, {:.6e}]; material `{}`",
            scene.bodies[b].name,
            body.element_count(),
            body.kind_counts(),
            body.nodes.len(),
            3 * body.nodes.len(),
            (3 * body.nodes.start..3 * body.nodes.end)
                .filter(|&d| !model.fixed[d])
                .count(),
            c[0],
            c[1],
            c[2],
            scene.materials[body.material].name
        );
    }
}

/// The stable explicit step and the element that sets it.
fn stable_step(out: &mut String, scene: &Scene, setup: &Setup) {
    let model = &setup.model;
    if let Some((stable, e)) = setup.bound {
        let material = model.mesh.element(e).material;
        let body = model.mesh.body_of(e).unwrap_or(0);
        let pairs = match model.cohesive.is_empty() {
            true => String::new(),
            false => " and lowered for the cohesive pairs' springs".into(),
        };
        let _ = writeln!(
            out,
            "stable explicit step: {stable:.6e}, set by element {e} (body `{}`, material `{}`){pairs}",
            scene.bodies[body].name, scene.materials[model.material_source[material as usize]].name
        );
    }
}

/// The method, its reason, the step and the end time; and what "auto" would choose.
fn method(out: &mut String, scene: &Scene, setup: &Setup) {
    let model = &setup.model;
    let _ = writeln!(
        out,
        "method: {} ({}); time step {:.6e}, {} steps to t = {:.6e}",
        setup.method.name(),
        setup
            .method_choice
            .clone()
            .unwrap_or_else(|| match scene.run.method {
                Method::Auto => "auto".into(),
                m => format!("run.method = \"{}\"", m.name()),
            }),
        setup.dt,
        setup.steps,
        setup.end_time()
    );
    if setup.method_choice.is_none() {
        // what "auto" would choose, from the stable step on the CPU
        let stable = setup
            .bound
            .map(|b| b.0)
            .or_else(|| stable_step_on(model, None).ok().map(|b| b.0));
        if let Some(stable) = stable {
            let _ = writeln!(
                out,
                "method = \"auto\" would choose {}",
                choose_method(scene, model, stable).1
            );
        }
    }
}

/// Each cohesive interface: its bonded pairs and area, and its law's onsets and final
/// separations in the pure modes.
fn cohesive(out: &mut String, setup: &Setup) {
    for c in &setup.model.cohesive {
        let p = &c.pairs;
        let (n0, nf, _) = p.law.envelope(0.0);
        let (s0, sf, _) = p.law.envelope(1.0);
        let _ = writeln!(
            out,
            "  `{}`: {} bonded node pairs over {:.4e} (length^2); opening from {n0:.3e} to {nf:.3e}, sliding from {s0:.3e} to {sf:.3e}",
            c.name,
            p.area.len(),
            p.area.iter().sum::<f64>()
        );
    }
}

/// Each contact interface with its initial gaps and penetrations.
fn interfaces(out: &mut String, setup: &Setup) {
    let model = &setup.model;
    if model.interfaces.is_empty() {
        let _ = writeln!(out, "  none");
    }
    for (itf, r) in model.interfaces.iter().zip(&setup.initial) {
        let gaps = match (r.gap_min, r.gap_max) {
            (Some(lo), Some(hi)) => format!(
                "initial gap {lo:.4e} to {hi:.4e} over the {} nodes within reach",
                r.nodes_in_reach
            ),
            _ => "no secondary node within reach of the primary surface".into(),
        };
        let pen = if r.penetrating > 0 {
            format!(
                "; {} nodes penetrate (deepest {:.4e}, node {}): initial_penetration = \"{}\"{}",
                r.penetrating,
                r.depth,
                r.deepest_node.unwrap_or_default(),
                r.policy,
                if r.moved > 0 {
                    format!(", {} moved onto the surface", r.moved)
                } else {
                    String::new()
                }
            )
        } else {
            String::new()
        };
        let pen = match r.primary_inside {
            0 => pen,
            n => format!(
                "{pen}; {n} points of the primary surface lie inside the secondary body (one at {:?})",
                r.primary_inside_at.unwrap_or_default()
            ),
        };
        let _ = writeln!(
            out,
            "  {}: {} secondary nodes against {}, {}; {gaps}{pen}",
            itf.name,
            itf.nodes.len(),
            match itf.primary {
                crate::model::Primary::Plane { .. } => "a rigid plane".to_string(),
                crate::model::Primary::Rigid { body, .. } => format!(
                    "rigid body `{}` (mass {}, {})",
                    model.rigid[body].name,
                    model.rigid[body].mass,
                    model.rigid[body].motion.name()
                ),
                crate::model::Primary::Surface { .. } => "a surface".to_string(),
            },
            itf.law
        );
    }
}

/// Each fix: its nodes and held components.
fn fixes(out: &mut String, scene: &Scene, setup: &Setup) {
    let model = &setup.model;
    if scene.fixes.is_empty() {
        let _ = writeln!(out, "  none");
    }
    for (i, (f, n)) in scene.fixes.iter().zip(&model.fix_nodes).enumerate() {
        let comps: String = ["x", "y", "z"]
            .iter()
            .zip(f.components)
            .filter(|(_, on)| *on)
            .map(|(c, _)| *c)
            .collect();
        let _ = match f.nodes {
            crate::scene::NodeSelection::RigidBody => writeln!(
                out,
                "  fix[{i}]: rigid body `{}`, components {comps}",
                scene.rigid_bodies[f.body].name
            ),
            _ => writeln!(
                out,
                "  fix[{i}]: {n} nodes of body `{}`, components {comps}",
                scene.bodies[f.body].name
            ),
        };
    }
}
