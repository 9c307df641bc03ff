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
//! Each table row also gives the resident engine's setup time (model, stable step, solver and
//! uploads) and its achieved bandwidth: the bytes a step must move at least (each node's and
//! element's data once per kernel, see [`step_bytes`]) over its time, against the adapter's
//! measured buffer copy. A second table splits the resident step into its stages.
//!
//! `cargo bench --bench explicit_step` (10^4 to 10^6 elements on the three engines, and a
//! 10^7-element row on the resident engine alone where the adapter is a hardware GPU;
//! `-- --quick` for 10^4 and 10^5 only; `-- --large` adds the 10^7 row on any adapter;
//! `-- --resident` times the resident engine alone; `-- --sweeps N` fixes the contact
//! sweeps the resident engine records per step; `-- --search-interval N` fixes the steps
//! between its contact search's sorts of the faces (1: every step); `-- --plate` runs the
//! plate scene alone; `-- --dispatches` times each kernel of a resident submission on the
//! device (adapters with timestamps inside passes); `-- --zone on` or `-- --zone off` runs
//! each step's contact iteration in one workgroup (`contact_zone`) or staged, whatever the
//! zone's size; `-- --relax on` or `-- --relax off` records the staged iteration's sweeps as
//! `contact_relax` (one dispatch a sweep) or as `contact_sweep` and `contact_apply` (either
//! fixes the form; by default the run's trial times the forms on its first submissions and
//! takes the fastest, a table gives its figures, and the timed steps run that form fixed);
//! `-- --lanes N` builds `contact_zone` and `contact_finish` with N lanes (256 by default;
//! up to 1,024 where the adapter allows, the same results); and `-- --no-large` leaves the
//! 10^7-element rows out).

use std::path::Path;
use std::time::Instant;

use impact::backend::{CpuKernels, Kernels};
use impact::gpu::inspect::{KernelTime, Stage};
use impact::gpu::{ContactForm, GpuContext, GpuKernels};
use impact::integrate::resident;
use impact::integrate::stable_step::{stable_step, stable_step_on};
use impact::integrate::{ExplicitSolver, Integrator, ResidentSolver};
use impact::model::Model;
use impact::scene::Scene;
use impact::setup::explicit_time_step;

#[path = "../tests/common/bench_scenes.rs"]
#[allow(dead_code)]
mod bench_scenes;
use bench_scenes::contact_scene;

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
    let elements = model.mesh.element_count() as f64;
    let steps = ((3e7 / elements) as usize).clamp(3, max_steps.min(200));
    let mut sweeps = 0;
    let t = Instant::now();
    for _ in 0..steps {
        sweeps += s.step().expect("step").iterations;
    }
    let per_step = t.elapsed().as_secs_f64() / steps as f64;
    (per_step * 1e9 / elements, sweeps as f64 / steps as f64)
}

/// What the resident engine measured at one size.
struct Resident {
    ns: f64,
    /// Model, stable step and solver (uploads included), seconds.
    setup: f64,
    /// Stage name and microseconds per step.
    /// Microseconds per step of each stage; none where the step runs it inside another.
    stages: Vec<(&'static str, Option<f64>)>,
    copy: f64,
    /// Steps timed, the contact sweeps recorded (as dispatches of their own) and needed
    /// per step over them, and the contact search's sorts of the faces per step.
    steps: usize,
    sweeps: Option<(f64, f64)>,
    rebuilds: Option<f64>,
    /// The contact iteration's parts alone, microseconds: setup; setup keeping the faces'
    /// sort; setup and every sweep in `contact_finish`; setup, the recorded sweeps and
    /// `contact_finish`; report.
    contact_parts: Option<[f64; 5]>,
    /// The search and the iteration in one workgroup alone, microseconds, where the
    /// adapter runs `contact_zone`; and which iteration the timed steps ran.
    zone_part: Option<f64>,
    zone: bool,
    relax: bool,
    /// The run's trial of the contact iteration's forms before the timed steps: each form's
    /// microseconds per step in its last round, and the form it chose.
    trial: Option<(Vec<(ContactForm, f64)>, ContactForm)>,
    /// The lanes of the one-workgroup kernels (`contact_zone`, `contact_finish`).
    lanes: u32,
    /// `-- --dispatches`: each kernel of a submission timed on the device (kernel,
    /// dispatches per step, microseconds per step), where the adapter has timestamps
    /// inside passes.
    dispatches: Option<Vec<KernelTime>>,
}

/// The bytes one explicit step moves at least: per node the predictor (a, v), drift (v, u),
/// gather (offsets, forces), corrector (lumped data, u, f, v, a) and each node's reference
/// and displacement read once by the element kernel; per element its connectivity, corner
/// forces written and read, and the incidence entries; per contact node a plane or pair's
/// state. (f32 values, split pairs of two.)
fn step_bytes(nodes: usize, elements: usize, contact_nodes: usize) -> f64 {
    let node = 36.0 + 60.0 + 16.0 + 100.0 + 48.0;
    let element = 36.0 + 96.0 + 96.0 + 32.0;
    node * nodes as f64 + element * elements as f64 + 200.0 * contact_nodes as f64
}

/// ns per element-step of the device-resident step, after one submission of warm-up; the
/// setup time, each stage's time alone, and the device copy bandwidth.
fn time_resident(
    model_time: f64,
    model: &Model,
    sc: &Scene,
    mut ctx: GpuContext,
    max_steps: usize,
) -> Resident {
    let start = Instant::now();
    if let Some(lanes) = fixed_lanes() {
        // that width alone
        ctx.zone_lanes = lanes;
        ctx.zone_trial.clear();
    }
    let (stable, _) = stable_step_on(model, Some(&ctx)).expect("stable step");
    let dt = explicit_time_step(sc, (stable, 0)).expect("time step");
    let elements = model.mesh.element_count() as f64;
    // the run's steps per submission (on a software adapter at most 16: a submission there
    // takes seconds)
    let software = ctx.adapter.software;
    let mut chunk = resident::chunk_steps(model.mesh.element_count());
    if software {
        chunk = chunk.min(16);
    }
    // no last step within reach: the run reads the state back at its last step
    let mut s = ResidentSolver::with_chunk(
        ctx,
        model,
        &sc.explicit,
        dt,
        1.0,
        (usize::MAX / 2, None, chunk),
        (None, None),
    )
    .expect("resident solver");
    let setup = model_time + start.elapsed().as_secs_f64();
    // half a second of device copies first (a GPU idle through the setup runs at a low
    // clock), then a submission of steps
    let warm = Instant::now();
    while !software && warm.elapsed().as_secs_f64() < 0.5 {
        s.engine_mut()
            .copy_bandwidth(256 << 20, 4)
            .expect("warm-up copies");
    }
    for _ in 0..chunk {
        s.step().expect("warm-up");
    }
    // then whole submissions (the device runs one ahead of the host) for about a second, at
    // least one and at most `max_steps` steps' worth (the scene stays in contact)
    if let Some(n) = fixed_sweeps() {
        s.fix_recorded_sweeps(n);
    }
    if let Some(n) = fixed_search_interval() {
        s.fix_search_interval(n);
    }
    if let Some(zone) = fixed_zone() {
        s.fix_contact_zone(zone);
    }
    if let Some(relax) = on_off("--relax") {
        s.fix_contact_relax(relax);
    }
    // the run's trial of the contact iteration's forms (none with a form fixed above, without
    // timestamps or with one form) ends its first round before the timed steps
    let mut submissions = 0;
    while s
        .form_trial()
        .is_some_and(|t| t.rounds == 0 && t.trialling())
        && submissions < 64
    {
        for _ in 0..chunk {
            s.step().expect("the forms' trial");
        }
        submissions += 1;
    }
    let trial = (s.form_trial())
        .filter(|t| t.rounds > 0)
        .map(|t| (t.last_round.clone(), t.current()));
    // the timed steps run the form the round chose, fixed: a later round (at twice the
    // submissions) would otherwise time the other forms inside the timed window
    if let Some((_, chosen)) = &trial {
        s.fix_contact_form(*chosen);
    }
    let before = s.sweep_counts();
    let sorts_before = s.search_counts().0;
    let t = Instant::now();
    let mut steps = 0;
    while steps == 0 || (steps + chunk <= max_steps && t.elapsed().as_secs_f64() < 1.0) {
        for _ in 0..chunk {
            s.step().expect("step");
        }
        steps += chunk;
    }
    let ns = t.elapsed().as_secs_f64() / steps as f64 * 1e9 / elements;
    let after = s.sweep_counts();
    let per_step = |a: u64, b: u64| (a - b) as f64 / steps as f64;
    let sweeps = s
        .engine_mut()
        .impulse_sweeps()
        .is_some()
        .then(|| (per_step(after.0, before.0), per_step(after.1, before.1)));
    let sorts = s.search_counts().0;
    let rebuilds = (sorts > 0).then(|| per_step(sorts, sorts_before));
    let engine = s.engine_mut();
    let reps = steps.clamp(4, 50);
    let recorded = engine.sweeps();
    let form = s.form_trial().map(|t| t.current());
    let engine = s.engine_mut();
    let zone = form.is_some_and(ContactForm::is_zone);
    let relax = form == Some(ContactForm::Relax);
    let lanes = match form {
        Some(ContactForm::Zone(lanes)) => lanes,
        _ => engine.impulse_sweeps_ref().map_or(0, |c| c.zone_lanes()),
    };
    // every timing below starts from the state the timed steps left
    engine.drain().expect("the last submissions");
    let state = engine.read_step_state().expect("the step state");
    let dispatches = match std::env::args().any(|a| a == "--dispatches") {
        true => engine.profile_dispatches(chunk).expect("dispatch profile"),
        false => None,
    };
    let contact_parts = engine
        .time_contact_parts(reps, recorded)
        .expect("contact part timing")
        .map(|t| t.map(|d| d.as_secs_f64() / reps as f64 * 1e6));
    let zone_part = (engine.time_zone(reps).expect("contact_zone timing"))
        .map(|d| d.as_secs_f64() / reps as f64 * 1e6);
    // the stages as the step dispatches them: where the iteration predicts, the predictor
    // runs in it and it drifts every node
    let predicts = engine.predicts();
    let contact = match predicts {
        true => Stage::PredictContact,
        false => Stage::PlaneContact,
    };
    let stages = [
        ("predict", (!predicts).then_some(Stage::Predict)),
        ("contact", Some(contact)),
        ("drift", (!predicts).then_some(Stage::Drift)),
        ("element forces", Some(Stage::ElementForces)),
        ("gather and correct", Some(Stage::GatherCorrect)),
        ("reduce", Some(Stage::Reduce)),
    ]
    .into_iter()
    .map(|(name, stage)| {
        let us = stage.map(|stage| {
            engine.write_step_state(&state).expect("the step state");
            let t = engine.time_stage(stage, reps).expect("stage timing");
            t.as_secs_f64() / reps as f64 * 1e6
        });
        (name, us)
    })
    .collect::<Vec<_>>();
    engine.write_step_state(&state).expect("the step state");
    let host = engine.recording_time(chunk).expect("recording time");
    let mut stages: Vec<(&'static str, Option<f64>)> = stages;
    stages.push((
        "host recording",
        Some(host.as_secs_f64() / chunk.min(engine.chunk_capacity) as f64 * 1e6),
    ));
    let copy = engine
        .copy_bandwidth(256 << 20, 20)
        .expect("copy bandwidth");
    Resident {
        ns,
        setup,
        stages,
        copy,
        steps,
        sweeps,
        rebuilds,
        contact_parts,
        zone_part,
        zone,
        relax,
        trial,
        lanes,
        dispatches,
    }
}

/// Which engines a table row times.
#[derive(Clone, Copy, PartialEq)]
enum Engines {
    All,
    ResidentOnly,
}

/// One table row per scene text: the three engines' ns per element-step, then the resident
/// step's stages.
/// `max_steps`: the most steps the host engines and the resident engine time.
fn table(
    title: &str,
    scenes: &[(String, Engines)],
    adapter: Option<&str>,
    max_steps: (usize, usize),
) {
    let (max_steps, resident_steps) = max_steps;
    println!("\n{title}\n");
    println!(
        "| elements | contact nodes | dt | CPU twin ns/element-step | GPU kernels + host loop | GPU resident | resident setup s | resident GB/s | % of copy | adapter | contact sweeps/step |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|");
    let mut stage_rows = Vec::new();
    for (text, engines) in scenes {
        let t = Instant::now();
        let sc = Scene::parse(text, Path::new("bench.toml")).expect("bench scene");
        let model = Model::from_scene(&sc).expect("model");
        let model_time = t.elapsed().as_secs_f64();
        let dt = explicit_time_step(&sc, stable_step(&model)).expect("stable step");
        let (cpu, gpu_ns, sweeps) = if *engines == Engines::All {
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
            (format!("{cpu:.0}"), gpu_ns, format!("{sweeps:.2}"))
        } else {
            ("(not timed)".into(), "(not timed)".into(), "-".into())
        };
        let elements = model.mesh.element_count();
        let contact_nodes = model.interfaces[0].nodes.len();
        let resident = GpuContext::new()
            .ok()
            .map(|ctx| time_resident(model_time, &model, &sc, ctx, resident_steps));
        let (ns, setup, gbs, share) = match &resident {
            Some(r) => {
                let bytes = step_bytes(model.mesh.node_count(), elements, contact_nodes);
                let rate = bytes / (r.ns * 1e-9 * elements as f64);
                (
                    format!("{:.2}", r.ns),
                    format!("{:.2}", r.setup),
                    format!("{:.0}", rate * 1e-9),
                    format!("{:.0}%", 100.0 * rate / r.copy),
                )
            }
            None => ("-".into(), "-".into(), "-".into(), "-".into()),
        };
        println!(
            "| {elements} | {contact_nodes} | {dt:.3e} | {cpu} | {gpu_ns} | {ns} | {setup} | {gbs} | {share} | {} | {sweeps} |",
            adapter.unwrap_or("none"),
        );
        if let Some(r) = resident {
            stage_rows.push((elements, r));
        }
    }
    if stage_rows.is_empty() {
        return;
    }
    println!("\nThe resident step's stages alone, as the step dispatches them (microseconds per step; each stage repeated in one submission; where the contact iteration has a device search, the predictor runs in its first kernel and it drifts every node, so \"contact\" holds the predictor and the drift, and their own columns are \"-\"), and the host's time to record and submit a step (it overlaps the device's work on the submission before):\n");
    let names: Vec<&str> = stage_rows[0].1.stages.iter().map(|s| s.0).collect();
    println!(
        "| elements | {} | sum | whole step | steps timed | contact sweeps recorded per step | needed per step | search rebuilds per step |",
        names.join(" | ")
    );
    println!(
        "|---:|{}---:|---:|---:|---:|---:|---:|",
        "---:|".repeat(names.len())
    );
    for (elements, r) in &stage_rows {
        let cells: Vec<String> = (r.stages.iter())
            .map(|s| s.1.map_or("-".into(), |us| format!("{us:.1}")))
            .collect();
        // the stages' sum leaves the host's recording out: it overlaps the device
        let sum: f64 = r
            .stages
            .iter()
            .filter(|s| s.0 != "host recording")
            .filter_map(|s| s.1)
            .sum();
        println!(
            "| {elements} | {} | {sum:.1} | {:.1} | {} | {} | {} | {} |",
            cells.join(" | "),
            r.ns * *elements as f64 * 1e-3,
            r.steps,
            r.sweeps.map_or("-".into(), |x| format!("{:.2}", x.0)),
            r.sweeps.map_or("-".into(), |x| format!("{:.2}", x.1)),
            r.rebuilds.map_or("-".into(), |x| format!("{x:.3}")),
        );
    }
    for (elements, r) in &stage_rows {
        if let Some(d) = &r.dispatches {
            print_dispatches(*elements, d);
        }
    }
    print_trials(&stage_rows);
    if stage_rows.iter().all(|(_, r)| r.contact_parts.is_none()) {
        return;
    }
    println!("\nThe contact iteration's parts alone (microseconds per step): its setup (search with the faces' sort into the grid, constraints, sort, compliance), the setup keeping the faces' last sort, the setup with every sweep in `contact_finish` (one workgroup), the setup with the sweeps the run records per step and `contact_finish`, the report, and the search with the whole iteration in one workgroup (`contact_zone`); which of the two the timed steps ran (and the lanes of `contact_zone` and `contact_finish`):\n");
    println!("| elements | setup | setup keeping the sort | setup + finish | setup + recorded + finish | report | search + contact_zone | timed steps ran |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---|");
    for (elements, r) in &stage_rows {
        if let Some(p) = r.contact_parts {
            println!(
                "| {elements} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {} | {}, {} lanes |",
                p[0],
                p[1],
                p[2],
                p[3],
                p[4],
                r.zone_part.map_or("-".into(), |z| format!("{z:.1}")),
                match (r.zone, r.relax) {
                    (true, _) => "contact_zone",
                    (false, true) => "staged, sweeps in contact_relax",
                    (false, false) => "staged, sweeps in contact_sweep and contact_apply",
                },
                r.lanes,
            );
        }
    }
}

/// The run's trial of the contact iteration's forms before the timed steps, where it ran.
fn print_trials(stage_rows: &[(usize, Resident)]) {
    if stage_rows.iter().all(|(_, r)| r.trial.is_none()) {
        return;
    }
    println!("\nThe run's trial of the contact iteration's forms before the timed steps (`integrate::form_trial`): microseconds per step of each form in the trial's last round (the device's time for a submission's compute pass, or the host's time to record it where that is longer), and the form the run took:\n");
    // a column per form any row timed, in the trial's order
    let mut forms: Vec<ContactForm> = (stage_rows.iter())
        .filter_map(|(_, r)| r.trial.as_ref())
        .flat_map(|(costs, _)| costs.iter().map(|c| c.0))
        .collect();
    forms.sort();
    forms.dedup();
    let names: Vec<String> = forms.iter().map(|f| f.name()).collect();
    println!("| elements | {} | the run took |", names.join(" | "));
    println!("|---:|{}---|", "---:|".repeat(forms.len()));
    for (elements, r) in stage_rows {
        let Some((costs, chosen)) = &r.trial else {
            continue;
        };
        let cost = |form: &ContactForm| {
            (costs.iter().find(|(f, _)| f == form))
                .map_or("-".to_string(), |(_, c)| format!("{:.1}", c * 1e6))
        };
        let cells: Vec<String> = forms.iter().map(cost).collect();
        println!("| {elements} | {} | {} |", cells.join(" | "), chosen.name());
    }
}

/// A submission's kernels (`-- --dispatches`), timed on the device in the step's sequence.
fn print_dispatches(elements: usize, kernels: &[KernelTime]) {
    let dispatches: f64 = kernels.iter().map(|k| k.dispatches).sum();
    let sum: f64 = kernels.iter().map(|k| k.us).sum();
    println!(
        "\nThe resident step's kernels at {elements} elements, timed in one submission as the run records it (a timestamp after each dispatch; a dispatch's time, from the timestamp before it, includes its barrier and launch): {dispatches:.1} dispatches and {sum:.1} us per step:\n"
    );
    println!("| kernel | dispatches per step | us per step |");
    println!("|---|---:|---:|");
    for k in kernels {
        println!("| {} | {:.2} | {:.1} |", k.name, k.dispatches, k.us);
    }
}

/// The CPU twin's step on one thread and on all of them, side by side.
fn thread_table(title: &str, scenes: &[String], max_steps: usize) {
    let all = rayon::current_num_threads();
    println!("\n{title}: the CPU twin (f64)\n");
    println!("| elements | 1 thread ns/element-step | {all} threads ns/element-step | speed-up |");
    println!("|---:|---:|---:|---:|");
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    for text in scenes {
        let sc = Scene::parse(text, Path::new("bench.toml")).expect("bench scene");
        let model = Model::from_scene(&sc).expect("model");
        let dt = explicit_time_step(&sc, stable_step(&model)).expect("stable step");
        let time = || {
            time_steps(
                &model,
                &sc,
                dt,
                Box::new(CpuKernels::new(model.element_data())),
                max_steps,
            )
            .0
        };
        let single = one.install(time);
        let many = time();
        println!(
            "| {} | {single:.0} | {many:.0} | {:.2} |",
            model.mesh.element_count(),
            single / many
        );
    }
}

/// `-- --search-interval N`: the resident engine sorts the faces into its search grid every
/// N steps instead of following the grid's fill.
fn fixed_search_interval() -> Option<usize> {
    let args: Vec<String> = std::env::args().collect();
    let at = args.iter().position(|a| a == "--search-interval")?;
    args.get(at + 1).and_then(|n| n.parse().ok())
}

/// `-- --sweeps N`: the resident engine records N contact sweeps per step as dispatches of
/// their own instead of following the steps' needs.
/// `-- --zone on|off`: the contact iteration in one workgroup or staged.
fn fixed_zone() -> Option<bool> {
    on_off("--zone")
}

/// `-- FLAG on|off`, where given.
fn on_off(flag: &str) -> Option<bool> {
    let args: Vec<String> = std::env::args().collect();
    let at = args.iter().position(|a| a == flag)?;
    match args.get(at + 1).map(String::as_str) {
        Some("on") => Some(true),
        Some("off") => Some(false),
        other => panic!("{flag} takes on or off, not {other:?}"),
    }
}

/// `-- --lanes N`: the lanes of the one-workgroup kernels (`impact::gpu::one_group`).
fn fixed_lanes() -> Option<u32> {
    let args: Vec<String> = std::env::args().collect();
    let at = args.iter().position(|a| a == "--lanes")?;
    match args.get(at + 1).and_then(|n| n.parse().ok()) {
        Some(n) => Some(n),
        None => panic!("--lanes takes a number of lanes (256, 512 or 1024)"),
    }
}

fn fixed_sweeps() -> Option<u32> {
    let args: Vec<String> = std::env::args().collect();
    let at = args.iter().position(|a| a == "--sweeps")?;
    args.get(at + 1).and_then(|n| n.parse().ok())
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    if std::env::args().any(|a| a == "--cpu") {
        // the CPU twin alone, on one thread and on all
        let mut floors = vec![[25, 20, 20], [50, 50, 40]];
        let mut plates = vec![36, 76];
        if !quick {
            floors.push([100, 100, 100]);
            plates.push(164);
        }
        thread_table(
            "Block dropped on a rigid floor",
            &floors.iter().map(|&n| scene(n)).collect::<Vec<_>>(),
            2000,
        );
        thread_table(
            "Block sliding on a supported plate",
            &plates.iter().map(|&n| contact_scene(n)).collect::<Vec<_>>(),
            200,
        );
        return;
    }
    let large = std::env::args().any(|a| a == "--large");
    // the resident engine alone (a quick look at the device step)
    let resident_only = std::env::args().any(|a| a == "--resident");
    let ctx = GpuContext::new().ok();
    let adapter = ctx.as_ref().map(|c| c.adapter.name.clone());
    let hardware = ctx.as_ref().is_some_and(|c| !c.adapter.software);
    let mut sizes: Vec<([usize; 3], Engines)> =
        vec![([25, 20, 20], Engines::All), ([50, 50, 40], Engines::All)];
    let mut plates: Vec<(usize, Engines)> = vec![(36, Engines::All), (76, Engines::All)];
    if !quick {
        sizes.push(([100, 100, 100], Engines::All));
        plates.push((164, Engines::All));
    }
    let no_large = std::env::args().any(|a| a == "--no-large");
    if ((!quick && hardware) || large) && !no_large {
        // the CPU engines would take minutes a step: the resident engine alone
        sizes.push(([216, 216, 216], Engines::ResidentOnly));
        plates.push((354, Engines::ResidentOnly));
    } else if !quick {
        println!(
            "(the 10^7-element rows run on a hardware GPU, or with --large: this adapter is {})",
            adapter.as_deref().unwrap_or("none")
        );
    }
    if resident_only {
        sizes.iter_mut().for_each(|s| s.1 = Engines::ResidentOnly);
        plates.iter_mut().for_each(|s| s.1 = Engines::ResidentOnly);
    }
    let plate_only = std::env::args().any(|a| a == "--plate");
    if !plate_only {
        floor_table(&sizes, adapter.as_deref());
    }
    // fewer steps: the host loop's contact iteration is slow on a software adapter, and the
    // block stays on the plate for about 0.8 of simulated time (4,000 steps at 10^4
    // elements)
    table(
        "Block sliding on a supported plate (contact between meshed bodies, friction 0.2)",
        &plates
            .iter()
            .map(|&(n, e)| (contact_scene(n), e))
            .collect::<Vec<_>>(),
        adapter.as_deref(),
        (200, 4000),
    );
}

/// The floor scene's table.
fn floor_table(sizes: &[([usize; 3], Engines)], adapter: Option<&str>) {
    table(
        "Block dropped on a rigid floor (plane contact)",
        &sizes
            .iter()
            .map(|&(n, e)| (scene(n), e))
            .collect::<Vec<_>>(),
        adapter,
        (2000, 20000),
    );
}
