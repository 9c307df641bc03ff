//! A run tells the truth: model checks before it starts, honest outcomes when it ends, and a
//! checkpoint to continue it from. Each test quotes the input it guards against.

mod common;
use common::*;
use impact::run::{run, RunOptions};
use impact::scene::Scene;
use std::path::{Path, PathBuf};

fn two_bars() -> String {
    scene_text("two_bars.toml")
}

/// The two bars on the explicit path with the stable step.
fn two_bars_explicit() -> String {
    edit(
        &two_bars(),
        "method = \"implicit\"",
        "method = \"explicit\"",
    )
    .replace("time_step = 0.01\n", "")
}

fn parse(text: &str, tag: &str) -> Scene {
    Scene::parse(text, &repo().join("scenes").join(format!("{tag}.toml"))).expect("parses")
}

fn opts(tag: &str) -> RunOptions {
    RunOptions {
        out: Some(out_dir(tag)),
        quiet: true,
        ..Default::default()
    }
}

/// The error of running `text`, which must be refused; every part must be in its message.
fn refused(tag: &str, text: &str, parts: &[&str]) -> String {
    let msg = run(&parse(text, tag), &opts(tag))
        .expect_err("must be refused")
        .to_string();
    for p in parts {
        assert!(msg.contains(p), "{msg:?} should contain {p:?}");
    }
    msg
}

#[test]
fn a_fix_that_holds_no_node_is_refused() {
    let text = two_bars()
        + "\n[[fix]]\nbody = \"A\"\nregion = { min = [50.0, 0.0, 0.0], max = [60.0, 1.0, 1.0] }\ncomponents = [\"x\"]\n";
    refused(
        "fix_empty",
        &text,
        &["fix[0]", "holds no node of body `A`", "region.min"],
    );
}

#[test]
fn duplicate_probe_names_are_refused() {
    let text = edit(&two_bars(), "name = \"endB\"", "name = \"tipA\"");
    let e = Scene::parse(&text, Path::new("dup.toml")).expect_err("refused");
    assert!(e.to_string().contains("probe[1].name"), "{e}");
}

/// Bar B moved 2 units into bar A: "a 2-unit overlap gives no force".
fn overlapping(depth: f64, policy: Option<&str>) -> String {
    let text = edit(
        &two_bars_explicit(),
        "box = { min = [0.0, 0.0, 0.0], max = [10.0",
        &format!(
            "box = {{ min = [{}, 0.0, 0.0], max = [{}",
            -depth,
            10.0 - depth
        ),
    );
    match policy {
        Some(p) => edit(
            &text,
            "friction = 0.0\n",
            &format!("friction = 0.0\ninitial_penetration = \"{p}\"\n"),
        ),
        None => text,
    }
}

#[test]
fn an_initial_overlap_is_refused_with_its_count_and_depth() {
    refused(
        "overlap_refused",
        &overlapping(2.0, None),
        &[
            "contact[0] (contact `impact`).initial_penetration",
            "4 secondary nodes",
            "by 2.0000e0",
            "\"adjust\"",
        ],
    );
}

#[test]
fn adjust_moves_the_nodes_onto_the_surface_and_adds_no_energy() {
    // "a 0.05 overlap explicit gains energy 0.050 -> 0.123"
    let tag = "overlap_adjusted";
    let s = run(&parse(&overlapping(0.05, Some("adjust")), tag), &opts(tag)).expect("runs");
    assert_eq!(s.status, "completed", "{:?}", s.warnings);
    let r = &s.initial_contact[0];
    assert_eq!((r.penetrating, r.moved), (4, 4));
    assert!((r.depth - 0.05).abs() < 1e-12, "{}", r.depth);
    assert!(
        s.energy_max <= s.energy_initial * (1.0 + 1e-3),
        "energy {} -> max {}",
        s.energy_initial,
        s.energy_max
    );
}

#[test]
fn ignore_runs_as_given_and_ends_with_a_warning() {
    let tag = "overlap_ignored";
    let s = run(&parse(&overlapping(0.05, Some("ignore")), tag), &opts(tag)).expect("runs");
    assert_eq!(s.status, "completed_with_warnings");
    assert!(
        s.warnings.iter().any(|w| w.kind == "initial_penetration"),
        "{:?}",
        s.warnings
    );
}

#[test]
fn surfaces_that_face_the_same_way_are_refused() {
    let text = edit(
        &two_bars(),
        "primary = { body = \"B\", face = \"x-\" }",
        "primary = { body = \"B\", face = \"x+\" }",
    );
    refused("facing", &text, &["contact[0]", "face the same way"]);
}

/// block_hex_drop.toml with its deck edited by `change` (written beside a copy of the scene).
fn edited_deck(tag: &str, change: impl Fn(&str) -> String) -> PathBuf {
    let dir = out_dir(tag);
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    let deck = std::fs::read_to_string(repo().join("scenes/meshes/block_hex.inp")).unwrap();
    std::fs::write(dir.join("meshes/block_hex.inp"), change(&deck)).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, scene_text("block_hex_drop.toml")).unwrap();
    scene
}

#[test]
fn two_swapped_node_tags_fold_an_element_and_are_refused() {
    // "a mesh with two node tags swapped (stable step 1.2e-9, the run never ends)"
    let msg = deck_error("swapped_tags", |d| {
        edit(
            &edit(
                d,
                "\n1, -0.500000, -0.500000, 0.000000",
                "\n1, -0.250000, -0.500000, 0.000000",
            ),
            "\n3, -0.250000, -0.500000, 0.000000",
            "\n3, -0.500000, -0.500000, 0.000000",
        )
    });
    for p in [
        "body[0] (body `block`)",
        "hex8 element 0",
        "Jacobian determinant",
    ] {
        assert!(msg.contains(p), "{msg:?} should contain {p:?}");
    }
}

#[test]
fn a_body_moved_where_f64_cannot_resolve_it_is_refused() {
    // "translate = [0, 0, -9.2e18]": the nodes collapse onto each other in f64
    let text = edit(
        &scene_text("block_hex_drop.toml"),
        "translate = [0.0, 0.0, 0.01]",
        "translate = [0.0, 0.0, -9.2e18]",
    );
    refused("far_away", &text, &["body[0]", "hex8 element"]);
}

#[test]
fn a_tiny_density_or_a_huge_modulus_is_refused() {
    for (from, to) in [
        ("density = 0.01", "density = 1e-320"),
        ("youngs_modulus = 100.0", "youngs_modulus = 1e308"),
    ] {
        let e = Scene::parse(&edit(&two_bars(), from, to), Path::new("m.toml")).expect_err(to);
        let msg = e.to_string();
        assert!(msg.contains("wave speed"), "{msg}");
    }
}

#[test]
fn an_explicit_end_time_shorter_than_one_step_is_refused() {
    // "end_time = 1e-320" and "end_time = 1e-3 with a step of 9e-3"
    for end in ["1e-320", "1e-3"] {
        let text = edit(
            &two_bars_explicit(),
            "end_time = 0.4",
            &format!("end_time = {end}"),
        );
        refused(
            "short_end",
            &text,
            &["run.end_time", "shorter than one time step"],
        );
    }
}

#[test]
fn explicit_runs_end_exactly_at_end_time() {
    // the stable step (0.9 of 0.01) does not divide 0.4: the last step is shortened
    let tag = "exact_end";
    let s = run(&parse(&two_bars_explicit(), tag), &opts(tag)).expect("runs");
    let h = History::read(&out_path(tag).join("history.csv"));
    assert_eq!(h.last("time"), 0.4);
    assert_eq!(s.end_time, 0.4);
    assert_eq!(s.steps, 45, "ceil(0.4 / 0.009)");
    let t = h.col("time");
    assert!(
        (t[44] - 44.0 * s.time_step).abs() < 1e-15,
        "whole steps before the last"
    );
    // the bars have parted: central difference conserves the time-centred energy exactly,
    // and the shortened step's measure shift is taken off (to rounding)
    let e = h.col("total_energy");
    let (before, last) = (e[44], e[45]);
    assert!(
        (last - before).abs() <= 1e-12 * before,
        "total energy {before} -> {last} over the shortened step"
    );
}

#[test]
fn unconverged_implicit_steps_end_the_run_with_a_warning() {
    // "6 of 20 steps unconverged: completed, exit 0"; Anderson's iteration, since the
    // Newton step solves the bars' contact in two iterations
    let text = edit(
        &two_bars(),
        "penalty = \"adaptive\"",
        "penalty = \"adaptive\"\nmax_iterations = 2\nacceleration = \"anderson\"",
    );
    let tag = "unconverged";
    let s = run(&parse(&text, tag), &opts(tag)).expect("runs");
    assert_eq!(s.status, "completed_with_warnings");
    let w = s
        .warnings
        .iter()
        .find(|w| w.kind == "unconverged_steps")
        .expect("warned");
    assert!(
        w.message.contains("implicit.max_iterations = 2"),
        "{}",
        w.message
    );
    assert!(s.unconverged_steps > 0);
}

#[test]
fn a_penalty_too_large_to_hold_contact_ends_with_a_deep_penetration_warning() {
    // "a fixed penalty of 1e300 (zero force while penetration grows to 0.4)": the paper's
    // update with Anderson's acceleration (the Newton step does not depend on the penalty)
    let text = edit(
        &two_bars(),
        "penalty = \"adaptive\"",
        "penalty = \"fixed\"\npenalty_normal = 1e300\nacceleration = \"anderson\"",
    );
    let tag = "huge_penalty";
    let s = run(&parse(&text, tag), &opts(tag)).expect("runs");
    assert_eq!(s.status, "completed_with_warnings");
    assert!(
        s.warnings.iter().any(|w| w.kind == "deep_penetration"),
        "{:?}",
        s.warnings
    );
}

#[test]
fn the_shipped_scenes_complete_without_warnings() {
    for name in [
        "two_bars",
        "two_bars_fine",
        "bar_on_wall",
        "cube_on_plate",
        "block_hex_drop",
        "block_tet_drop",
    ] {
        let tag = format!("shipped_{name}");
        let mut o = opts(&tag);
        o.device = Some(impact::scene::DeviceChoice::Cpu);
        let s = run(
            &Scene::load(repo().join("scenes").join(format!("{name}.toml"))).unwrap(),
            &o,
        )
        .expect("runs");
        assert_eq!(s.status, "completed", "{name}: {:?}", s.warnings);
        assert!(s.warnings.is_empty());
    }
}

#[test]
fn a_folder_with_an_earlier_run_is_refused_without_overwrite() {
    let tag = "earlier_run";
    let scene = parse(&two_bars(), tag);
    run(&scene, &opts(tag)).expect("first run");
    let again = RunOptions {
        out: Some(out_path(tag)),
        quiet: true,
        ..Default::default()
    };
    let msg = run(&scene, &again).expect_err("refused").to_string();
    assert!(
        msg.contains("--overwrite") && msg.contains("summary.json"),
        "{msg}"
    );
    let overwrite = RunOptions {
        overwrite: true,
        ..again
    };
    assert_eq!(
        run(&scene, &overwrite).expect("overwrites").status,
        "completed"
    );
}

#[test]
fn the_last_step_always_gets_a_vtu_frame() {
    let text = two_bars() + "\n[output]\nvtu_every = 7\n";
    let tag = "last_frame";
    run(&parse(&text, tag), &opts(tag)).expect("runs");
    let dir = out_path(tag);
    for step in [0, 7, 35, 40] {
        assert!(
            dir.join(format!("{tag}_{step:06}.vtu")).exists(),
            "frame {step}"
        );
    }
    let pvd = std::fs::read_to_string(dir.join(format!("{tag}.pvd"))).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 7, "0, 7, ..., 35 and 40");
}

/// Runs `text` in `tag`'s folder (fresh unless `resume`), returning the summary.
fn run_in(tag: &str, text: &str, resume: bool) -> impact::Result<impact::output::Summary> {
    run_resumable(tag, "resumed", text, (resume, None))
}

#[test]
fn a_run_stopped_at_half_its_end_time_and_resumed_equals_the_unbroken_run() {
    // implicit (whole steps) and explicit (the half run's last step is shortened: its
    // checkpoint stays on the whole steps)
    for (name, text, half) in [
        ("implicit", two_bars(), "end_time = 0.2"),
        ("explicit", two_bars_explicit(), "end_time = 0.2"),
    ] {
        let text = text + "\n[output]\ncheckpoint_every = 7\nvtu_every = 10\n";
        let full = format!("resume_full_{name}");
        let part = format!("resume_part_{name}");
        let s = run_in(&full, &text, false).expect("unbroken");
        run_in(&part, &edit(&text, "end_time = 0.4", half), false).expect("half");
        let r = run_in(&part, &text, true).expect("resumed");
        assert_eq!(
            history_text(&full),
            history_text(&part),
            "{name}: histories"
        );
        assert_eq!(
            (r.steps, r.energy_final.to_bits()),
            (s.steps, s.energy_final.to_bits())
        );
        assert_eq!(r.status, "completed");
        let pvd = std::fs::read_to_string(out_path(&part).join("resumed.pvd")).unwrap();
        let frames = pvd.matches("<DataSet").count();
        assert_eq!(
            frames,
            s.steps / 10 + 1 + usize::from(s.steps % 10 != 0),
            "{name}: {pvd}"
        );
    }
}

#[test]
fn a_checkpoint_is_refused_by_another_scene_and_when_nothing_is_left() {
    let text = two_bars() + "\n[output]\ncheckpoint_every = 10\n";
    let tag = "resume_refused";
    run_in(tag, &text, false).expect("first run");
    let other = edit(&text, "density = 0.01", "density = 0.02");
    let msg = run_in(tag, &other, true)
        .expect_err("another scene")
        .to_string();
    assert!(
        msg.contains("cannot resume") && msg.contains("another scene"),
        "{msg}"
    );
    let before = history_text(tag);
    let msg = run_in(tag, &text, true).expect_err("finished").to_string();
    assert!(msg.contains("nothing is left to run"), "{msg}");
    assert_eq!(
        history_text(tag),
        before,
        "a refused resume leaves the history alone"
    );
}

#[test]
fn overwrite_removes_the_earlier_runs_checkpoint() {
    let tag = "overwrite_checkpoint";
    run_in(
        tag,
        &(two_bars() + "\n[output]\ncheckpoint_every = 10\n"),
        false,
    )
    .expect("first");
    assert!(out_path(tag).join("checkpoint.bin").exists());
    let o = RunOptions {
        out: Some(out_path(tag)),
        quiet: true,
        overwrite: true,
        ..Default::default()
    };
    run(&parse(&two_bars(), tag), &o).expect("overwrites");
    assert!(!out_path(tag).join("checkpoint.bin").exists());
}

#[test]
fn the_scene_hash_knows_a_mesh_by_its_contents_not_its_path() {
    let shipped = Scene::load(repo().join("scenes/block_hex_drop.toml")).unwrap();
    let copy = edited_deck("hash_copy", |d| d.to_string());
    let moved = Scene::load(&copy).unwrap();
    let hash = impact::checkpoint::scene_hash;
    assert_eq!(hash(&shipped), hash(&moved));
    let changed = Scene::load(edited_deck("hash_changed", |d| {
        edit(
            d,
            "\n2, -0.375000, -0.500000, 0.000000",
            "\n2, -0.370000, -0.500000, 0.000000",
        )
    }))
    .unwrap();
    assert_ne!(hash(&shipped), hash(&changed));
}

#[test]
fn the_large_shipped_scene_starts_touching_and_not_penetrating() {
    // the block rests on the plate: its bottom nodes lie on plate faces, edges and corners
    // (to rounding), all within reach, none behind the surface
    let scene = Scene::load(repo().join("scenes/block_on_plate_large.toml")).unwrap();
    let setup = impact::setup::prepare(
        &scene,
        impact::scene::DeviceChoice::Cpu,
        &mut |_| {},
        &mut impact::output::summary::SetupClock::start(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let r = &setup.initial[0];
    assert_eq!((r.nodes_in_reach, r.penetrating), (61 * 61, 0));
    assert_eq!((r.gap_min, r.gap_max), (Some(0.0), Some(0.0)));
}

/// The error of preparing block_hex_drop.toml with its deck edited by `change`.
fn deck_error(tag: &str, change: impl Fn(&str) -> String) -> String {
    let path = edited_deck(tag, change);
    let scene = Scene::load(&path).expect("the deck parses");
    impact::setup::prepare(
        &scene,
        impact::scene::DeviceChoice::Cpu,
        &mut |_| {},
        &mut impact::output::summary::SetupClock::start(),
    )
    .err()
    .expect("refused")
    .to_string()
}

#[test]
fn a_c3d8_with_a_concave_corner_is_refused() {
    // "a C3D8 with a concave corner runs 0 steps explicit": node 1 pushed up into its element
    // (height 0.125) folds the element at that corner
    let msg = deck_error("concave", |d| {
        edit(
            d,
            "\n1, -0.500000, -0.500000, 0.000000",
            "\n1, -0.400000, -0.400000, 0.200000",
        )
    });
    for p in [
        "body[0]",
        "hex8 element 0",
        "Jacobian determinant at corner",
    ] {
        assert!(msg.contains(p), "{msg:?} should contain {p:?}");
    }
}

#[test]
fn a_c3d8_with_a_repeated_node_is_refused() {
    // "hex8 elements with a repeated node": element 1's last corner is its fourth
    let msg = deck_error("repeated_node", |d| {
        edit(
            d,
            "1, 1, 2, 11, 10,\n    82, 83, 92, 91",
            "1, 1, 2, 11, 10,\n    82, 83, 92, 10",
        )
    });
    assert!(
        msg.contains("hex8 element 0") && msg.contains("repeats node 9"),
        "{msg}"
    );
}

/// Four separate tet4 in one body, the last flattened to a height of 1e-4 (as two swapped
/// node coordinates leave one): its stable step is about 1e-4 of the others', so it would
/// set the explicit step of the whole model. The run warns, naming the element, its body and
/// its aspect, and ends `completed_with_warnings`.
#[test]
fn a_sliver_that_sets_the_step_is_a_warning() {
    let dir = out_dir("sliver");
    std::fs::create_dir_all(&dir).unwrap();
    let mut deck = String::from("*NODE\n");
    for k in 0..4 {
        let x = 3.0 * k as f64;
        let top = if k == 3 { 1e-4 } else { 1.0 };
        for (i, p) in [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.3, 0.3, top],
        ]
        .iter()
        .enumerate()
        {
            deck += &format!("{}, {}, {}, {}\n", 4 * k + i + 1, x + p[0], p[1], p[2]);
        }
    }
    deck += "*ELEMENT, TYPE=C3D4, ELSET=ALL\n";
    for k in 0..4 {
        let n = 4 * k + 1;
        deck += &format!("{}, {}, {}, {}, {}\n", k + 1, n, n + 1, n + 2, n + 3);
    }
    std::fs::write(dir.join("tets.inp"), deck).unwrap();
    let text = format!(
        "[run]\nend_time = 1e-4\nmethod = \"explicit\"\n\n\
         [[material]]\nname = \"elastic\"\ndensity = 0.01\nyoungs_modulus = 100.0\npoissons_ratio = 0.3\n\n\
         [[body]]\nname = \"tets\"\nmaterial = \"elastic\"\nmesh = \"{}\"\n",
        dir.join("tets.inp").display()
    );
    let scene = Scene::parse(&text, &dir.join("sliver.toml")).expect("parses");
    let s = run(&scene, &opts("sliver_run")).expect("runs");
    assert_eq!(s.status, "completed_with_warnings");
    let w = s
        .warnings
        .iter()
        .find(|w| w.kind == "element_quality")
        .expect("a quality warning");
    assert!(
        w.message.contains("body `tets`: 1 element(s)") && w.message.contains("element 3 "),
        "{}",
        w.message
    );
    println!("{}", w.message);
}

/// `poissons_ratio = 0.4999999` runs, but warns of volumetric locking.
#[test]
fn a_nearly_incompressible_hex8_warns_of_locking() {
    let text = edit(
        &two_bars(),
        "poissons_ratio = 0.0",
        "poissons_ratio = 0.4999999",
    );
    let s = run(&parse(&text, "locking"), &opts("locking")).expect("runs");
    assert_eq!(s.status, "completed_with_warnings");
    let w = s.warnings.iter().find(|w| w.kind == "volumetric_locking");
    assert!(
        w.is_some_and(|w| w.message.contains("`elastic`") && w.message.contains("0.49")),
        "{:?}",
        s.warnings
    );
}

/// "A probe far outside every body silently takes the nearest node": refused, naming the
/// probe, the node it would take and the body's size.
#[test]
fn a_probe_far_outside_its_body_is_refused() {
    let text = edit(
        &two_bars(),
        "point = [0.0, 0.5, 0.5]",
        "point = [0.0, 0.5, 50.0]",
    );
    refused(
        "probe_far",
        &text,
        &["probe[0].point", "probe `tipA`", "body `A`"],
    );
}

/// A probe at the centre of a face of a coarse body (a unit cube of 3 x 3 x 3) is 0.24 from
/// its nearest node, more than 0.1 of the body's size but within one element: accepted.
#[test]
fn a_probe_inside_a_coarse_element_is_accepted() {
    let text = edit(
        &scene_text("bar_on_wall.toml"),
        "box = { min = [-10.0, 0.0, 0.0], max = [0.0, 1.0, 1.0], divisions = [10, 1, 1] }",
        "box = { min = [-1.0, 0.0, 0.0], max = [0.0, 1.0, 1.0], divisions = [3, 3, 3] }",
    );
    let text = edit(&text, "end_time = 0.4", "end_time = 0.02");
    let s = run(&parse(&text, "probe_coarse"), &opts("probe_coarse")).expect("runs");
    assert!(s.status.starts_with("completed"), "{}", s.status);
}

/// A rigid ball of radius 0.1 started at the centre of a 3 x 3 x 3 block: no node of the
/// block's top is behind the ball's surface, but the ball is inside the block.
fn ball_in_block(centre: [f64; 3], policy: &str) -> String {
    format!(
        r#"[run]
end_time = 0.05
method = "explicit"

[[material]]
name = "m"
density = 1.0
youngs_modulus = 100.0
poissons_ratio = 0.3

[[body]]
name = "block"
material = "m"
box = {{ min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], divisions = [3, 3, 3] }}

[[rigid_body]]
name = "ball"
mass = 1.0
position = {centre:?}
velocity = [0.0, 0.0, -1.0]
shape = {{ sphere = {{ radius = 0.1 }} }}

[[contact]]
name = "strike"
secondary = {{ body = "block", face = "z+" }}
primary = {{ rigid_body = "ball" }}
initial_penetration = "{policy}"
"#
    )
}

#[test]
fn a_rigid_ball_started_inside_a_block_is_seen() {
    for policy in ["error", "adjust"] {
        refused(
            "ball_inside",
            &ball_in_block([0.5, 0.5, 0.5], policy),
            &[
                "contact[0] (contact `strike`).initial_penetration",
                "the primary surface lies inside the secondary body",
                "[0.5, 0.5, 0.5]",
            ],
        );
    }
    let tag = "ball_inside_ignored";
    let text = ball_in_block([0.5, 0.5, 0.5], "ignore");
    let s = run(&parse(&text, tag), &opts(tag)).expect("runs as given");
    assert_eq!(s.status, "completed_with_warnings");
    assert_eq!(s.initial_contact[0].primary_inside, 1);
    // above the block, and touching its top, it is not inside
    for z in [1.2, 1.1] {
        let tag = "ball_above";
        let s = run(
            &parse(&ball_in_block([0.5, 0.5, z], "error"), tag),
            &opts(tag),
        )
        .expect("runs");
        assert_eq!(s.initial_contact[0].primary_inside, 0);
    }
}

/// A rigid ball fast enough to cross the block between two steps ends the run with a
/// `fast_contact` warning, explicit (v = 100 against the block's stable step) and implicit
/// (v = 1,000 at dt = 1e-3); at v = 1 it does not.
#[test]
fn a_rigid_ball_that_can_cross_a_block_between_steps_is_a_warning() {
    let ball = |speed: f64, implicit: bool| {
        let mut text = ball_in_block([0.5, 0.5, 1.2], "error").replace(
            "velocity = [0.0, 0.0, -1.0]",
            &format!("velocity = [0.0, 0.0, {}]", -speed),
        );
        if implicit {
            text = text.replace(
                "method = \"explicit\"",
                "method = \"implicit\"\ntime_step = 1e-3\n",
            );
        }
        text
    };
    for (tag, speed, implicit, fast) in [
        ("fast_ball_explicit", 100.0, false, true),
        ("fast_ball_implicit", 1000.0, true, true),
        ("slow_ball_implicit", 1.0, true, false),
    ] {
        let s = run(&parse(&ball(speed, implicit), tag), &opts(tag)).expect("runs");
        let warned = s.warnings.iter().any(|w| w.kind == "fast_contact");
        assert_eq!(warned, fast, "{tag}: {:?}", s.warnings);
        if fast {
            assert_eq!(s.status, "completed_with_warnings", "{tag}");
        }
    }
}

/// A material whose modulus overflows the matrices (E = 1e300), or whose density leaves
/// them no mass (1e-300), stops the run before its first step with the likely cause named
/// and a `failed` summary saying it.
#[test]
fn an_unfactorisable_model_names_its_likely_cause_in_a_failed_summary() {
    for (tag, from, to) in [
        (
            "stiff_e300",
            "youngs_modulus = 100.0",
            "youngs_modulus = 1e300",
        ),
        ("light_d300", "density = 0.01", "density = 1e-300"),
    ] {
        let text = edit(&scene_text("two_bars.toml"), from, to);
        let o = opts(tag);
        let e = run(&parse(&text, tag), &o).expect_err(tag).to_string();
        assert!(
            e.contains("likely cause: material[0] (material `elastic`)"),
            "{e}"
        );
        assert!(e.contains(&format!("{tag}.toml")), "names the scene: {e}");
        let dir = o.out.expect("a folder");
        let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        let json: serde_json::Value = serde_json::from_str(&summary).unwrap();
        assert_eq!(json["status"], "failed");
        assert!(json["message"].as_str().unwrap().contains("likely cause"));
    }
}
