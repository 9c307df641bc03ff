//! Static steps (`method = "static"`): two stacked blocks pressed together, with hard
//! contact and with a penalty law, against the exact uniaxial answer; pressed by a
//! prescribed displacement, the named fix's reaction against it and the energy balance; and
//! CalculiX's own contact and equation decks (static, and dynamic with steps) against their
//! reference output, where the Debian package `calculix-ccx-test` is installed.

mod common;
use common::*;

use impact::run::{run, RunOptions};
use impact::scene::Scene;
use std::path::Path;

const E: f64 = 1000.0;
const P: f64 = 2.0;

/// A 1 x 1 x 1 base on z = 0 (its bottom held along z) and a block on it, Poisson 0, no
/// density (a static step needs none); `top` appended (the block's load or fix), `contact`
/// the contact's extra keys.
fn stacked_blocks(contact: &str, top: &str) -> String {
    format!(
        r#"title = "two stacked blocks pressed together"
[run]
method = "static"
end_time = 1.0
time_step = 0.25

[[material]]
name = "soft"
youngs_modulus = {E}
poissons_ratio = 0.0

[[body]]
name = "base"
material = "soft"
box = {{ min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], divisions = [2, 2, 2] }}

[[body]]
name = "block"
material = "soft"
box = {{ min = [0.0, 0.0, 1.0], max = [1.0, 1.0, 2.0], divisions = [2, 2, 2] }}

[[fix]]
name = "floor"
body = "base"
face = "z-"
components = ["z"]

[[contact]]
name = "joint"
secondary = {{ body = "block", face = "z-" }}
primary = {{ body = "base", face = "z+" }}
{contact}

[[probe]]
name = "base_top"
body = "base"
point = [0.5, 0.5, 1.0]

[[probe]]
name = "block_bottom"
body = "block"
point = [0.5, 0.5, 1.0]

[[probe]]
name = "block_top"
body = "block"
point = [0.5, 0.5, 2.0]

{top}"#
    )
}

/// A ramped pressure P on the block's top.
const PRESSED: &str = "[[load]]\nbody = \"block\"\nface = \"z+\"\npressure = 2.0\namplitude = [[0.0, 0.0], [1.0, 1.0]]\n";

fn run_text(tag: &str, text: &str) -> (impact::output::Summary, History) {
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    run_path(tag, &path)
}

fn run_path(tag: &str, path: &Path) -> (impact::output::Summary, History) {
    let (s, h) = run_scene_at(path, &out_dir(&format!("{tag}_run")));
    let s = s.unwrap_or_else(|e| panic!("{tag}: {e}"));
    assert_eq!(s.status, "completed", "{tag}: {:?}", s.warnings);
    (s, h)
}

/// The energy balance: what the loads and supports did is the strain energy (and the
/// springs' share), to `tol` of the strain energy.
fn balanced(tag: &str, h: &History, tol: f64) {
    let (total, strain) = (h.last("total_energy"), h.last("strain_energy"));
    assert!(
        strain > 0.0 && total.abs() <= tol * strain,
        "{tag}: total energy {total:e} against strain energy {strain:e}"
    );
}

#[test]
fn hard_contact_passes_the_load_with_no_overlap() {
    let (_, h) = run_text("static_hard", &stacked_blocks("", PRESSED));
    // each block shortens by P L / E under the ramped pressure, at every step
    for (k, &t) in h.col("time").iter().enumerate().skip(1) {
        let strain = t * P / E;
        let at = |c: &str| h.col(c)[k];
        assert!((at("base_top.uz") + strain).abs() <= 2e-5 * strain, "t {t}");
        assert!(
            (at("block_top.uz") + 2.0 * strain).abs() <= 2e-5 * strain,
            "t {t}"
        );
        let overlap = at("block_bottom.uz") - at("base_top.uz");
        assert!(overlap.abs() <= 1e-4 * strain, "t {t}: overlap {overlap:e}");
    }
    assert!((h.last("joint.normal_force") - P).abs() <= 2e-5 * P);
    balanced("static_hard", &h, 1e-5);
}

#[test]
fn a_penalty_law_overlaps_by_the_pressure_over_its_stiffness() {
    let k = 500.0;
    let (_, h) = run_text(
        "static_penalty",
        &stacked_blocks(&format!("stiffness = {k}"), PRESSED),
    );
    let strain = P / E;
    let overlap = h.last("block_bottom.uz") - h.last("base_top.uz");
    assert!((h.last("base_top.uz") + strain).abs() <= 2e-5 * strain);
    assert!(
        (overlap + P / k).abs() <= 2e-5 * P / k,
        "overlap {overlap:e} against {:e}",
        -P / k
    );
    assert!((h.last("block_top.uz") + 2.0 * strain + P / k).abs() <= 2e-5 * (2.0 * strain + P / k));
    balanced("static_penalty", &h, 1e-5);
}

#[test]
fn a_prescribed_displacement_is_resisted_by_the_exact_reaction() {
    let d = 0.01;
    let top = format!(
        "[[fix]]\nname = \"press\"\nbody = \"block\"\nface = \"z+\"\ncomponents = [\"z\"]\ndisplacement = [0.0, 0.0, {}]\n",
        -d
    );
    let (_, h) = run_text("static_pressed", &stacked_blocks("", &top));
    // two unit blocks in series shortened by d: stress E d / 2, through the contact
    let force = E * d / 2.0;
    // the supports push back: down on the block's top, up on the base's bottom (to the
    // stabilisation's 1e-6 of the stiffness)
    assert!(
        (h.last("press.fz") + force).abs() <= 2e-5 * force,
        "{}",
        h.last("press.fz")
    );
    assert!((h.last("floor.fz") - force).abs() <= 2e-5 * force);
    assert!((h.last("joint.normal_force") - force).abs() <= 2e-5 * force);
    assert!((h.last("base_top.uz") + d / 2.0).abs() <= 2e-5 * d);
    balanced("static_pressed", &h, 1e-5);
    let work = 0.5 * force * d;
    let strain = h.last("strain_energy");
    assert!((strain - work).abs() <= 2e-5 * work, "{strain}");
}

/// A slender steel cantilever (10 x 1 x 1, 20 x 2 x 2 hex8) clamped at one end and loaded
/// by 100 down at the other in a single increment. A tip load is a small fraction of the
/// stiffness's diagonal times the displacement, so the static stabilisation's springs held
/// 6% of it before they were relaxed: the strain energy was 73.9 against the load's 78.5.
/// Relaxed, the strain energy is half the load's work within 1e-6 (Clapeyron), and the
/// springs hold nothing: the balance closes within 1e-6 of it.
#[test]
fn a_cantilever_loaded_in_one_increment_stores_half_the_loads_work() {
    let text = r#"title = "a cantilever loaded in one increment"
[run]
method = "static"
end_time = 1.0
time_step = 1.0

[[material]]
name = "steel"
density = 7.85e-9
youngs_modulus = 210000.0
poissons_ratio = 0.3

[[body]]
name = "beam"
material = "steel"
box = { min = [0.0, 0.0, 0.0], max = [10.0, 1.0, 1.0], divisions = [20, 2, 2], element = "hex8" }

[[fix]]
body = "beam"
face = "x-"
components = ["x", "y", "z"]

[[load]]
body = "beam"
face = "x+"
force = [0.0, 0.0, -11.111111111111111]
amplitude = [[0.0, 0.0], [1.0, 1.0]]
"#;
    let mut text = text.to_string();
    let tip: Vec<[f64; 3]> = (0..3)
        .flat_map(|j| (0..3).map(move |k| [10.0, 0.5 * j as f64, 0.5 * k as f64]))
        .collect();
    for (i, p) in tip.iter().enumerate() {
        text += &format!(
            "\n[[probe]]\nname = \"tip{i}\"\nbody = \"beam\"\npoint = [{:?}, {:?}, {:?}]\n",
            p[0], p[1], p[2]
        );
    }
    let (_, h) = run_text("static_cantilever", &text);
    let work: f64 = (0..tip.len())
        .map(|i| -0.5 * 100.0 / 9.0 * h.last(&format!("tip{i}.uz")))
        .sum();
    let strain = h.last("strain_energy");
    assert!(
        (strain - work).abs() <= 1e-6 * work,
        "strain energy {strain} against half the load's work {work}"
    );
    balanced("static_cantilever", &h, 1e-6);
}

/// The refusal of the scene `text`, run from `tag`'s folder.
fn refusal(tag: &str, text: &str) -> String {
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let scene = Scene::load(&path).unwrap();
    let opts = RunOptions {
        out: Some(dir.join("out")),
        quiet: true,
        ..Default::default()
    };
    run(&scene, &opts).expect_err("refused").to_string()
}

#[test]
fn a_static_step_refuses_what_it_cannot_solve() {
    let text = stacked_blocks("friction = 0.3", PRESSED);
    // a free rigid body, which nothing holds without inertia
    let free = text.clone()
        + "\n[[rigid_body]]\nname = \"wall\"\nmass = 1.0\nposition = [5.0, 0.5, 0.5]\nshape = { plane = { normal = [1.0, 0.0, 0.0] } }\n";
    let e = refusal("static_refused", &free);
    assert!(e.contains("rigid_body[0]") && e.contains("static"), "{e}");
    // a stick slope outside a static step
    let stick = text
        .replace("friction = 0.3", "friction = 0.3\nstick_slope = 100.0")
        .replace("method = \"static\"", "method = \"implicit\"")
        .replace(
            "[[material]]\nname = \"soft\"",
            "[[material]]\nname = \"soft\"\ndensity = 1.0",
        );
    let e = refusal("static_refused_stick", &stick);
    assert!(e.contains("contact[0].stick_slope"), "{e}");
    // a penalty stiffness outside a static step
    let dynamic = text
        .replace("friction = 0.3", "stiffness = 100.0")
        .replace("method = \"static\"", "method = \"implicit\"")
        .replace(
            "[[material]]\nname = \"soft\"",
            "[[material]]\nname = \"soft\"\ndensity = 1.0",
        );
    let e = refusal("static_refused_penalty", &dynamic);
    assert!(e.contains("contact[0].stiffness"), "{e}");
    // an interference fit pushed apart outside a static step
    let resolve = dynamic.replace("stiffness = 100.0", "initial_penetration = \"resolve\"");
    let e = refusal("static_refused_resolve", &resolve);
    assert!(e.contains("contact[0]") && e.contains("resolve"), "{e}");
}

/// A unit cube on z in [0, 1] (its bottom held, its top's z tied together) and a second
/// cube of side `S` standing on it, turned 45 degrees about z and overlapping it by `G0`;
/// the second's bottom corner node 10 is the node-based slave surface (`*SURFACE,
/// TYPE=NODE`), its other bottom corners' z tied to it, its four top corners loaded by 1
/// each, in a static step with a linear pressure-overclosure of slope `K` (CalculiX's
/// contact3, written out).
fn corner_on_cube_deck() -> String {
    corner_on_cube_with(&format!("LINEAR\n{K:e}, 3."), G0)
}

/// [`corner_on_cube_deck`] with the pressure-overclosure `law` (its parameter, then its
/// data line) and the overlap `g0`.
fn corner_on_cube_with(law: &str, g0: f64) -> String {
    let (c, h, z0) = (0.5, S / 2f64.sqrt(), 1.0 - g0);
    let mut t = String::from("*NODE, NSET=NALL\n");
    let base = [[1., 1., 0.], [1., 0., 0.], [1., 0., 1.], [1., 1., 1.]];
    let base = base
        .iter()
        .chain(&[[0., 1., 0.], [0., 0., 0.], [0., 0., 1.], [0., 1., 1.]]);
    for (i, p) in base.enumerate() {
        t += &format!("{}, {}, {}, {}\n", i + 1, p[0], p[1], p[2]);
    }
    let turned = [
        [c, c + h, z0],
        [c + h, c, z0],
        [c + h, c, z0 + S],
        [c, c + h, z0 + S],
        [c - h, c, z0],
        [c, c - h, z0],
        [c, c - h, z0 + S],
        [c - h, c, z0 + S],
    ];
    for (i, p) in turned.iter().enumerate() {
        t += &format!("{}, {}, {}, {}\n", i + 9, p[0], p[1], p[2]);
    }
    t += "*ELEMENT, TYPE=C3D8, ELSET=EALL\n1, 1, 2, 3, 4, 5, 6, 7, 8\n2, 9, 10, 11, 12, 13, 14, 15, 16\n";
    t += "*NSET, NSET=NFIX\n1, 2, 5, 6\n*NSET, NSET=NFIXXY\n3, 4, 7, 8, 9, 10, 13, 14\n";
    t += "*BOUNDARY\nNFIX, 1, 3\nNFIXXY, 1, 2\n";
    for (n, m) in [(4, 3), (7, 3), (8, 3), (9, 10), (13, 10), (14, 10)] {
        t += &format!("*EQUATION\n2\n{n}, 3, 1., {m}, 3, -1.\n");
    }
    t += "*MATERIAL, NAME=EL\n*ELASTIC\n210000., .3\n*SOLID SECTION, ELSET=EALL, MATERIAL=EL\n";
    t += "*ELSET, ELSET=EMAST\n1\n*NSET, NSET=NSLAV\n10\n*SURFACE, NAME=SMAST\nEMAST, S5\n";
    t += "*SURFACE, NAME=SSLAV, TYPE=NODE\nNSLAV\n";
    t += "*CONTACT PAIR, INTERACTION=SI1, TYPE=NODE TO SURFACE\nSSLAV, SMAST\n";
    t +=
        &format!("*SURFACE INTERACTION, NAME=SI1\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE={law}\n");
    t += "*STEP\n*STATIC\n*CLOAD\n11, 3, -1.\n12, 3, -1.\n15, 3, -1.\n16, 3, -1.\n";
    t += "*NODE PRINT, NSET=NALL\nU\n*END STEP\n";
    t
}

const S: f64 = 0.2;
const G0: f64 = 0.02;
const K: f64 = 1e7;

/// The slave node of a node-based surface that covers no face takes a quarter of each of
/// its three boundary faces as its area, 3 S^2 / 4: the overlap left under the load of 4 is
/// 4 / (K 3 S^2 / 4). The first increment pushes the 0.02 overlap apart (an interference
/// fit, initial_penetration = "resolve"), its springs' energy 1/2 K A G0^2 held at t = 0.
#[test]
fn a_node_based_slave_node_carries_the_load_through_its_three_faces() {
    let deck = written_deck("corner_on_cube", &corner_on_cube_deck());
    let (_, h) = run_path("corner_on_cube", &deck);
    let area = 3.0 * S * S / 4.0;
    let overlap = G0 - (h.last("NALL_10.uz") - h.last("NALL_3.uz"));
    let expected = 4.0 / (K * area);
    // the stabilisation's springs take 1e-6 of the stiffness times the 0.02 lift
    assert!(
        (overlap - expected).abs() <= 1e-3 * expected,
        "overlap {overlap:e} against {expected:e}"
    );
    let stored = 0.5 * K * area * G0 * G0;
    let e0 = h.col("total_energy")[0];
    assert!(
        (e0 - stored).abs() <= 1e-9 * stored,
        "{e0} against {stored}"
    );
    // the same deck in a dynamic step: "resolve" is a static step's
    let dynamic = corner_on_cube_deck()
        .replace("*STEP\n*STATIC\n", "*STEP\n*DYNAMIC\n1e-7, 1e-6\n")
        .replace(".3\n*SOLID", ".3\n*DENSITY\n7.8e-9\n*SOLID");
    let scene = written_deck("corner_on_cube_dynamic", &dynamic);
    let e = impact::run::run(
        &Scene::load(&scene).unwrap(),
        &RunOptions {
            out: Some(out_dir("corner_on_cube_dynamic_run")),
            quiet: true,
            ..Default::default()
        },
    );
    let e = e.expect_err("refused").to_string();
    assert!(e.contains("initial_penetration"), "{e}");
}

/// The same corner, touching at the start, under CalculiX's exponential
/// pressure-overclosure, p = p0 exp(beta g) with beta = ln 100 / c0: the overclosure under
/// the load of 4 on the area 3 S^2 / 4 is ln(4 / (A p0)) / beta.
#[test]
fn an_exponential_pressure_overclosure_leaves_the_overclosure_of_its_law() {
    let (c0, p0) = (1e-4, 10.0);
    let deck = corner_on_cube_with(&format!("EXPONENTIAL\n{c0:e}, {p0}"), 0.0);
    let (_, h) = run_path(
        "corner_exponential",
        &written_deck("corner_exponential", &deck),
    );
    let area = 3.0 * S * S / 4.0;
    let beta = 100f64.ln() / c0;
    let expected = (4.0 / (area * p0)).ln() / beta;
    let overclosure = h.last("NALL_3.uz") - h.last("NALL_10.uz");
    assert!(
        (overclosure - expected).abs() <= 2e-3 * expected,
        "overclosure {overclosure:e} against {expected:e}"
    );
}

/// Runs CalculiX's deck `name` as it stands and returns the largest difference of its
/// printed displacements from the reference output's, relative to the largest of them. The
/// probes are matched to the printed nodes by position (where two bodies' nodes coincide,
/// on a contact face, the closer of their two displacements counts).
fn ccx_difference(dir: &Path, name: &str) -> f64 {
    let text = deck_text(dir, &format!("{name}.inp"));
    let deck = written_deck(name, &text);
    let scene = Scene::load(&deck).unwrap();
    let probes: Vec<(String, [f64; 3])> = (scene.probes.iter())
        .map(|p| (p.name.clone(), p.point))
        .collect();
    let (_, h) = run_path(name, &deck);
    let reference = reference_displacements(&deck_text(dir, &format!("{name}.dat.ref")));
    let nodes = deck_nodes(&text);
    let largest = reference
        .iter()
        .flat_map(|(_, v)| v.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let mut worst = 0.0f64;
    let mut matched = 0;
    for (n, v) in &reference {
        let x = nodes[n];
        let near = |p: &[f64; 3]| (0..3).all(|a| (p[a] - x[a]).abs() <= 1e-9 * (1.0 + x[a].abs()));
        let diffs = (probes.iter().filter(|(_, p)| near(p))).map(|(name, _)| {
            (0..3)
                .map(|a| (h.last(&format!("{name}.u{}", ["x", "y", "z"][a])) - v[a]).abs())
                .fold(0.0, f64::max)
        });
        if let Some(d) = diffs.reduce(f64::min) {
            worst = worst.max(d / largest);
            matched += 1;
        }
    }
    assert!(
        matched * 10 >= reference.len() * 9,
        "{name}: {matched} of {} matched",
        reference.len()
    );
    worst
}

/// Runs CalculiX's deck `name` and returns the largest difference of every printed
/// displacement, at every printed time, from the reference output's, relative to the
/// largest of them (probes matched by position, as [`ccx_difference`]).
fn ccx_history_difference(dir: &Path, name: &str) -> f64 {
    let text = deck_text(dir, &format!("{name}.inp"));
    let deck = written_deck(name, &text);
    let scene = Scene::load(&deck).unwrap();
    let (_, h) = run_path(name, &deck);
    let blocks = reference_blocks(&deck_text(dir, &format!("{name}.dat.ref")));
    let nodes = deck_nodes(&text);
    let largest = (blocks.iter().flat_map(|(_, b)| b.iter()))
        .flat_map(|(_, v)| v.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let times = h.col("time");
    let mut worst = 0.0f64;
    for (t, block) in &blocks {
        let row = (times.iter())
            .position(|x| (x - t).abs() <= 1e-9 * t)
            .expect("a row at each printed time");
        for (n, v) in block {
            let x = nodes[n];
            let near =
                |p: &[f64; 3]| (0..3).all(|a| (p[a] - x[a]).abs() <= 1e-9 * (1.0 + x[a].abs()));
            let probe = (scene.probes.iter())
                .find(|p| near(&p.point))
                .expect("a probe on each printed node");
            for (a, c) in ["x", "y", "z"].iter().enumerate() {
                let u = h.col(&format!("{}.u{c}", probe.name))[row];
                worst = worst.max((u - v[a]).abs() / largest);
            }
        }
    }
    worst
}

#[test]
fn calculix_static_contact_decks_match_their_reference_output() {
    let Some(dir) = ccx_decks() else {
        return;
    };
    // two cubes stacked with a linear pressure-overclosure; a cube pressed on a block
    // through a penalty; Hüeber's two-material contact patch, with two penalties, each with
    // either block as the slave side
    for (name, bound) in [
        ("contactenergy", 1e-5),
        ("cubespring", 0.01),
        ("hueeber1", 1e-3),
        ("hueeber2", 0.01),
        ("hueeber3", 1e-3),
        ("hueeber4", 0.01),
        // a node-based slave surface of one node, overlapping by 0.02 and by 1e-4, and
        // touching under an exponential pressure-overclosure
        ("contact3", 1e-3),
        ("contact6", 0.01),
        ("contact1", 1e-4),
    ] {
        let d = ccx_difference(&dir, name);
        eprintln!("{name}: {d:e} of the largest printed displacement");
        assert!(
            d <= bound,
            "{name}: {d:e} of the largest printed displacement"
        );
    }
}

/// CalculiX's equrem decks: two cubes, the top one's bottom tied to the bottom one's top
/// by `*EQUATION`s, pulled by a pressure in a `*DYNAMIC` step; a second step removes the
/// equations (all of them, two by node, two by node set). ccx's `*DYNAMIC` is the
/// alpha-method at alpha = -0.05, impact's the trapezoidal rule (alpha = 0), which ccx
/// itself follows within 7.5e-5 of the largest printed displacement; the reference is
/// ccx's own, 0.9% from it at most.
#[test]
fn calculix_dynamic_decks_that_remove_their_equations_match_their_reference_output() {
    let Some(dir) = ccx_decks() else {
        return;
    };
    for name in ["equrem1", "equrem2", "equrem3"] {
        let d = ccx_history_difference(&dir, name);
        eprintln!("{name}: {d:e} of the largest printed displacement");
        assert!(
            d <= 0.01,
            "{name}: {d:e} of the largest printed displacement"
        );
    }
}

/// Two unit blocks side by side, their bottoms held along z; the first pressed on its top,
/// the second's top nodes tied to the first's by `[[equation]]`s (u_z of B = u_z of A): the
/// two carry the load together, each top lowered by P L / (2 E).
#[test]
fn equations_tie_a_second_block_to_the_pressed_one() {
    let mut text = String::from(
        r#"title = "two blocks tied by equations"
[run]
method = "static"
end_time = 1.0
time_step = 0.5

[[material]]
name = "soft"
youngs_modulus = 1000.0
poissons_ratio = 0.0
"#,
    );
    for (name, x) in [("a", 0.0), ("b", 2.0)] {
        text += &format!(
            "\n[[body]]\nname = \"{name}\"\nmaterial = \"soft\"\nbox = {{ min = [{x}, 0.0, 0.0], max = [{}, 1.0, 1.0], divisions = [2, 2, 2] }}\n\n[[fix]]\nbody = \"{name}\"\nface = \"z-\"\ncomponents = [\"z\"]\n\n[[probe]]\nname = \"{name}_top\"\nbody = \"{name}\"\npoint = [{}, 0.5, 1.0]\n",
            x + 1.0,
            x + 0.5
        );
    }
    text += "\n[[load]]\nbody = \"a\"\nface = \"z+\"\npressure = 2.0\namplitude = [[0.0, 0.0], [1.0, 1.0]]\n";
    let near = |x: f64, y: f64| {
        format!(
            "region = {{ min = [{}, {}, 0.99], max = [{}, {}, 1.01] }}",
            x - 0.01,
            y - 0.01,
            x + 0.01,
            y + 0.01
        )
    };
    for i in 0..3 {
        for j in 0..3 {
            let (x, y) = (0.5 * i as f64, 0.5 * j as f64);
            text += &format!(
                "\n[[equation]]\nterms = [{{ body = \"b\", {}, component = \"z\", coefficient = 1.0 }}, {{ body = \"a\", {}, component = \"z\", coefficient = -1.0 }}]\n",
                near(x + 2.0, y),
                near(x, y)
            );
        }
    }
    let (_, h) = run_text("static_equations", &text);
    let exact = -P / (2.0 * E);
    for probe in ["a_top", "b_top"] {
        let uz = h.last(&format!("{probe}.uz"));
        assert!(
            (uz - exact).abs() <= 2e-5 * exact.abs(),
            "{probe}: {uz} against {exact}"
        );
    }
    assert!(
        (h.last("a_top.uz") - h.last("b_top.uz")).abs() <= 1e-12,
        "tied exactly"
    );
    balanced("static_equations", &h, 1e-5);
    // an equation on the explicit path is refused
    let dynamic = text
        .replace("method = \"static\"", "method = \"explicit\"")
        .replace(
            "poissons_ratio = 0.0",
            "poissons_ratio = 0.0\ndensity = 1.0",
        );
    let e = refusal("static_equations_explicit", &dynamic);
    assert!(e.contains("equation[0]") && e.contains("static"), "{e}");
}

/// Friction in a static step: the block pressed by P (over the first half), then its top
/// dragged sideways by 0.2, far more than the blocks shear: every pressed node slides, its
/// traction on the Coulomb cone, so the friction force is mu times the normal force; the
/// balance closes on the friction's dissipation.
#[test]
fn a_block_dragged_over_its_base_slides_on_the_coulomb_cone() {
    let mu = 0.3;
    let top = "[[load]]\nbody = \"block\"\nface = \"z+\"\npressure = 2.0\namplitude = [[0.0, 0.0], [0.5, 1.0], [1.0, 1.0]]\n\n[[fix]]\nname = \"drag\"\nbody = \"block\"\nface = \"z+\"\ncomponents = [\"x\", \"y\"]\ndisplacement = [0.2, 0.0, 0.0]\namplitude = [[0.0, 0.0], [0.5, 0.0], [1.0, 1.0]]\n\n[[fix]]\nname = \"base_held\"\nbody = \"base\"\nface = \"z-\"\ncomponents = [\"x\", \"y\"]\n";
    let text = stacked_blocks(&format!("friction = {mu}"), top);
    let (s, h) = run_text("static_dragged", &text);
    assert_eq!(s.status, "completed");
    let (tangential, normal) = (
        h.last("joint.tangential_force"),
        h.last("joint.normal_force"),
    );
    assert!((normal - P).abs() <= 0.01 * P, "{normal}");
    assert!(
        (tangential - mu * normal).abs() <= 1e-6 * mu * normal,
        "friction {tangential} against mu N = {}",
        mu * normal
    );
    assert_eq!(h.last("joint.sliding"), h.last("joint.active"));
    // the supports hold the friction, less the normal force's share on the base's top,
    // which the friction's couple tilts
    let drag = h.last("drag.fx");
    assert!(
        (drag.abs() - tangential).abs() <= 0.05 * tangential,
        "{drag}"
    );
    // (to the stabilisation's share)
    assert!((drag + h.last("base_held.fx")).abs() <= 1e-3 * drag.abs());
    // before the drag: no friction
    let t = h.col("time");
    let half = t.iter().position(|&x| (x - 0.5).abs() < 1e-9).unwrap();
    assert!(h.col("joint.tangential_force")[half].abs() <= 1e-9);
    assert!(h.last("joint.friction_work") > 0.0);
    // the trapezoid over two dragging increments, where nodes pass from stick to slip
    balanced("static_dragged", &h, 0.05);
}
