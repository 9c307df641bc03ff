//! The run's steps in time. Each `[[step]]` is a stage from its start on, with its model,
//! method and time step; the run's step counter runs on through them. Where no step changes
//! the method or the time step, every stage steps at the run's step. Where one does (a
//! preload, then an impact), each stage steps at its own: a step's `time_step`, else the
//! run's where the method is the run's, else (an explicit stage after another method) the
//! stable step's share, shortened to land on the next stage's start.

use crate::error::{ImpactError, Result};
use crate::model::Model;
use crate::scene::{Method, Scene};

/// A `[[step]]` as the run steps it.
#[derive(Debug, Clone)]
pub struct Stage {
    /// The run's step from which it holds.
    pub from: usize,
    pub start: f64,
    pub method: Method,
    pub dt: f64,
    pub model: Model,
}

/// Where a run of mixed steps steps: the run's own stage's step (an explicit one landed on
/// the first `[[step]]`'s start), the run's step count and the shortened last step of an
/// explicit end (as [`super::time_step`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Mixed {
    pub dt: f64,
    pub steps: usize,
    pub last_step: Option<f64>,
}

/// The run's own stage (its method and step) and the scene's steps' models: each stage, and
/// where the steps are mixed, the run's own step and count ([`Mixed`]). `bound` is the
/// stable explicit step and its element, where a stage is explicit.
pub(super) fn stages(
    scene: &Scene,
    (method, dt): (Method, f64),
    bound: Option<(f64, usize)>,
    models: Vec<Model>,
) -> Result<(Vec<Stage>, Option<Mixed>)> {
    if !scene.mixed_steps() {
        let out = (scene.steps.iter().zip(models))
            .map(|(s, model)| Stage {
                from: (s.start / dt).round() as usize,
                start: s.start,
                method,
                dt,
                model,
            })
            .collect();
        return Ok((out, None));
    }
    let err = |key: String, message: String| ImpactError::SceneValue {
        path: scene.path.clone(),
        key,
        message,
    };
    let mut out: Vec<Stage> = Vec::with_capacity(models.len());
    // an explicit run's own step lands on the first step's start
    let first = match (method, scene.run.time_step, scene.steps.first()) {
        (Method::Explicit, None, Some(s)) => landed(dt, s.start),
        _ => dt,
    };
    let (mut from, mut start, mut step) = (0usize, 0.0f64, first);
    for (k, (s, model)) in scene.steps.iter().zip(models).enumerate() {
        let n = (s.start - start) / step;
        if (n - n.round()).abs() > 1e-9 * n.max(1.0) {
            return Err(err(
                format!("step[{k}].start"),
                format!("{} is not a whole number of the steps before it ({step:e} from {start}): give a time_step that divides the span, or move the start", s.start),
            ));
        }
        from += n.round() as usize;
        let method = s.method.unwrap_or(scene.run.method);
        let next = scene.steps.get(k + 1).map(|n| n.start);
        step = stage_step(scene, (k, s, method), (first, bound), (s.start, next))?;
        start = s.start;
        out.push(Stage {
            from,
            start,
            method,
            dt: step,
            model,
        });
    }
    let end = scene.run.end_time;
    let n = ((end - start) / step - 1e-9).ceil().max(1.0) as usize;
    let steps = from + n;
    let whole = (n as f64 * step - (end - start)).abs() <= 1e-9 * end;
    let method = out.last().map_or(method, |s| s.method);
    let last_step =
        (method == Method::Explicit && !whole).then(|| end - start - (n - 1) as f64 * step);
    let mixed = Mixed {
        dt: first,
        steps,
        last_step,
    };
    Ok((out, Some(mixed)))
}

/// `dt`, shortened so that a whole number of steps spans `span`.
fn landed(dt: f64, span: f64) -> f64 {
    span / (span / dt - 1e-9).ceil().max(1.0)
}

/// The step of stage `k` (method `method`) from `start` to the next stage's start or the
/// run's end: its own `time_step`, the run's own stage's (`run_dt`) for the run's method,
/// else an explicit one at the stable step's share, or the run's `time_step`; an explicit
/// step not given lands on `next`.
fn stage_step(
    scene: &Scene,
    (k, s, method): (usize, &crate::scene::StepSpec, Method),
    (run_dt, bound): (f64, Option<(f64, usize)>),
    (start, next): (f64, Option<f64>),
) -> Result<f64> {
    let explicit = (method == Method::Explicit).then_some(bound).flatten();
    if let (Some(dt), Some((stable, element))) = (s.time_step, explicit) {
        if dt > stable * (1.0 + 1e-9) && !scene.explicit.allow_unstable {
            return Err(ImpactError::SceneValue {
                path: scene.path.clone(),
                key: format!("step[{k}].time_step"),
                message: format!("{dt:.4e} is above the stable explicit step {stable:.4e} (set by element {element}); use at most that, or leave it out"),
            });
        }
    }
    let dt = match (s.time_step, explicit) {
        (Some(dt), _) => return Ok(dt),
        _ if method == scene.run.method => run_dt,
        (None, Some((stable, _))) => scene.explicit.safety_factor * stable,
        (None, None) => scene
            .run
            .time_step
            .expect("validated: a static or implicit step has a time step"),
    };
    Ok(match next {
        Some(next) if method == Method::Explicit => landed(dt, next - start),
        _ => dt,
    })
}
