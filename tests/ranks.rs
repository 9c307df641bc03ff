//! The decomposed explicit path without MPI: a rank's shared-node sums against the
//! single-process forces, bit for bit, for every rank of a 1-, 2-, 3- and 5-part split; and a
//! run on one rank through the decomposed solver (the surface gather, the contact on the
//! surface model, the owned sums) against the single-process run, the history file identical.
//! `tests/mpi_ranks.rs` runs the same scenes on 2 and 4 MPI ranks.

mod common;
use common::*;

use impact::backend::{CpuKernels, Kernels};
use impact::domain::forces::RankForces;
use impact::domain::subdomain::Subdomain;
use impact::domain::{Partition, Single};
use impact::element::ElementKind;
use impact::gpu::{GpuContext, GpuKernels};
use impact::model::Model;
use impact::run::{run, run_ranks, RunOptions};
use impact::scene::{DeviceChoice, Scene};
use rand::{Rng, SeedableRng};

/// A hex8 block on a tet4 plate and a hex8i bar beside them (every element kind), its nodes
/// jittered by the random displacement the forces are taken at.
fn mixed_model() -> Model {
    let text = edit(
        &tet4_cube_on_plate(),
        "divisions = [4, 4, 4], element = \"tet4\" }",
        "divisions = [3, 4, 5] }",
    ) + r#"
[[body]]
name = "bar"
material = "soft"
box = { min = [-2.0, 2.0, 0.0], max = [2.0, 2.5, 0.5], divisions = [6, 2, 1], element = "hex8i" }
"#;
    let scene = Scene::parse(&text, &repo().join("scenes/mixed.toml")).expect("valid scene");
    Model::from_scene(&scene).expect("a model")
}

/// Each rank's internal forces on `ctx` (or the CPU) from its own corners and the corners
/// its neighbours send (exchanged here in memory), on every node it holds, against the
/// forces of the whole model on one device of the same kind, bit for bit, for 1-, 2-, 3- and
/// 5-part splits; each element is on one rank and each node owned by one.
fn shared_node_sums_match_one_device(ctx: Option<GpuContext>) {
    let model = mixed_model();
    let els = &model.mesh.elements;
    assert!(ElementKind::ALL.iter().all(|&k| els.count_of(k) > 0));
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed("ranks_forces"));
    let u: Vec<f64> = (0..model.dofs())
        .map(|_| rng.random_range(-0.02..0.02))
        .collect();
    let mut whole: Box<dyn Kernels> = match &ctx {
        Some(ctx) => Box::new(GpuKernels::new(ctx.clone(), &model.element_data()).unwrap()),
        None => Box::new(CpuKernels::new(model.element_data())),
    };
    let mut f = vec![0.0; model.dofs()];
    whole.internal_forces_into(&u, &mut f).unwrap();
    for parts in [1, 2, 3, 5] {
        let partition = Partition::bisect(&model, parts);
        let mut subs: Vec<Subdomain> = (0..parts)
            .map(|r| Subdomain::new(&model, &partition, r))
            .collect();
        let mut kernels: Vec<RankForces> = (subs.iter_mut())
            .map(|s| RankForces::new(s, ctx.clone(), (None, false)).unwrap())
            .collect();
        let mut local_f: Vec<Vec<f64>> = Vec::new();
        for (s, k) in subs.iter().zip(&mut kernels) {
            let mut fl = vec![0.0; 3 * s.nodes.len()];
            k.internal_forces(&s.restrict(&u), &mut fl).unwrap();
            local_f.push(fl);
        }
        assert!(
            parts == 1 || subs.iter().all(|s| !s.shared.is_empty()),
            "{parts} parts share no node"
        );
        let sends: Vec<Vec<Vec<f64>>> = (subs.iter().zip(&kernels))
            .map(|(s, k)| k.sends(s))
            .collect();
        let mut owners = vec![0usize; model.mesh.node_count()];
        for (r, s) in subs.iter().enumerate() {
            // what each neighbour sends this rank: its corners on the list it keeps for r
            let mut received = vec![0.0; 3 * s.received];
            for nb in &s.neighbours {
                let theirs = &subs[nb.rank];
                let back = (theirs.neighbours.iter())
                    .position(|x| x.rank == r)
                    .expect("neighbours both ways");
                let sent = &sends[nb.rank][back];
                assert_eq!(
                    sent.len(),
                    3 * nb.receive.len(),
                    "{parts} parts, {r} <- {}",
                    nb.rank
                );
                received[3 * nb.receive.start..3 * nb.receive.end].copy_from_slice(sent);
            }
            let mut fl = local_f[r].clone();
            kernels[r].sum_shared(s, &received, &mut fl);
            for (i, &n) in s.nodes.iter().enumerate() {
                let n = n as usize;
                for a in 0..3 {
                    assert_eq!(
                        fl[3 * i + a].to_bits(),
                        f[3 * n + a].to_bits(),
                        "{parts} parts, rank {r}, node {n}: {} against {}",
                        fl[3 * i + a],
                        f[3 * n + a]
                    );
                }
                owners[n] += usize::from(s.owned[i]);
            }
        }
        assert!(
            owners.iter().all(|&o| o == 1),
            "{parts} parts: a node not owned once"
        );
        let elements: usize = subs.iter().map(|s| s.data.elements.count()).sum();
        assert_eq!(elements, model.mesh.element_count());
    }
}

#[test]
fn shared_node_sums_are_the_single_process_forces_bit_for_bit() {
    shared_node_sums_match_one_device(None);
}

/// On a GPU the shared nodes' corners are read back in f32 and summed in f32 in global corner
/// order, as the GPU's own gather adds them: every node's force is the bits of the whole
/// model's forces on one GPU.
#[test]
fn shared_node_sums_on_gpus_are_one_gpus_forces_bit_for_bit() {
    if let Some(ctx) = gpu_context("ranks on gpus") {
        shared_node_sums_match_one_device(Some(ctx));
    }
}

/// Runs `text` on one process and through the decomposed solver on one rank.
fn both_ways(tag: &str, text: &str) -> (String, String) {
    let scene = Scene::parse(text, &repo().join("scenes").join(format!("{tag}.toml")))
        .expect("valid scene");
    let opts = |d: &str| RunOptions {
        out: Some(out_dir(&format!("{tag}_{d}"))),
        quiet: true,
        device: Some(impact::scene::DeviceChoice::Cpu),
        ..Default::default()
    };
    let (one, ranked) = (opts("process"), opts("rank"));
    let s = run(&scene, &one).expect("single-process run completes");
    let r = run_ranks(&scene, &ranked, &Single).expect("one-rank run completes");
    assert_eq!(s.status, "completed", "{tag}");
    assert_eq!(r.status, "completed", "{tag}");
    assert_eq!(r.ranks.as_ref().map(|d| d.ranks), Some(1));
    let read = |o: &RunOptions| {
        std::fs::read_to_string(o.out.as_ref().unwrap().join("history.csv")).expect("history")
    };
    (read(&one), read(&ranked))
}

/// Friction, two bodies, a rigid wall, tet4 faces: the history of the decomposed solver on
/// one rank is the single-process history, byte for byte.
#[test]
fn one_rank_runs_the_single_process_history_byte_for_byte() {
    for (tag, text) in [
        ("ranks_cube_on_plate", scene_text("cube_on_plate.toml")),
        ("ranks_two_bars", scene_text("two_bars_fine.toml")),
        ("ranks_bar_on_wall", scene_text("bar_on_wall.toml")),
        ("ranks_tet4_cube_on_plate", tet4_cube_on_plate()),
        ("ranks_loaded_bar", loaded_bar("explicit", 0.002, 0.4)),
        (
            "ranks_pushed_bar",
            pushed_bar(0.4, "displacement = [-0.05, 0.0, 0.0]\namplitude = [[0.0, 0.0], [0.1, 1.0], [0.3, 0.0]]\n"),
        ),
    ] {
        let (one, ranked) = both_ways(tag, &explicit_at_default_step(&text));
        assert!(
            one.lines().count() > 10,
            "{tag}: {} rows",
            one.lines().count()
        );
        assert!(one == ranked, "{tag}: the histories differ");
    }
}

/// What a decomposed run cannot do is refused with the key that asks for it.
#[test]
fn a_decomposed_run_refuses_the_implicit_path() {
    let implicit = scene_text("two_bars.toml");
    let scene = Scene::parse(&implicit, &repo().join("scenes/ranks_implicit.toml")).unwrap();
    let opts = RunOptions {
        out: Some(out_dir("ranks_implicit")),
        quiet: true,
        ..Default::default()
    };
    let e = run_ranks(&scene, &opts, &Single).expect_err("implicit is refused");
    assert!(e.to_string().contains("run.method"), "{e}");
}

/// Two blocks glued by a cohesive interface and pulled apart until it separates: the
/// decomposed solver on one rank gives the single-process history byte for byte, the
/// interface's areas and dissipation among it.
#[test]
fn one_rank_separates_a_cohesive_interface_as_the_single_process() {
    let text = r#"
[run]
end_time = 3e-5
method = "explicit"
[[material]]
name = "steel"
density = 7.8e-9
youngs_modulus = 2e5
poissons_ratio = 0.3
[[body]]
name = "top"
material = "steel"
box = { min = [0.0, 0.0, 1.0], max = [2.0, 2.0, 2.0], divisions = [2, 2, 1] }
[[body]]
name = "bottom"
material = "steel"
box = { min = [0.0, 0.0, 0.0], max = [2.0, 2.0, 1.0], divisions = [2, 2, 1] }
[[cohesive]]
name = "glue"
between = [{ body = "top", face = "z-" }, { body = "bottom", face = "z+" }]
stiffness = 1e6
strength = { normal = 50.0, shear = 50.0 }
toughness = { normal = 0.3, shear = 0.6, bk = 2.0 }
[[fix]]
body = "top"
face = "z+"
components = ["x", "y", "z"]
velocity = [0.0, 0.0, 1000.0]
[[fix]]
body = "bottom"
face = "z-"
components = ["x", "y", "z"]
"#;
    let (one, ranked) = both_ways("ranks_cohesive", text);
    let h = History::parse(&one);
    assert!(h.last("glue.delaminated_area") > 0.0, "the glue separated");
    assert!(one == ranked, "the histories differ");
}

/// Rigid bodies on the decomposed solver: a free sphere and a prescribed one pressed into a
/// block (each on its own node, its contacts gathered on every rank); the history of one
/// rank is the single process's, byte for byte (the bodies' columns, the contact forces on
/// them and the energy balance with the driver's work included).
#[test]
fn one_rank_runs_rigid_bodies_as_the_single_process() {
    let free = edit(
        &scene_text("rigid_sphere_on_block.toml"),
        "end_time = 0.62",
        "end_time = 0.08",
    );
    let prescribed = edit(
        &free,
        "name = \"ball\"",
        "name = \"ball\"\nmotion = \"prescribed\"",
    );
    for (tag, text) in [
        ("ranks_rigid_free", free),
        ("ranks_rigid_prescribed", prescribed),
    ] {
        let (one, ranked) = both_ways(tag, &text);
        let rows = one.lines().count();
        assert!(rows > 10, "{tag}: {rows} rows");
        let header = one.lines().next().unwrap_or_default();
        assert!(
            header.contains("ball.vz") && header.contains("hertz.fz"),
            "{header}"
        );
        assert!(one == ranked, "{tag}: the histories differ");
    }
}

/// The shipped spinning roller made free: its mass and inertia, its spin changed by the
/// friction on the block.
fn free_roller() -> String {
    edit(
        &scene_text("spinning_roller.toml"),
        "motion = \"prescribed\"",
        "mass = 0.02\ninertia = [[4e-4, 0.0, 0.0], [0.0, 4e-4, 0.0], [0.0, 0.0, 4e-4]]",
    )
}

/// Rotating rigid bodies on the decomposed solver: the shipped spinning roller (prescribed)
/// and the same roller free, whose spin the friction on the block slows. Every rank holds
/// the bodies' rotation and works the same sweeps, so the history of one rank is the single
/// process's byte for byte (the rotation columns, the forces and the energy balance with
/// the rotation's kinetic energy and the spinning driver's work); and a run stopped halfway
/// on a rank resumes on one process (and the other way) to the unbroken history.
#[test]
fn one_rank_runs_rotating_rigid_bodies_as_the_single_process() {
    let prescribed = scene_text("spinning_roller.toml");
    for (tag, text) in [
        ("ranks_roller_prescribed", prescribed),
        ("ranks_roller_free", free_roller()),
    ] {
        let (one, ranked) = both_ways(tag, &text);
        assert!(one.lines().count() > 10, "{tag}");
        let header = one.lines().next().unwrap_or_default();
        assert!(
            header.contains("roller.wy") && header.contains("roll.fx"),
            "{header}"
        );
        assert!(one == ranked, "{tag}: the histories differ");
    }
    let text = free_roller() + "\n[output]\ncheckpoint_every = 20\n";
    let half = edit(&text, "end_time = 0.05", "end_time = 0.025");
    run_as("roller_unbroken", &text, false, false);
    let unbroken = std::fs::read_to_string(out_path("roller_unbroken/history.csv")).unwrap();
    run_as("roller_process_first", &half, false, false);
    run_as("roller_rank_first", &half, true, false);
    run_as("roller_process_first", &text, true, true);
    run_as("roller_rank_first", &text, false, true);
    for tag in ["roller_process_first", "roller_rank_first"] {
        let h = std::fs::read_to_string(out_path(tag).join("history.csv")).unwrap();
        assert!(h == unbroken, "{tag}: the resumed history differs");
    }
}

/// Runs `text` in `tag`'s folder on one process or through the decomposed solver on one
/// rank (fresh unless `resume`), on the CPU; the run must complete.
fn run_as(tag: &str, text: &str, ranked: bool, resume: bool) {
    run_as_on(tag, text, (ranked, DeviceChoice::Cpu), resume);
}

/// [`run_as`] on `device`.
fn run_as_on(
    tag: &str,
    text: &str,
    (ranked, device): (bool, DeviceChoice),
    resume: bool,
) -> impact::output::Summary {
    let scene = Scene::parse(text, &repo().join("scenes/checkpoints.toml")).expect("valid");
    let opts = RunOptions {
        out: Some(if resume { out_path(tag) } else { out_dir(tag) }),
        quiet: true,
        resume,
        device: Some(device),
        ..Default::default()
    };
    let s = match ranked {
        true => run_ranks(&scene, &opts, &Single),
        false => run(&scene, &opts),
    };
    let s = s.unwrap_or_else(|e| panic!("{tag}: {e}"));
    assert_eq!(s.status, "completed", "{tag}");
    s
}

/// The frames a run's collection indexes, each checked to exist.
fn indexed_frames(tag: &str) -> Vec<String> {
    let dir = out_path(tag);
    let pvd = std::fs::read_to_string(dir.join("checkpoints.pvd")).expect("a collection");
    let names: Vec<String> = (pvd.split("file=\"").skip(1))
        .map(|s| s[..s.find('"').unwrap()].to_string())
        .collect();
    for n in &names {
        assert!(dir.join(n).exists(), "{tag}: {n} is indexed and missing");
    }
    names
}

/// A decomposed run's checkpoint is the single process's: stopped at half its end time, the
/// single process and the decomposed solver write the same state, bit for bit; and each
/// resumes the other's to the unbroken single-process history, byte for byte, its frame
/// collection indexing the frames both wrote.
#[test]
fn checkpoints_cross_between_one_process_and_the_decomposed_solver() {
    let text = explicit_at_default_step(&scene_text("cube_on_plate.toml"))
        + "\n[output]\ncheckpoint_every = 7\nvtu_every = 10\n";
    let half = edit(&text, "end_time = 0.1", "end_time = 0.05");
    run_as("ckpt_unbroken", &text, false, false);
    let unbroken = std::fs::read_to_string(out_path("ckpt_unbroken/history.csv")).unwrap();
    run_as("ckpt_process_first", &half, false, false);
    run_as("ckpt_rank_first", &half, true, false);
    let scene = Scene::parse(&text, &repo().join("scenes/checkpoints.toml")).unwrap();
    let read = |tag: &str| impact::checkpoint::Checkpoint::read(&out_path(tag), &scene).unwrap();
    let (a, b) = (read("ckpt_process_first"), read("ckpt_rank_first"));
    assert!(a.tally.steps > 10, "{} steps", a.tally.steps);
    assert_eq!(a.tally.steps, b.tally.steps);
    let bytes = |c: &impact::checkpoint::Checkpoint| bincode::serialize(&c.solver).unwrap();
    assert!(bytes(&a) == bytes(&b), "the states differ");
    let times =
        |c: &impact::checkpoint::Checkpoint| c.frames.iter().map(|f| f.0).collect::<Vec<_>>();
    assert_eq!(times(&a), times(&b), "the frames' times");
    run_as("ckpt_process_first", &text, true, true);
    run_as("ckpt_rank_first", &text, false, true);
    for tag in ["ckpt_process_first", "ckpt_rank_first"] {
        let h = std::fs::read_to_string(out_path(tag).join("history.csv")).unwrap();
        assert!(h == unbroken, "{tag}: the resumed history differs");
        assert_eq!(
            indexed_frames(tag).len(),
            indexed_frames("ckpt_unbroken").len()
        );
    }
    // one process wrote the first half's frames whole, the rank the second half's pieces
    let mixed = indexed_frames("ckpt_process_first");
    assert!(mixed.first().unwrap().ends_with(".vtu") && mixed.last().unwrap().ends_with(".pvtu"));
}

/// A rank on its GPU with its element forces there (a model with a rigid body, which the
/// resident step on ranks does not take) stopped at half its end time and resumed
/// continues to its unbroken history, byte for byte: the checkpoint holds the host's f64
/// state, from which the GPU takes u each step.
#[test]
fn a_rank_on_its_gpu_resumes_to_its_unbroken_history() {
    if skip_gpu("a gpu rank's resume") {
        return;
    }
    let text = with_idle_rigid_body(&explicit_at_default_step(&scene_text("cube_on_plate.toml")))
        + "\n[output]\ncheckpoint_every = 7\n";
    let half = edit(&text, "end_time = 0.1", "end_time = 0.05");
    let on_gpu = (true, DeviceChoice::Gpu);
    run_as_on("ckpt_gpu_unbroken", &text, on_gpu, false);
    run_as_on("ckpt_gpu_cut", &half, on_gpu, false);
    let s = run_as_on("ckpt_gpu_cut", &text, on_gpu, true);
    assert_eq!(s.engine, "gpu kernels, decomposed over mpi ranks");
    let read = |tag: &str| std::fs::read_to_string(out_path(tag).join("history.csv")).unwrap();
    assert!(
        read("ckpt_gpu_cut") == read("ckpt_gpu_unbroken"),
        "the histories differ"
    );
}

/// A single process's checkpoint on a GPU is the resident engine's device state: resumed
/// on ranks on the CPU it is refused, saying so (one process on that kind of adapter, or
/// ranks resident on their GPUs, resume it: `tests/mpi_ranks.rs`).
#[test]
fn a_resident_checkpoint_is_refused_on_cpu_ranks() {
    if skip_gpu("a resident checkpoint on ranks") {
        return;
    }
    let text = explicit_at_default_step(&scene_text("cube_on_plate.toml"))
        + "\n[output]\ncheckpoint_every = 7\n";
    let half = edit(&text, "end_time = 0.1", "end_time = 0.05");
    let s = run_as_on("ckpt_resident", &half, (false, DeviceChoice::Gpu), false);
    assert!(s.engine.contains("resident"), "{}", s.engine);
    let scene = Scene::parse(&text, &repo().join("scenes/checkpoints.toml")).unwrap();
    let opts = RunOptions {
        out: Some(out_path("ckpt_resident")),
        quiet: true,
        resume: true,
        device: Some(DeviceChoice::Cpu),
        ..Default::default()
    };
    let e = run_ranks(&scene, &opts, &Single).expect_err("refused on ranks");
    assert!(e.to_string().contains("resident engine"), "{e}");
    assert_eq!(e.exit_code(), 2, "a usage error");
}

/// A rank's contact clears, each step, only the entries its last constraints set. After a
/// restore it has none: the next step clears every entry, so that a checkpoint's contacts
/// that the step no longer holds are not reported again (here a step with no candidate).
#[test]
fn a_restored_contact_clears_every_entry_on_its_next_step() {
    use impact::integrate::explicit::{ContactFields, ExplicitContact};
    let text = scene_text("cube_on_plate.toml");
    let scene = Scene::parse(&text, &repo().join("scenes/restored.toml")).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    let mut contact = ExplicitContact::new(&model, &scene.explicit, 1.0, 1.0);
    let mut stale = contact.interfaces.clone();
    for st in &mut stale {
        st.impulse.fill(1.0);
        st.tangential.fill([1.0; 3]);
        st.gap.fill(-1.0);
    }
    assert!(stale.iter().any(|st| !st.impulse.is_empty()));
    contact.restore(stale);
    let n = model.dofs();
    let (u, v_half, inv_mass) = (vec![0.0; n], vec![0.0; n], vec![1.0; n]);
    let mut v = vec![0.0; n];
    let fields = ContactFields {
        spins: None,
        u: &u,
        v: &mut v,
        v_half: &v_half,
        inv_mass: &inv_mass,
        interval: 1e-6,
        planes: None,
    };
    let r = (contact.step_from_points(&model, fields, 1e-6, 1.0, Some(&[]))).unwrap();
    assert!(r.converged && r.iterations == 0);
    for st in &contact.interfaces {
        assert!(st.impulse.iter().all(|&j| j == 0.0), "a stale impulse");
        assert!(
            st.tangential.iter().all(|&t| t == [0.0; 3]),
            "a stale friction impulse"
        );
        assert!(st.gap.iter().all(|g| g.is_nan()), "a stale gap");
    }
}

/// One rank on its GPU (element forces in f32, the contact on the host in f64: a model with
/// a rigid body) through the decomposed solver, against the single process on the CPU: the
/// history within the bound of the GPU tests, every step converged.
#[test]
fn one_rank_on_its_gpu_follows_the_cpu() {
    if skip_gpu("one rank on its gpu") {
        return;
    }
    let tag = "ranks_gpu_cube_on_plate";
    let text = with_idle_rigid_body(&explicit_at_default_step(&scene_text("cube_on_plate.toml")));
    let scene = Scene::parse(&text, &repo().join("scenes").join(format!("{tag}.toml")))
        .expect("valid scene");
    let opts = |d: &str, device| RunOptions {
        out: Some(out_dir(&format!("{tag}_{d}"))),
        quiet: true,
        device: Some(device),
        ..Default::default()
    };
    let (cpu, gpu) = (
        opts("cpu", DeviceChoice::Cpu),
        opts("gpu", DeviceChoice::Gpu),
    );
    let c = run(&scene, &cpu).expect("cpu run completes");
    let g = run_ranks(&scene, &gpu, &Single).expect("one rank on its gpu completes");
    assert_eq!(c.status, "completed");
    assert_eq!(g.status, "completed");
    assert_eq!(g.engine, "gpu kernels, decomposed over mpi ranks");
    assert_ne!(g.device, "cpu", "the rank computes on its GPU");
    eprintln!(
        "device {}; sweeps cpu {}, gpu {}",
        g.device, c.iterations_total, g.iterations_total
    );
    let read = |o: &RunOptions| History::read(&o.out.as_ref().unwrap().join("history.csv"));
    compare_histories(&read(&cpu), &read(&gpu), 0.125, 1e-5);
}

/// One rank with its whole step on its GPU runs the single GPU's resident step: the same
/// engine, and the history byte for byte. A block dropped on a rigid plane (the plane its
/// only contact), the cube on the plate (the contact iteration on the surfaces) and a rigid
/// ball dropped on a block.
#[test]
fn one_rank_resident_on_its_gpu_is_the_single_gpu_byte_for_byte() {
    if skip_gpu("one rank resident on its gpu") {
        return;
    }
    let scenes = [
        ("block_drop", scene_text("block_hex_drop.toml")),
        (
            "cube_on_plate",
            explicit_at_default_step(&scene_text("cube_on_plate.toml")),
        ),
        ("rigid_ball", rigid_ball_on_block()),
    ];
    for (name, text) in scenes {
        let tag = format!("ranks_resident_{name}");
        let scene = Scene::parse(&text, &repo().join("scenes").join(format!("{tag}.toml")))
            .expect("valid scene");
        let opts = |d: &str| RunOptions {
            out: Some(out_dir(&format!("{tag}_{d}"))),
            quiet: true,
            device: Some(DeviceChoice::Gpu),
            ..Default::default()
        };
        let (one, ranked) = (opts("gpu"), opts("rank"));
        let s = run(&scene, &one).expect("single gpu run completes");
        let r = run_ranks(&scene, &ranked, &Single).expect("one resident rank completes");
        for x in [&s, &r] {
            assert_eq!(x.status, "completed", "{name}");
            assert_eq!(x.engine, "gpu resident", "{name}");
        }
        assert_eq!(r.ranks.as_ref().map(|d| d.ranks), Some(1));
        let read = |o: &RunOptions| {
            std::fs::read_to_string(o.out.as_ref().unwrap().join("history.csv")).expect("history")
        };
        let (a, b) = (read(&one), read(&ranked));
        assert!(a.lines().count() > 40, "{name}: {} rows", a.lines().count());
        assert_eq!(
            a, b,
            "{name}: the history of one resident rank is the single gpu's"
        );
    }
}
