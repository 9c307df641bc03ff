//! A run decomposed over the ranks of an MPI job: what it refuses, and the device each rank
//! computes on.

use super::{run_on, RunOptions};
use crate::domain::ranks::agree;
use crate::domain::Ranks;
use crate::error::{ImpactError, Result};
use crate::gpu::context::AUTO_GPU_MIN_ELEMENTS;
use crate::gpu::{list_adapters, GpuContext};
use crate::output::Summary;
use crate::scene::{DeviceChoice, Scene};

/// Runs the scene decomposed over `ranks`, every rank calling it: the explicit path on
/// each rank's share of the elements ([`crate::domain`]), each rank on the CPU or on its own
/// GPU ([`rank_context`]); rank 0 writes the files, checkpoints included (the single
/// process's, [`crate::domain::checkpoint`]). The implicit path is refused with the key that
/// asks for it. The ranks stop together, with a checkpoint, after the step in which any of
/// them found its `opts.interrupt` set.
pub fn run_ranks(scene: &Scene, opts: &RunOptions, ranks: &dyn Ranks) -> Result<Summary> {
    let opts = RunOptions {
        quiet: opts.quiet || ranks.rank() != 0,
        ..opts.clone()
    };
    run_on(scene, &opts, Some(ranks))
}

/// `mine`, the outcome of a stage that may fail on some ranks only, once every rank's is
/// known ([`agree`]): a rank that failed keeps its own error (as [`ImpactError::Agreed`] on
/// several ranks: every rank stops), one that did not stops with the others' reasons.
/// Without ranks, `mine`.
pub(super) fn agreed<T>(ranks: Option<&dyn Ranks>, mine: Result<T>) -> Result<T> {
    let Some(r) = ranks else {
        return mine;
    };
    match (agree(r, mine.as_ref().map(|_| ())), mine) {
        (_, Err(e)) if r.size() > 1 => Err(ImpactError::Agreed(Box::new(e))),
        (_, Err(e)) => Err(e),
        (Err(why), Ok(_)) => Err(ImpactError::Ranks(why)),
        (Ok(()), Ok(t)) => Ok(t),
    }
}

/// The GPU rank `ranks.rank()` computes on, or `None` for the CPU, agreed by every rank:
/// - `device = "gpu"`: each rank opens the adapter its place among the processes on its
///   machine picks ([`GpuContext::for_local_rank`]); if a rank cannot, every rank stops
///   with an error naming the ranks that could not and why;
/// - `"auto"`: the ranks' GPUs where the model's elements per rank are at least
///   [`AUTO_GPU_MIN_ELEMENTS`] and every rank's machine has a hardware GPU, else the CPU;
/// - `"cpu"`: the CPU.
///
/// Ranks on adapters of different kinds (model, driver, backend) get a notice: the run is
/// then not one kind of GPU's bits.
pub(crate) fn rank_context(
    scene: &Scene,
    device: DeviceChoice,
    ranks: &dyn Ranks,
    elements: usize,
    notice: &mut dyn FnMut(&str),
) -> Result<Option<GpuContext>> {
    let ctx = match device {
        DeviceChoice::Cpu => return Ok(None),
        DeviceChoice::Gpu => open_on_every_rank(scene, "gpu", ranks)?,
        DeviceChoice::Auto => {
            let share = elements / ranks.size();
            if share < AUTO_GPU_MIN_ELEMENTS {
                notice(&format!(
                    "device auto: {share} elements per rank (< {AUTO_GPU_MIN_ELEMENTS}): kernels on the CPU in f64"
                ));
                return Ok(None);
            }
            let hardware = list_adapters().iter().any(|a| a.compute && !a.software);
            if ranks.max(f64::from(u8::from(!hardware))) > 0.0 {
                notice(
                    "device auto: a rank's machine has no hardware GPU: kernels on the CPU in f64",
                );
                return Ok(None);
            }
            open_on_every_rank(scene, "auto", ranks)?
        }
    };
    let a = &ctx.adapter;
    let kinds = ranks.gather_text(&format!(
        "{} ({:?}, {} {})",
        a.name, a.backend, a.driver, a.driver_info
    ));
    if kinds.iter().any(|k| *k != kinds[0]) {
        notice(&format!(
            "the ranks compute on different kinds of adapter ({}): the results are not one GPU's bits",
            kinds.join("; ")
        ));
    }
    Ok(Some(ctx))
}

/// Each rank's GPU, or on every rank the error naming the ranks that could not open one
/// (under `run.device`, whose value `device` is).
fn open_on_every_rank(scene: &Scene, device: &str, ranks: &dyn Ranks) -> Result<GpuContext> {
    let mine = GpuContext::for_local_rank(ranks.local_rank());
    agree(ranks, mine).map_err(|why| ImpactError::Unsupported {
        path: scene.path.clone(),
        key: "run.device".into(),
        message: format!("device = \"{device}\": a rank found no GPU to open: {why}"),
    })
}
