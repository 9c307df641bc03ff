//! Results do not depend on the number of threads: the same scene on 1, 2 and 4 threads
//! writes the same history, bit for bit.

mod common;
use common::*;
use impact::run::{run, RunOptions};
use impact::scene::{DeviceChoice, Scene};

/// The history text of `text` run on the CPU with `threads` threads.
fn history_on(tag: &str, text: &str, threads: usize) -> String {
    let tag = format!("{tag}_{threads}_threads");
    let scene = Scene::parse(text, &repo().join("scenes").join("threads.toml")).expect("parses");
    let opts = RunOptions {
        out: Some(out_dir(&tag)),
        device: Some(DeviceChoice::Cpu),
        quiet: true,
        ..Default::default()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    let s = pool.install(|| run(&scene, &opts)).expect("runs");
    assert_eq!(s.status, "completed", "{:?}", s.warnings);
    std::fs::read_to_string(out_path(&tag).join("history.csv")).unwrap()
}

fn same_on_any_thread_count(tag: &str, text: &str) {
    let one = history_on(tag, text, 1);
    for threads in [2, 4] {
        assert!(
            one == history_on(tag, text, threads),
            "{tag}: the history on {threads} threads differs from one thread's"
        );
    }
}

/// The paper's cube on the plate (oblique impact, mu = 0.3) meshed finer: 7,168 elements
/// and 9,225 nodes, so that the element loops, node loops and sums split across threads
/// (pieces of [`impact::parallel::CHUNK`] nodes), for `end_time`.
fn fine_cube(end_time: &str) -> String {
    let text = edit(
        &edit(
            &scene_text("cube_on_plate.toml"),
            "divisions = [4, 4, 4]",
            "divisions = [8, 8, 8]",
        ),
        "divisions = [16, 4, 4]",
        "divisions = [32, 8, 8]",
    );
    edit(&text, "end_time = 0.1", &format!("end_time = {end_time}"))
}

#[test]
fn explicit_contact_with_friction_is_the_same_on_any_thread_count() {
    let text = edit(
        &fine_cube("0.02"),
        "time_step = 0.002",
        "method = \"explicit\"",
    );
    const { assert!(9225 > 2 * impact::parallel::CHUNK) };
    same_on_any_thread_count("explicit_cube", &text);
}

#[test]
fn explicit_tet_block_on_a_plane_is_the_same_on_any_thread_count() {
    same_on_any_thread_count("explicit_tets", &scene_text("block_tet_drop.toml"));
}

#[test]
fn implicit_contact_with_friction_is_the_same_on_any_thread_count() {
    same_on_any_thread_count("implicit_cube", &fine_cube("0.006"));
}

/// The drop-weight coupon on a coarse mesh (1,200 layered hex8i, 1,302 surface nodes against
/// five rigid bodies, the per-step failure survey), its first 400 steps.
#[test]
fn rigid_bodies_and_layered_plies_are_the_same_on_any_thread_count() {
    let text = edit(
        &scene_text("drop_weight_d7136_elastic.toml"),
        "divisions = [50, 34, 4]",
        "divisions = [30, 20, 2]",
    );
    let text = edit(&text, "end_time = 4.5e-3", "end_time = 2.2e-4");
    let text = edit(&text, "vtu_every = 500", "vtu_every = 1000000");
    same_on_any_thread_count("drop_weight", &text);
}

/// A rotating rigid body (the spinning roller driving a block by friction) on a block fine
/// enough that its 625 contact nodes split across threads.
#[test]
fn a_spinning_rigid_body_is_the_same_on_any_thread_count() {
    let text = edit(
        &edit(
            &scene_text("spinning_roller.toml"),
            "divisions = [8, 8, 4]",
            "divisions = [24, 24, 4]",
        ),
        "end_time = 0.05",
        "end_time = 0.01",
    );
    same_on_any_thread_count("spinning_roller", &text);
}

/// The implicit block drop iterating on its contact space with the Newton step: the
/// flexibility's block solves, W's dense solve and the recovery's solve are the same on any
/// thread count.
#[test]
fn implicit_newton_on_the_contact_space_is_the_same_on_any_thread_count() {
    let text = implicit_block_drop([10; 3], 12, "");
    same_on_any_thread_count("implicit_block_space", &text);
}

/// A flat plate dropped on a floor, whose contact space is declined: the iterations move
/// the contact nodes by the flexibility's columns kept at their equations, and the
/// recovery solves once a step; the same on any thread count.
#[test]
fn implicit_newton_moves_without_a_contact_space_are_the_same_on_any_thread_count() {
    let text = implicit_block_drop([8, 8, 2], 12, "");
    same_on_any_thread_count("implicit_plate_moves", &text);
}

/// Ply damage: a plate of hex8i refined at its centre (14 x 14 x 2, more than a thread's share)
/// pulled across its fibres until its plies crack, some elements first (its nodes a little
/// off the grid, so that the damage starts unevenly).
#[test]
fn ply_damage_is_the_same_on_any_thread_count() {
    let text = r#"
[run]
method = "explicit"
end_time = 3.5e-5

[[material]]
name = "im7"
density = 1.57e-9
transversely_isotropic = { e1 = 171420.0, e2 = 9080.0, nu12 = 0.32, nu23 = 0.52, g12 = 5290.0 }
strength = { xt = 2326.2, xc = 1200.1, yt = 62.3, yc = 199.8, s12 = 92.3, s23 = 75.3 }
fracture_energy = { ft = 133.3, fc = 47.5, mt = 0.277, mc = 0.788 }

[[body]]
name = "plate"
material = "im7"
box = { min = [0.0, 0.0, 0.0], max = [4.0, 4.0, 1.0], divisions = [12, 12, 2], element = "hex8i", refine = { min = [1.5, 1.5, 0.0], max = [2.5, 2.5, 1.0], size = [0.25, 0.25, 1.0] } }

[[fix]]
body = "plate"
face = "y-"
components = ["y"]

[[fix]]
body = "plate"
region = { min = [0.0, 0.0, 0.0], max = [0.0, 0.0, 1.0] }
components = ["x", "z"]

[[fix]]
name = "pull"
body = "plate"
face = "y+"
components = ["y"]
velocity = [0.0, 1200.0, 0.0]
"#;
    let h = history_on("ply_damage", text, 1);
    let last = h.lines().last().unwrap();
    let damage: f64 = last.split(',').rev().nth(3).unwrap().parse().unwrap();
    assert!(damage > 0.0, "the plate damaged: {last}");
    same_on_any_thread_count("ply_damage", text);
}
