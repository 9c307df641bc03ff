//! A run decomposed over the ranks of an MPI job: what it refuses, and the device each rank
//! computes on.

use super::{run_on, RunOptions};
use crate::domain::Ranks;
use crate::error::{ImpactError, Result};
use crate::gpu::context::AUTO_GPU_MIN_ELEMENTS;
use crate::gpu::{list_adapters, GpuContext};
use crate::output::Summary;
use crate::scene::{DeviceChoice, Scene};
use crate::setup::gpu_error;

/// Runs the scene decomposed over `ranks`, every rank calling it: the explicit path on
/// each rank's share of the elements ([`crate::domain`]), each rank on the CPU or on its own
/// GPU ([`rank_context`]); rank 0 writes the files. The implicit path, checkpoints and
/// `--resume` are refused with the key that asks for them.
pub fn run_ranks(scene: &Scene, opts: &RunOptions, ranks: &dyn Ranks) -> Result<Summary> {
    if scene.checkpoint_every.is_some() || opts.resume {
        return Err(ImpactError::Unsupported {
            path: scene.path.clone(),
            key: "output.checkpoint_every".into(),
            message: format!(
                "a decomposed run writes no checkpoints and does not resume: run on one process to checkpoint (this run is on {} ranks)",
                ranks.size()
            ),
        });
    }
    let opts = RunOptions {
        quiet: opts.quiet || ranks.rank() != 0,
        interrupt: None,
        ..opts.clone()
    };
    run_on(scene, &opts, Some(ranks))
}

/// The GPU rank `ranks.rank()` computes on, or `None` for the CPU, agreed by every rank:
/// - `device = "gpu"`: each rank opens the adapter its place among the processes on its
///   machine picks ([`GpuContext::for_local_rank`]); if a rank has none, every rank stops
///   with an error naming the ranks without one;
/// - `"auto"`: the ranks' GPUs where each rank's share of the `elements` is at least
///   [`AUTO_GPU_MIN_ELEMENTS`] and every rank's machine has a hardware GPU, else the CPU;
/// - `"cpu"`: the CPU.
pub fn rank_context(
    scene: &Scene,
    device: DeviceChoice,
    ranks: &dyn Ranks,
    elements: usize,
    notice: &mut dyn FnMut(&str),
) -> Result<Option<GpuContext>> {
    match device {
        DeviceChoice::Cpu => Ok(None),
        DeviceChoice::Gpu => open_on_every_rank(scene, ranks),
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
            open_on_every_rank(scene, ranks)
        }
    }
}

/// Each rank's GPU, or on every rank the error naming the ranks that could not open one.
fn open_on_every_rank(scene: &Scene, ranks: &dyn Ranks) -> Result<Option<GpuContext>> {
    let mine = GpuContext::for_local_rank(ranks.local_rank());
    let failed = ranks.gather_all(&[f64::from(u8::from(mine.is_err()))]);
    let without: Vec<String> = (failed.iter().enumerate())
        .filter(|(_, f)| f[0] > 0.0)
        .map(|(r, _)| r.to_string())
        .collect();
    if without.is_empty() {
        return mine.map(Some);
    }
    let why = match mine {
        Err(e) => e.to_string(),
        Ok(_) => {
            "its machine has no adapter with compute shaders, or it could not be opened".into()
        }
    };
    Err(gpu_error(
        scene,
        ImpactError::Gpu(format!(
            "rank {} of {} found no GPU to open ({why})",
            without.join(", "),
            ranks.size()
        )),
    ))
}
