//! The cost of ply damage, in ns per element-step, on the CPU twins (f64) and on the GPU
//! adapter in use (f32). Prints two Markdown tables.
//!
//! 1. **Kernels.** A plate of IM7/8552 hex8i, [0/90]s through four element layers (one ply
//!    an element) and through two (two plies an element, layered), the element forces of an
//!    explicit step: elastic (no `fracture_energy`), damaging but far from initiation (every
//!    element's elastic forces and the sieve: what most of a damaging run's elements cost),
//!    and every element damaged (the points' loop: the damaging element's own cost). On the
//!    CPU also with corotational kinematics (each element in its turning frame). On the GPU
//!    through the host path (upload, dispatch, read back), so the rows compare the device's
//!    work plus the same transfers.
//! 2. **Whole runs.** The drop-weight coupon of `scenes/drop_weight_d7136_elastic.toml` on a coarser
//!    mesh, its first 1.1 ms (the tup's load climbs and the plies under it start to crack),
//!    with and without the plies' fracture energies: each engine's ns per element-step (the
//!    CPU's wall time; the GPU resident engine's device time where the adapter has
//!    timestamps, else wall time) and their ratio, the issue's target being 1.5 at most.
//!
//! 3. **Cohesive interfaces.** The [0/90]s plate of four element layers split at its two ply
//!    changes (`[[cohesive]] at = "ply_changes"`): the interfaces' pair forces of a step,
//!    bonded and in the softening, in ns per pair and per interface face (a zero-thickness
//!    cohesive element), beside the plate's hex8i element-step: on the CPU
//!    (`cohesive_forces` on the host's threads, the host paths' form) and on the GPU adapter
//!    (the resident step's `cohesive_pairs` and `cohesive_scatter`, device work alone, beside
//!    the `hex8i_forces` kernel alone).
//!
//! `cargo bench --bench damage` (`-- --quick`: a smaller plate and a shorter run;
//! `-- --cohesive`: the third table alone).

use std::time::Instant;

use impact::backend::{CpuKernels, Kernels};
use impact::gpu::{GpuContext, GpuKernels};
use impact::kernels::damage_data::DamageState;
use impact::material::damage::POINT_STATE;
use impact::model::Model;
use impact::run::{run, RunOptions};
use impact::scene::{DeviceChoice, Scene};

const IM7: &str = r#"[[material]]
name = "im7"
density = 1.57e-9
transversely_isotropic = { e1 = 171420.0, e2 = 9080.0, nu12 = 0.32, nu23 = 0.52, g12 = 5290.0 }
strength = { xt = 2326.2, xc = 1200.1, yt = 62.3, yc = 199.8, s12 = 92.3, s23 = 75.3 }
"#;
const ENERGIES: &str = "fracture_energy = { ft = 133.3, fc = 47.5, mt = 0.277, mc = 0.788 }\n";

/// A [0/90]s plate of `n x n` hex8i in the plane and `layers` element layers (1 mm).
fn plate(n: usize, layers: usize, damage: bool) -> Model {
    plate_with(n, layers, damage, "")
}

/// The plate with `extra` scene text after it.
fn plate_with(n: usize, layers: usize, damage: bool, extra: &str) -> Model {
    let energies = if damage { ENERGIES } else { "" };
    let text = format!(
        r#"[run]
method = "explicit"
end_time = 1e-6
{IM7}{energies}
[[body]]
name = "plate"
material = "im7"
box = {{ min = [0.0, 0.0, 0.0], max = [{n}.0, {n}.0, 1.0], divisions = [{n}, {n}, {layers}], element = "hex8i" }}
plies = {{ normal = "z", layers = [
  {{ angle = 0.0, thickness = 0.25 }}, {{ angle = 90.0, thickness = 0.25 }},
  {{ angle = 90.0, thickness = 0.25 }}, {{ angle = 0.0, thickness = 0.25 }},
] }}
{extra}"#
    );
    let scene = Scene::parse(&text, std::path::Path::new("damage_bench.toml")).expect("scene");
    Model::from_scene(&scene).expect("model")
}

/// A bending field of the plate (strains up to `strain`), and its mid-step velocities.
fn motion(model: &Model, strain: f64) -> (Vec<f64>, Vec<f64>) {
    let mut u = Vec::with_capacity(model.dofs());
    for x in &model.mesh.nodes {
        let z = x[2] - 0.5;
        u.extend([
            strain * z * x[0],
            0.3 * strain * x[1],
            -0.5 * strain * x[0] * x[0],
        ]);
    }
    let v = u.iter().map(|x| 10.0 * x).collect();
    (u, v)
}

/// Seconds per call of `f`, over enough calls for 0.3 s (one call first).
fn time(mut f: impl FnMut()) -> f64 {
    f();
    let start = Instant::now();
    let mut calls = 0;
    while calls < 3 || start.elapsed().as_secs_f64() < 0.3 {
        f();
        calls += 1;
    }
    start.elapsed().as_secs_f64() / calls as f64
}

/// Every point of every damageable element damaged a little (5% in each mode).
fn damaged(model: &Model) -> Vec<f64> {
    let data = model.damage_data().expect("damage");
    let mut s = DamageState::new(&data);
    for (k, b) in data.blocks.iter().enumerate() {
        for i in 0..b.len() {
            for p in s.points[k][b.state_range(i)].chunks_exact_mut(POINT_STATE) {
                p.fill(0.05);
            }
            s.damaged[k][i] = true;
            s.first[k][i] = [1, 0];
        }
    }
    s.flat()
}

/// (elastic, damaging far from initiation, all damaged) seconds per step on `kernels`.
fn kernel_row(
    elastic: &mut dyn Kernels,
    damaging: &mut dyn Kernels,
    model: &Model,
    all_damaged: &[f64],
) -> [f64; 3] {
    let (u_small, v_small) = motion(model, 1e-5);
    let mut f = vec![0.0; model.dofs()];
    let e = time(|| {
        elastic
            .internal_forces_into(&u_small, &mut f)
            .expect("forces")
    });
    let uv = (&u_small[..], &v_small[..]);
    let quiet = time(|| {
        damaging.step_forces_into(uv, 1e-9, &mut f).expect("forces");
    });
    damaging.restore_damage(all_damaged).expect("state");
    let (u, v) = motion(model, 3e-3);
    let uv = (&u[..], &v[..]);
    let all = time(|| {
        damaging.step_forces_into(uv, 1e-9, &mut f).expect("forces");
    });
    [e, quiet, all]
}

fn kernels_table(ctx: &Option<GpuContext>, quick: bool) {
    println!("| plate | elements | plies an element | engine | elastic ns/el | damaging, quiet ns/el | all damaged ns/el | damaged / elastic |");
    println!("|---|---:|---:|---|---:|---:|---:|---:|");
    let n = if quick { 16 } else { 48 };
    for layers in [4, 2] {
        let (elastic, damaging) = (plate(n, layers, false), plate(n, layers, true));
        let all = damaged(&damaging);
        let ne = elastic.mesh.element_count() as f64;
        let mut rows: Vec<(&str, [f64; 3])> = Vec::new();
        let mut cpu_e = CpuKernels::new(elastic.element_data());
        let mut cpu_d =
            CpuKernels::new(damaging.element_data()).with_damage(damaging.damage_data());
        rows.push(("cpu", kernel_row(&mut cpu_e, &mut cpu_d, &damaging, &all)));
        // each element in its turning frame (`run.kinematics = "corotational"`)
        let mut cor_e = CpuKernels::new(elastic.element_data()).corotational(true);
        let mut cor_d = CpuKernels::new(damaging.element_data())
            .with_damage(damaging.damage_data())
            .corotational(true);
        let row = kernel_row(&mut cor_e, &mut cor_d, &damaging, &all);
        rows.push(("cpu, corotational", row));
        if let Some(ctx) = ctx {
            let mut gpu_e = GpuKernels::new(ctx.clone(), &elastic.element_data()).expect("engine");
            let mut gpu_d = GpuKernels::new(ctx.clone(), &damaging.element_data())
                .and_then(|k| k.with_damage(damaging.damage_data()))
                .expect("engine");
            rows.push((
                "gpu (host path)",
                kernel_row(&mut gpu_e, &mut gpu_d, &damaging, &all),
            ));
        }
        for (engine, [e, q, a]) in rows {
            println!(
                "| {n} x {n} x {layers} | {} | {} | {engine} | {:.1} | {:.1} | {:.1} | {:.1} |",
                ne as usize,
                4 / layers,
                1e9 * e / ne,
                1e9 * q / ne,
                1e9 * a / ne,
                a / e
            );
        }
    }
}

/// The coarse drop weight's text, its first `end` seconds, with or without fracture energies.
fn drop_weight(end: f64, damage: bool) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/drop_weight_d7136_elastic.toml");
    let text = std::fs::read_to_string(path).expect("the shipped scene");
    let text = text
        .replace("divisions = [50, 34, 4]", "divisions = [30, 20, 2]")
        .replace("end_time = 4.5e-3", &format!("end_time = {end:e}"));
    let text: String = text
        .lines()
        .filter(|l| !l.starts_with("vtu_every"))
        .collect::<Vec<_>>()
        .join("\n");
    match damage {
        // Camanho et al.'s constants (the scene's), the fracture energies of Maimi et al. 2007
        true => text.replace(
            "strength = { xt = 2323.5, xc = 1200.1, yt = 62.3, yc = 199.8, s12 = 92.3, s23 = 75.3 }",
            "strength = { xt = 2323.5, xc = 1200.1, yt = 62.3, yc = 199.8, s12 = 92.3, s23 = 75.3 }\nfracture_energy = { ft = 81.5, fc = 106.3, mt = 0.28, mc = 0.79 }",
        ),
        false => text,
    }
}

/// ns per element-step of the drop weight on `device`, and its damage energy.
fn whole_run(end: f64, damage: bool, device: DeviceChoice) -> (f64, f64) {
    let text = drop_weight(end, damage);
    let scene =
        Scene::parse(&text, std::path::Path::new("scenes/drop_weight_bench.toml")).expect("scene");
    let tag = format!("damage_bench_{}_{}", damage, device.name());
    let opts = RunOptions {
        out: Some(std::env::temp_dir().join(tag)),
        device: Some(device),
        quiet: true,
        overwrite: true,
        ..Default::default()
    };
    let s = run(&scene, &opts).expect("the drop weight runs");
    let seconds = s.device_seconds.unwrap_or(s.wall_seconds - s.setup_seconds);
    (
        1e9 * seconds / (s.elements * s.steps) as f64,
        s.damage_energy.unwrap_or(0.0),
    )
}

fn runs_table(gpu: bool, quick: bool) {
    let end = if quick { 4e-4 } else { 1.1e-3 };
    println!("| drop weight, 30 x 20 x 2 hex8i, first {:.1} ms | elastic ns/el-step | damaging ns/el-step | ratio | damage energy (mJ) |", 1e3 * end);
    println!("|---|---:|---:|---:|---:|");
    let mut devices = vec![DeviceChoice::Cpu];
    if gpu {
        devices.push(DeviceChoice::Gpu);
    }
    for device in devices {
        let (e, _) = whole_run(end, false, device);
        let (d, energy) = whole_run(end, true, device);
        println!(
            "| {} | {e:.1} | {d:.1} | {:.2} | {energy:.3} |",
            device.name(),
            d / e
        );
    }
}

/// IM7/8552's interface (CompDam's strengths and toughnesses), at the plate's ply changes.
const INTERFACES: &str = r#"
[[cohesive]]
name = "plies"
body = "plate"
at = "ply_changes"
stiffness = 1e5
strength = { normal = 62.3, shear = 92.3 }
toughness = { normal = 0.277, shear = 0.788, bk = 1.634 }
"#;

fn cohesive_table(ctx: &Option<GpuContext>, quick: bool) {
    use impact::kernels::cohesive_forces::{cohesive_forces, CohesiveState};
    let n = if quick { 16 } else { 48 };
    let model = plate_with(n, 4, false, INTERFACES);
    let pairs = || model.cohesive.iter().map(|c| &c.pairs);
    let count: usize = pairs().map(|p| p.area.len()).sum();
    let faces: usize = model.cohesive.iter().map(|c| c.faces.len()).sum();
    let ne = model.mesh.element_count() as f64;
    let mut hex = CpuKernels::new(model.element_data());
    let mut f = vec![0.0; model.dofs()];
    let (u, _) = motion(&model, 1e-5);
    let element = time(|| hex.internal_forces_into(&u, &mut f).expect("forces")) / ne;
    // the pairs' separations: the bending field's (bonded), and a slide of 0.01 mm of the
    // upper nodes (past the shear strength: every pair in its softening, advancing)
    let mut slid = u.clone();
    for c in pairs() {
        for &a in &c.upper {
            slid[3 * a as usize] += 0.01;
        }
    }
    println!("| interfaces of the {n} x {n} x 4 plate | engine | pairs | faces | ns/pair | ns/face | hex8i ns/el | face / hex8i |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|");
    for (label, u) in [("bonded", &u), ("softening", &slid)] {
        let t = time(|| {
            let mut state = CohesiveState::new(pairs());
            cohesive_forces(pairs(), u, &mut state, &mut f);
        });
        println!(
            "| {label} | cpu | {count} | {faces} | {:.1} | {:.1} | {:.1} | {:.2} |",
            1e9 * t / count as f64,
            1e9 * t / faces as f64,
            1e9 * element,
            t / faces as f64 / element
        );
    }
    if let Some(ctx) = ctx {
        device_cohesive_rows(ctx, &model, (&u, &slid), (count, faces));
    }
}

/// The cohesive table's device rows: the resident step's pair kernels alone against the
/// `hex8i_forces` kernel alone, on the same displacements.
fn device_cohesive_rows(
    ctx: &GpuContext,
    model: &Model,
    (u, slid): (&[f64], &[f64]),
    (count, faces): (usize, usize),
) {
    use impact::gpu::inspect::{time_cohesive, KernelId};
    use impact::kernels::cohesive_pairs::{CohesiveSetup, PairState};
    use impact::kernels::cohesive_scatter::BondedNodes;
    use impact::kernels::node_gather::Incidence;
    const REPS: usize = 200;
    let data = model.element_data();
    let mut gpu = GpuKernels::new(ctx.clone(), &data).expect("the GPU engine");
    let mut f = vec![0.0; model.dofs()];
    gpu.internal_forces_into(u, &mut f).expect("forces");
    let kind = impact::element::ElementKind::Hex8i;
    let hex = (gpu.time_kernel(KernelId::Forces(kind), REPS))
        .expect("timed")
        .as_secs_f64()
        / (REPS * model.mesh.element_count()) as f64;
    let setup = CohesiveSetup::of(model.cohesive.iter().map(|c| &c.pairs));
    let layout = data.layout();
    let mut bonded = BondedNodes::new(
        &setup,
        &Incidence::new(&data.elements, model.mesh.node_count()),
    );
    for b in &mut bonded.nodes {
        b.corner = layout.to_device(b.corner as usize) as u32;
    }
    let corners = vec![[0.0; 3]; layout.count()];
    let state = vec![PairState::default(); setup.pairs.len()];
    for (label, u) in [("bonded", u), ("softening", slid)] {
        let t = time_cohesive(ctx, &setup, &bonded, (u, &state, &corners), REPS)
            .expect("timed")
            .as_secs_f64()
            / REPS as f64;
        println!(
            "| {label} | {} | {count} | {faces} | {:.1} | {:.1} | {:.1} | {:.2} |",
            ctx.adapter.name,
            1e9 * t / count as f64,
            1e9 * t / faces as f64,
            1e9 * hex,
            t / faces as f64 / hex
        );
    }
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let ctx = GpuContext::new().ok();
    match &ctx {
        Some(c) => println!("adapter: {}", c.adapter.describe()),
        None => println!("adapter: none (CPU rows only)"),
    }
    println!();
    if std::env::args().any(|a| a == "--cohesive") {
        cohesive_table(&ctx, quick);
        return;
    }
    kernels_table(&ctx, quick);
    println!();
    cohesive_table(&ctx, quick);
    println!();
    runs_table(ctx.is_some(), quick);
}
