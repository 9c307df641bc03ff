//! One implicit step with contact on a 3D block (>= 50,000 dofs): assembly, factorisation,
//! solve and step times, iterations per step. Prints a table.
//!
//! Each size runs with the plain multiplier iteration and with Anderson acceleration, with
//! plain steps, and once more with the default event sub-steps: the first steps are the
//! block's impact, so they are refined into 4 sub-steps each (the sub-step's factorisation
//! is counted in its step).
//!
//! `cargo bench --bench implicit_step` (add `-- --quick` for a smaller block).

use std::path::Path;
use std::time::Instant;

use impact::integrate::ImplicitSolver;
use impact::kernels::CpuKernels;
use impact::linalg::{assemble, SpdSolver};
use impact::model::Model;
use impact::scene::{Acceleration, Scene};

fn scene(n: [usize; 3]) -> String {
    // a steel-like block (E = 200, rho = 7.8e-3 in consistent units) dropped at 1 on a rigid
    // plane it touches at t = 0; dt = h / c, the wave-resolving implicit step
    let h = 1.0 / n[0] as f64;
    let c = (200.0f64 / 7.8e-3).sqrt();
    let dt = h / c;
    format!(
        r#"
[run]
end_time = {end}
time_step = {dt}

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
        end = 100.0 * dt,
        dt = dt,
        ly = n[1] as f64 * h,
        lz = n[2] as f64 * h,
        nx = n[0],
        ny = n[1],
        nz = n[2],
    )
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let sizes: &[[usize; 3]] = if quick {
        &[[12, 12, 8]]
    } else {
        &[[16, 16, 12], [30, 30, 20]]
    };
    println!(
        "| elements | free dofs | contact nodes | assembly s | factorisation s | solve ms | acceleration | event sub-steps | step ms (mean of 5) | iterations/step | steps refined |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|");
    for &n in sizes {
        let sc = Scene::parse(&scene(n), Path::new("bench.toml")).expect("bench scene");
        let model = Model::from_scene(&sc).expect("model");
        let dt = sc.run.time_step.unwrap();
        let c_m = 1.0 / (0.25 * dt * dt);
        let t = Instant::now();
        let asm = assemble(&model, sc.implicit.mass, c_m);
        let t_asm = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let solver = SpdSolver::new(&asm.effective).expect("factorises");
        let t_fact = t.elapsed().as_secs_f64();
        let mut b = vec![1.0; asm.dof_of.len()];
        let t = Instant::now();
        let reps = 5;
        for _ in 0..reps {
            solver.solve_in_place(&mut b);
        }
        let t_solve = t.elapsed().as_secs_f64() / reps as f64;
        for (name, acc, k) in [
            ("none", Acceleration::None, 1),
            ("anderson", Acceleration::Anderson, 1),
            (
                "anderson",
                Acceleration::Anderson,
                sc.implicit.event_substeps,
            ),
        ] {
            let mut settings = sc.implicit.clone();
            settings.acceleration = acc;
            settings.event_substeps = k;
            let kernels = Box::new(CpuKernels::new(model.element_data()));
            let mut s = ImplicitSolver::new(&model, settings, dt, sc.speed_scale(), kernels)
                .expect("solver");
            let steps = 5;
            let mut iters = 0;
            let t = Instant::now();
            for _ in 0..steps {
                iters += s.step().expect("step").iterations;
            }
            let t_step = t.elapsed().as_secs_f64() / steps as f64;
            println!(
                "| {} | {} | {} | {:.2} | {:.2} | {:.1} | {name} | {k} | {:.0} | {:.1} | {} |",
                model.mesh.hexes.len(),
                asm.dof_of.len(),
                model.interfaces[0].nodes.len(),
                t_asm,
                t_fact,
                1e3 * t_solve,
                1e3 * t_step,
                iters as f64 / steps as f64,
                s.event_steps
            );
        }
    }
}
