//! The whole explicit step (predictor, contact impulses, element forces, corrector) in ns per
//! element-step, on the CPU twins (f64) and on the GPU kernels (f32, the first adapter wgpu
//! finds: a hardware GPU, else lavapipe or llvmpipe). Prints a table.
//!
//! Two scenes, at the default step (0.9 of the stable bound): a steel-like block dropped at 1
//! on a rigid floor it touches at t = 0 (plane contact), and a block sliding on a supported
//! plate (contact between meshed bodies, with friction). Three engines: the CPU twin (f64),
//! the GPU kernels with the host loop (element forces and the contact search on the device,
//! the impulses on the host, a round trip per step), and the device-resident step (every
//! stage on the device, many steps per submission, the history rows read back
//! asynchronously; what `device = "gpu"` runs).
//!
//! `cargo bench --bench explicit_step` (10^4, 10^5 and 10^6 elements; `-- --quick` for 10^4
//! and 10^5 only).

use std::path::Path;
use std::time::Instant;

use impact::gpu::{GpuContext, GpuKernels};
use impact::integrate::stable_step::stable_step;
use impact::integrate::{resident, ExplicitSolver, ResidentSolver};
use impact::kernels::{CpuKernels, Kernels};
use impact::model::Model;
use impact::run::explicit_time_step;
use impact::scene::Scene;

fn scene(n: [usize; 3]) -> String {
    let h = 1.0 / n[0] as f64;
    format!(
        r#"
[run]
method = "explicit"
end_time = 1.0

[[material]]
name = "steel"
density = 7.8e-3
youngs_modulus = 200.0
poissons_ratio = 0.3

[[body]]
name = "block"
material = "steel"
box = {{ min = [0.0, 0.0, 0.0], max = [1.0, {ly}, {lz}], divisions = [{nx}, {ny}, {nz}] }}
velocity = [0.0, 0.0, -1.0]

[[rigid_plane]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
"#,
        ly = n[1] as f64 * h,
        lz = n[2] as f64 * h,
        nx = n[0],
        ny = n[1],
        nz = n[2],
    )
}

fn time_steps(
    model: &Model,
    sc: &Scene,
    dt: f64,
    kernels: Box<dyn Kernels + '_>,
    max_steps: usize,
) -> (f64, f64) {
    let mut s = ExplicitSolver::new(model, sc.explicit.clone(), dt, 1.0, kernels).expect("solver");
    s.step().expect("warm-up step");
    let elements = model.mesh.hexes.len() as f64;
    let steps = ((3e7 / elements) as usize).clamp(3, max_steps.min(200));
    let mut sweeps = 0;
    let t = Instant::now();
    for _ in 0..steps {
        sweeps += s.step().expect("step").iterations;
    }
    let per_step = t.elapsed().as_secs_f64() / steps as f64;
    (per_step * 1e9 / elements, sweeps as f64 / steps as f64)
}

/// ns per element-step of the device-resident step, after one submission of warm-up.
fn time_resident(model: &Model, sc: &Scene, dt: f64, ctx: GpuContext, max_steps: usize) -> f64 {
    let elements = model.mesh.hexes.len() as f64;
    let chunk = resident::chunk_steps(model.mesh.hexes.len());
    let steps = ((3e7 / elements) as usize).clamp(2 * chunk.min(16), max_steps);
    let mut s = ResidentSolver::new(ctx, model, &sc.explicit, dt, 1.0, chunk + steps, None)
        .expect("resident solver");
    for _ in 0..chunk {
        s.step().expect("warm-up");
    }
    let t = Instant::now();
    for _ in 0..steps {
        s.step().expect("step");
    }
    t.elapsed().as_secs_f64() / steps as f64 * 1e9 / elements
}

/// A block resting on a plate supported along its four bottom edges, pressed by gravity and
/// moving across it at (0.3, 0.2, -1): contact between meshed bodies with friction. About
/// 0.225 n^3 elements.
fn contact_scene(n: usize) -> String {
    let h = 1.0 / n as f64;
    let nz = (n / 10).max(2);
    let nb = (n / 2).max(2);
    format!(
        r#"
gravity = [0.0, 0.0, -9.8]

[run]
method = "explicit"
end_time = 1.0

[[material]]
name = "steel"
density = 7.8e-3
youngs_modulus = 200.0
poissons_ratio = 0.3

[[body]]
name = "plate"
material = "steel"
box = {{ min = [0.0, 0.0, {pz}], max = [1.0, 1.0, 0.0], divisions = [{n}, {n}, {nz}] }}

[[body]]
name = "block"
material = "steel"
box = {{ min = [0.25, 0.25, 0.0], max = [0.75, 0.75, 0.5], divisions = [{nb}, {nb}, {nb}] }}
velocity = [0.3, 0.2, -1.0]

[[contact]]
name = "impact"
secondary = {{ body = "block", face = "z-" }}
primary = {{ body = "plate", face = "z+" }}
friction = 0.2

[[fix]]
body = "plate"
region = {{ min = [0.0, 0.0, {pz}], max = [0.0, 1.0, {pz}] }}
components = ["z"]

[[fix]]
body = "plate"
region = {{ min = [1.0, 0.0, {pz}], max = [1.0, 1.0, {pz}] }}
components = ["x", "y", "z"]
"#,
        pz = -(nz as f64) * h,
    )
}

/// One table row per scene text: the three engines' ns per element-step.
fn table(title: &str, scenes: &[String], adapter: Option<&str>, max_steps: usize) {
    println!("\n{title}\n");
    println!(
        "| elements | contact nodes | dt | CPU twin ns/element-step | GPU kernels + host loop | GPU resident | adapter | contact sweeps/step |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---|---:|");
    for text in scenes {
        let sc = Scene::parse(text, Path::new("bench.toml")).expect("bench scene");
        let model = Model::from_scene(&sc);
        let dt = explicit_time_step(&sc, stable_step(&model)).expect("stable step");
        let (cpu, sweeps) = time_steps(
            &model,
            &sc,
            dt,
            Box::new(CpuKernels::new(model.element_data())),
            max_steps,
        );
        let gpu_ns = match GpuContext::new().ok() {
            Some(ctx) => {
                let k = GpuKernels::new(ctx, &model.element_data()).expect("gpu kernels");
                format!(
                    "{:.0}",
                    time_steps(&model, &sc, dt, Box::new(k), max_steps).0
                )
            }
            None => "-".into(),
        };
        let resident_ns = match GpuContext::new().ok() {
            Some(ctx) => format!("{:.1}", time_resident(&model, &sc, dt, ctx, max_steps)),
            None => "-".into(),
        };
        println!(
            "| {} | {} | {dt:.3e} | {cpu:.0} | {gpu_ns} | {resident_ns} | {} | {sweeps:.2} |",
            model.mesh.hexes.len(),
            model.interfaces[0].nodes.len(),
            adapter.unwrap_or("none"),
        );
    }
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let sizes: &[[usize; 3]] = if quick {
        &[[25, 20, 20], [50, 50, 40]]
    } else {
        &[[25, 20, 20], [50, 50, 40], [100, 100, 100]]
    };
    let plates: &[usize] = if quick { &[36, 76] } else { &[36, 76, 164] };
    let adapter = GpuContext::new().ok().map(|c| c.adapter.name.clone());
    table(
        "Block dropped on a rigid floor (plane contact)",
        &sizes.iter().map(|&n| scene(n)).collect::<Vec<_>>(),
        adapter.as_deref(),
        2000,
    );
    // the contact iteration records every sweep the limit allows (most are empty dispatches
    // once it has converged), which a software adapter pays for: fewer steps are timed
    table(
        "Block sliding on a supported plate (contact between meshed bodies, friction 0.2)",
        &plates.iter().map(|&n| contact_scene(n)).collect::<Vec<_>>(),
        adapter.as_deref(),
        200,
    );
}
