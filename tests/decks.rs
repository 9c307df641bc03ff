//! Abaqus/CalculiX decks run as they stand (`impact run model.inp`): the shipped two bars
//! against wave theory and their TOML twin, a block sliding on a supported plate (supports,
//! friction, gravity, the explicit step) against its twin, `impact convert`'s scene against
//! the deck, and what a deck asks that impact cannot honour, refused by keyword and line.

mod common;
use common::*;

use impact::run::{run, RunOptions};
use impact::scene::{DeviceChoice, Scene};
use std::path::{Path, PathBuf};

/// Runs the scene (or deck) at `path` on the CPU into `tag`'s folder.
fn run_file(tag: &str, path: &Path) -> (impact::output::Summary, History) {
    let scene = Scene::load(path).unwrap_or_else(|e| panic!("{tag}: {e}"));
    let out = out_dir(tag);
    let opts = RunOptions {
        out: Some(out.clone()),
        quiet: true,
        device: Some(DeviceChoice::Cpu),
        ..Default::default()
    };
    let s = run(&scene, &opts).unwrap_or_else(|e| panic!("{tag}: {e}"));
    assert_eq!(s.status, "completed", "{tag}");
    (s, History::read(&out.join("history.csv")))
}

/// `text` written as `name` in the output folder of `tag` (made anew); its path.
fn written(tag: &str, name: &str, text: &str) -> PathBuf {
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The largest difference of `a`'s column `ca` from `b`'s `cb`, relative to `b`'s largest
/// magnitude in it (absolute where that is below `floor`).
fn difference(a: &History, ca: &str, b: &History, cb: &str, floor: f64) -> f64 {
    let (x, y) = (a.col(ca), b.col(cb));
    assert_eq!(x.len(), y.len(), "{ca}: rows");
    let scale = y.iter().fold(floor, |m, v| m.max(v.abs()));
    x.iter()
        .zip(&y)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max)
        / scale
}

#[test]
fn the_two_bars_deck_runs_as_it_stands_and_matches_wave_theory_and_its_scene() {
    let deck = repo().join("scenes/two_bars.inp");
    let scene = Scene::load(&deck).expect("the deck reads");
    let notice = scene.notices.join("\n");
    for passed in [
        "*SURFACE BEHAVIOR (line 133)",
        "*CONTACT PRINT (line 146)",
        "penalty",
    ] {
        assert!(notice.contains(passed), "{passed} in: {notice}");
    }
    assert!(!notice.contains("keywords not read"), "{notice}");
    let (s, h) = run_file("deck_two_bars", &deck);
    let m = measures(&h, "TIPA-ENDB", TWO_BARS_FORCE, 0.01);
    eprintln!(
        "deck: plateau mean {:.5}, release {}, impulse {:.5}",
        m.plateau_mean, m.last_contact, m.impulse
    );
    // the paper's coarse-mesh tolerances (tests/two_bars.rs)
    assert!((m.plateau_mean - TWO_BARS_FORCE).abs() <= 0.02 * TWO_BARS_FORCE);
    assert!(
        (m.last_contact - 0.2).abs() <= 0.02 + 1e-9,
        "release at {}",
        m.last_contact
    );
    assert!(
        (m.impulse - 0.1).abs() <= 0.03 * 0.1,
        "impulse {}",
        m.impulse
    );
    assert_eq!(s.unconverged_steps, 0);
    // the TOML twin: the same model with box meshes numbered otherwise
    let (_, twin) = run_file("deck_two_bars_twin", &repo().join("scenes/two_bars.toml"));
    for (a, b) in [
        ("TIPA-ENDB.normal_force", "impact.normal_force"),
        ("A.vx", "A.vx"),
        ("B.vx", "B.vx"),
        ("total_energy", "total_energy"),
        ("strain_energy", "strain_energy"),
    ] {
        let d = difference(&h, a, &twin, b, 0.0);
        assert!(d <= 1e-8, "{a} against the scene's {b}: {d:e}");
    }
    // the printed node, a corner of A's struck end, against the scene's probe at the end's
    // centre: every node of the end moves alike, to the contact iteration's tolerance
    let d = difference(&h, "TIP.vx", &twin, "tipA.vx", 0.0);
    assert!(
        d <= 1e-4,
        "the printed node's velocity against the scene's probe: {d:e}"
    );
    // NB's 44 nodes, however many, each make a probe: bar B at rest until struck
    for k in [1, 44] {
        let ux = h.col(&format!("NB_{k}.ux"));
        assert!(ux.iter().all(|u| u.is_finite()) && ux[0] == 0.0, "NB_{k}");
    }
}

/// A deck's brick of `n` = [nx, ny, nz] C3D8 over `min`..`max`, nodes from `node0` and
/// elements from `el0`, its elements in `elset`, its nodes in `nset`.
fn brick(
    (min, max, n): ([f64; 3], [f64; 3], [usize; 3]),
    (node0, el0): (usize, usize),
    (elset, nset): (&str, &str),
) -> String {
    let id = |i: usize, j: usize, k: usize| node0 + i + (n[0] + 1) * (j + (n[1] + 1) * k);
    let mut t = format!("*NODE, NSET={nset}\n");
    for k in 0..=n[2] {
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                let x = [i, j, k].map(|q| q as f64);
                let p: Vec<String> = (0..3)
                    .map(|a| format!("{}", min[a] + (max[a] - min[a]) * x[a] / n[a] as f64))
                    .collect();
                t += &format!("{}, {}\n", id(i, j, k), p.join(", "));
            }
        }
    }
    t += &format!("*ELEMENT, TYPE=C3D8, ELSET={elset}\n");
    let mut e = el0;
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let c = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                let c: Vec<String> = c.iter().map(|x| x.to_string()).collect();
                t += &format!("{e}, {}\n", c.join(", "));
                e += 1;
            }
        }
    }
    t
}

/// A block sliding on a plate held at its base, with friction and gravity, explicit: as a
/// CalculiX deck (surfaces as element sides, S1 the bottom and S2 the top of a C3D8).
fn sliding_block_deck() -> String {
    let mut t = String::from("*HEADING\nA block slides on a held plate\n");
    t += &brick(
        ([0.0, 0.0, -1.0], [4.0, 4.0, 0.0], [4, 4, 1]),
        (1, 1),
        ("PLATE", "NPLATE"),
    );
    t += &brick(
        ([1.0, 1.0, 0.01], [3.0, 3.0, 2.01], [2, 2, 2]),
        (101, 101),
        ("BLOCK", "NBLOCK"),
    );
    t += "*NSET, NSET=BASE, GENERATE\n1, 25, 1\n";
    t += "*ELSET, ELSET=PLATETOP, GENERATE\n1, 16, 1\n";
    t += "*ELSET, ELSET=BLOCKBOTTOM, GENERATE\n101, 104, 1\n";
    t += "*SURFACE, NAME=TOP, TYPE=ELEMENT\nPLATETOP, S2\n";
    t += "*SURFACE, NAME=BOTTOM, TYPE=ELEMENT\nBLOCKBOTTOM, S1\n";
    t += "*MATERIAL, NAME=SOFT\n*ELASTIC, TYPE=ISOTROPIC\n100.0, 0.3\n*DENSITY\n0.01\n";
    t += "*SOLID SECTION, ELSET=PLATE, MATERIAL=SOFT\n";
    t += "*SOLID SECTION, ELSET=BLOCK, MATERIAL=SOFT\n";
    t += "*BOUNDARY\nBASE, 1, 3\n";
    t += "*SURFACE INTERACTION, NAME=ROUGH\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD\n";
    t += "*FRICTION\n0.2\n";
    t += "*CONTACT PAIR, INTERACTION=ROUGH, TYPE=NODE TO SURFACE\nBOTTOM, TOP\n";
    t += "*INITIAL CONDITIONS, TYPE=VELOCITY\nNBLOCK, 1, 0.5\nNBLOCK, 3, -1.0\n";
    t += "*STEP\n*DYNAMIC, EXPLICIT\n1e-4, 0.05\n";
    t += "*DLOAD\nPLATE, GRAV, 9.81, 0., 0., -1.\nBLOCK, GRAV, 9.81, 0., 0., -1.\n";
    t += "*NODE OUTPUT\nU\n*END STEP\n";
    t
}

/// The same block and plate as a scene.
const SLIDING_BLOCK_SCENE: &str = r#"title = "A block slides on a held plate"
gravity = [0.0, 0.0, -9.81]
[run]
end_time = 0.05
method = "explicit"
[[material]]
name = "SOFT"
density = 0.01
youngs_modulus = 100.0
poissons_ratio = 0.3
[[body]]
name = "PLATE"
material = "SOFT"
box = { min = [0.0, 0.0, -1.0], max = [4.0, 4.0, 0.0], divisions = [4, 4, 1] }
[[body]]
name = "BLOCK"
material = "SOFT"
box = { min = [1.0, 1.0, 0.01], max = [3.0, 3.0, 2.01], divisions = [2, 2, 2] }
velocity = [0.5, 0.0, -1.0]
[[fix]]
body = "PLATE"
face = "z-"
components = ["x", "y", "z"]
[[contact]]
name = "BOTTOM-TOP"
secondary = { body = "BLOCK", face = "z-" }
primary = { body = "PLATE", face = "z+" }
friction = 0.2
"#;

#[test]
fn a_block_sliding_on_a_held_plate_as_a_deck_matches_its_scene() {
    let tag = "deck_sliding_block_files";
    let deck = written(tag, "sliding_block.inp", &sliding_block_deck());
    let scene = written(
        "deck_sliding_block_twin_files",
        "sliding_block.toml",
        SLIDING_BLOCK_SCENE,
    );
    let (_, h) = run_file("deck_sliding_block", &deck);
    let (_, twin) = run_file("deck_sliding_block_twin", &scene);
    let friction = h.col("BOTTOM-TOP.tangential_force");
    assert!(
        friction.iter().any(|&f| f > 0.0),
        "the block slides with friction"
    );
    // the deck numbers the nodes and elements as the boxes do: the same model, the same
    // numbers
    for c in [
        "BLOCK.vx",
        "BLOCK.vz",
        "PLATE.vz",
        "total_energy",
        "BOTTOM-TOP.normal_force",
    ] {
        let d = difference(&h, c, &twin, c, 0.0);
        eprintln!("{c}: {d:.2e}");
        assert!(d <= 1e-12, "{c} against the scene's: {d:e}");
    }
}

/// `*ELASTIC, TYPE=ORTHOTROPIC` (the stiffness D1111 .. D2323) runs the sliding block as
/// `TYPE=ENGINEERING CONSTANTS` of the same material does, to the rounding of the
/// conversion.
#[test]
fn an_abaqus_orthotropic_stiffness_runs_as_its_engineering_constants() {
    let c = [100.0, 80.0, 60.0, 0.3, 0.25, 0.2, 35.0, 30.0, 25.0];
    let m = impact::material::Orthotropic {
        e: [c[0], c[1], c[2]],
        nu: [c[3], c[4], c[5]],
        g: [c[6], c[7], c[8]],
    };
    let d = m.stiffness();
    let stiffness = [
        d[0][0], d[0][1], d[1][1], d[0][2], d[1][2], d[2][2], c[6], c[7], c[8],
    ];
    let lines = |v: [f64; 9]| {
        let t: Vec<String> = v.iter().map(|x| format!("{x:e}")).collect();
        format!("{}\n{}\n", t[..8].join(", "), t[8])
    };
    let isotropic = "*ELASTIC, TYPE=ISOTROPIC\n100.0, 0.3\n";
    let deck = sliding_block_deck();
    assert!(deck.contains(isotropic));
    let dir = out_dir("deck_orthotropic");
    std::fs::create_dir_all(&dir).unwrap();
    let mut histories = Vec::new();
    for (ty, values) in [("ENGINEERING CONSTANTS", c), ("ORTHOTROPIC", stiffness)] {
        let text = deck.replace(
            isotropic,
            &format!("*ELASTIC, TYPE={ty}\n{}", lines(values)),
        );
        let path = dir.join(format!("{}.inp", ty.replace(' ', "_")));
        std::fs::write(&path, text).unwrap();
        let (s, h) = run_file(&format!("deck_{}", ty.replace(' ', "_")), &path);
        assert_eq!(s.status, "completed");
        histories.push(h);
    }
    for col in [
        "BLOCK.vx",
        "BLOCK.vz",
        "strain_energy",
        "BOTTOM-TOP.normal_force",
    ] {
        let e = difference(&histories[0], col, &histories[1], col, 0.0);
        eprintln!("{col}: {e:.2e}");
        assert!(e <= 1e-9, "{col}: {e:e}");
    }
    // a stiffness that is not positive definite is refused at its keyword
    let mut bad = stiffness;
    bad[1] = 2.0 * (bad[0] * bad[2]).sqrt();
    let text = deck.replace(
        isotropic,
        &format!("*ELASTIC, TYPE=ORTHOTROPIC\n{}", lines(bad)),
    );
    let path = dir.join("bad.inp");
    std::fs::write(&path, text).unwrap();
    let e = Scene::load(&path).expect_err("refused").to_string();
    assert!(
        e.contains("bad.inp:") && e.contains("positive definite"),
        "{e}"
    );
}

#[test]
fn a_converted_deck_runs_to_the_decks_history() {
    let dir = out_dir("deck_convert_files");
    std::fs::create_dir_all(&dir).unwrap();
    let deck = dir.join("two_bars.inp");
    std::fs::copy(repo().join("scenes/two_bars.inp"), &deck).unwrap();
    let scene = dir.join("two_bars_scene.toml");
    let o = impact(&["convert", s(&deck), "--to", s(&scene)]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).contains("*CONTACT PRINT"), "{}", stderr(&o));
    let text = std::fs::read_to_string(&scene).unwrap();
    assert!(
        text.contains("elset = \"A\"") && text.contains("mesh = \"two_bars.inp\""),
        "{text}"
    );
    let (_, a) = run_file("deck_convert_deck", &deck);
    let (_, b) = run_file("deck_convert_scene", &scene);
    let read = |h: &History| format!("{:?}{:?}", h.columns, h.rows);
    assert!(
        read(&a) == read(&b),
        "the scene's history differs from the deck's"
    );
    // a rigid body that turns: its surface placed by `origin` where the deck has it
    let deck = dir.join("rigid_tup.inp");
    std::fs::copy(repo().join("scenes/rigid_tup.inp"), &deck).unwrap();
    let scene = dir.join("rigid_tup_scene.toml");
    let o = impact(&["convert", s(&deck), "--to", s(&scene)]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let text = std::fs::read_to_string(&scene).unwrap();
    assert!(
        text.contains("origin = [") && text.contains("inertia = ["),
        "{text}"
    );
    let (_, a) = run_file("deck_convert_rigid_deck", &deck);
    let (_, b) = run_file("deck_convert_rigid_scene", &scene);
    assert!(
        read(&a) == read(&b),
        "the rigid scene's history differs from the deck's"
    );
}

/// `convert` never loses a file: onto the deck itself (by its name or a symlink), onto a file
/// the deck includes, or onto an existing file without `--overwrite`, it is refused (exit 2,
/// naming the file) and the file is as it was; with `--overwrite` it replaces the scene.
#[test]
fn convert_refuses_to_write_over_the_deck_its_includes_or_a_file() {
    let dir = out_dir("deck_convert_refusals");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(repo().join("scenes/two_bars.inp")).unwrap();
    // the deck's *STEP moved into an included file
    let at = text.find("*STEP").expect("a step");
    std::fs::write(dir.join("step.inc"), &text[at..]).unwrap();
    let deck = dir.join("two_bars.inp");
    let main = format!("{}*INCLUDE, INPUT=step.inc\n", &text[..at]);
    std::fs::write(&deck, &main).unwrap();
    std::os::unix::fs::symlink("two_bars.inp", dir.join("link.inp")).unwrap();
    for (to, words) in [
        ("two_bars.inp", "is the deck or a file it reads"),
        ("link.inp", "is the deck or a file it reads"),
        ("step.inc", "step.inc"),
    ] {
        let o = impact(&["convert", s(&deck), "--to", s(&dir.join(to)), "--overwrite"]);
        assert_eq!(code(&o), 2, "{to}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(words) && stderr(&o).contains(to),
            "{}",
            stderr(&o)
        );
    }
    assert_eq!(std::fs::read_to_string(&deck).unwrap(), main);
    assert_eq!(
        std::fs::read_to_string(dir.join("step.inc")).unwrap(),
        &text[at..]
    );
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, "kept").unwrap();
    let o = impact(&["convert", s(&deck), "--to", s(&scene)]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("--overwrite"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), "kept");
    let o = impact(&["convert", s(&deck), "--to", s(&scene), "--overwrite"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(std::fs::read_to_string(&scene)
        .unwrap()
        .contains("two_bars.inp"));
    // a scene outside the deck's folder names it, and is usage
    let o = impact(&["convert", s(&deck), "--to", s(&dir.join("sub/x.toml"))]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("deck's folder"), "{}", stderr(&o));
}

/// The deck `text` (written as `bad.inp`) is refused with every piece of `words`.
fn refused(tag: &str, text: &str, words: &[&str]) {
    let deck = written(tag, "bad.inp", text);
    let e = Scene::load(&deck)
        .expect_err("the deck is refused")
        .to_string();
    for w in words {
        assert!(e.contains(w), "`{w}` in: {e}");
    }
}

#[test]
fn what_a_deck_asks_that_impact_cannot_honour_is_refused_by_keyword_and_line() {
    let deck = std::fs::read_to_string(repo().join("scenes/two_bars.inp")).unwrap();
    let plastic = edit(&deck, "*DENSITY\n", "*PLASTIC\n1.0, 0.0\n*DENSITY\n");
    refused(
        "deck_plastic",
        &plastic,
        &["bad.inp:128", "*PLASTIC", "cannot honour"],
    );
    // a second step goes on from the first: its procedure and increment the first's, and
    // between the two only equations may change
    let second = deck.clone() + "*STEP\n*DYNAMIC\n0.01, 0.4\n*END STEP\n";
    let scene =
        Scene::load(written("deck_second_step", "bad.inp", &second)).expect("a second step reads");
    assert_eq!(scene.run.end_time, 0.8);
    assert_eq!(scene.steps.len(), 1);
    assert_eq!(scene.steps[0].start, 0.4);
    let loaded = deck.clone() + "*STEP\n*DYNAMIC\n0.01, 0.4\n*CLOAD\n1, 1, 1.0\n*END STEP\n";
    refused(
        "deck_second_step_load",
        &loaded,
        &["bad.inp:152", "*CLOAD in a later *STEP"],
    );
    // another increment: every step runs at the smallest, on which each step must end
    let other = deck.clone() + "*STEP\n*DYNAMIC\n0.02, 0.4\n*END STEP\n";
    let scene = Scene::load(written("deck_second_step_increment", "bad.inp", &other))
        .expect("another increment reads");
    assert_eq!(scene.run.time_step, Some(0.01));
    let between = deck.clone() + "*STEP\n*DYNAMIC\n0.004, 0.01\n*END STEP\n";
    refused(
        "deck_second_step_between",
        &between,
        &["bad.inp:150", "not a whole number of increments of 0.004"],
    );
    // a later step of another procedure is a step of that method, at its own increment
    let procedure = deck.clone() + "*STEP\n*STATIC\n0.01, 0.4\n*END STEP\n";
    let scene = Scene::load(written("deck_second_step_procedure", "bad.inp", &procedure))
        .expect("a later static step reads");
    let step = &scene.steps[0];
    assert_eq!(step.method, Some(impact::scene::Method::Static));
    assert_eq!(step.time_step, Some(0.01));
    // a later step's supports (OP=NEW ends those before) and friction
    let changed = deck.clone()
        + "*STEP\n*DYNAMIC\n0.01, 0.4\n*BOUNDARY, OP=NEW\nNB, 1, 1\n*CHANGE FRICTION, INTERACTION=BARS\n*FRICTION\n0.3\n*END STEP\n";
    let scene = Scene::load(written("deck_second_step_changes", "bad.inp", &changed))
        .expect("a later step's supports and friction read");
    let step = &scene.steps[0];
    assert_eq!(step.release_fixes, impact::scene::Release::All);
    assert_eq!(step.fixes.len(), 1);
    assert_eq!(step.fixes[0].components, [true, false, false]);
    // a dynamic step's 0 holds the nodes where they are
    assert!(step.fixes[0].displacement.is_none());
    assert_eq!(step.contacts.len(), 1);
    assert_eq!(step.contacts[0].friction, Some(0.3));
    let moved_later =
        deck.clone() + "*STEP\n*DYNAMIC\n0.01, 0.4\n*BOUNDARY\nNB, 1, 1, 0.1\n*END STEP\n";
    refused(
        "deck_second_step_jump",
        &moved_later,
        &["bad.inp:153", "a jump"],
    );
    let moved = edit(
        &deck,
        "*INITIAL CONDITIONS",
        "*BOUNDARY\nNA, 1, 1, 0.5\n*INITIAL CONDITIONS",
    );
    refused("deck_moved", &moved, &["*BOUNDARY NA", "a jump at t = 0"]);
    // a static step reads as one: its increments, and the linear pressure-overclosure as
    // the contact's penalty
    let static_step = edit(&deck, "*DYNAMIC\n", "*STATIC\n");
    let scene =
        Scene::load(written("deck_static", "bad.inp", &static_step)).expect("a static step reads");
    assert_eq!(scene.run.method, impact::scene::Method::Static);
    assert_eq!((scene.run.time_step, scene.run.end_time), (Some(0.01), 0.4));
    assert!((scene.statics.minimum_step - 4e-6).abs() <= 1e-18);
    assert_eq!(
        scene.contacts[0].pressure_law,
        Some(impact::scene::PressureLaw::Linear { stiffness: 1.0e4 })
    );
    // an *EQUATION's terms on node numbers, over two lines
    let tied = edit(
        &static_step,
        "*NODE PRINT, NSET=NB",
        "*EQUATION\n3\n1, 1, 1.0, 2, 1, -0.5\n3, 2, -0.5\n*NODE PRINT, NSET=NB",
    );
    let scene = Scene::load(written("deck_equation", "bad.inp", &tied)).expect("reads");
    let terms: Vec<(usize, usize, f64)> = (scene.equations[0].terms.iter())
        .map(|t| (t.body, t.component, t.coefficient))
        .collect();
    assert_eq!(terms, vec![(0, 0, 1.0), (0, 0, -0.5), (0, 1, -0.5)]);
    refused(
        "deck_frequency",
        &edit(&deck, "*DYNAMIC\n", "*FREQUENCY\n"),
        &["*FREQUENCY", "cannot honour"],
    );
    let no_step: String = deck
        .lines()
        .take_while(|l| !l.starts_with("*STEP"))
        .collect::<Vec<_>>()
        .join("\n");
    refused("deck_no_step", &no_step, &["no *STEP with *DYNAMIC"]);
    let no_material = edit(
        &deck,
        "ELSET=B, MATERIAL=ELASTIC",
        "ELSET=B, MATERIAL=STEEL",
    );
    refused(
        "deck_no_material",
        &no_material,
        &["no *MATERIAL named `STEEL`"],
    );
    let warm = edit(&deck, "100.0, 0.0\n", "100.0, 0.0, 20.0\n");
    refused(
        "deck_warm",
        &warm,
        &["bad.inp:127", "more than its 2 constants"],
    );
    let dense = edit(&deck, "0.01\n", "0.01, 20.0\n0.011, 100.0\n");
    refused("deck_dense", &dense, &["*DENSITY over temperatures"]);
    let dof = edit(&deck, "NA, 1, 1.0", "NA, 7, 1.0");
    refused("deck_dof", &dof, &["degree of freedom `7`"]);
    let rotation = edit(&deck, "NA, 1, 1.0", "NA, 5, 1.0");
    refused(
        "deck_rotation",
        &rotation,
        &["bad.inp:138", "dofs 4-6 are rotations"],
    );
}

/// What a deck gets wrong is told at its own line, in its own words, never by the scene
/// keys the reader writes: a material without `*DENSITY`, a density of 0, a contact pair
/// given twice or without its data line, an element in two sections. The names the reader
/// makes (contacts, walls) never take a name the deck gives.
#[test]
fn a_decks_mistakes_are_told_at_its_lines_and_its_names_never_clash() {
    let deck = std::fs::read_to_string(repo().join("scenes/two_bars.inp")).unwrap();
    let line = |text: &str, what: &str| {
        let at = text.find(what).unwrap_or_else(|| panic!("{what}"));
        format!("bad.inp:{}", text[..at].lines().count() + 1)
    };
    let dry = edit(&deck, "*DENSITY\n0.01\n", "");
    let at = line(&dry, "*MATERIAL");
    refused(
        "deck_no_density",
        &dry,
        &[&at, "NAME=ELASTIC", "no *DENSITY"],
    );
    let light = edit(&deck, "*DENSITY\n0.01\n", "*DENSITY\n0.0\n");
    let at = line(&light, "*MATERIAL");
    refused(
        "deck_zero_density",
        &light,
        &[&at, "NAME=ELASTIC, its density"],
    );
    let twice = edit(&deck, "TIPA, ENDB\n", "TIPA, ENDB\nTIPA, ENDB\n");
    let at = format!(
        "bad.inp:{}",
        twice[..twice.find("TIPA, ENDB").unwrap()].lines().count() + 2
    );
    refused("deck_pair_twice", &twice, &[&at, "given twice"]);
    let empty = edit(
        &deck,
        "TYPE=SURFACE TO SURFACE\nTIPA, ENDB\n",
        "TYPE=SURFACE TO SURFACE\n",
    );
    let at = line(&empty, "*CONTACT PAIR");
    refused("deck_pair_empty", &empty, &[&at, "needs a data line"]);
    let sections = edit(
        &deck,
        "*SOLID SECTION, ELSET=B,",
        "*ELSET, ELSET=C\n10, 101\n*SOLID SECTION, ELSET=C, MATERIAL=ELASTIC\n*SOLID SECTION, ELSET=B,",
    );
    let at = line(&sections, "*SOLID SECTION, ELSET=C");
    refused(
        "deck_two_sections",
        &sections,
        &[&at, "element 10 is in two *SOLID SECTIONs"],
    );
    // an LS-DYNA part titled as the reader names a wall or a contact keeps its title
    let k = std::fs::read_to_string(repo().join("scenes/block_drop.k")).unwrap();
    let titled = edit(&k, "$# title\nblock\n", "$# title\nwall1\n");
    let path = written("k_wall1_files", "wall1.k", &titled);
    let scene = Scene::load(&path).expect("a part titled wall1 reads");
    assert_eq!(scene.bodies[0].name, "wall1");
    assert_eq!(scene.planes[0].name, "wall1_2");
    let light = edit(
        &k,
        "         1      0.01     100.0       0.3",
        "         1       0.0     100.0       0.3",
    );
    let path = written("k_light_files", "light.k", &light);
    let e = Scene::load(&path).expect_err("no mass").to_string();
    let at = format!(
        "light.k:{}",
        light[..light.find("         1       0.0").unwrap()]
            .lines()
            .count()
            + 1
    );
    assert!(e.contains(&at) && e.contains("*MAT 1, its density"), "{e}");
}

/// CalculiX's spellings run as the spelled-out deck does, to its history byte for byte:
/// keywords without their blanks (`*SOLIDSECTION`, `*CONTACTPAIR`, `*INITIALCONDITIONS`,
/// `*NODEPRINT`, `*ENDSTEP`), `TYPE=SURFACETOSURFACE`, `*ELASTIC, TYPE=ISO`, Fortran's `D`
/// exponents, a node set printed twice, and a node-based slave surface (`TYPE=NODE`).
#[test]
fn calculix_spellings_run_as_the_spelled_out_deck() {
    let deck = std::fs::read_to_string(repo().join("scenes/two_bars.inp")).unwrap();
    let mut ccx = deck.clone();
    for (from, to) in [
        ("*SOLID SECTION", "*SOLIDSECTION"),
        ("*CONTACT PAIR", "*CONTACTPAIR"),
        ("*INITIAL CONDITIONS", "*INITIAL CONDITIONS"),
        ("*INITIAL CONDITIONS", "*INITIALCONDITIONS"),
        ("*NODE PRINT", "*NODEPRINT"),
        ("*END STEP", "*ENDSTEP"),
        ("TYPE=SURFACE TO SURFACE", "TYPE=SURFACETOSURFACE"),
        ("*ELASTIC\n100.0, 0.0", "*ELASTIC, TYPE=ISO\n1.0D2, 0.0"),
        ("*DENSITY\n0.01", "*DENSITY\n1.0d-2"),
        (
            "*NODEPRINT, NSET=TIP\nV\n",
            "*NODEPRINT, NSET=TIP\nV\n*NODE PRINT, NSET=TIP\nU\n",
        ),
    ] {
        assert!(ccx.contains(from), "{from}");
        ccx = ccx.replace(from, to);
    }
    // the struck end as a node-based slave surface: the faces its nodes cover
    ccx = edit(
        &ccx,
        "*SURFACE, NAME=TIPA, TYPE=ELEMENT\n10, S4\n",
        "*NSET, NSET=TIPN\n41, 42, 43, 44\n*SURFACE, NAME=TIPA, TYPE=NODE\nTIPN\n",
    );
    let path = written("deck_ccx_spelling_files", "ccx.inp", &ccx);
    let (_, a) = run_file("deck_ccx_spelling", &path);
    let (_, b) = run_file("deck_spelled_out", &repo().join("scenes/two_bars.inp"));
    let read = |h: &History| format!("{:?}{:?}", h.columns, h.rows);
    assert!(
        read(&a) == read(&b),
        "the blank-free deck's history differs"
    );
}

/// Both bars in one `*SOLID SECTION` (as CalculiX's contact tests write their parts): the
/// section's two connected pieces are two bodies, the pair between them ordinary contact,
/// and the velocity on one bar's node set that bar's. The run is the two-section deck's,
/// byte for byte, and wave theory's plateau within 2%.
#[test]
fn one_section_of_two_bars_is_two_bodies() {
    let deck = std::fs::read_to_string(repo().join("scenes/two_bars.inp")).unwrap();
    let mut one = deck.clone();
    for (from, to) in [
        ("TYPE=C3D8, ELSET=A\n", "TYPE=C3D8, ELSET=BARS\n"),
        ("TYPE=C3D8, ELSET=B\n", "TYPE=C3D8, ELSET=BARS\n"),
        (
            "*SOLID SECTION, ELSET=A, MATERIAL=ELASTIC\n*SOLID SECTION, ELSET=B, MATERIAL=ELASTIC\n",
            "*SOLID SECTION, ELSET=BARS, MATERIAL=ELASTIC\n",
        ),
    ] {
        one = edit(&one, from, to);
    }
    let path = written("deck_one_section_files", "one.inp", &one);
    let scene = Scene::load(&path).expect("one section reads");
    let names: Vec<&str> = scene.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["BARS_1", "BARS_2"]);
    assert_eq!(scene.bodies[0].velocity, [1.0, 0.0, 0.0]);
    let (_, h) = run_file("deck_one_section", &path);
    let (_, two) = run_file("deck_two_sections", &repo().join("scenes/two_bars.inp"));
    for (a, b) in [
        ("TIPA-ENDB.normal_force", "TIPA-ENDB.normal_force"),
        ("BARS_1.vx", "A.vx"),
        ("BARS_2.vx", "B.vx"),
        ("total_energy", "total_energy"),
    ] {
        assert!(h.col(a) == two.col(b), "{a} against {b}");
    }
    let m = measures(&h, "TIPA-ENDB", TWO_BARS_FORCE, 0.01);
    assert!((m.plateau_mean - TWO_BARS_FORCE).abs() <= 0.02 * TWO_BARS_FORCE);
    // the scene's `piece`: a piece that is not there, or on a box, is refused by its key
    let body = |select: &str| {
        format!("[run]\nend_time = 0.1\nmethod = \"explicit\"\n[[material]]\nname = \"m\"\ndensity = 1.0\nyoungs_modulus = 1.0\npoissons_ratio = 0.0\n[[body]]\nname = \"b\"\nmaterial = \"m\"\n{select}\n")
    };
    let parse = |text: &str| Scene::parse(text, &repo().join("scenes/keys.toml"));
    let e = parse(&body("mesh = \"two_bars.inp\"\npiece = 3"))
        .expect_err("no third")
        .to_string();
    assert!(
        e.contains("body[0].piece") && e.contains("2 connected piece(s)"),
        "{e}"
    );
    let e = parse(&body("mesh = \"two_bars.inp\"\npiece = 0"))
        .expect_err("from 1")
        .to_string();
    assert!(e.contains("body[0].piece"), "{e}");
    let boxed =
        "box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], divisions = [1, 1, 1] }\npiece = 1";
    let e = parse(&body(boxed)).expect_err("a box").to_string();
    assert!(e.contains("body[0].piece"), "{e}");
    parse(&body("mesh = \"two_bars.inp\"\npiece = 2")).expect("bar B");
}

/// Odd lines a deck may hold, each refused at its line with what is wrong (node 0, dofs
/// from last to first, gravity without a direction, a set that names itself, a data line
/// before the first keyword, a third surface on a pair line, a rigid body or a velocity
/// given twice, coordinates whose volume overflows, IMFLAG 2); a heading keeps its spaces.
#[test]
fn odd_deck_lines_are_refused_at_their_lines() {
    let deck = std::fs::read_to_string(repo().join("scenes/two_bars.inp")).unwrap();
    let at = |text: &str, what: &str| {
        let k = text.find(what).unwrap_or_else(|| panic!("{what}"));
        format!("bad.inp:{}", text[..k].lines().count() + 1)
    };
    let cases = [
        (
            "*NODE, NSET=NA\n",
            "*NODE, NSET=NA\n0, 0, 0, 0\n",
            "0, 0, 0, 0",
            "node numbers start at 1",
        ),
        (
            "*INITIAL CONDITIONS",
            "*BOUNDARY\nTIP, 3, 1\n*INITIAL CONDITIONS",
            "TIP, 3, 1",
            "the last dof comes before the first",
        ),
        (
            "0.01, 0.4\n",
            "0.01, 0.4\n*DLOAD\nA, GRAV, 9.81, 0, 0, 0\n",
            "A, GRAV",
            "direction is zero",
        ),
        (
            "*SURFACE, NAME=TIPA",
            "*ELSET, ELSET=D\nD\n*SURFACE, NAME=TIPA",
            "D\n*SURFACE",
            "*ELSET D names itself",
        ),
        (
            "TIPA, ENDB\n",
            "TIPA, ENDB, TIPA\n",
            "TIPA, ENDB, TIPA",
            "two surfaces",
        ),
        (
            "NA, 1, 1.0\n",
            "NA, 1, 1.0\nNA, 1, 2.0\n",
            "NA, 1, 2.0",
            "given twice",
        ),
        (
            "1, -10, 0, 0\n",
            "1, -1e300, 0, 0\n",
            "",
            "overflows a double",
        ),
    ];
    for (k, (from, to, line, words)) in cases.into_iter().enumerate() {
        let text = edit(&deck, from, to);
        let mut expected = vec![words.to_string()];
        if !line.is_empty() {
            expected.push(at(&text, line));
        }
        let words: Vec<&str> = expected.iter().map(String::as_str).collect();
        refused(&format!("deck_odd_{k}"), &text, &words);
    }
    let first = format!("1, 2, 3\n{deck}");
    refused(
        "deck_odd_first",
        &first,
        &["bad.inp:1", "before the first keyword"],
    );
    let rigid = abaqus_tup_deck((0.25, 0.75), "", "REF, 3, -1.0\n");
    let twice = edit(
        &rigid,
        "*BOUNDARY\n",
        "*RIGID BODY, ELSET=TUP, REF NODE=REF\n*BOUNDARY\n",
    );
    let line = at(&twice, "*RIGID BODY, ELSET=TUP, REF NODE=REF\n*BOUNDARY");
    refused("deck_rigid_twice", &twice, &[&line, "given twice"]);
    let heading = edit(
        &deck,
        "Two elastic bars, longitudinal",
        "Two elastic bars,  longitudinal",
    );
    let path = written("deck_heading", "heading.inp", &heading);
    let title = Scene::load(&path).expect("reads").title;
    assert!(
        title.starts_with("Two elastic bars,  longitudinal impact"),
        "{title}"
    );
    let k = std::fs::read_to_string(repo().join("scenes/block_drop.k")).unwrap();
    let springback = edit(&k, "*PART\n", "*CONTROL_IMPLICIT_GENERAL\n2, 0.01\n*PART\n");
    let path = written("k_imflag", "imflag.k", &springback);
    let e = Scene::load(&path).expect_err("IMFLAG 2").to_string();
    assert!(e.contains("IMFLAG 2") && e.contains("imflag.k:"), "{e}");
}

/// The paper's second example (`scenes/cube_on_plate.toml`) as a CalculiX deck: the cube
/// strikes the plate obliquely (friction 0.3), the plate held on its two bottom edges
/// (pinned on one, on rollers along x on the other), the cube's bottom centre printed.
fn oblique_cube_deck() -> String {
    let mut t = String::from("*HEADING\nOblique impact of a cube on a simply supported plate\n");
    t += &brick(
        ([-1.0, 0.0, 0.0], [0.0, 1.0, 1.0], [4, 4, 4]),
        (1, 1),
        ("CUBE", "NCUBE"),
    );
    t += &brick(
        ([-2.0, 0.0, -1.0], [2.0, 1.0, 0.0], [16, 4, 4]),
        (1001, 1001),
        ("PLATE", "NPLATE"),
    );
    // plate node (i, j, 0) is 1001 + i + 17 j; the cube's bottom centre (2, 2, 0) is 13
    let edge = |i: usize| -> String {
        let n: Vec<String> = (0..5).map(|j| (1001 + i + 17 * j).to_string()).collect();
        n.join(", ")
    };
    t += &format!(
        "*NSET, NSET=PINNED\n{}\n*NSET, NSET=ROLLER\n{}\n",
        edge(0),
        edge(16)
    );
    t += "*NSET, NSET=BOTTOM\n13\n";
    t += "*ELSET, ELSET=CUBEBASE, GENERATE\n1, 16, 1\n";
    t += "*ELSET, ELSET=PLATETOP, GENERATE\n1193, 1256, 1\n";
    t += "*SURFACE, NAME=BASE, TYPE=ELEMENT\nCUBEBASE, S1\n";
    t += "*SURFACE, NAME=TOP, TYPE=ELEMENT\nPLATETOP, S2\n";
    t += "*MATERIAL, NAME=SOFT\n*ELASTIC\n100.0, 0.0\n*DENSITY\n0.01\n";
    t += "*SOLID SECTION, ELSET=CUBE, MATERIAL=SOFT\n*SOLID SECTION, ELSET=PLATE, MATERIAL=SOFT\n";
    t += "*BOUNDARY\nPINNED, 1, 3\nROLLER, 2, 3\n";
    t += "*SURFACE INTERACTION, NAME=ROUGH\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD\n*FRICTION\n0.3\n";
    t += "*CONTACT PAIR, INTERACTION=ROUGH, TYPE=SURFACE TO SURFACE\nBASE, TOP\n";
    t += "*INITIAL CONDITIONS, TYPE=VELOCITY\nNCUBE, 1, 5.0\nNCUBE, 3, -5.0\n";
    t += "*STEP\n*DYNAMIC\n0.002, 0.1\n*NODE PRINT, NSET=BOTTOM\nU, V\n*END STEP\n";
    t
}

#[test]
fn the_papers_oblique_cube_as_a_deck_matches_its_scene() {
    let deck = written(
        "deck_oblique_cube_files",
        "cube_on_plate.inp",
        &oblique_cube_deck(),
    );
    let (_, h) = run_file("deck_oblique_cube", &deck);
    let (_, twin) = run_file(
        "deck_oblique_cube_twin",
        &repo().join("scenes/cube_on_plate.toml"),
    );
    assert!(
        h.col("BASE-TOP.tangential_force").iter().any(|&f| f > 0.0),
        "friction acts"
    );
    // the deck numbers the nodes and elements as the boxes do: the same model
    for (a, b) in [
        ("BASE-TOP.normal_force", "impact.normal_force"),
        ("BASE-TOP.tangential_force", "impact.tangential_force"),
        ("CUBE.vx", "cube.vx"),
        ("CUBE.vz", "cube.vz"),
        ("PLATE.vz", "plate.vz"),
        ("total_energy", "total_energy"),
        ("BOTTOM.uz", "bottom.uz"),
        ("BOTTOM.vx", "bottom.vx"),
    ] {
        let d = difference(&h, a, &twin, b, 0.0);
        eprintln!("{a}: {d:.2e}");
        assert!(d <= 1e-9, "{a} against the scene's {b}: {d:e}");
    }
    // Abaqus's named condition for the pinned edge, its set named in another case
    let named = edit(&oblique_cube_deck(), "PINNED, 1, 3", "pinned, PINNED");
    let deck = written(
        "deck_oblique_cube_named_files",
        "cube_on_plate_named.inp",
        &named,
    );
    let (_, n) = run_file("deck_oblique_cube_named", &deck);
    assert!(
        format!("{:?}", n.rows) == format!("{:?}", h.rows),
        "PINNED holds as 1, 3 does"
    );
}

/// `scenes/block_drop.k` as a scene: the same block of boxes, the same wall.
const BLOCK_DROP_SCENE: &str = r#"title = "Block dropped on a rigid wall"
[run]
end_time = 0.06
method = "explicit"
[[material]]
name = "mat1"
density = 0.01
youngs_modulus = 100.0
poissons_ratio = 0.3
[[body]]
name = "block"
material = "mat1"
box = { min = [-0.5, -0.5, 0.01], max = [0.5, 0.5, 1.01], divisions = [4, 4, 4] }
velocity = [0.0, 0.0, -1.0]
[[rigid_plane]]
name = "wall1"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
friction = 0.0
"#;

#[test]
fn the_lsdyna_block_drop_runs_as_it_stands_and_matches_its_scene() {
    let deck = repo().join("scenes/block_drop.k");
    let scene = Scene::load(&deck).expect("the keyword file reads");
    let notice = scene.notices.join("\n");
    for passed in [
        "*CONTROL_TIMESTEP (line 10)",
        "*DATABASE_GLSTAT (line 13)",
        "ELFORM",
    ] {
        assert!(notice.contains(passed), "{passed} in: {notice}");
    }
    let (s, h) = run_file("deck_block_drop", &deck);
    let twin_path = written("deck_block_drop_files", "block_drop.toml", BLOCK_DROP_SCENE);
    let (_, twin) = run_file("deck_block_drop_twin", &twin_path);
    // the block rebounds: its momentum turns, and the wall's impulse is its change
    let vz = h.col("block.vz");
    assert!(*vz.last().unwrap() > 0.5, "the block rebounds: {vz:?}");
    assert_eq!(s.unconverged_steps, 0);
    // the file's coordinates are the boxes' printed to 8 decimals: the same model to rounding
    for c in [
        "block.vz",
        "total_energy",
        "wall1.normal_force",
        "strain_energy",
    ] {
        let d = difference(&h, c, &twin, c, 0.0);
        eprintln!("{c}: {d:.2e}");
        assert!(d <= 1e-9, "{c} against the scene's: {d:e}");
    }
    // free format (commas) reads as the fixed columns do
    let text = std::fs::read_to_string(&deck).unwrap();
    let free = edit(
        &text,
        "         1         2       0.0       0.0       0.0      -1.0         0         0",
        "1, 2, 0.0, 0.0, 0.0, -1.0, 0, 0",
    );
    let free_path = written("deck_block_drop_free_files", "block_drop_free.k", &free);
    let (_, f) = run_file("deck_block_drop_free", &free_path);
    assert!(
        format!("{:?}", f.rows) == format!("{:?}", h.rows),
        "free format"
    );
}

/// `*INCLUDE` in a keyword file: `scenes/block_drop.k` with its nodes and elements moved
/// into an included file (in a subfolder, named on two cards joined by ` +`) runs to the
/// single file's history, byte for byte (the included file's own `*END` ends it, the
/// lines after it unread); a keyword the included file asks that impact cannot
/// honour is refused naming that file and its line, and an include without its file's name
/// is refused at its line.
#[test]
fn an_lsdyna_include_reads_as_the_one_file_does() {
    let deck = repo().join("scenes/block_drop.k");
    let text = std::fs::read_to_string(&deck).unwrap();
    let (_, whole) = run_file("deck_block_drop_whole", &deck);
    let at = text.find("*NODE").expect("the nodes");
    let end = text.find("*END").expect("the end");
    let (head, mesh) = (&text[..at], &text[at..end]);
    let dir = out_dir("deck_include");
    std::fs::create_dir_all(dir.join("mesh")).unwrap();
    let included =
        format!("$ the block's nodes and elements\n{mesh}*END\n*NODE\n1, 0.0, 0.0, 9.0\n");
    std::fs::write(dir.join("mesh/block_mesh.k"), &included).unwrap();
    let main = format!("{head}*INCLUDE\n$ the mesh\nmesh/block_ +\nmesh.k\n*END\n");
    let path = dir.join("block_drop_include.k");
    std::fs::write(&path, &main).unwrap();
    let (s, split) = run_file("deck_block_drop_include", &path);
    assert_eq!(s.status, "completed");
    assert!(
        format!("{:?}", split.rows) == format!("{:?}", whole.rows),
        "the included mesh"
    );
    // a keyword in the included file is refused at its file and line
    let bad =
        format!("$ the block's nodes and elements\n{mesh}*MAT_PLASTIC_KINEMATIC\n         1\n");
    std::fs::write(dir.join("mesh/block_mesh.k"), &bad).unwrap();
    let e = Scene::load(&path).expect_err("refused").to_string();
    let line = bad.lines().count() - 1;
    assert!(
        e.contains(&format!("block_mesh.k:{line}")) && e.contains("*MAT_PLASTIC_KINEMATIC"),
        "{e}"
    );
    let nameless = format!("{head}*INCLUDE\n*END\n");
    std::fs::write(&path, &nameless).unwrap();
    let e = Scene::load(&path).expect_err("refused").to_string();
    let line = head.lines().count() + 1;
    assert!(
        e.contains(&format!("block_drop_include.k:{line}")) && e.contains("file's name"),
        "{e}"
    );
}

/// `*MAT_ORTHOTROPIC_ELASTIC` with its axes given globally (AOPT 2): the block drop with
/// an orthotropic block turned off the global axes runs as the TOML scene with the
/// engineering constants (PRBA, PRCA, PRCB are LS-DYNA's minor ratios: nu12 = PRBA EA / EB)
/// and `orientation = { axes = [a, d] }`; element-based axes (AOPT 0) are refused at the card.
#[test]
fn an_lsdyna_orthotropic_material_runs_as_its_scene() {
    let deck = std::fs::read_to_string(repo().join("scenes/block_drop.k")).unwrap();
    let elastic = "*MAT_ELASTIC\n$#     mid        ro         e        pr\n         1      0.01     100.0       0.3\n";
    assert!(deck.contains(elastic));
    let card = |aopt: &str| {
        format!(
            "*MAT_ORTHOTROPIC_ELASTIC\n\
             $#     mid        ro        ea        eb        ec      prba      prca      prcb\n\
             {:>10}{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}\n\
             $#     gab       gbc       gca      aopt\n\
             {:>10}{:>10}{:>10}{:>10}\n\
             {:>10}{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}\n\
             {:>10}{:>10}{:>10}{:>10}{:>10}{:>10}\n",
            1,
            0.01,
            200.0,
            100.0,
            50.0,
            0.15,
            0.06,
            0.1,
            40.0,
            30.0,
            20.0,
            aopt,
            0.0,
            0.0,
            0.0,
            1.0,
            1.0,
            0.0,
            1.0,
            0.0,
            0.0,
            0.0,
            -1.0,
            1.0,
            0.5
        )
    };
    let dir = out_dir("deck_lsdyna_orthotropic");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("ortho_drop.k");
    std::fs::write(&path, deck.replace(elastic, &card("2.0"))).unwrap();
    let (s, h) = run_file("deck_lsdyna_orthotropic", &path);
    assert_eq!(s.status, "completed");
    let scene = BLOCK_DROP_SCENE
        .replace(
            "youngs_modulus = 100.0\npoissons_ratio = 0.3",
            "orthotropic = { e1 = 200.0, e2 = 100.0, e3 = 50.0, nu12 = 0.3, nu13 = 0.24, nu23 = 0.2, g12 = 40.0, g13 = 20.0, g23 = 30.0 }",
        )
        .replace(
            "velocity = [0.0, 0.0, -1.0]",
            "velocity = [0.0, 0.0, -1.0]\norientation = { axes = [[1.0, 1.0, 0.0], [-1.0, 1.0, 0.5]] }",
        );
    let twin_path = dir.join("ortho_drop.toml");
    std::fs::write(&twin_path, scene).unwrap();
    let (_, twin) = run_file("deck_lsdyna_orthotropic_twin", &twin_path);
    let (_, isotropic) = run_file("deck_lsdyna_isotropic", &repo().join("scenes/block_drop.k"));
    for c in ["block.vz", "block.vx", "total_energy", "strain_energy"] {
        let d = difference(&h, c, &twin, c, 0.0);
        eprintln!("{c}: {d:.2e}");
        assert!(d <= 1e-9, "{c} against the scene's: {d:e}");
    }
    // the constants and the axes both reach the run: the same drop with the isotropic
    // block, or with the orthotropic one on the global axes, strains otherwise
    let global = std::fs::read_to_string(&twin_path).unwrap().replace(
        "orientation = { axes = [[1.0, 1.0, 0.0], [-1.0, 1.0, 0.5]] }\n",
        "",
    );
    let global_path = dir.join("ortho_drop_global.toml");
    std::fs::write(&global_path, global).unwrap();
    let (_, unturned) = run_file("deck_lsdyna_orthotropic_global", &global_path);
    let peak = |h: &History| {
        h.col("wall1.normal_force")
            .iter()
            .fold(0.0f64, |m, &f| m.max(f))
    };
    for (other, what) in [(&isotropic, "isotropic"), (&unturned, "global axes")] {
        let d = (peak(&h) - peak(other)).abs() / peak(&h);
        eprintln!("peak wall force against the {what} block: {d:.2e}");
        assert!(
            d > 1e-2,
            "the {what} block strikes as the turned one: {d:e}"
        );
    }
    std::fs::write(&path, deck.replace(elastic, &card("0.0"))).unwrap();
    let e = Scene::load(&path).expect_err("refused").to_string();
    assert!(e.contains("AOPT") && e.contains("ortho_drop.k:"), "{e}");
}

#[test]
fn what_a_keyword_file_asks_that_impact_cannot_honour_is_refused_by_keyword_and_line() {
    let deck = std::fs::read_to_string(repo().join("scenes/block_drop.k")).unwrap();
    let k = |tag: &str, text: &str, words: &[&str]| {
        let path = written(tag, "bad.k", text);
        let e = Scene::load(&path).expect_err("refused").to_string();
        for w in words {
            assert!(e.contains(w), "`{w}` in: {e}");
        }
    };
    let plastic = edit(&deck, "*MAT_ELASTIC", "*MAT_PLASTIC_KINEMATIC");
    k(
        "k_plastic",
        &plastic,
        &["bad.k:24", "*MAT_PLASTIC_KINEMATIC", "cannot honour"],
    );
    let spin = edit(
        &deck,
        "         1         2       0.0       0.0",
        "         1         2       5.0       0.0",
    );
    k(
        "k_spin_axis",
        &spin,
        &["bad.k:31", "rotation axis (NX, NY, NZ) is zero"],
    );
    let spin = edit(
        &spin,
        "       0.0       0.0       0.0       0.0       0.0       0.0",
        "       0.0       0.0       0.0       0.0       0.0       1.0",
    );
    k(
        "k_spin",
        &spin,
        &["bad.k:29", "part 1 is not rigid", "without a rotation"],
    );
    let no_end = edit(&deck, "*CONTROL_TERMINATION", "*CONTROL_ENERGY");
    k("k_no_end", &no_end, &["no *CONTROL_TERMINATION"]);
    let no_mat = edit(
        &deck,
        "         1         1         1",
        "         1         1         7",
    );
    k(
        "k_no_mat",
        &no_mat,
        &["bad.k:20", "no *MAT_ELASTIC or *MAT_RIGID 7"],
    );
    let load = deck.replace("*END", "*LOAD_BODY_Z\n         1\n*END");
    k("k_load", &load, &["*LOAD_BODY_Z", "cannot honour"]);
}

/// A scene's `elset` selects an Abaqus/CalculiX deck's body, `part` an LS-DYNA file's;
/// each is refused elsewhere by its key.
#[test]
fn elset_and_part_are_each_their_formats_key() {
    let scene = |mesh: &str, key: &str| {
        format!(
            "[run]\nend_time = 0.1\nmethod = \"explicit\"\n[[material]]\nname = \"m\"\ndensity = 1.0\nyoungs_modulus = 1.0\npoissons_ratio = 0.0\n[[body]]\nname = \"b\"\nmaterial = \"m\"\nmesh = \"{mesh}\"\n{key}\n"
        )
    };
    let parse = |text: &str| {
        Scene::parse(text, &repo().join("scenes/keys.toml"))
            .expect_err("refused")
            .to_string()
    };
    let e = parse(&scene("block_drop.k", "elset = \"A\""));
    assert!(e.contains("body[0].elset") && e.contains("part"), "{e}");
    let e = parse(&scene("two_bars.inp", "part = 1"));
    assert!(e.contains("body[0].part") && e.contains("elset"), "{e}");
    let e = parse(&scene("two_bars.inp", "elset = \"C\""));
    assert!(e.contains("no *ELSET named `C`"), "{e}");
    let e = parse(&scene("block_drop.k", "part = 3"));
    assert!(e.contains("no *ELEMENT_SOLID of part 3"), "{e}");
    let boxed = scene("x.inp", "").replace(
        "mesh = \"x.inp\"",
        "box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], divisions = [1, 1, 1] }\npart = 1",
    );
    assert!(parse(&boxed).contains("body[0].part"));
    let two_bars = repo().join("scenes/two_bars.toml");
    let ok = scene("two_bars.inp", "elset = \"B\"");
    Scene::parse(&ok, &two_bars).expect("bar B alone");
}

/// An LS-DYNA rigid part (`*MAT_RIGID`, rotations held) as a tup: a 0.5 cube of density 0.08
/// (mass 0.01) dropped at 1 on an elastic block held at its base, the contact between the
/// block's top and the tup's boundary segment sets.
fn rigid_tup_deck() -> String {
    let mut t =
        String::from("*KEYWORD\n*TITLE\nA rigid tup on a block\n*CONTROL_TERMINATION\n0.05\n");
    t += "*PART\nblock\n1, 1, 1\n*PART\ntup\n2, 1, 2\n*SECTION_SOLID\n1, 2\n";
    t += "*MAT_ELASTIC\n1, 0.01, 100.0, 0.3\n*MAT_RIGID\n2, 0.08, 100.0, 0.3\n1.0, 0.0, 7.0\n";
    t += "*INITIAL_VELOCITY_GENERATION\n2, 2, 0.0, 0.0, 0.0, -1.0, 0, 0\n0, 0, 0, 0, 0, 0, 0, 0\n";
    t += "*NODE\n";
    let mut nodes = String::new();
    let mut elements = String::new();
    // block: 2 x 2 x 2 over [0, 1]^3, nodes 1.., elements 1..; tup: 1 element over
    // [0.25, 0.75]^2 x [1.01, 1.51], nodes 101.., element 101
    let id = |i: usize, j: usize, k: usize| 1 + i + 3 * (j + 3 * k);
    for k in 0..3 {
        for j in 0..3 {
            for i in 0..3 {
                let x = [i, j, k].map(|q| q as f64 * 0.5);
                nodes += &format!("{}, {}, {}, {}\n", id(i, j, k), x[0], x[1], x[2]);
            }
        }
    }
    let mut e = 1;
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..2 {
                let c = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                let c: Vec<String> = c.iter().map(|n| n.to_string()).collect();
                elements += &format!("{e}, 1, {}\n", c.join(", "));
                e += 1;
            }
        }
    }
    let tup = [
        [0.25, 0.25, 1.01],
        [0.75, 0.25, 1.01],
        [0.75, 0.75, 1.01],
        [0.25, 0.75, 1.01],
        [0.25, 0.25, 1.51],
        [0.75, 0.25, 1.51],
        [0.75, 0.75, 1.51],
        [0.25, 0.75, 1.51],
    ];
    for (k, x) in tup.iter().enumerate() {
        nodes += &format!("{}, {}, {}, {}\n", 101 + k, x[0], x[1], x[2]);
    }
    elements += "101, 2, 101, 102, 103, 104, 105, 106, 107, 108\n";
    t += &nodes;
    t += "*ELEMENT_SOLID\n";
    t += &elements;
    // the block's base nodes (k = 0), its top faces (k = 2, outward +z), the tup's bottom
    t += "*SET_NODE_LIST\n1\n1, 2, 3, 4, 5, 6, 7, 8\n9\n";
    t += "*SET_SEGMENT\n1\n";
    for j in 0..2 {
        for i in 0..2 {
            let s = [
                id(i, j, 2),
                id(i + 1, j, 2),
                id(i + 1, j + 1, 2),
                id(i, j + 1, 2),
            ];
            t += &format!("{}, {}, {}, {}\n", s[0], s[1], s[2], s[3]);
        }
    }
    // the tup's whole boundary: a closed surface
    t += "*SET_SEGMENT\n2\n101, 104, 103, 102\n105, 106, 107, 108\n101, 102, 106, 105\n";
    t += "102, 103, 107, 106\n103, 104, 108, 107\n104, 101, 105, 108\n";
    t += "*BOUNDARY_SPC_SET\n1, 0, 1, 1, 1, 0, 0, 0\n";
    t += "*CONTACT_AUTOMATIC_NODES_TO_SURFACE\n1, 2, 0, 0\n0.0, 0.0\n*END\n";
    t
}

/// LS-DYNA reads a blank card as a card of its defaults (a blank contact card 2 is FS = FD
/// = 0, so card 3's SFS is not the friction), stops at `*END`, and takes `*KEYWORD` with
/// its memory; so does impact.
#[test]
fn an_lsdyna_file_reads_blank_cards_as_defaults_and_stops_at_its_end() {
    let deck = rigid_tup_deck();
    let load = |tag: &str, text: &str| {
        Scene::load(written(tag, "tup.k", text)).unwrap_or_else(|e| panic!("{tag}: {e}"))
    };
    let friction = |text: &str| load("k_friction", text).contacts[0].friction;
    let card2 = "1, 2, 0, 0\n0.0, 0.0\n";
    assert_eq!(friction(&edit(&deck, card2, "1, 2, 0, 0\n0.3, 0.0\n")), 0.3);
    assert_eq!(
        friction(&edit(&deck, card2, "1, 2, 0, 0\n\n1.0, 1.0\n")),
        0.0
    );
    let fixed = edit(
        &deck,
        card2,
        "1, 2, 0, 0\n          \n       1.0       1.0\n",
    );
    assert_eq!(friction(&fixed), 0.0);
    // the cards after *END are not read
    let after = format!("{deck}*INITIAL_VELOCITY_GENERATION\n1, 2, 0.0, 0.0, 0.0, -5.0, 0, 0\n0, 0, 0, 0, 0, 0, 0, 0\n*LOAD_BODY_Z\n1\n");
    let s = load("k_after_end", &after);
    let block = s
        .bodies
        .iter()
        .find(|b| b.name == "block")
        .expect("the block");
    assert_eq!(block.velocity, [0.0; 3]);
    let s = load(
        "k_memory",
        &edit(&deck, "*KEYWORD\n", "*KEYWORD 100000000\n"),
    );
    assert_eq!(s.bodies.len(), 1);
}

/// What LS-DYNA refuses in a keyword file, impact refuses by file, line and what is wrong:
/// an element, part, set or material id given twice, an element of a part no `*PART`
/// defines, a keyword that does not start in column 1, a card before the first keyword.
#[test]
fn an_lsdyna_file_with_an_id_given_twice_or_a_card_out_of_place_is_refused_at_its_line() {
    let deck = rigid_tup_deck();
    let line_of = |text: &str, what: &str| text[..text.find(what).unwrap()].lines().count() + 1;
    let check = |tag: &str, text: &str, at: &str, words: &[&str]| {
        let e = Scene::load(written(tag, "bad.k", text))
            .expect_err(tag)
            .to_string();
        let line = format!("bad.k:{}", line_of(text, at));
        assert!(e.contains(&line), "{tag}: {line} in {e}");
        for w in words {
            assert!(e.contains(w), "{tag}: `{w}` in {e}");
        }
    };
    let twice = edit(&deck, "101, 2, 101,", "8, 2, 101,");
    check(
        "k_element_twice",
        &twice,
        "8, 2, 101,",
        &["element 8 is defined twice"],
    );
    let part = edit(&deck, "*PART\ntup\n2, 1, 2\n", "*PART\ntup\n1, 1, 2\n");
    check(
        "k_part_twice",
        &part,
        "1, 1, 2\n",
        &["*PART 1 is defined twice"],
    );
    let orphan = edit(&deck, "101, 2, 101,", "101, 3, 101,");
    check(
        "k_orphan",
        &orphan,
        "101, 3, 101,",
        &["element 101", "no *PART 3"],
    );
    let set = edit(&deck, "*SET_SEGMENT\n2\n", "*SET_SEGMENT\n1\n");
    let at = "1\n101, 104";
    check(
        "k_set_twice",
        &set,
        at,
        &["*SET_SEGMENT 1 is defined twice"],
    );
    let mat = edit(&deck, "*MAT_RIGID\n2,", "*MAT_RIGID\n1,");
    check(
        "k_material_twice",
        &mat,
        "1, 0.08",
        &["material 1 is defined twice"],
    );
    let blank = edit(&deck, "*NODE\n", " *NODE\n");
    check("k_blank_keyword", &blank, " *NODE", &["column 1"]);
    let velocity =
        "*INITIAL_VELOCITY_GENERATION\n2, 2, 0.0, 0.0, 0.0, -1.0, 0, 0\n0, 0, 0, 0, 0, 0, 0, 0\n";
    let again = edit(
        &deck,
        velocity,
        &format!("{velocity}{}", velocity.replace("-1.0", "-2.0")),
    );
    check(
        "k_velocity_twice",
        &again,
        "2, 2, 0.0, 0.0, 0.0, -2.0",
        &["part 2 is given twice"],
    );
    let zero = edit(&deck, "101, 2, 101,", "0, 2, 101,");
    check(
        "k_element_0",
        &zero,
        "0, 2, 101,",
        &["element ids start at 1"],
    );
    let before = format!("0.05\n{deck}");
    check(
        "k_card_first",
        &before,
        "0.05",
        &["before the first keyword"],
    );
}

#[test]
fn an_lsdyna_rigid_part_strikes_as_a_rigid_body_of_its_mass() {
    let deck = written("deck_rigid_tup_files", "rigid_tup.k", &rigid_tup_deck());
    let (_, h) = run_file("deck_rigid_tup", &deck);
    let (t, fz, vz) = (h.col("time"), h.col("contact1.fz"), h.col("tup.vz"));
    assert!(fz.iter().any(|&f| f > 0.0), "the tup strikes the block");
    // the contact's impulse on the tup is its change of momentum, with its mass RO x V
    let mass = 0.08 * 0.125;
    let impulse = common::impulse(&t, &fz);
    let n = t.len() - 1;
    let change = mass * (vz[n] - vz[0]);
    eprintln!(
        "impulse {impulse:.6e}, change of momentum {change:.6e}, vz {}",
        vz[n]
    );
    assert!(vz[n] > -0.9, "the block slows the tup: {}", vz[n]);
    assert!(
        (impulse - change).abs() <= 1e-9 * mass,
        "{impulse} against {change}"
    );
    let e = h.col("total_energy");
    let rise = e.iter().fold(f64::MIN, |m, &x| m.max(x)) - e[0];
    assert!(rise <= 1e-9 * e[0], "energy rises by {rise}");
    // a rigid part with some of its rotations held is refused at its constraints card
    let turning = edit(&rigid_tup_deck(), "1.0, 0.0, 7.0", "1.0, 0.0, 3.0");
    std::fs::write(&deck, turning).unwrap();
    let e = Scene::load(&deck).expect_err("refused").to_string();
    assert!(
        e.contains("rigid_tup.k:18") && e.contains("CON2 = 0 (free to turn) or 7"),
        "{e}"
    );
}

/// The rigid tup of [`rigid_tup_deck`] free to turn (CMO = 0), over the block's edge (x
/// from 0.6 to 1.1), started turning at 3 about z through (0.5, 0.5, 0), run to 0.3.
fn turning_tup_deck() -> String {
    let mut deck = edit(&rigid_tup_deck(), "1.0, 0.0, 7.0\n", "0.0, 0.0, 0.0\n");
    deck = edit(
        &deck,
        "0, 0, 0, 0, 0, 0, 0, 0\n",
        "0.5, 0.5, 0.0, 0.0, 0.0, 1.0, 0, 0\n",
    );
    deck = edit(
        &deck,
        "2, 2, 0.0, 0.0, 0.0, -1.0",
        "2, 2, 3.0, 0.0, 0.0, -1.0",
    );
    deck = edit(&deck, "TERMINATION\n0.05\n", "TERMINATION\n0.3\n");
    for (from, to) in [("0.25, ", "0.6, "), ("0.75, ", "1.1, ")] {
        for k in 101..109 {
            deck = deck.replace(&format!("{k}, {from}"), &format!("{k}, {to}"));
        }
    }
    deck
}

/// The rigid tup of [`rigid_tup_deck`] free to turn (CMO = 0), moved to overhang the
/// block's edge (x from 0.6 to 1.1) and started turning at 3 about z through (0.5, 0.5, 0):
/// its mass, centre and inertia are the cube's, its centre starts at v + w x (c - a), the
/// off-centre blow turns it, and it keeps its angular velocity once free (a cube's inertia
/// is isotropic); the contact's impulse is its change of momentum and the energy does not
/// rise.
#[test]
fn an_lsdyna_rigid_part_free_to_turn_takes_its_inertia_from_its_elements() {
    let deck = turning_tup_deck();
    let path = written("deck_turning_tup_files", "turning_tup.k", &deck);
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let tup = &scene.rigid_bodies[0];
    let (mass, c) = (0.01, [0.85, 0.5, 1.26]);
    assert!((tup.mass - mass).abs() <= 1e-15, "{}", tup.mass);
    let off = tup.position.iter().zip(c).map(|(p, q)| (p - q).abs());
    assert!(off.fold(0.0, f64::max) <= 1e-14, "{:?}", tup.position);
    let inertia = tup.inertia.expect("it turns");
    let i0 = mass * 0.5 / 12.0;
    for a in 0..3 {
        for b in 0..3 {
            let want = if a == b { i0 } else { 0.0 };
            assert!((inertia[a][b] - want).abs() <= 1e-14 * i0, "{inertia:?}");
        }
    }
    // w x (c - a) with w = 3 z, c - a = (0.35, 0, 1.26)
    let v = [0.0, 3.0 * 0.35, -1.0];
    assert_eq!(tup.angular_velocity, [0.0, 0.0, 3.0]);
    assert!(
        (0..3).all(|a| (tup.velocity[a] - v[a]).abs() <= 1e-15),
        "{:?}",
        tup.velocity
    );
    let (_, h) = run_file("deck_turning_tup", &path);
    let (t, fz, vz) = (h.col("time"), h.col("contact1.fz"), h.col("tup.vz"));
    let last = (0..t.len())
        .rev()
        .find(|&i| fz[i] != 0.0)
        .expect("the tup strikes");
    let n = t.len() - 1;
    assert!(
        last < n - 10,
        "the tup leaves the block before the end ({last} of {n})"
    );
    let w: Vec<[f64; 3]> = (0..=n)
        .map(|i| ["wx", "wy", "wz"].map(|c| h.col(&format!("tup.{c}"))[i]))
        .collect();
    assert!((w[0][2] - 3.0).abs() <= 1e-12, "{:?}", w[0]);
    assert!(
        w[n][1].abs() > 1e-3,
        "the off-centre blow turns it about y: {:?}",
        w[n]
    );
    for i in last + 1..=n {
        assert!(
            (0..3).all(|a| (w[i][a] - w[n][a]).abs() <= 1e-12),
            "free, it keeps its angular velocity: {:?} against {:?}",
            w[i],
            w[n]
        );
    }
    let impulse = common::impulse(&t, &fz);
    let change = mass * (vz[n] - vz[0]);
    assert!(
        (impulse - change).abs() <= 1e-9 * mass,
        "{impulse} against {change}"
    );
    let e = h.col("total_energy");
    let rise = e.iter().fold(f64::MIN, |m, &x| m.max(x)) - e[0];
    eprintln!(
        "w end {:?}, vz end {}, energy {} -> {}, rise {rise:e}",
        w[n], vz[n], e[0], e[n]
    );
    assert!(rise <= 1e-6 * e[0], "energy rises by {rise}");
}

/// The tup of [`rigid_tup_deck`] as a CalculiX deck: `*RIGID BODY, ELSET=TUP, REF NODE=REF`
/// with its reference node at (0.5, 0.5, 0), its x from `x0` to `x1`; `lines` are its
/// reference node's `*BOUNDARY` and `*INITIAL CONDITIONS` data lines.
fn abaqus_tup_deck((x0, x1): (f64, f64), boundary: &str, velocity: &str) -> String {
    let mut t = String::from("*HEADING\nA rigid tup on a block\n");
    t += &brick(
        ([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2, 2, 2]),
        (1, 1),
        ("BLOCK", "NBLOCK"),
    );
    t += &brick(
        ([x0, 0.25, 1.01], [x1, 0.75, 1.51], [1, 1, 1]),
        (101, 101),
        ("TUP", "NTUP"),
    );
    t += "*NODE, NSET=REF\n1000, 0.5, 0.5, 0.0\n";
    t += "*NSET, NSET=BASE, GENERATE\n1, 9, 1\n";
    t += "*ELSET, ELSET=BLOCKTOP, GENERATE\n5, 8, 1\n";
    t += "*SURFACE, NAME=BTOP, TYPE=ELEMENT\nBLOCKTOP, S2\n";
    t += "*SURFACE, NAME=TUPS, TYPE=ELEMENT\n";
    for k in 1..=6 {
        t += &format!("TUP, S{k}\n");
    }
    t += "*MATERIAL, NAME=SOFT\n*ELASTIC\n100.0, 0.3\n*DENSITY\n0.01\n";
    t += "*MATERIAL, NAME=HEAVY\n*ELASTIC\n100.0, 0.3\n*DENSITY\n0.08\n";
    t += "*SOLID SECTION, ELSET=BLOCK, MATERIAL=SOFT\n";
    t += "*SOLID SECTION, ELSET=TUP, MATERIAL=HEAVY\n";
    t += "*RIGID BODY, ELSET=TUP, REF NODE=REF\n";
    t += &format!("*BOUNDARY\nBASE, 1, 3\n{boundary}");
    t += &format!("*INITIAL CONDITIONS, TYPE=VELOCITY\n{velocity}");
    t += "*SURFACE INTERACTION, NAME=SMOOTH\n*FRICTION\n0.0\n";
    t += "*CONTACT PAIR, INTERACTION=SMOOTH, TYPE=NODE TO SURFACE\nBTOP, TUPS\n";
    t += "*STEP\n*DYNAMIC, EXPLICIT\n1e-4, 0.05\n*NODE PRINT, NSET=REF\nU\n*END STEP\n";
    t
}

/// The turning tup's deck in CalculiX's own form, as `scenes/rigid_tup.inp` ships it for
/// ccx 2.20: the rotations on a `ROT NODE` (ccx's reference node has no dofs 4-6), the
/// reference nodes by number, a pressure-overclosure in place of a zero friction (ccx
/// refuses both a zero coefficient and an interaction without one), room for ccx's
/// increments and `NLGEOM` (ccx's rigid body turns by exact rotations with it). impact reads
/// the two forms as one model.
fn ccx_form(deck: &str) -> String {
    let mut t = deck.to_string();
    for (from, to) in [
        (
            "*NODE, NSET=REF\n1000, 0.5, 0.5, 0.0\n",
            "*NODE, NSET=REF\n1000, 0.5, 0.5, 0.0\n1001, 0.5, 0.5, 0.0\n",
        ),
        ("REF NODE=REF\n", "REF NODE=1000, ROT NODE=1001\n"),
        (
            "REF, 3, -1.0\nREF, 6, 3.0\n",
            "1000, 3, -1.0\n1001, 3, 3.0\n",
        ),
        (
            "*FRICTION\n0.0\n",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1.0e3\n",
        ),
        ("*STEP\n", "*STEP, INC=1000000, NLGEOM\n"),
    ] {
        assert!(t.contains(from), "{from}");
        t = t.replace(from, to);
    }
    t
}

/// The largest difference of the CalculiX tup's history from the LS-DYNA tup's in the
/// contact force, the tup's motion (and turning where `turning`) and the energy,
/// relative to each column's largest magnitude.
fn tup_difference(a: &History, b: &History, turning: bool) -> f64 {
    let mut pairs = vec![
        ("BTOP-TUPS.fz", "contact1.fz"),
        ("TUP.uz", "tup.uz"),
        ("TUP.vz", "tup.vz"),
        ("TUP.vy", "tup.vy"),
        ("total_energy", "total_energy"),
    ];
    if turning {
        pairs.extend([
            ("TUP.wx", "tup.wx"),
            ("TUP.wy", "tup.wy"),
            ("TUP.wz", "tup.wz"),
        ]);
    }
    let mut worst: f64 = 0.0;
    for (ca, cb) in pairs {
        let d = difference(a, ca, b, cb, 1e-30);
        eprintln!("{ca}: {d:.2e}");
        worst = worst.max(d);
    }
    worst
}

/// A CalculiX `*RIGID BODY` strikes as the LS-DYNA rigid part of the same tup does: held
/// rotations (dofs 4-6 of its reference node) make it translate; free, and started turning
/// about z at its reference node (dof 6), it turns about its centre of mass with the
/// inertia of its elements. The two readers build the rigid mesh from differently ordered
/// corners, so the histories need agree only to rounding (they agree to the bit).
#[test]
fn an_abaqus_rigid_body_strikes_as_the_lsdyna_rigid_part_does() {
    let inp = abaqus_tup_deck((0.25, 0.75), "REF, 4, 6\n", "REF, 3, -1.0\n");
    let inp = written("deck_abaqus_tup_files", "tup.inp", &inp);
    let k = written("deck_lsdyna_tup_files", "tup.k", &rigid_tup_deck());
    let converted = impact::scene::from_deck::convert(&inp).unwrap();
    let notice = converted.notice.unwrap_or_default();
    assert!(
        notice.contains("NSET=REF, a rigid body's reference node"),
        "{notice}"
    );
    let (_, a) = run_file("deck_abaqus_tup", &inp);
    let (_, b) = run_file("deck_lsdyna_tup", &k);
    assert!(
        b.col("contact1.fz").iter().any(|&f| f > 0.0),
        "the tup strikes"
    );
    let d = tup_difference(&a, &b, false);
    assert!(d <= 1e-9, "translating: {d:e}");

    // the shipped deck is this tup free to turn, over the block's edge, run to 0.3
    let inp = repo().join("scenes/rigid_tup.inp");
    let shipped = std::fs::read_to_string(&inp).unwrap();
    let generated = ccx_form(&abaqus_tup_deck(
        (0.6, 1.1),
        "",
        "REF, 3, -1.0\nREF, 6, 3.0\n",
    ));
    let data = |t: &str| -> String {
        let t = t.replace("0.05\n*NODE PRINT", "0.3\n*NODE PRINT");
        let kept = t
            .lines()
            .filter(|l| !l.starts_with("**") && !l.starts_with("A rigid tup"));
        kept.collect::<Vec<_>>().join("\n")
    };
    assert_eq!(data(&shipped), data(&generated), "scenes/rigid_tup.inp");
    let deck = turning_tup_deck();
    let k = written("deck_lsdyna_turning_files", "turning.k", &deck);
    let (_, a) = run_file("deck_abaqus_turning", &inp);
    let (_, b) = run_file("deck_lsdyna_turning", &k);
    assert!(
        b.col("tup.wy").last().unwrap().abs() > 1e-3,
        "the blow turns it"
    );
    let d = tup_difference(&a, &b, true);
    assert!(d <= 1e-9, "turning: {d:e}");
}

/// What a `*RIGID BODY` asks that impact cannot honour is refused at its line.
#[test]
fn what_a_rigid_body_asks_that_impact_cannot_honour_is_refused() {
    let tup = |b: &str| abaqus_tup_deck((0.25, 0.75), b, "REF, 3, -1.0\n");
    // the file and line of the first line of `text` that is `line`
    let at = |text: &str, line: &str| {
        let n = text.lines().position(|l| l == line).expect("the line") + 1;
        format!("bad.inp:{n}")
    };
    let check = |tag: &str, text: &str, line: &str, words: &str| {
        refused(tag, text, &[&at(text, line), words]);
    };
    // some rotations held, named at the *BOUNDARY line
    let some = tup("REF, 5, 5\n");
    check(
        "rigid_some",
        &some,
        "REF, 5, 5",
        "some of its reference node's rotations",
    );
    // a node set holding CalculiX's reference and rotation nodes: dofs 1-3 hold both the
    // translations and the rotations, so the body is held
    let both = edit(&tup("BOTH, 1, 3\n"), "*RIGID BODY, ELSET=TUP, REF NODE=REF\n", "*NODE, NSET=ROT\n1001, 0.5, 0.5, 0.0\n*NSET, NSET=BOTH\nREF, ROT\n*RIGID BODY, ELSET=TUP, REF NODE=REF, ROT NODE=ROT\n");
    let both = edit(&both, "REF, 3, -1.0\n", "");
    let path = written("rigid_both_files", "both.inp", &both);
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        scene.rigid_bodies[0].motion,
        impact::scene::RigidMotion::Fixed
    );
    // held at a reference node off its centre of mass while free to turn: a pivot
    let pivot = tup("REF, 1, 3\n");
    check(
        "rigid_pivot",
        &pivot,
        "REF, 1, 3",
        "POSITION=CENTER OF MASS",
    );
    // ... which POSITION=CENTER OF MASS makes a body held at its centre; its velocity along
    // a held axis is refused at the velocity's line
    let centred = edit(
        &tup("REF, 1, 2\n"),
        "REF NODE=REF\n",
        "REF NODE=REF, POSITION=CENTER OF MASS\n",
    );
    let path = written("rigid_centred_files", "centred.inp", &centred);
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.rigid_bodies[0].inertia.is_some());
    let pushed = edit(&centred, "REF, 3, -1.0\n", "REF, 1, 0.5\n");
    check("rigid_pushed", &pushed, "REF, 1, 0.5", "along x");
    // a rigid body of nodes, without elements to take its mass from
    let nodes = edit(
        &tup("REF, 4, 6\n"),
        "ELSET=TUP, REF NODE",
        "NSET=NTUP, REF NODE",
    );
    let line = "*RIGID BODY, NSET=NTUP, REF NODE=REF";
    check("rigid_nset", &nodes, line, "*RIGID BODY, NSET=");
    // a rotation on a solid's nodes
    let solid = tup("REF, 4, 6\nBASE, 4, 4\n");
    check(
        "rigid_solid_rotation",
        &solid,
        "BASE, 4, 4",
        "dofs 4-6 are rotations",
    );
    // a rigid body's element set without a density
    let light = edit(&tup("REF, 4, 6\n"), "*DENSITY\n0.08\n", "");
    let line = "*RIGID BODY, ELSET=TUP, REF NODE=REF";
    check("rigid_no_density", &light, line, "no *DENSITY");
    // a master surface on the rigid body and on the block
    let spanning = edit(&tup("REF, 4, 6\n"), "TUP, S1\n", "TUP, S1\nBLOCKTOP, S2\n");
    let line = "BTOP, TUPS";
    check(
        "rigid_spanning",
        &spanning,
        line,
        "on a rigid body and on a deformable one",
    );
}

/// A rigid part whose initial velocity moves it along a translation its CON1 holds is
/// refused at the velocity's card.
#[test]
fn an_lsdyna_rigid_part_held_along_its_velocity_is_refused() {
    let deck = edit(&rigid_tup_deck(), "1.0, 0.0, 7.0", "1.0, 3.0, 7.0");
    let path = written("k_rigid_held_files", "bad.k", &deck);
    let e = Scene::load(&path).expect_err("refused").to_string();
    assert!(
        e.contains("bad.k:20") && e.contains("along z, which its *MAT_RIGID CON1 holds"),
        "{e}"
    );
    // held along x only, it drops along z as before
    let deck = edit(&rigid_tup_deck(), "1.0, 0.0, 7.0", "1.0, 1.0, 7.0");
    std::fs::write(&path, deck).unwrap();
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.rigid_bodies[0].velocity, [0.0, 0.0, -1.0]);
}

/// A reference node named by its number reads as the set of that one node does.
#[test]
fn a_rigid_bodys_reference_node_may_be_given_by_number() {
    let named = abaqus_tup_deck((0.25, 0.75), "REF, 4, 6\n", "REF, 3, -1.0\n");
    let numbered = abaqus_tup_deck((0.25, 0.75), "1000, 4, 6\n", "1000, 3, -1.0\n");
    let numbered = edit(&numbered, "REF NODE=REF", "REF NODE=1000");
    // a generated set of the one node
    let generated = edit(&named, "*NODE, NSET=REF\n1000", "*NODE\n1000");
    let generated = edit(
        &generated,
        "*NSET, NSET=BASE",
        "*NSET, NSET=REF, GENERATE\n1000, 1000, 1\n*NSET, NSET=BASE",
    );
    let a = written("rigid_named_files", "tup.inp", &named);
    let b = written("rigid_numbered_files", "tup.inp", &numbered);
    let c = written("rigid_generated_files", "tup.inp", &generated);
    let [a, b, c] = [a, b, c].map(|p| impact::scene::from_deck::convert(&p).unwrap().toml);
    assert_eq!(a, b);
    assert_eq!(a, c);
    assert!(
        a.contains("motion = \"free\"") && a.contains("velocity = [0.0, 0.0, -1.0]"),
        "{a}"
    );
    assert!(!a.contains("inertia"), "its rotations are held: {a}");
}

/// Node numbers where a node set may stand (`*BOUNDARY`, `*INITIAL CONDITIONS`), and a
/// velocity on a node set that holds part of a body: bar A's velocity given on nodes 1-40
/// by a set and on its struck end's four nodes by number (then zero on other components, by
/// number and by the whole bar's set: each line sets its own component), bar B's far end
/// held across by number, run as the deck with a set for each, byte for byte.
#[test]
fn node_numbers_and_a_part_of_a_body_run_as_their_node_sets() {
    let deck = std::fs::read_to_string(repo().join("scenes/two_bars.inp")).unwrap();
    let model_data = "*MATERIAL, NAME=ELASTIC\n";
    let sets = edit(
        &deck,
        model_data,
        &format!("*NSET, NSET=FAR\n141, 142, 143, 144\n*BOUNDARY\nFAR, 2, 3\n{model_data}"),
    );
    let ahead: Vec<String> = (1..=40).map(|n| n.to_string()).collect();
    let numbers = edit(
        &deck,
        model_data,
        &format!(
            "*NSET, NSET=AHEAD\n{}\n*BOUNDARY\n141, 2, 3\n142, 2, 3\n143, 2\n143, 3\n144, 2, 3\n{model_data}",
            ahead.join(", ")
        ),
    );
    let numbers = edit(
        &numbers,
        "NA, 1, 1.0\n",
        // a leading zero, and later lines on the same nodes' other components (a part's, then
        // the whole bar's), which leave x as it is
        "AHEAD, 1, 1.0\n041, 1, 1.0\n42, 1, 1.0\n43, 1, 1.0\n44, 1, 1.0\n41, 2, 0.0\nNA, 3, 0.0\n",
    );
    let a = written("deck_by_sets_files", "sets.inp", &sets);
    let b = written("deck_by_numbers_files", "numbers.inp", &numbers);
    let scene = Scene::load(&b).expect("node numbers read");
    assert_eq!(scene.initial_velocities.len(), 7, "a line each");
    assert_eq!(scene.bodies[0].velocity, [0.0; 3]);
    assert_eq!(scene.fixes.len(), 5, "a fix a node number line");
    let (sa, ha) = run_file("deck_by_sets", &a);
    let (sb, hb) = run_file("deck_by_numbers", &b);
    assert_eq!(
        (sa.status.as_str(), sb.status.as_str()),
        ("completed", "completed")
    );
    let read = |h: &History| format!("{:?}{:?}", h.columns, h.rows);
    assert!(read(&ha) == read(&hb), "the node numbers' history differs");
    refused(
        "deck_node_absent",
        &edit(&deck, "NA, 1, 1.0\n", "NA, 1, 1.0\n999, 1, 1.0\n"),
        &["node 999: no *NODE line gives it"],
    );
}

/// `*CONTACT PAIR, ADJUST=`: bar B moved 0.05 ahead of bar A's struck end, and the pair's
/// `ADJUST=0.1` moves A's end nodes onto B's face before t = 0, so the force starts at once
/// (without it the first 0.05 of time passes with no contact); an `ADJUST=` naming a node set
/// is refused at its line.
#[test]
fn a_contact_pairs_adjust_closes_the_gap_before_the_start() {
    let deck = std::fs::read_to_string(repo().join("scenes/two_bars.inp")).unwrap();
    let apart: String = deck
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').map(str::trim).collect();
            match f[0].parse::<u64>() {
                Ok(id) if (101..=144).contains(&id) && f.len() == 4 => {
                    let x: f64 = f[1].parse().unwrap();
                    format!("{id}, {}, {}, {}", x + 0.05, f[2], f[3])
                }
                _ => l.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let pair = "*CONTACT PAIR, INTERACTION=BARS";
    let adjusted = edit(&apart, pair, &format!("{pair}, ADJUST=0.1"));
    let (sa, ha) = run_file(
        "deck_adjusted",
        &written("deck_adjusted_files", "a.inp", &adjusted),
    );
    let (sg, hg) = run_file("deck_apart", &written("deck_apart_files", "g.inp", &apart));
    assert_eq!(
        (sa.status.as_str(), sg.status.as_str()),
        ("completed", "completed")
    );
    assert_eq!(
        sa.initial_contact[0].moved, 4,
        "the struck end's four nodes"
    );
    touching_from_the_start(&ha, &hg, "TIPA-ENDB.normal_force");
    refused(
        "deck_adjust_set",
        &edit(&deck, pair, &format!("{pair}, ADJUST=NA")),
        &["ADJUST=NA", "a distance"],
    );
}

/// Every keyword a deck is refused for is told at once, each at its line: a plastic
/// material, a frequency step and a cyclic symmetry tie in one deck give three lines.
#[test]
fn a_decks_refusals_are_told_together() {
    let deck = std::fs::read_to_string(repo().join("scenes/two_bars.inp")).unwrap();
    let three = edit(&deck, "*DENSITY\n", "*PLASTIC\n1.0, 0.0\n*DENSITY\n");
    let three = edit(&three, "*DYNAMIC\n", "*FREQUENCY\n");
    let three = edit(
        &three,
        "*NODE PRINT, NSET=NB",
        "*TIE, CYCLIC SYMMETRY, NAME=GLUE\nTIPA, ENDB\n*NODE PRINT, NSET=NB",
    );
    let path = written("deck_three_refusals", "bad.inp", &three);
    let e = Scene::load(&path).expect_err("refused").to_string();
    let lines: Vec<&str> = e.lines().filter(|l| l.contains("bad.inp:")).collect();
    assert_eq!(lines.len(), 3, "{e}");
    for (line, word) in lines.iter().zip(["*PLASTIC", "*FREQUENCY", "*TIE"]) {
        assert!(
            line.contains(word) && line.contains("cannot honour"),
            "{line}"
        );
    }
    assert!(e.contains("3 refusals in all"), "{e}");
}

/// An LS-DYNA `*INITIAL_VELOCITY` on node sets that each hold part of a part: the block's
/// nodes split into two `*SET_NODE_LIST`s, each given the part's -1 along z, run as the part's
/// `*INITIAL_VELOCITY_GENERATION`, byte for byte.
#[test]
fn an_lsdyna_velocity_on_parts_of_a_part_runs_as_the_parts() {
    let deck = std::fs::read_to_string(repo().join("scenes/block_drop.k")).unwrap();
    let lines: Vec<&str> = deck.lines().collect();
    let at = lines
        .iter()
        .position(|l| l.starts_with("*INITIAL_VELOCITY_GENERATION"))
        .unwrap();
    let ids: Vec<u64> = (lines.iter())
        .skip_while(|l| !l.starts_with("*NODE"))
        .skip(1)
        .take_while(|l| !l.starts_with('*'))
        .filter_map(|l| l.split_whitespace().next()?.parse().ok())
        .collect();
    let (a, b) = ids.split_at(ids.len() / 2);
    let set = |sid: usize, ids: &[u64]| {
        let rows: Vec<String> = (ids.chunks(8))
            .map(|c| c.iter().map(u64::to_string).collect::<Vec<_>>().join(", "))
            .collect();
        format!("*SET_NODE_LIST\n{sid}\n{}\n", rows.join("\n"))
    };
    let velocity =
        |sid: usize| format!("*INITIAL_VELOCITY\n{sid}, 0, 0\n0.0, 0.0, -1.0, 0.0, 0.0, 0.0\n");
    let mut split: Vec<String> = lines[..at].iter().map(|l| l.to_string()).collect();
    split.push(set(1, a) + &set(2, b) + &velocity(1) + &velocity(2));
    split.extend(lines[at + 5..].iter().map(|l| l.to_string()));
    let path = written(
        "deck_lsdyna_split_velocity",
        "split.k",
        &(split.join("\n") + "\n"),
    );
    let scene = Scene::load(&path).expect("the split velocities read");
    assert_eq!(
        scene.initial_velocities.len(),
        6,
        "two sets, three components each"
    );
    let (s, h) = run_file("deck_lsdyna_split_velocity", &path);
    let (_, whole) = run_file(
        "deck_lsdyna_whole_velocity",
        &repo().join("scenes/block_drop.k"),
    );
    assert_eq!(s.status, "completed");
    let read = |h: &History| format!("{:?}{:?}", h.columns, h.rows);
    assert!(
        read(&h) == read(&whole),
        "the split velocity's history differs"
    );
}

/// The held bar of `tests/loads.rs` as a CalculiX deck: a pressure `*DLOAD` on its end's
/// side with an `*AMPLITUDE`, and a `*CLOAD` on one node given by its number.
fn loaded_bar_deck() -> String {
    let mut t = String::from("*HEADING\nA held bar under an end pressure\n");
    t += &brick(
        ([0.0, 0.0, 0.0], [10.0, 1.0, 1.0], [100, 1, 1]),
        (1, 1),
        ("BAR", "NBAR"),
    );
    // the nodes at x = 0 and at the tip, of a brick numbered x first (101 a row)
    t += "*NSET, NSET=NFIX\n1, 102, 203, 304\n*NSET, NSET=NTIP\n101\n";
    t += "*MATERIAL, NAME=EL\n*ELASTIC\n100.0, 0.0\n*DENSITY\n0.01\n";
    t += "*SOLID SECTION, ELSET=BAR, MATERIAL=EL\n*ELSET, ELSET=END\n100\n";
    t += "*AMPLITUDE, NAME=UP\n0.0, 0.0, 0.05, 1.0, 0.3, 0.5\n";
    t += "*BOUNDARY\nNFIX, 1, 1\n*STEP\n*DYNAMIC, EXPLICIT\n0.0008, 0.4\n";
    t += "*DLOAD, AMPLITUDE=UP\nEND, P4, 2.0\n*CLOAD\n51, 2, 0.02\n";
    t += "*NODE PRINT, NSET=NTIP\nU\n*END STEP\n";
    t
}

/// A deck's loads give the history of their `[[load]]` twin: the tip's motion, the loads'
/// work and the total energy.
#[test]
fn a_decks_cload_dload_and_amplitude_run_as_their_scene_twin() {
    let deck = written("deck_loads", "loaded_bar.inp", &loaded_bar_deck());
    let (s, h) = run_file("deck_loads", &deck);
    assert!(s.steps > 400, "{} steps", s.steps);
    let twin = held_bar(
        "explicit",
        0.0008,
        100,
        &format!("{PRESSURE}amplitude = [[0.0, 0.0], [0.05, 1.0], [0.3, 0.5]]\n\n[[load]]\nbody = \"bar\"\nregion = {{ min = [4.99, -0.01, -0.01], max = [5.01, 0.01, 0.01] }}\nforce = [0.0, 0.02, 0.0]\n"),
    )
    .replace("time_step = 0.0008\n", "");
    let (st, ht) = run_text("deck_loads_twin", &twin);
    assert_eq!(st.expect("twin runs").status, "completed");
    for (a, b, floor) in [
        ("NTIP.ux", "tip.ux", 1e-9),
        ("NTIP.uy", "tip.uy", 1e-9),
        ("external_work", "external_work", 1e-9),
        ("total_energy", "total_energy", 0.1),
    ] {
        let d = difference(&h, a, &ht, b, floor);
        assert!(d < 1e-9, "{a} differs from the twin's {b} by {d}");
    }
    let most = h.col("external_work").into_iter().fold(0.0, f64::max);
    assert!(most > 0.1, "the loads did {most} at most");
}

#[test]
fn a_decks_loads_that_cannot_be_applied_are_refused_at_their_lines() {
    let deck = loaded_bar_deck();
    refused(
        "deck_moment",
        &edit(&deck, "51, 2, 0.02", "51, 5, 0.02"),
        &["*CLOAD 51, 5: a moment"],
    );
    refused(
        "deck_no_amplitude",
        &edit(&deck, "AMPLITUDE=UP\nEND", "AMPLITUDE=DOWN\nEND"),
        &["AMPLITUDE=DOWN: no *AMPLITUDE of that name"],
    );
    refused(
        "deck_odd_amplitude",
        &edit(&deck, "0.3, 0.5\n", "0.3\n"),
        &["*AMPLITUDE UP: 5 numbers"],
    );
    refused(
        "deck_back_amplitude",
        &edit(&deck, "0.3, 0.5\n", "0.01, 0.5\n"),
        &["*AMPLITUDE UP: time 0.01 does not follow 0.05"],
    );
    refused(
        "deck_smooth_amplitude",
        &edit(&deck, "NAME=UP", "NAME=UP, DEFINITION=SMOOTH STEP"),
        &["DEFINITION=TABULAR"],
    );
    refused(
        "deck_twice",
        &edit(&deck, "51, 2, 0.02", "51, 2, 0.02\n51, 2, 0.03"),
        &["the load on 51, dof 2, is given twice"],
    );
    refused(
        "deck_body_force",
        &edit(&deck, "END, P4, 2.0", "END, BX, 2.0"),
        &["*DLOAD BX: impact reads GRAV (gravity) and Pn"],
    );
    // a load on a held component goes to the support, as in CalculiX: the model leaves
    // that force out and keeps the rest
    let held = written(
        "deck_held_load",
        "bad.inp",
        &edit(&deck, "51, 2, 0.02", "51, 2, 0.02\n1, 1, 0.02"),
    );
    let scene = Scene::load(&held).expect("the deck reads");
    let model = impact::model::Model::from_scene(&scene).expect("the model builds");
    let pushed: usize = model.loads.iter().map(|l| l.dofs.len()).sum();
    assert_eq!(
        model.held_loads.iter().sum::<usize>(),
        1,
        "one force left to the support"
    );
    assert!(
        pushed > 0
            && model
                .loads
                .iter()
                .all(|l| l.dofs.iter().all(|&d| !model.fixed[d as usize]))
    );
}

/// The pushed bar of `tests/prescribed.rs` as a deck: a `*BOUNDARY` with a value along an
/// `*AMPLITUDE` (or the step's ramp) gives its `[[fix]] displacement` twin's history; without
/// either, a dynamic step's value would be a jump at t = 0, and it is refused.
#[test]
fn a_decks_boundary_displacement_runs_as_its_scene_twin() {
    let deck = loaded_bar_deck()
        .replace(
            "*DLOAD, AMPLITUDE=UP\nEND, P4, 2.0\n*CLOAD\n51, 2, 0.02\n",
            "",
        )
        .replace(
            "*NSET, NSET=NTIP\n101\n",
            "*NSET, NSET=NTIP\n101\n*NSET, NSET=NEND\n101, 202, 303, 404\n",
        )
        .replace(
            "*BOUNDARY\nNFIX, 1, 1\n",
            "*BOUNDARY\nNFIX, 1, 1\n*BOUNDARY, AMPLITUDE=UP\nNEND, 1, 1, -0.05\n",
        )
        .replace(
            "0.0, 0.0, 0.05, 1.0, 0.3, 0.5",
            "0.0, 0.0, 0.1, 1.0, 0.3, 0.0",
        );
    let path = written("deck_push", "pushed.inp", &deck);
    let (_, h) = run_file("deck_push", &path);
    let twin = pushed_bar(
        0.4,
        "displacement = [-0.05, 0.0, 0.0]\namplitude = [[0.0, 0.0], [0.1, 1.0], [0.3, 0.0]]\n",
    )
    .replace("divisions = [10, 1, 1]", "divisions = [100, 1, 1]")
    .replace("time_step = 0.0009\n", "");
    let (st, ht) = run_text("deck_push_twin", &twin);
    assert_eq!(st.expect("twin runs").status, "completed");
    for (a, b, floor) in [
        ("NTIP.ux", "tip.ux", 1e-9),
        ("strain_energy", "strain_energy", 1e-9),
        ("total_energy", "total_energy", 1e-3),
    ] {
        let d = difference(&h, a, &ht, b, floor);
        assert!(d < 1e-9, "{a} differs from the twin's {b} by {d}");
    }
    // the step's ramp in place of the amplitude
    let ramp = deck
        .replace("*BOUNDARY, AMPLITUDE=UP\n", "*BOUNDARY\n")
        .replace("*STEP\n", "*STEP, AMPLITUDE=RAMP\n");
    let path = written("deck_push_ramp", "pushed.inp", &ramp);
    let (_, h) = run_file("deck_push_ramp", &path);
    for (&t, u) in h.col("time").iter().zip(h.col("NTIP.ux")) {
        assert!(
            (u + 0.05 * t / 0.4).abs() < 1e-12,
            "the ramp's tip at {u} at {t}"
        );
    }
    refused(
        "deck_push_jump",
        &deck.replace("*BOUNDARY, AMPLITUDE=UP\n", "*BOUNDARY\n"),
        &["*BOUNDARY NEND", "a jump at t = 0", "AMPLITUDE=RAMP"],
    );
}

/// `scenes/loaded_bar.inp`: a bar held at one end under a step pressure `*DLOAD` on the
/// other, an implicit `*DYNAMIC` step, as it runs in CalculiX 2.20 too. Its end's
/// displacement against CalculiX's printed values (`ccx -i loaded_bar`, Debian's
/// calculix-ccx 2.20) and against wave theory; the trapezoidal rule keeps the energy.
#[test]
fn the_loaded_bar_deck_runs_as_calculix_runs_it() {
    let (s, h) = run_file("deck_loaded_bar", &repo().join("scenes/loaded_bar.inp"));
    assert_eq!(s.steps, 200);
    // ccx 2.20's NTIP x displacements at t = 0.05, 0.1, ..., 0.4
    let ccx = [
        -9.998408e-02,
        -1.999991e-01,
        -3.000000e-01,
        -3.939954e-01,
        -2.994876e-01,
        -2.000458e-01,
        -9.999571e-02,
        -7.600122e-03,
    ];
    let (t, u) = (h.col("time"), h.col("NTIP.ux"));
    for (k, c) in ccx.iter().enumerate() {
        let at = 0.05 * (k + 1) as f64;
        let i = t
            .iter()
            .position(|&x| (x - at).abs() < 1e-9)
            .expect("a row there");
        // within 0.3% of the largest printed value (0.22% measured over every row)
        assert!(
            (u[i] - c).abs() < 0.003 * 0.394,
            "{} at {at} against ccx's {c}",
            u[i]
        );
        // wave theory: -2 t out to -0.4 at 0.2, then back (2% of the peak: the mesh's)
        let wave = -2.0 * if at <= 0.2 { at } else { 0.4 - at };
        assert!(
            (u[i] - wave).abs() < 0.02 * 0.4,
            "{} at {at} against {wave}",
            u[i]
        );
    }
    let work = s.external_work.expect("the loads' work");
    assert!(work.abs() > 0.0);
    let drift = h
        .col("total_energy")
        .iter()
        .fold(0.0f64, |m, e| m.max(e.abs()));
    let most = h.col("external_work").into_iter().fold(0.0, f64::max);
    assert!(
        drift < 1e-9 * most,
        "total energy moved by {drift} of {most}"
    );
}
