//! What a `[[step]]` changes besides the equations: its own supports (`[[step.fix]]`, a
//! displacement ramped from where the nodes are), the supports it ends (`release_fixes`) and
//! a contact's friction (`[[step.contact]]`), each against an exact answer; and CalculiX's
//! decks that change them between steps (`*BOUNDARY`, `OP=NEW`, `*CHANGE FRICTION`)
//! against ccx's own output, where the Debian packages `calculix-ccx` and
//! `calculix-ccx-test` are installed.

mod common;
use common::*;

use std::path::Path;

const E: f64 = 1000.0;

/// A unit block (Poisson 0) held on its bottom, its top pressed down by the named fix
/// `press` to `d1` over the first step (t = 0 to 1); `steps` appended.
fn pressed_block(d1: f64, steps: &str) -> String {
    format!(
        r#"title = "a block pressed by a support that a step moves on"
[run]
method = "static"
end_time = 2.0
time_step = 0.25

[[material]]
name = "soft"
youngs_modulus = {E}
poissons_ratio = 0.0

[[body]]
name = "block"
material = "soft"
box = {{ min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], divisions = [2, 2, 2] }}

[[fix]]
body = "block"
face = "z-"
components = ["x", "y", "z"]

[[fix]]
name = "press"
body = "block"
face = "z+"
components = ["z"]
displacement = [0.0, 0.0, {d1}]

[[probe]]
name = "top"
body = "block"
point = [0.5, 0.5, 1.0]
{steps}"#
    )
}

/// The value of column `name` at time `t`.
fn at(h: &History, name: &str, t: f64) -> f64 {
    let row = (h.col("time").iter())
        .position(|x| (x - t).abs() < 1e-9)
        .unwrap_or_else(|| panic!("no row at t = {t}"));
    h.col(name)[row]
}

/// A step's fix takes the top over from the run's own and moves it on from -0.01 to -0.03:
/// the top follows the two ramps, and the reaction the named fix gives is E A u / L at
/// every increment, to 2e-5 (the static stabilisation's 1e-6 of the stiffness).
#[test]
fn a_steps_displacement_ramps_on_from_where_the_nodes_are() {
    let step = "\n[[step]]\nstart = 1.0\n\n[[step.fix]]\nbody = \"block\"\nface = \"z+\"\ncomponents = [\"z\"]\ndisplacement = [0.0, 0.0, -0.03]\n";
    let (_, h) = run_completed("step_ramp", &pressed_block(-0.01, step));
    for (t, u) in [
        (0.5, -0.005),
        (1.0, -0.01),
        (1.25, -0.015),
        (1.5, -0.02),
        (2.0, -0.03),
    ] {
        let top = at(&h, "top.uz", t);
        assert!(
            (top - u).abs() <= 1e-9 * u.abs(),
            "t = {t}: {top} against {u}"
        );
        let reaction = at(&h, "press.fz", t);
        assert!(
            (reaction - E * u).abs() <= 2e-5 * (E * u).abs(),
            "t = {t}: reaction {reaction} against E A u / L = {}",
            E * u
        );
    }
    assert!(h.last("total_energy").abs() <= 1e-5 * h.last("strain_energy"));
}

/// A step that releases the pressing fix: the block springs back, its strain energy gone,
/// and the energy the fix put in is the strain energy it held.
#[test]
fn a_released_support_lets_the_block_spring_back() {
    let step = "\n[[step]]\nstart = 1.0\nrelease_fixes = [\"press\"]\n";
    let (_, h) = run_completed("step_release", &pressed_block(-0.01, step));
    let held = at(&h, "strain_energy", 1.0);
    let exact = 0.5 * E * 0.01 * 0.01;
    assert!(
        (held - exact).abs() <= 1e-9 * exact,
        "{held} against {exact}"
    );
    assert!(h.last("strain_energy") <= 1e-12 * held);
    assert!(h.last("top.uz").abs() <= 1e-12);
    assert!(h.last("press.fz").abs() <= 1e-9 * E * 0.01);
}

/// A block pressed on its base by 2 and dragged 0.2 over the first step at mu = 0.3; a
/// step lowers the friction to 0.1 and drags it back to 0.
const DRAGGED: &str = r#"title = "a block dragged over its base, its friction lowered by a step"
[run]
method = "static"
end_time = 2.0
time_step = 0.125

[[material]]
name = "soft"
youngs_modulus = 1000.0
poissons_ratio = 0.0

[[body]]
name = "base"
material = "soft"
box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], divisions = [2, 2, 2] }

[[body]]
name = "block"
material = "soft"
box = { min = [0.0, 0.0, 1.0], max = [1.0, 1.0, 2.0], divisions = [2, 2, 2] }

[[fix]]
body = "base"
face = "z-"
components = ["x", "y", "z"]

[[contact]]
name = "joint"
secondary = { body = "block", face = "z-" }
primary = { body = "base", face = "z+" }
friction = 0.3

[[load]]
body = "block"
face = "z+"
pressure = 2.0
amplitude = [[0.0, 0.0], [0.5, 1.0], [2.0, 1.0]]

[[fix]]
body = "block"
face = "z+"
components = ["x", "y"]
displacement = [0.2, 0.0, 0.0]
amplitude = [[0.0, 0.0], [0.5, 0.0], [1.0, 1.0]]

[[step]]
start = 1.0
end = 2.0

[[step.fix]]
body = "block"
face = "z+"
components = ["x", "y"]
displacement = [0.0, 0.0, 0.0]

[[step.contact]]
name = "joint"
friction = 0.1
"#;

/// A block pressed on its base by 2 and dragged 0.2 over the first step at mu = 0.3; a
/// step lowers the friction to 0.1 and drags it back: the friction force is mu N on
/// each step's cone, at once after the change too, to 1e-5 (the normal force is reported
/// after the pressure's last update; the cone was met before it).
#[test]
fn a_step_lowers_the_friction_to_its_new_cone() {
    let text = DRAGGED;
    let (_, h) = run_completed("step_friction", text);
    for (t, mu) in [(1.0, 0.3), (1.125, 0.1), (2.0, 0.1)] {
        let (tangential, normal) = (
            at(&h, "joint.tangential_force", t),
            at(&h, "joint.normal_force", t),
        );
        assert!((normal - 2.0).abs() <= 0.01 * 2.0, "t = {t}: {normal}");
        assert!(
            (tangential - mu * normal).abs() <= 1e-5 * mu * normal,
            "t = {t}: friction {tangential} against mu N = {}",
            mu * normal
        );
    }
    // the stick slopes let go of what the lower cone no longer holds: dissipated
    assert!(at(&h, "joint.friction_work", 1.125) > at(&h, "joint.friction_work", 1.0));
    let (total, work) = (h.last("total_energy"), h.last("joint.friction_work"));
    assert!(total.abs() <= 0.05 * work, "{total} against {work}");
}

/// The same block dragged on forward at the lower friction: the trailing nodes' pressure
/// sits near zero, and Newton's active set cycles between 6 and 9 pressed nodes until its
/// updates are damped. It slides on the new cone (1e-5). The balance closes within 10% of
/// the friction's work: the first increment takes the supports' work as the trapezoid of
/// their force before the change (0.6) and after it (0.2), 7% measured.
#[test]
fn a_block_dragged_on_at_a_lowered_friction_settles_on_its_cone() {
    let forward = DRAGGED.replace(
        "displacement = [0.0, 0.0, 0.0]\n\n[[step.contact]]",
        "displacement = [0.4, 0.0, 0.0]\n\n[[step.contact]]",
    );
    assert_ne!(forward, DRAGGED);
    let (_, h) = run_completed("step_friction_forward", &forward);
    for t in [1.25, 2.0] {
        let (tangential, normal) = (
            at(&h, "joint.tangential_force", t),
            at(&h, "joint.normal_force", t),
        );
        assert!(
            (tangential - 0.1 * normal).abs() <= 1e-5 * 0.1 * normal,
            "t = {t}: friction {tangential} against mu N = {}",
            0.1 * normal
        );
    }
    let (total, work) = (h.last("total_energy"), h.last("joint.friction_work"));
    assert!(total.abs() <= 0.1 * work, "{total} against {work}");
}

#[test]
fn step_changes_refuse_what_they_cannot_mean() {
    let named = "\n[[step]]\nstart = 1.0\n\n[[step.fix]]\nname = \"again\"\nbody = \"block\"\nface = \"z+\"\ncomponents = [\"z\"]\n";
    let e = refusal_of("step_fix_named", &pressed_block(-0.01, named));
    assert!(e.contains("step[0].fix[0].name"), "{e}");
    let unknown = "\n[[step]]\nstart = 1.0\nrelease_fixes = [\"clamp\"]\n";
    let e = refusal_of("step_release_unknown", &pressed_block(-0.01, unknown));
    assert!(
        e.contains("step[0].release_fixes") && e.contains("press"),
        "{e}"
    );
    let contact = "\n[[step]]\nstart = 1.0\n\n[[step.contact]]\nname = \"joint\"\nfriction = 0.1\n";
    let e = refusal_of("step_contact_unknown", &pressed_block(-0.01, contact));
    assert!(e.contains("step[0].contact[0].name"), "{e}");
    // a step's moving support on the implicit path, whose first step has none
    let step = "\n[[step]]\nstart = 1.0\n\n[[step.fix]]\nbody = \"block\"\nface = \"z+\"\ncomponents = [\"z\"]\ndisplacement = [0.0, 0.0, -0.03]\n";
    let moved = (pressed_block(-0.01, step))
        .replace("displacement = [0.0, 0.0, -0.01]\n", "")
        .replace("method = \"static\"", "method = \"implicit\"")
        .replace(
            "poissons_ratio = 0.0",
            "poissons_ratio = 0.0\ndensity = 1.0",
        );
    let e = refusal_of("step_fix_implicit", &moved);
    assert!(e.contains("explicit"), "{e}");
}

/// `*NODE PRINT, NSET=Nall` of `U` at the end of every step of `text`: the probes impact
/// makes and the displacements ccx prints.
fn printing_every_step(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        if line.trim().to_ascii_uppercase().starts_with("*END STEP") {
            out += "*NODE PRINT,NSET=Nall\nU\n";
        }
        out += line;
        out.push('\n');
    }
    out
}

/// The largest difference of impact's probes from ccx's printed displacements, at every
/// printed time on impact's increments, relative to the largest printed value.
fn difference_from(dat: &str, deck: &Path, h: &History) -> f64 {
    let scene = impact::scene::Scene::load(deck).unwrap();
    let nodes = deck_nodes(&std::fs::read_to_string(deck).unwrap());
    let blocks = reference_blocks(dat);
    let largest = (blocks.iter().flat_map(|(_, b)| b.iter()))
        .flat_map(|(_, v)| v.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let times = h.col("time");
    let mut worst = 0.0f64;
    let mut compared = 0;
    for (t, block) in &blocks {
        // ccx sizes its own increments; those on impact's are compared
        let Some(row) = times.iter().position(|x| (x - t).abs() <= 1e-9 * t) else {
            continue;
        };
        compared += 1;
        for (n, v) in block {
            let x = nodes[n];
            let near =
                |p: &[f64; 3]| (0..3).all(|a| (p[a] - x[a]).abs() <= 1e-9 * (1.0 + x[a].abs()));
            let probe = (scene.probes.iter()).find(|p| near(&p.point)).unwrap();
            for (a, c) in ["x", "y", "z"].iter().enumerate() {
                let u = h.col(&format!("{}.u{c}", probe.name))[row];
                worst = worst.max((u - v[a]).abs() / largest);
            }
        }
    }
    assert!(
        compared >= 4,
        "{compared} printed times on impact's increments"
    );
    worst
}

/// Two cubes stacked, pressed, the top one's corner pulled sideways and back
/// (`*BOUNDARY` in later steps, fricloop) and its friction changed (`*CHANGE FRICTION`,
/// changefric), in steps of different increments: every displacement ccx prints at the
/// times both reach agrees with ccx's within 1e-4 of the largest (2.4e-5 measured; ccx's
/// NLGEOM against impact's small strains).
#[test]
fn calculix_decks_that_change_supports_and_friction_between_steps_match_ccx() {
    let Some(dir) = ccx_decks() else {
        return;
    };
    for name in ["fricloop", "changefric"] {
        let text = printing_every_step(&deck_text(&dir, &format!("{name}.inp")));
        let deck = written_deck(name, &text);
        let Some(dat) = ccx_output(&deck) else {
            return;
        };
        let (s, h) = run_scene_at(&deck, &out_dir(&format!("{name}_run")));
        let s = s.unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(s.status, "completed", "{name}: {:?}", s.warnings);
        let d = difference_from(&dat, &deck, &h);
        assert!(
            d <= 1e-4,
            "{name}: {d:e} of the largest printed displacement"
        );
    }
}

/// friction2: a cube pressed on a block by 100 slides 1 one way, back 2 (`*BOUNDARY,
/// OP=NEW`), and 2 again at half the friction (`*CHANGE FRICTION`). Its reference output
/// prints the contact stresses on the unit face at each step's end: impact's normal force
/// is their sum within 1e-3 (ccx's NLGEOM pressure is 100.0126), and the friction force is
/// mu N exactly (1e-6), so ccx's within 1e-3.
#[test]
fn calculix_friction2_slides_on_the_cone_its_reference_output_prints() {
    let Some(dir) = ccx_decks() else {
        return;
    };
    let deck = written_deck("friction2", &deck_text(&dir, "friction2.inp"));
    let (s, h) = run_scene_at(&deck, &out_dir("friction2_run"));
    let s = s.unwrap_or_else(|e| panic!("friction2: {e}"));
    assert_eq!(s.status, "completed", "{:?}", s.warnings);
    let reference = deck_text(&dir, "friction2.dat.ref");
    let stresses = contact_stress_blocks(&reference);
    assert_eq!(stresses.len(), 4);
    for ((t, nodes), mu) in stresses.iter().zip([0.2, 0.2, 0.2, 0.1]) {
        // four nodes of the unit face, a quarter of it each
        let pressure: f64 = nodes.iter().map(|v| 0.25 * v[0]).sum();
        let shear = [1, 2].map(|a| nodes.iter().map(|v| 0.25 * v[a]).sum::<f64>());
        let shear = shear[0].hypot(shear[1]);
        let (normal, tangential) = (
            at(&h, "Sslav-Smast.normal_force", *t),
            at(&h, "Sslav-Smast.tangential_force", *t),
        );
        assert!(
            (normal - pressure).abs() <= 1e-3 * pressure,
            "t = {t}: {normal} against {pressure}"
        );
        if *t > 1.0 {
            assert!(
                (tangential - mu * normal).abs() <= 1e-6 * normal,
                "t = {t}: {tangential}"
            );
            assert!(
                (tangential - shear).abs() <= 1e-3 * shear,
                "t = {t}: {tangential} against {shear}"
            );
        }
    }
}

/// Each `contact stress` block of a `.dat`: its time and each node's (pressure, tangential
/// 1, tangential 2).
fn contact_stress_blocks(text: &str) -> Vec<(f64, Vec<[f64; 3]>)> {
    let mut out = Vec::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        if !line.trim_start().starts_with("contact stress") {
            continue;
        }
        let t: f64 = line.split_whitespace().last().unwrap().parse().unwrap();
        let rows: Vec<[f64; 3]> = (lines.by_ref())
            .skip(1)
            .map(|l| l.split_whitespace().collect::<Vec<_>>())
            .take_while(|f| f.len() == 4)
            .map(|f| [1, 2, 3].map(|i| f[i].parse::<f64>().unwrap()))
            .collect();
        out.push((t, rows));
    }
    out
}

/// The dragged block stopped before its second step and inside it, and resumed: the
/// unbroken history, byte for byte (the step's ramp goes on from where the nodes are to
/// its `end`, so a resumed run follows it too, whatever end time the stopped run had).
#[test]
fn a_run_whose_steps_change_supports_and_friction_resumes_to_the_unbroken_history() {
    let whole = format!("{DRAGGED}\n[output]\ncheckpoint_every = 2\n");
    let s = run_resumable("step_changes_whole", "dragged", &whole, (false, None)).unwrap();
    assert_eq!(s.status, "completed");
    for (tag, stop) in [
        ("step_changes_before", "0.75"),
        ("step_changes_inside", "1.25"),
    ] {
        let early = whole.replace("end_time = 2.0", &format!("end_time = {stop}"));
        let s = run_resumable(tag, "dragged", &early, (false, None)).unwrap();
        assert_eq!(s.status, "completed");
        let r = run_resumable(tag, "dragged", &whole, (true, None)).expect("resumed");
        assert_eq!(r.status, "completed");
        assert_eq!(
            history_text("step_changes_whole"),
            history_text(tag),
            "{tag}"
        );
    }
}
