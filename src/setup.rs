//! From a checked scene to a model ready to run: the memory guard, the model, its checks
//! (elements, facing surfaces, initial penetration), the device, the stable step, the
//! method and the time step. `impact run` and `impact check` share it.

use crate::backend::{CpuKernels, Kernels};
use crate::check::penetration::InitialContact;
use crate::check::{elements, facing, memory, penetration, quality, Warning};
use crate::error::{ImpactError, Result};
use crate::gpu::{AdapterPolicy, GpuContext, GpuKernels};
use crate::integrate::stable_step::survey;
use crate::model::Model;
use crate::output::summary::SetupClock;
use crate::scene::{DeviceChoice, Kinematics, Method, PenetrationPolicy, Scene};

pub use crate::gpu::context::AUTO_GPU_MIN_ELEMENTS;

/// A run longer than this many steps is refused: at a microsecond a step it would take
/// three hours, and a stable step this small against the end time comes from a unit or
/// material typo far more often than from a real model.
pub(crate) const MAX_STEPS: f64 = 1e10;

mod timeline;
pub use timeline::Stage;

/// A model ready to run.
pub struct Setup {
    pub model: Model,
    /// The GPU the kernels run on, or `None` for the CPU twins.
    pub ctx: Option<GpuContext>,
    /// The mesh's stable explicit step and the element that sets it (explicit and auto).
    pub bound: Option<(f64, usize)>,
    pub method: Method,
    /// Under `method = "auto"`: the rule's choice and why.
    pub method_choice: Option<String>,
    pub dt: f64,
    pub steps: usize,
    /// An explicit run whose end time is not a whole number of steps shortens its last step
    /// to this, so that it ends exactly at `end_time`.
    pub last_step: Option<f64>,
    /// t = 0 on every interface.
    pub initial: Vec<InitialContact>,
    pub estimate: memory::Estimate,
    /// What the model's checks found doubtful but not wrong ([`quality`]); a run ends with
    /// them among its warnings.
    pub warnings: Vec<Warning>,
    /// The damage kernels' inputs, where a material damages.
    pub damage: Option<crate::kernels::damage_data::DamageData>,
    /// Each `[[step]]` after the first: the run's step from which it holds, its start, model,
    /// method and time step.
    pub stages: Vec<Stage>,
}

impl Setup {
    /// The `[[step]]` in force from the run's step `n` (0-based) on; `None` before the
    /// first.
    fn stage_at(&self, n: usize) -> Option<&Stage> {
        self.stages.iter().rev().find(|s| s.from <= n)
    }

    /// The time step of the run's step `n` (0-based): its stage's.
    pub fn step_at(&self, n: usize) -> f64 {
        self.stage_at(n).map_or(self.dt, |s| s.dt)
    }

    /// The time after the run's first `n` steps (whole steps: the shortened last step
    /// aside).
    pub fn time_after(&self, n: usize) -> f64 {
        match self.stage_at(n) {
            Some(s) => s.start + (n - s.from) as f64 * s.dt,
            None => n as f64 * self.dt,
        }
    }

    /// The run's end: its last whole step's time, and the shortened last step.
    pub fn end_time(&self) -> f64 {
        match self.last_step {
            Some(last) => self.time_after(self.steps - 1) + last,
            None => self.time_after(self.steps),
        }
    }
}

/// Builds and checks the model and picks the device, method and step. `notice` receives
/// one-line reasons for automatic choices; `clock` times the stages.
pub fn prepare(
    scene: &Scene,
    device: DeviceChoice,
    notice: &mut dyn FnMut(&str),
    clock: &mut SetupClock,
) -> Result<Setup> {
    for line in &scene.notices {
        notice(&format!("notice: {line}"));
    }
    let counts = memory::Counts::of(scene);
    if counts.nodes > u64::from(u32::MAX) {
        return Err(ImpactError::SceneValue {
            path: scene.path.clone(),
            key: "body".into(),
            message: format!(
                "the bodies hold {} nodes together; a model holds at most {} (node numbers are 32-bit)",
                counts.nodes,
                u32::MAX
            ),
        });
    }
    memory::check(scene, &memory::estimate(scene, Method::Explicit, false), 0)?;
    let mut model = Model::from_scene(scene)?;
    for (i, &n) in model.held_loads.iter().enumerate().filter(|(_, &n)| n > 0) {
        notice(&format!(
            "notice: load[{i}]: {n} of its nodal forces push components a [[fix]] holds; the supports take them (their reactions show them)"
        ));
    }
    for line in tie_notices(&model) {
        notice(&line);
    }
    clock.lap("model");
    elements::check(scene, &model.mesh)?;
    facing::check(scene, &model)?;
    let initial = penetration::resolve(
        &mut model,
        &scene.penetration_policies(),
        &scene.adjust_distances(),
    );
    refuse_penetration(scene, &initial)?;
    if initial.iter().any(|r| r.moved > 0) {
        // nodes moved onto a surface can fold an element
        elements::check(scene, &model.mesh)?;
    }
    model.check_probes(scene)?;
    clock.lap("checks");
    let ctx = gpu_context(scene, model.mesh.element_count(), device, notice)?;
    clock.lap("device");
    let mut warnings = quality::locking(scene);
    let explicit_step = (scene.steps.iter()).any(|s| s.method == Some(Method::Explicit));
    let bound = match scene.run.method {
        Method::Implicit | Method::Static if !explicit_step => None,
        _ => {
            let s = survey(&model, ctx.as_ref()).map_err(|e| gpu_error(scene, e))?;
            warnings.extend(quality::slivers(scene, &model.mesh, &s.steps));
            Some(check_stable(scene, &model, (s.step, s.element))?)
        }
    };
    clock.lap("stable step");
    let (method, method_choice) = match (scene.run.method, bound) {
        (Method::Auto, Some((stable, _))) => {
            let (m, why) = choose_method(scene, &model, stable);
            notice(&format!("method auto: {why}"));
            (m, Some(why))
        }
        (m, _) => (m, None),
    };
    let dynamic = |m: Method| m != Method::Static;
    let waits = (scene.steps.iter()).any(|s| dynamic(s.method.unwrap_or(method)));
    if method == Method::Static && waits {
        hold_free_rigid_bodies(&mut model);
    }
    refuse_implicit(scene, &model, method)?;
    let (dt, steps, last_step) = time_step(scene, method, bound, method_choice.is_some())?;
    let estimate = memory::estimate(scene, method, ctx.is_some() && method == Method::Explicit);
    // the built model already left the memory available now
    let built = memory::estimate(scene, Method::Explicit, false).host;
    memory::check(scene, &estimate, built)?;
    let damage = model.damage_data();
    clock.lap("damage");
    if !scene.steps.is_empty() && !scene.mixed_steps() && scene.run.time_step != Some(dt) {
        return Err(ImpactError::SceneValue {
            path: scene.path.clone(),
            key: "step[0].start".into(),
            message: format!("the run's steps are {dt:e} long, not run.time_step: the steps could not land on the [[step]] starts"),
        });
    }
    let (mut stages, mixed) =
        timeline::stages(scene, (method, dt), bound, model.for_steps(scene)?)?;
    let (dt, steps, last_step) = match mixed {
        Some(m) => (m.dt, m.steps, m.last_step),
        None => (dt, steps, last_step),
    };
    if dynamic(method) || waits {
        let held = stages.iter_mut().filter(|s| s.method == Method::Static);
        held.for_each(|s| hold_free_rigid_bodies(&mut s.model));
    }
    for s in &stages {
        refuse_implicit(scene, &s.model, s.method)?;
    }
    Ok(Setup {
        stages,
        damage,
        model,
        ctx,
        bound,
        method,
        method_choice,
        dt,
        steps,
        last_step,
        initial,
        estimate,
        warnings,
    })
}

/// A line for each `[[tie]]`: the nodes it tied, how far they were from the surface, and
/// those it left free (out of reach, or held by a fix).
fn tie_notices(model: &Model) -> Vec<String> {
    (model.ties.iter())
        .map(|t| {
            let held = (t.equations.iter())
                .filter(|e| model.fixed[e.dependent as usize])
                .count();
            let mut line = format!(
                "notice: tie `{}`: {} secondary nodes tied (the largest {:.3e} from the primary surface; tolerance {:.3e})",
                t.name, t.tied, t.largest_gap, t.tolerance
            );
            if t.untied > 0 {
                line += &format!(", {} farther left free", t.untied);
            }
            if held > 0 {
                line += &format!(", {held} of their components held by a [[fix]] instead");
            }
            line
        })
        .collect()
}

/// Holds the free rigid bodies where they are: in the static steps of a run that has
/// dynamic ones, they wait there (nothing else holds them in a static step) and move in the
/// dynamic steps.
fn hold_free_rigid_bodies(model: &mut Model) {
    let free = |b: &crate::model::rigid::RigidBody| !b.is_prescribed();
    crate::model::fixes::hold_rigid(&mut model.fixed, &model.rigid, free);
}

/// The error for interfaces with `initial_penetration = "error"` that penetrate at t = 0.
fn refuse_penetration(scene: &Scene, initial: &[InitialContact]) -> Result<()> {
    let policies = scene.penetration_policies();
    for (k, r) in initial.iter().enumerate() {
        if policies[k] == PenetrationPolicy::Resolve && scene.run.method != Method::Static {
            return Err(ImpactError::SceneValue {
                path: scene.path.clone(),
                key: format!("{}.initial_penetration", scene.interface_key(k)),
                message: format!("\"resolve\" pushes overlapping bodies apart in a static step's first increment; the {} path would throw them apart: use \"adjust\" (or method = \"static\")", scene.run.method.name()),
            });
        }
        let accepted = matches!(
            policies[k],
            PenetrationPolicy::Ignore | PenetrationPolicy::Resolve
        );
        if r.primary_inside > 0 && !accepted {
            return Err(ImpactError::SceneValue {
                path: scene.path.clone(),
                key: format!("{}.initial_penetration", scene.interface_key(k)),
                message: format!(
                    "the primary surface lies inside the secondary body at t = 0: {} of its points, one at {:?} (no secondary node is behind it, so the contact would let the bodies pass through each other). Move the bodies apart (\"adjust\" moves secondary nodes, it cannot move a surface out of a body), or set initial_penetration = \"ignore\"",
                    r.primary_inside,
                    r.primary_inside_at.unwrap_or_default(),
                ),
            });
        }
        if r.penetrating > 0 && policies[k] == PenetrationPolicy::Error {
            return Err(ImpactError::SceneValue {
                path: scene.path.clone(),
                key: format!("{}.initial_penetration", scene.interface_key(k)),
                message: format!(
                    "{} secondary nodes lie behind the primary surface at t = 0; the deepest, node {} at {:?}, by {:.4e}. Move the bodies apart, or set initial_penetration = \"adjust\" (move those nodes onto the surface before t = 0) or \"ignore\"",
                    r.penetrating,
                    r.deepest_node.unwrap_or_default(),
                    r.deepest_at.unwrap_or_default(),
                    r.depth
                ),
            });
        }
    }
    Ok(())
}

/// A stable step that is not finite and positive is an error naming the element's material.
fn check_stable(scene: &Scene, model: &Model, (stable, e): (f64, usize)) -> Result<(f64, usize)> {
    if stable.is_finite() && stable > 0.0 {
        return Ok((stable, e));
    }
    let m = model.material_source[model.mesh.element(e).material as usize];
    Err(ImpactError::SceneValue {
        path: scene.path.clone(),
        key: format!("material[{m}] (material `{}`)", scene.materials[m].name),
        message: format!(
            "the stable explicit step of element {e} is {stable:e}: density and youngs_modulus give no finite wave speed (check their units)"
        ),
    })
}

/// The step, the step count and the shortened last step. An explicit run ends exactly at
/// `end_time`: when the end time is not a whole number of steps, the last step is shortened
/// to what is left (the central-difference step takes any step up to the stable one). An
/// implicit run takes whole steps of `time_step` up to the first at or past `end_time`.
fn time_step(
    scene: &Scene,
    method: Method,
    bound: Option<(f64, usize)>,
    auto: bool,
) -> Result<(f64, usize, Option<f64>)> {
    let end = scene.run.end_time;
    let dt = match (method, bound) {
        (Method::Explicit, Some((stable, element))) => match scene.run.time_step {
            // auto: the scene's step if the explicit path can take it, else its own
            Some(dt) if auto && dt <= stable * (1.0 + 1e-9) => dt,
            _ if auto => scene.explicit.safety_factor * stable,
            _ => explicit_time_step(scene, (stable, element))?,
        },
        _ => scene
            .run
            .time_step
            .expect("validated: implicit has a time step; auto picks implicit only with one"),
    };
    let ratio = end / dt;
    if ratio > MAX_STEPS {
        return Err(ImpactError::SceneValue {
            path: scene.path.clone(),
            key: "run.end_time".into(),
            message: format!(
                "{end:e} needs {ratio:.3e} steps of {dt:.4e} (more than {MAX_STEPS:e}); check the end time, the materials' units and the mesh (a tiny or distorted element sets the step)"
            ),
        });
    }
    if ratio < 1.0 - 1e-9 {
        return Err(ImpactError::SceneValue {
            path: scene.path.clone(),
            key: "run.end_time".into(),
            message: format!(
                "{end:e} is shorter than one time step ({dt:.4e}, the {} step): nothing would run",
                method.name()
            ),
        });
    }
    let steps = (ratio - 1e-9).ceil().max(1.0) as usize;
    let whole = (steps as f64 * dt - end).abs() <= 1e-9 * end;
    Ok(match method {
        Method::Explicit if !whole => (dt, steps, Some(end - (steps - 1) as f64 * dt)),
        _ => (dt, steps, None),
    })
}

/// The GPU the requested device resolves to, or `None` for the CPU twins; `notice` receives
/// the one-line reason when "auto" falls back to the CPU.
pub fn gpu_context(
    scene: &Scene,
    elements: usize,
    device: DeviceChoice,
    notice: &mut dyn FnMut(&str),
) -> Result<Option<GpuContext>> {
    if scene.run.kinematics == Kinematics::Corotational {
        return match device {
            DeviceChoice::Gpu => Err(ImpactError::Unsupported {
                path: scene.path.clone(),
                key: "run.kinematics".into(),
                message: "\"corotational\" runs its element kernels on the CPU (the GPU's are linear): set run.device = \"cpu\" or \"auto\", or kinematics = \"linear\"".into(),
            }),
            DeviceChoice::Auto => {
                notice("device auto: run.kinematics = \"corotational\": kernels on the CPU in f64");
                Ok(None)
            }
            DeviceChoice::Cpu => Ok(None),
        };
    }
    match device {
        DeviceChoice::Cpu => Ok(None),
        DeviceChoice::Gpu => GpuContext::new().map(Some).map_err(|e| gpu_error(scene, e)),
        DeviceChoice::Auto => {
            if elements < AUTO_GPU_MIN_ELEMENTS {
                notice(&format!(
                    "device auto: {elements} elements (< {AUTO_GPU_MIN_ELEMENTS}): kernels on the CPU in f64"
                ));
                return Ok(None);
            }
            let ctx = GpuContext::open(AdapterPolicy::HardwareOnly)?;
            if ctx.is_none() {
                notice("device auto: no hardware GPU found: kernels on the CPU in f64");
            }
            Ok(ctx)
        }
    }
}

/// Why a model runs on the explicit path alone, if it does: a material whose plies damage
/// (softening is not solved implicitly), or a `[[fix]]` that moves.
fn explicit_only(scene: &Scene, model: &Model) -> Option<String> {
    if scene.run.kinematics == Kinematics::Corotational {
        return Some(
            "run.kinematics = \"corotational\" turns each element's forces with it, which the explicit path runs".into(),
        );
    }
    if let Some(m) = scene.materials.iter().find(|m| m.damage.is_some()) {
        return Some(format!(
            "material `{}` damages (fracture_energy), and softening plies run on the explicit path",
            m.name
        ));
    }
    if let Some(c) = model.cohesive.first() {
        return Some(format!(
            "cohesive interface `{}` softens, and softening interfaces run on the explicit path",
            c.name
        ));
    }
    if !model.fix_motion.is_empty() || !model.fix_paths.is_empty() {
        return Some(
            "a [[fix]] moves its nodes (velocity or displacement), which the explicit path runs"
                .into(),
        );
    }
    None
}

/// Why a static step cannot run a model, if it cannot, and the scene key to name.
fn not_static(scene: &Scene, model: &Model) -> Option<(String, String)> {
    if let Some(m) = scene.materials.iter().position(|m| m.damage.is_some()) {
        let why = "damages (fracture_energy): softening plies run on the explicit path";
        return Some((format!("material[{m}]"), why.into()));
    }
    if !model.cohesive.is_empty() {
        let why = "softening interfaces run on the explicit path";
        return Some(("cohesive[0]".into(), why.into()));
    }
    // (a run's static steps before its dynamic ones hold its free rigid bodies where they are)
    let free = |b: &&crate::model::rigid::RigidBody| {
        b.motion == crate::scene::RigidMotion::Free && !model.fixed[3 * b.node as usize]
    };
    if let Some(b) = model.rigid.iter().position(|b| free(&b)) {
        let why = "a free rigid body has no stiffness to hold it in a static step: make its motion \"prescribed\" or \"fixed\" (in a run whose dynamic steps follow its static ones, it waits where it is until the first dynamic step)";
        return Some((format!("rigid_body[{b}].motion"), why.into()));
    }
    None
}

/// Refuses an implicit run of a model that runs explicit only ([`explicit_only`]), a static
/// run of one it cannot solve ([`not_static`]), and a penalty `stiffness` outside a static
/// step.
fn refuse_implicit(scene: &Scene, model: &Model, method: Method) -> Result<()> {
    if method == Method::Static {
        return match not_static(scene, model) {
            Some((key, why)) => Err(ImpactError::SceneValue {
                path: scene.path.clone(),
                key,
                message: format!("method = \"static\": {why}"),
            }),
            None => Ok(()),
        };
    }
    let contact = !model.interfaces.is_empty() || !model.cohesive.is_empty();
    if !model.equations.is_empty() && (method != Method::Implicit || contact) {
        let why = match method {
            Method::Implicit => "the implicit path takes them without contact (its contact iteration works on the unconstrained factor)".to_string(),
            m => format!("the {} path does not take them", m.name()),
        };
        let (key, what) = match scene.equations.is_empty() {
            true => (
                format!("tie[0] (tie `{}`)", model.ties[0].name),
                "tied surfaces (linear constraints)",
            ),
            false => ("equation[0]".to_string(), "linear constraints"),
        };
        return Err(ImpactError::Unsupported {
            path: scene.path.clone(),
            key,
            message: format!(
                "{what} are honoured by static steps (method = \"static\") and implicit ones without contact; {why}"
            ),
        });
    }
    let step_slope = (scene.steps.iter().enumerate()).find_map(|(i, s)| {
        let j = s.contacts.iter().position(|c| c.stick_slope.is_some())?;
        Some(format!("step[{i}].contact[{j}].stick_slope"))
    });
    if let Some(key) = step_slope {
        return Err(ImpactError::Unsupported {
            path: scene.path.clone(),
            key,
            message: format!("a stick slope is honoured by static steps (method = \"static\"); the {} path's friction sticks exactly: remove the key", method.name()),
        });
    }
    if let Some(k) = scene.contacts.iter().position(|c| c.stick_slope.is_some()) {
        return Err(ImpactError::Unsupported {
            path: scene.path.clone(),
            key: format!("contact[{k}].stick_slope"),
            message: format!("a stick slope is honoured by static steps (method = \"static\"); the {} path's friction sticks exactly: remove the key", method.name()),
        });
    }
    if let Some(k) = scene.contacts.iter().position(|c| c.pressure_law.is_some()) {
        let law = match scene.contacts[k].pressure_law {
            Some(crate::scene::PressureLaw::Exponential { .. }) => "exponential",
            _ => "stiffness",
        };
        return Err(ImpactError::Unsupported {
            path: scene.path.clone(),
            key: format!("contact[{k}].{law}"),
            message: format!(
                "a penalty law is honoured by static steps (method = \"static\"); the {} path's contact is the augmented Lagrange iteration, which leaves no penetration: remove the key",
                method.name()
            ),
        });
    }
    let not_explicit =
        |s: &crate::scene::StepSpec| matches!(s.method, Some(Method::Implicit | Method::Static));
    if scene.run.kinematics == Kinematics::Corotational {
        if let Some(i) = scene.steps.iter().position(not_explicit) {
            return Err(ImpactError::Unsupported {
                path: scene.path.clone(),
                key: format!("step[{i}].method"),
                message: "run.kinematics = \"corotational\" runs explicit steps only (the implicit and static paths factorise a linear stiffness)".into(),
            });
        }
    }
    match (method, explicit_only(scene, model)) {
        (Method::Implicit, Some(why)) => Err(ImpactError::SceneValue {
            path: scene.path.clone(),
            key: "run.method".into(),
            message: format!(
                "\"implicit\": {why}; set method = \"explicit\" (or \"auto\", which picks it)"
            ),
        }),
        _ => Ok(()),
    }
}

/// A GPU failure under `device = "gpu"` names the scene key that asked for it.
pub(crate) fn gpu_error(scene: &Scene, e: ImpactError) -> ImpactError {
    match e {
        ImpactError::Gpu(message) => ImpactError::Unsupported {
            path: scene.path.clone(),
            key: "run.device".into(),
            message: format!("device = \"gpu\": {message}"),
        },
        other => other,
    }
}

/// Picks the kernels for the requested device; `notice` receives the one-line reason when
/// "auto" falls back to the CPU.
pub fn kernels<'m>(
    scene: &Scene,
    model: &'m Model,
    device: DeviceChoice,
    notice: &mut dyn FnMut(&str),
) -> Result<Box<dyn Kernels + 'm>> {
    let data = model.element_data();
    let elements = data.elements.count();
    Ok(match gpu_context(scene, elements, device, notice)? {
        Some(ctx) => Box::new(GpuKernels::new(ctx, &data).map_err(|e| gpu_error(scene, e))?),
        None => Box::new(
            CpuKernels::new(data)
                .with_damage(model.damage_data())
                .corotational(scene.run.kinematics == Kinematics::Corotational),
        ),
    })
}

/// The time step of an explicit run given the mesh's stable bound `(step, element)` from
/// [`crate::integrate::stable_step::stable_step_on`]: the scene's, which must not exceed the bound (unless
/// `explicit.allow_unstable`), or `safety_factor` of the bound.
pub fn explicit_time_step(scene: &Scene, (stable, element): (f64, usize)) -> Result<f64> {
    match scene.run.time_step {
        // a step equal to the bound up to rounding is the bound
        Some(dt) if dt > stable * (1.0 + 1e-9) && !scene.explicit.allow_unstable => Err(ImpactError::SceneValue {
            path: scene.path.clone(),
            key: "run.time_step".into(),
            message: format!(
                "{dt:.4e} is above the stable explicit step {stable:.4e} (set by element {element}: 2/omega_max of its lumped-mass eigenproblem); use at most that, or leave time_step out for {:.4e} (explicit.safety_factor = {} of it)",
                scene.explicit.safety_factor * stable,
                scene.explicit.safety_factor
            ),
        }),
        Some(dt) => Ok(dt),
        None => Ok(scene.explicit.safety_factor * stable),
    }
}

/// The cost of one implicit step in explicit steps of the same mesh, from this project's
/// benchmarks on one machine (`docs/performance.md`, "The implicit step"): 95 at 3,072 elements and 180 at 18,000
/// (a factorised solve pair per contact iteration, about 15 iterations, against one element
/// sweep), so $K(n) = 95\,(n / 3072)^{0.36}$.
pub(crate) fn implicit_step_cost(elements: usize) -> f64 {
    95.0 * (elements.max(1) as f64 / 3072.0).powf(0.36)
}

/// `method = "auto"`: explicit unless the scene asks for a step so much longer than the
/// explicit one that the implicit path's fewer, dearer steps cost less. Without a
/// `time_step` the scene asks for no particular accuracy in time and the explicit path's
/// stable step is the wave-resolving one, so it is explicit. With one, implicit is chosen
/// when time_step / (explicit step) exceeds [`implicit_step_cost`]. Returns the method and a
/// sentence for `summary.json`.
/// `stable` is the mesh's stable explicit step ([`crate::integrate::stable_step::stable_step_on`]).
pub(crate) fn choose_method(scene: &Scene, model: &Model, stable: f64) -> (Method, String) {
    let explicit_dt = scene.explicit.safety_factor * stable;
    if let Some(why) = explicit_only(scene, model) {
        return (Method::Explicit, format!("explicit: {why}"));
    }
    let cost = implicit_step_cost(model.mesh.element_count());
    match scene.run.time_step {
        None => (
            Method::Explicit,
            format!("explicit: no time_step asked; the explicit step is {explicit_dt:.4e}"),
        ),
        Some(dt) => {
            let ratio = dt / explicit_dt;
            let method = if ratio > cost {
                Method::Implicit
            } else {
                Method::Explicit
            };
            (
                method,
                format!(
                    "{}: time_step {dt:.4e} is {ratio:.3} explicit steps ({explicit_dt:.4e}); an implicit step costs about {cost:.0} explicit steps on {} elements",
                    method.name(),
                    model.mesh.element_count()
                ),
            )
        }
    }
}
