//! The whole explicit step (predictor, contact impulses, element forces, corrector) in ns per
//! element-step, on the CPU twins (f64) and on the GPU kernels (f32, the first adapter wgpu
//! finds: a hardware GPU, else lavapipe or llvmpipe). Prints a table.
//!
//! The scene: a steel-like block dropped at 1 on a rigid floor it touches at t = 0, at the
//! default step (0.9 of the stable bound). Three engines: the CPU twin (f64), the GPU kernels
//! with the host loop (element forces on the device, a round trip per step; what scenes with
//! surface-to-surface contact use), and the device-resident step (every stage on the device,
//! many steps per submission, the history rows read back asynchronously).
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

fn time_steps(model: &Model, sc: &Scene, dt: f64, kernels: Box<dyn Kernels + '_>) -> (f64, f64) {
    let mut s = ExplicitSolver::new(model, sc.explicit.clone(), dt, 1.0, kernels).expect("solver");
    s.step().expect("warm-up step");
    let elements = model.mesh.hexes.len() as f64;
    let steps = ((3e7 / elements) as usize).clamp(3, 200);
    let mut sweeps = 0;
    let t = Instant::now();
    for _ in 0..steps {
        sweeps += s.step().expect("step").iterations;
    }
    let per_step = t.elapsed().as_secs_f64() / steps as f64;
    (per_step * 1e9 / elements, sweeps as f64 / steps as f64)
}

/// ns per element-step of the device-resident step, after one submission of warm-up.
fn time_resident(model: &Model, sc: &Scene, dt: f64, ctx: GpuContext) -> f64 {
    let elements = model.mesh.hexes.len() as f64;
    let chunk = resident::chunk_steps(model.mesh.hexes.len());
    let steps = ((3e7 / elements) as usize).clamp(2 * chunk.min(16), 2000);
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

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let sizes: &[[usize; 3]] = if quick {
        &[[25, 20, 20], [50, 50, 40]]
    } else {
        &[[25, 20, 20], [50, 50, 40], [100, 100, 100]]
    };
    let adapter = GpuContext::new().ok().map(|c| c.adapter.name.clone());
    println!(
        "| elements | floor nodes | dt | CPU twin ns/element-step | GPU kernels + host loop | GPU resident | adapter | contact sweeps/step |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---|---:|");
    for &n in sizes {
        let sc = Scene::parse(&scene(n), Path::new("bench.toml")).expect("bench scene");
        let model = Model::from_scene(&sc);
        let dt = explicit_time_step(&sc, stable_step(&model)).expect("stable step");
        let (cpu, sweeps) = time_steps(
            &model,
            &sc,
            dt,
            Box::new(CpuKernels::new(model.element_data())),
        );
        let gpu_ns = match GpuContext::new().ok() {
            Some(ctx) => {
                let k = GpuKernels::new(ctx, &model.element_data()).expect("gpu kernels");
                format!("{:.0}", time_steps(&model, &sc, dt, Box::new(k)).0)
            }
            None => "-".into(),
        };
        let resident_ns = match GpuContext::new().ok() {
            Some(ctx) => format!("{:.1}", time_resident(&model, &sc, dt, ctx)),
            None => "-".into(),
        };
        println!(
            "| {} | {} | {dt:.3e} | {cpu:.0} | {gpu_ns} | {resident_ns} | {} | {sweeps:.2} |",
            model.mesh.hexes.len(),
            model.interfaces[0].nodes.len(),
            adapter.as_deref().unwrap_or("none"),
        );
    }
}
