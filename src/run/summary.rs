//! The run's summary: what is known before the first step, the tally of each step, the
//! warnings, and the endings (completed, diverged, interrupted).

use std::time::Instant;

use super::charts::write_charts;
use super::outputs::{save, Outputs, RunIdentity};
use crate::check::penetration::InitialContact;
use crate::check::{self, Warning};
use crate::checkpoint::Tally;
use crate::error::ImpactError;
use crate::integrate::{ContactReport, Integrator, StepReport};
use crate::model::{Model, Primary};
use crate::output::summary::InterfaceSummary;
use crate::output::Summary;
use crate::scene::{Method, Scene};
use crate::setup::Setup;

/// The summary's fields known before the first step.
pub(super) fn initial_summary(scene: &Scene, setup: &Setup, solver: &dyn Integrator) -> Summary {
    let explicit = solver.method() == Method::Explicit;
    let statics = solver.method() == Method::Static;
    let model = &setup.model;
    // a static step's contact: augmented Lagrange on the gap increment (or a penalty law),
    // without mass
    let (constraint, penalty, mass) = match (explicit, statics) {
        (true, _) => ("gap_rate_impulse", "none", "lumped"),
        (_, true) => ("gap_increment", "stiffness", "none"),
        _ => (
            scene.implicit.constraint.name(),
            scene.implicit.penalty.name(),
            scene.implicit.mass.name(),
        ),
    };
    Summary {
        status: "running".into(),
        scene: scene.path.display().to_string(),
        title: scene.title.clone(),
        method: solver.method().name().into(),
        method_choice: setup.method_choice.clone(),
        device: solver.device_name(),
        engine: solver.engine().into(),
        kinematics: scene.run.kinematics.name().into(),
        time_step: setup.dt,
        stable_time_step: setup.bound.filter(|_| explicit).map(|b| b.0),
        end_time: setup.end_time(),
        constraint: constraint.into(),
        penalty: penalty.into(),
        mass: mass.into(),
        elements: model.mesh.element_count(),
        nodes: model.mesh.node_count(),
        free_dofs: model.fixed.iter().filter(|f| !**f).count(),
        initial_contact: setup.initial.clone(),
        memory_estimate_bytes: setup.estimate.host,
        ..Default::default()
    }
}

/// Adds a finished step to the tally.
pub(super) fn count_step(
    tally: &mut Tally,
    step: (usize, f64),
    r: StepReport,
    e: f64,
    reports: &[ContactReport],
) {
    tally.steps += 1;
    tally.iterations_total += r.iterations;
    tally.iterations_max = tally.iterations_max.max(r.iterations);
    tally.unconverged_steps += usize::from(!r.converged);
    tally.energy_final = e;
    tally.energy_max = tally.energy_max.max(e);
    let taken: f64 = (reports.iter())
        .map(|c| c.friction_work + c.impact_loss)
        .sum();
    if !taken.is_nan() {
        let departure = (e + taken - tally.energy_initial).abs();
        tally.balance_departure = Some(tally.balance_departure.unwrap_or(0.0).max(departure));
    }
    if !r.converged && tally.first_unconverged.is_none() {
        tally.first_unconverged = Some(step);
    }
    for (k, c) in reports.iter().enumerate() {
        tally.peak_force[k] = tally.peak_force[k].max(c.normal_force);
        if c.max_penetration > tally.deepest[k].0 {
            tally.deepest[k] = (c.max_penetration, step.0, step.1);
        }
    }
}

/// Adds a step's relative motion on each rigid body interface to the tally: the fastest
/// secondary node's speed relative to the rigid body's reference node, times the step
/// `dt`, over half the shape's thickness. Past 1, a node may have crossed the body between
/// two steps without the contact seeing it. The caller measures where the engine holds
/// every node's velocity after each step (the CPU, the GPU kernels with the host loop).
pub(super) fn count_motion(tally: &mut Tally, model: &Model, v: &[f64], dt: f64, at: (usize, f64)) {
    tally.fastest.resize(model.interfaces.len(), (0.0, 0, 0.0));
    let velocity = |n: u32| -> [f64; 3] { std::array::from_fn(|a| v[3 * n as usize + a]) };
    for (k, itf) in model.interfaces.iter().enumerate() {
        let Primary::Rigid { node, shape, .. } = &itf.primary else {
            continue;
        };
        let Some(half) = shape.half_thickness() else {
            continue;
        };
        let vr = velocity(*node);
        let fastest = (itf.nodes.iter())
            .map(|&n| crate::geometry::vector::norm(crate::geometry::vector::sub(velocity(n), vr)))
            .fold(0.0, f64::max);
        let ratio = fastest * dt / half;
        if ratio > tally.fastest[k].0 {
            tally.fastest[k] = (ratio, at.0, at.1);
        }
    }
}

/// The warnings of a finished run.
pub(super) fn warnings(
    scene: &Scene,
    model: &Model,
    tally: &Tally,
    implicit: bool,
    initial: &[InitialContact],
    energy_scale: f64,
) -> Vec<Warning> {
    let cap = if implicit {
        format!(
            "implicit.max_iterations = {} per solve",
            scene.implicit.max_iterations
        )
    } else {
        format!(
            "explicit.max_iterations = {} sweeps",
            scene.explicit.max_iterations
        )
    };
    let mut w: Vec<Warning> = check::unconverged(
        tally.unconverged_steps,
        tally.steps,
        tally.first_unconverged,
        &cap,
    )
    .into_iter()
    .collect();
    for (k, itf) in model.interfaces.iter().enumerate() {
        let (depth, step, time) = tally.deepest[k];
        w.extend(check::deep_penetration(
            &itf.name,
            depth,
            (step, time),
            check::face_size(&itf.area, itf.secondary_faces.len()),
        ));
    }
    w.extend(check::energy_rise(
        tally.energy_initial,
        tally.energy_max,
        energy_scale,
        scene.run.energy_tolerance,
    ));
    for ((itf, &(ratio, step, time)), k) in model.interfaces.iter().zip(&tally.fastest).zip(0..) {
        if ratio > 1.0 {
            let half = match &itf.primary {
                Primary::Rigid { shape, .. } => shape.half_thickness().unwrap_or_default(),
                _ => continue,
            };
            w.push(Warning::new(
                "fast_contact",
                format!(
                    "interface `{}` ({}): at step {step} (t = {time:.6e}) a secondary node moved {:.4e} relative to the rigid body in one step, {ratio:.2} times half its thickness {half:.4e}: a node can cross the body between two steps without the contact seeing it; take a shorter time step",
                    itf.name,
                    scene.interface_key(k),
                    ratio * half
                ),
            ));
        }
    }
    for r in initial {
        if r.primary_inside > 0 && r.policy == "ignore" {
            w.push(Warning::new(
                "initial_penetration",
                format!(
                    "interface `{}`: {} points of the primary surface started inside the secondary body (one at {:?}) and initial_penetration = \"ignore\" ran them as given",
                    r.interface, r.primary_inside, r.primary_inside_at.unwrap_or_default()
                ),
            ));
        }
        if r.penetrating > 0 && r.policy == "ignore" {
            w.push(Warning::new(
                "initial_penetration",
                format!(
                    "interface `{}`: {} nodes started behind the primary surface (deepest {:.4e}) and initial_penetration = \"ignore\" ran them as given",
                    r.interface, r.penetrating, r.depth
                ),
            ));
        }
    }
    w
}

/// The energy a run's divergence and energy-rise tests measure against: the initial energy,
/// or the work gravity can do across the model, whichever is larger.
pub(super) fn energy_scale(
    scene: &Scene,
    model: &Model,
    solver: &dyn Integrator,
    initial: f64,
) -> f64 {
    let total_mass: f64 = solver.nodal_mass().iter().sum();
    initial
        .abs()
        .max(
            total_mass
                * crate::scene::norm3(scene.gravity)
                * crate::geometry::vector::bbox_diagonal(&model.mesh.nodes),
        )
        .max(f64::MIN_POSITIVE)
}

/// The summary's counts and energies from the tally.
pub(super) fn copy_tally(summary: &mut Summary, tally: &Tally) {
    summary.steps = tally.steps;
    summary.iterations_total = tally.iterations_total;
    summary.iterations_max = tally.iterations_max;
    summary.unconverged_steps = tally.unconverged_steps;
    summary.energy_initial = tally.energy_initial;
    summary.energy_final = tally.energy_final;
    summary.energy_max = tally.energy_max;
    if let Some(max) = tally.failure_max {
        let names = crate::material::failure::INDICES
            .iter()
            .map(|s| s.to_string());
        summary.failure_index_max = Some(names.zip(max).collect());
        summary.first_failure = Some(tally.first_failure.clone());
    }
}

/// The summary's fields from the tally and the solver.
pub(super) fn fill_summary(
    summary: &mut Summary,
    tally: &Tally,
    model: &Model,
    solver: &dyn Integrator,
) {
    copy_tally(summary, tally);
    summary.external_work = (!model.loads.is_empty()).then_some(tally.external_work);
    // the explicit engines measure every contact's impact loss
    let explicit = solver.method() == crate::scene::Method::Explicit;
    summary.energy_balance = tally.balance_departure.filter(|_| explicit);
    let mut by_kind = None;
    if let Some(d) = solver.damage() {
        summary.damage_energy = Some(d.energy);
        by_kind = Some(crate::output::summary::DamageByKind {
            fibre: d.fibre,
            matrix: d.energy - d.fibre,
            interfaces: 0.0,
        });
        summary.first_damage = Some(d.first.map(|f| {
            crate::output::summary::FirstDamageSummary {
                time: f.time,
                cell: f.cell,
                body: (model.mesh.body_of(f.cell))
                    .map(|b| model.body_names[b].clone())
                    .unwrap_or_default(),
                ply: f.ply,
                mode: crate::material::damage::MODES[f.mode].into(),
            }
        }));
    }
    if let Some(state) = solver.cohesive_state() {
        use crate::output::delamination::{summary as delamination, DelaminationMap};
        let bonded: f64 = state.energy.iter().sum();
        summary.damage_energy = Some(summary.damage_energy.unwrap_or(0.0) + bonded);
        by_kind.get_or_insert_with(Default::default).interfaces = bonded;
        let map = DelaminationMap::of(model, &state);
        summary.delamination = Some(delamination(model, &state, &map));
    }
    summary.damage_energy_by_kind = by_kind;
    summary.iterations_mean = tally.iterations_total as f64 / tally.steps.max(1) as f64;
    summary.interfaces = interface_summaries(model, solver, &tally.peak_force);
    if let Some(f) = solver.implicit_figures() {
        summary.factorizations = f.factorizations;
        summary.linear_solver = Some(f.linear_solver);
        summary.mass_factor = f.mass_factor;
        summary.event_steps = f.event_steps;
        summary.newton = f.newton;
    }
    if let Some((recorded, needed)) = solver.recorded_sweeps() {
        summary.sweeps_recorded = Some(recorded);
        summary.sweeps_needed = Some(needed);
    }
    summary.contact_zone = solver.contact_zone();
    summary.contact_forms = solver.contact_forms();
    summary.device_seconds = solver.device_seconds();
    if let Some((rebuilds, stale)) = solver.search_rebuilds() {
        summary.search_rebuilds = Some(rebuilds);
        summary.search_stale_steps = Some(stale);
    }
}

/// Ends an interrupted run: a checkpoint (CPU integrators), the history, a summary with
/// `status = "interrupted"`, and the error.
#[allow(clippy::too_many_arguments)]
pub(super) fn interrupted(
    model: &Model,
    solver: &mut dyn Integrator,
    summary: &mut Summary,
    tally: &Tally,
    out: &mut Outputs,
    identity: &RunIdentity,
    start: Instant,
) -> ImpactError {
    let saved = save(solver, out, tally, identity);
    let _ = out.history.flush();
    fill_summary(summary, tally, model, solver);
    // every rank of a decomposed run stops at the same step
    summary.ranks = solver.decomposed_mut().map(|d| d.decomposition());
    summary.status = "interrupted".into();
    summary.message = Some(match &saved {
        Ok(()) => format!(
            "interrupted by a signal; continue with --resume (checkpoint at step {})",
            tally.steps
        ),
        Err(e) => format!("interrupted by a signal; the checkpoint could not be written: {e}"),
    });
    summary.wall_seconds = start.elapsed().as_secs_f64();
    if let Err(e) = out.summary(summary) {
        return e;
    }
    if let Err(e) = saved {
        return e;
    }
    ImpactError::Interrupted {
        step: tally.steps,
        time: solver.time(),
        dir: out.dir.clone(),
    }
}

/// Each interface's line of the summary.
fn interface_summaries(
    model: &Model,
    solver: &dyn Integrator,
    peak: &[f64],
) -> Vec<InterfaceSummary> {
    (model.interfaces.iter())
        .zip(solver.interface_ends())
        .zip(peak)
        .map(|((itf, end), &p)| InterfaceSummary {
            name: itf.name.clone(),
            penalty_normal_final: end.penalty_normal,
            penalty_tangential_final: end.penalty_tangential,
            friction_work: end.friction_work,
            impact_loss: end.impact_loss,
            penalty_increases: end.penalty_increases,
            penalty_decreases: end.penalty_decreases,
            peak_normal_force: p,
        })
        .collect()
}

/// Ends a diverged run: flushes the history, writes the summary and the charts, and returns
/// the error.
#[allow(clippy::too_many_arguments)]
pub(super) fn fail(
    scene: &Scene,
    model: &Model,
    summary: &mut Summary,
    tally: &Tally,
    out: &mut Outputs,
    (step, time): (usize, f64),
    reason: String,
    start: Instant,
) -> ImpactError {
    let _ = out.history.flush();
    copy_tally(summary, tally);
    summary.status = "diverged".into();
    summary.message = Some(reason.clone());
    summary.wall_seconds = start.elapsed().as_secs_f64();
    let _ = out.summary(summary);
    if out.writes {
        let _ = write_charts(scene, model, &out.dir);
    }
    ImpactError::Diverged {
        step,
        time,
        reason,
        dir: out.dir.clone(),
    }
}

/// Ends a run whose effective matrix did not factorise before its first step: the error,
/// and a summary (`failed`, where `writes`) with the likely cause ([`likely_cause`]).
pub(super) fn unfactorised(
    scene: &Scene,
    setup: &Setup,
    dir: &std::path::Path,
    message: String,
    writes: bool,
    start: Instant,
) -> ImpactError {
    let message = format!(
        "{}: {message}; likely cause: {}",
        scene.path.display(),
        likely_cause(scene, setup)
    );
    if writes {
        let summary = Summary {
            status: "failed".into(),
            scene: scene.path.display().to_string(),
            title: scene.title.clone(),
            method: setup.method.name().into(),
            time_step: setup.dt,
            message: Some(message.clone()),
            wall_seconds: start.elapsed().as_secs_f64(),
            ..Default::default()
        };
        let _ = summary.write(dir);
    }
    ImpactError::Solver(message)
}

/// Why the effective matrix K + M / (beta dt^2) may not factorise: a material whose
/// modulus or density is beyond what a double's products hold; one whose mass term is lost
/// against its stiffness in rounding (a free body then has nothing against rigid motion);
/// else a body neither held nor given mass.
fn likely_cause(scene: &Scene, setup: &Setup) -> String {
    let model = &setup.model;
    let size = model.mesh.min_edge();
    let key = |i: usize| format!("material[{i}] (material `{}`)", scene.materials[i].name);
    for (i, m) in model.materials.iter().enumerate() {
        let i = model.material_source.get(i).copied().unwrap_or(i);
        let modulus = m.density * m.wave_speed().powi(2);
        let range = 1e-150..1e150;
        if !range.contains(&modulus) || !range.contains(&m.density) {
            return format!(
                "{}: its modulus {modulus:.3e} or density {:.3e} lies outside 1e-150 to 1e150, where the matrices' products overflow or vanish in a double (check its units)",
                key(i),
                m.density
            );
        }
        let transit = size / m.wave_speed();
        let mass_term = (transit / setup.dt).powi(2) / scene.implicit.beta;
        if mass_term < 1e-12 {
            return format!(
                "{}: its mass term is {mass_term:.3e} of its stiffness (the elements' transit time {transit:.3e} against the step {:.3e}): a body free to move rests on its mass alone, which rounding loses; check the density's units or take a shorter time step",
                key(i),
                setup.dt
            );
        }
    }
    "a body neither held nor given mass (every body must be held or free to move with positive mass)".into()
}
