//! One implicit step with contact on a 3D block (>= 50,000 dofs). Prints two tables:
//!
//! - the factorisation and one solve pair of the effective matrix with each fill-reducing
//!   ordering, on one thread and on all of them;
//! - the contact space: the block's bottom layer (its nodes in contact with the floor)
//!   numbered last, so that its trailing block of the factor solves loads on those
//!   equations alone (`SpdSolver::with_last`): the factor's size and the solve's time
//!   against the full solve pair;
//! - assembly, step time and iterations per step with the plain multiplier iteration and with
//!   Anderson acceleration, with plain steps, and once more with the default event
//!   sub-steps: the first steps are the block's impact, so they are refined into 4 sub-steps
//!   each (the sub-step's factorisation is counted in its step); and the Newton step (the
//!   default iteration) with the default sub-steps, whose flexibility holds at most 2,500
//!   nodes: on wider contacts its steps go on with Anderson's update. The first step (the
//!   impact: the sub-step's factorisation and the flexibilities' columns are made there)
//!   is timed apart from the four after it.
//!
//! `cargo bench --bench implicit_step` (add `-- --quick` for a smaller block, or `-- --large`
//! for the steps table alone on a block of 101,376 elements, Anderson and Newton with the
//! default event sub-steps on the whole model and on the contact space: its factors need
//! about 16 GB).

use std::path::Path;
use std::time::Instant;

use impact::backend::CpuKernels;
use impact::integrate::{ImplicitSolver, Integrator};
use impact::linalg::cholesky::FAER_TASKS;
use impact::linalg::{assemble, Assembled, Ordering, SpdSolver};
use impact::model::Model;
use impact::scene::{Acceleration, ContactSpace, Scene};

#[path = "../tests/common/bench_scenes.rs"]
#[allow(dead_code)]
mod bench_scenes;
use bench_scenes::implicit_block_drop;

/// Seconds of `f`, and its value.
fn timed<T>(f: impl FnOnce() -> T) -> (f64, T) {
    let t = Instant::now();
    let v = f();
    (t.elapsed().as_secs_f64(), v)
}

/// The factorisation and one solve pair of the effective matrix, with each ordering, on one
/// thread and on all of them.
fn factor_table(asm: &Assembled, elements: usize) {
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    for &(name, ordering) in Ordering::CHOICES {
        let measure = || {
            let (t_fact, solver) =
                timed(|| SpdSolver::new(&asm.effective, ordering).expect("factorises"));
            let mut b = vec![1.0; asm.dof_of.len()];
            let reps = 5;
            let (t_solve, ()) = timed(|| {
                for _ in 0..reps {
                    solver.solve_in_place(&mut b);
                }
            });
            (t_fact, t_solve / reps as f64, solver.stats())
        };
        let (f1, s1, stats) = one.install(measure);
        let (fa, sa, _) = measure();
        println!(
            "| {elements} | {} | {name} | {} | {:.2} | {:.2} | {:.2} | {:.1} | {:.1} |",
            stats.equations,
            stats.factor_nonzeros,
            stats.analysis_seconds,
            f1,
            fa,
            1e3 * s1,
            1e3 * sa,
        );
    }
}

fn main() {
    let flag = |f: &str| std::env::args().any(|a| a == f);
    let (quick, large) = (flag("--quick"), flag("--large"));
    let sizes: &[[usize; 3]] = match (quick, large) {
        (true, _) => &[[12, 12, 8]],
        (false, true) => &[[48, 48, 44]],
        (false, false) => &[[16, 16, 12], [30, 30, 20]],
    };
    let all = rayon::current_num_threads();
    let models: Vec<(Scene, Model)> = sizes
        .iter()
        .map(|&n| {
            let sc = Scene::parse(&implicit_block_drop(n, 100, ""), Path::new("bench.toml"))
                .expect("bench scene");
            let model = Model::from_scene(&sc).expect("model");
            (sc, model)
        })
        .collect();
    if large {
        steps_table(&models, all, true);
        return;
    }
    println!("Factorisation of the effective matrix (1 thread and {all} threads; faer with {FAER_TASKS} tasks):\n");
    println!("| elements | equations | ordering | factor nonzeros | ordering + analysis s | factorisation s, 1 thread | factorisation s, {all} threads | solve pair ms, 1 thread | solve pair ms, {all} threads |");
    println!("|---:|---:|---|---:|---:|---:|---:|---:|---:|");
    for (sc, model) in &models {
        let dt = sc.run.time_step.unwrap();
        let asm = assemble(model, sc.implicit.mass, 1.0 / (0.25 * dt * dt));
        factor_table(&asm, model.mesh.element_count());
    }
    println!("\nThe contact space: the bottom layer's equations numbered last ({all} threads):\n");
    println!("| elements | equations | contact equations | factor nonzeros, plain | factor nonzeros, contact last | contact-space solve's values / plain factor's | solve pair ms | contact-space solve ms |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (sc, model) in &models {
        let dt = sc.run.time_step.unwrap();
        let asm = assemble(model, sc.implicit.mass, 1.0 / (0.25 * dt * dt));
        contact_space_row(&asm, model);
    }
    steps_table(&models, all, false);
}

/// The table of steps with contact; `large`: Anderson and Newton with the default sub-steps
/// only.
fn steps_table(models: &[(Scene, Model)], all: usize, large: bool) {
    println!(
        "\nSteps with contact ({all} threads, ordering {}):\n",
        Ordering::default().name()
    );
    println!(
        "| elements | free dofs | contact nodes | assembly s | acceleration | event sub-steps | contact space | setup s (factors s) | first step ms | later steps ms (mean of 4) | iterations/step | steps refined |"
    );
    println!("|---:|---:|---:|---:|---|---:|---|---:|---:|---:|---:|---:|");
    for (sc, model) in models {
        step_rows(sc, model, large);
    }
}

/// The effective matrix factorised with the bottom layer's equations last: its size, and the
/// contact-space solve against the full solve pair (means of 20).
fn contact_space_row(asm: &Assembled, model: &Model) {
    let last: Vec<bool> = (asm.dof_of.iter())
        .map(|&d| model.mesh.nodes[d as usize / 3][2] == 0.0)
        .collect();
    let plain = SpdSolver::new(&asm.effective, Ordering::NestedDissection).expect("factorises");
    let solver = SpdSolver::with_last(&asm.effective, &last).expect("factorises");
    let count = last.iter().filter(|&&m| m).count();
    let reps = 20;
    let mut b = vec![1.0; asm.dof_of.len()];
    let (t_full, ()) = timed(|| {
        for _ in 0..reps {
            solver.solve_in_place(&mut b);
        }
    });
    let mut c = vec![1.0; count];
    let (t_contact, solved) = timed(|| (0..reps).all(|_| solver.contact_solve_in_place(&mut c)));
    assert!(solved, "a supernodal factor has a contact space");
    let share = solver.contact_space().map_or(0.0, |t| t.values() as f64)
        / plain.stats().factor_nonzeros as f64;
    println!(
        "| {} | {} | {count} | {} | {} | {share:.3} | {:.2} | {:.3} |",
        model.mesh.element_count(),
        asm.dof_of.len(),
        plain.stats().factor_nonzeros,
        solver.stats().factor_nonzeros,
        1e3 * t_full / reps as f64,
        1e3 * t_contact / reps as f64,
    );
}

/// Five steps of the block's impact with each multiplier iteration, on the whole model and
/// on the contact space.
fn step_rows(sc: &Scene, model: &Model, large: bool) {
    let dt = sc.run.time_step.unwrap();
    let (t_asm, asm) = timed(|| assemble(model, sc.implicit.mass, 1.0 / (0.25 * dt * dt)));
    let configs = [
        ("none", Acceleration::None, 1),
        ("anderson", Acceleration::Anderson, 1),
        (
            "anderson",
            Acceleration::Anderson,
            sc.implicit.event_substeps,
        ),
        ("newton", Acceleration::Newton, sc.implicit.event_substeps),
    ];
    let configs = match large {
        true => &configs[2..],
        false => &configs[..],
    };
    let spaces = [ContactSpace::Off, ContactSpace::Auto];
    for (space, &(name, acc, k)) in spaces
        .iter()
        .flat_map(|&s| configs.iter().map(move |c| (s, c)))
    {
        let mut settings = sc.implicit.clone();
        settings.acceleration = acc;
        settings.event_substeps = k;
        settings.contact_space = space;
        let kernels = Box::new(CpuKernels::new(model.element_data()));
        let (t_setup, mut s) = timed(|| {
            ImplicitSolver::new(model, settings, dt, sc.speed_scale(), kernels).expect("solver")
        });
        let factors = [Some(s.linear_solver()), s.mass_factor()]
            .iter()
            .flatten()
            .map(|f| f.analysis_seconds + f.factorization_seconds)
            .sum::<f64>();
        let steps = 5;
        let mut iters = 0;
        let mut times = Vec::with_capacity(steps);
        for _ in 0..steps {
            let (t, r) = timed(|| s.step().expect("step"));
            iters += r.iterations;
            times.push(t);
        }
        let later = times[1..].iter().sum::<f64>() / (steps - 1) as f64;
        let contact = s.linear_solver().contact_equations;
        println!(
            "| {} | {} | {} | {:.2} | {name} | {k} | {} | {t_setup:.1} ({factors:.1}) | {:.0} | {:.0} | {:.1} | {} |",
            model.mesh.element_count(),
            asm.dof_of.len(),
            model.interfaces[0].nodes.len(),
            t_asm,
            match contact {
                0 => "off".to_string(),
                c => format!("{c} equations"),
            },
            1e3 * times[0],
            1e3 * later,
            iters as f64 / steps as f64,
            s.event_steps
        );
    }
}
