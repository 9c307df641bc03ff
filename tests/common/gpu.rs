//! The GPU tests' adapter, and comparisons of a GPU history against its CPU twin.

use super::history::History;
use super::scenes::run_text_on;

/// A GPU context for a test, or `None` when `IMPACT_SKIP_GPU_TESTS=1` says to skip (printed).
/// With no adapter and no skip request the test fails with a message naming the packages.
pub fn gpu_context(test: &str) -> Option<impact::gpu::GpuContext> {
    if std::env::var("IMPACT_SKIP_GPU_TESTS").as_deref() == Ok("1") {
        eprintln!("{test}: SKIPPED because IMPACT_SKIP_GPU_TESTS=1");
        return None;
    }
    match impact::gpu::GpuContext::new() {
        Ok(ctx) => {
            eprintln!("{test}: adapter {}", ctx.adapter.describe());
            Some(ctx)
        }
        Err(e) => panic!(
            "{test} needs a GPU adapter (hardware or software) and found none: {e}. \
             Set IMPACT_SKIP_GPU_TESTS=1 to skip the GPU tests deliberately."
        ),
    }
}

/// True when the GPU tests are deliberately skipped (see [`gpu_context`]).
pub fn skip_gpu(test: &str) -> bool {
    gpu_context(test).is_none()
}

/// Two runs' histories agree: each column within `bound` of its family's scale (energies and
/// friction work, velocities, displacements, forces; penetrations against the element size
/// `h`); the contact counts differ in at most 1% of the rows or by at most 1% of their total
/// over the run, and by at most 2 nodes in any row (a node at zero pressure or on the cone's
/// edge may flip).
pub fn compare_histories(hc: &History, hg: &History, h: f64, bound: f64) {
    assert_eq!(hc.rows.len(), hg.rows.len());
    assert_eq!(hc.columns, hg.columns);
    let energy = family_scale(hc, &["_energy", "friction_work", "impact_loss"]);
    let speed = family_scale(hc, &[".vx", ".vy", ".vz"]);
    let disp = family_scale(hc, &[".ux", ".uy", ".uz"]);
    let force = family_scale(
        hc,
        &["normal_force", "tangential_force", ".fx", ".fy", ".fz"],
    );
    for (j, c) in hc.columns.iter().enumerate() {
        let energy_like = ["_energy", "friction_work", "impact_loss"];
        let scale = if energy_like.iter().any(|f| c.ends_with(f)) {
            energy
        } else if c.ends_with(".vx") || c.ends_with(".vy") || c.ends_with(".vz") {
            speed
        } else if c.ends_with(".ux") || c.ends_with(".uy") || c.ends_with(".uz") {
            disp
        } else if c.ends_with("_force") || [".fx", ".fy", ".fz"].iter().any(|f| c.ends_with(f)) {
            force
        } else if c.ends_with("max_penetration") {
            h
        } else {
            continue; // time, step, counts (below)
        };
        let worst = hc
            .rows
            .iter()
            .zip(&hg.rows)
            .map(|(a, b)| (a[j] - b[j]).abs())
            .fold(0.0, f64::max)
            / scale;
        eprintln!("{c}: {worst:.2e} of {scale:.3e} (bound {bound:.0e})");
        assert!(
            worst <= bound,
            "{c}: GPU and CPU differ by {worst:.2e} of the scale {scale:.3e}"
        );
    }
    // contact counts: a node at zero pressure or on the cone's edge may flip
    for c in hc
        .columns
        .iter()
        .filter(|c| c.ends_with(".active") || c.ends_with(".sliding"))
    {
        let (a, b) = (hc.col(c), hg.col(c));
        let flips = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        let moved: f64 = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).sum();
        let worst = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        let total: f64 = a.iter().sum();
        eprintln!(
            "{c}: {flips} of {} rows differ, by {moved} of {total} node-steps (at most {worst})",
            a.len()
        );
        assert!(total > 0.0, "{c}: the scene must exercise it");
        assert!(
            (flips * 100 <= a.len() || moved <= 0.01 * total) && worst <= 2.0,
            "{c}: {flips} rows differ, by {moved} node-steps, at most {worst} in a row"
        );
    }
}

pub fn family_scale(h: &History, suffixes: &[&str]) -> f64 {
    h.columns
        .iter()
        .filter(|c| suffixes.iter().any(|s| c.ends_with(s)))
        .flat_map(|c| h.col(c))
        .fold(0.0f64, |m, x| m.max(x.abs()))
}

/// `text` with the contact tolerance the device iteration takes
/// ([`impact::integrate::resident::DEVICE_TOLERANCE`]), so that the CPU twin iterates to the
/// same (the scene must have no `[explicit]` table of its own).
pub fn at_device_tolerance(text: &str) -> String {
    assert!(
        !text.contains("[explicit]"),
        "a scene with its own [explicit]"
    );
    let tol = impact::integrate::resident::DEVICE_TOLERANCE;
    format!("{text}\n[explicit]\ntolerance = {tol:e}\n")
}

/// Runs `text` on the CPU twin and with the whole step on the device ("gpu resident"), at
/// least 1,000 steps, both at the device's contact tolerance ([`at_device_tolerance`]): the
/// same contact iteration (sweeps within 2%, unconverged steps within one) and the same
/// history ([`compare_histories`] with `h` and `bound`).
pub fn resident_against_cpu(tag: &str, text: &str, h: f64, bound: f64) {
    let text = &at_device_tolerance(text);
    let (cpu, hc) = run_text_on(
        &format!("{tag}_cpu"),
        text,
        Some(impact::scene::DeviceChoice::Cpu),
    );
    let (gpu, hg) = run_text_on(
        &format!("{tag}_gpu"),
        text,
        Some(impact::scene::DeviceChoice::Gpu),
    );
    let (cpu, gpu) = (cpu.expect("cpu run"), gpu.expect("gpu run"));
    assert_eq!(gpu.engine, "gpu resident");
    assert_eq!(cpu.engine, "cpu");
    assert!(cpu.steps >= 1000, "{} steps", cpu.steps);
    // the sweeps differ only where f32 stops an iteration a sweep earlier or later
    eprintln!(
        "sweeps: cpu {} (max {}, {} unconverged), gpu {} (max {}, {} unconverged)",
        cpu.iterations_total,
        cpu.iterations_max,
        cpu.unconverged_steps,
        gpu.iterations_total,
        gpu.iterations_max,
        gpu.unconverged_steps
    );
    let sweeps = (cpu.iterations_total as f64, gpu.iterations_total as f64);
    assert!(
        (sweeps.0 - sweeps.1).abs() <= 0.02 * sweeps.0,
        "sweeps {sweeps:?}"
    );
    assert!(gpu.unconverged_steps.abs_diff(cpu.unconverged_steps) <= 1);
    compare_histories(&hc, &hg, h, bound);
}

/// Relative 2-norm error of a device result against its CPU twin's, entries equal and
/// infinite (a gap out of reach) left out; a NaN counts as infinite error.
pub fn rel_err(gpu: &[f64], cpu: &[f64]) -> f64 {
    assert_eq!(gpu.len(), cpu.len());
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for (g, c) in gpu.iter().zip(cpu) {
        if g.is_infinite() && g == c {
            continue;
        }
        num += (g - c) * (g - c);
        den += c * c;
    }
    if num.is_nan() {
        return f64::INFINITY;
    }
    (num / den.max(f64::MIN_POSITIVE)).sqrt()
}
