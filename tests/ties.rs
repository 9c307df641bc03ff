//! `[[tie]]` (a deck's `*TIE`): a secondary surface's nodes follow the primary surface's
//! points beneath them. Checked against exact answers (a tie of matching meshes is one
//! body; a tie of nested meshes passes the patch test), and against CalculiX on the same
//! decks where ccx is installed, with the static cantilevers that need the stabilisation's
//! springs relaxed.

mod common;
use common::*;

use std::fmt::Write as _;
use std::path::Path;

const E: f64 = 210000.0;
const NU: f64 = 0.3;

/// A static scene of two boxes of hex8 stacked along `axis` (0 or 2), box `a` from the
/// origin to `a_max` in `na` divisions, box `b` from `b_min` to `b_max` in `nb`, `b`'s face
/// tied to `a`'s (`tie` false: one box over both, in `na` divisions doubled along `axis`).
/// `supports` and `extra` are appended.
struct TwoBoxes {
    a_max: [f64; 3],
    b_min: [f64; 3],
    b_max: [f64; 3],
    na: [usize; 3],
    nb: [usize; 3],
    axis: usize,
}

impl TwoBoxes {
    fn scene(&self, tie: bool, supports: &str) -> String {
        let v = |x: [f64; 3]| format!("[{:?}, {:?}, {:?}]", x[0], x[1], x[2]);
        let d = |n: [usize; 3]| format!("[{}, {}, {}]", n[0], n[1], n[2]);
        let mut t = format!(
            r#"title = "two boxes tied"
[run]
method = "static"
end_time = 1.0
time_step = 1.0

[[material]]
name = "steel"
density = 7.85e-9
youngs_modulus = {E:?}
poissons_ratio = {NU:?}
"#
        );
        let faces = [("x+", "x-"), ("", ""), ("z+", "z-")][self.axis];
        if tie {
            let _ = write!(
                t,
                r#"
[[body]]
name = "a"
material = "steel"
box = {{ min = [0.0, 0.0, 0.0], max = {}, divisions = {}, element = "hex8" }}

[[body]]
name = "b"
material = "steel"
box = {{ min = {}, max = {}, divisions = {}, element = "hex8" }}

[[tie]]
name = "glue"
secondary = {{ body = "b", face = "{}" }}
primary = {{ body = "a", face = "{}" }}
"#,
                v(self.a_max),
                d(self.na),
                v(self.b_min),
                v(self.b_max),
                d(self.nb),
                faces.1,
                faces.0,
            );
        } else {
            let mut n = self.na;
            n[self.axis] *= 2;
            let _ = write!(
                t,
                r#"
[[body]]
name = "a"
material = "steel"
box = {{ min = [0.0, 0.0, 0.0], max = {}, divisions = {}, element = "hex8" }}
"#,
                v(self.b_max),
                d(n),
            );
        }
        t + supports
    }
}

/// The probe lines of `points` on body `body`, named after it and their number from `first`.
fn probes(body: &str, points: &[[f64; 3]], first: usize) -> String {
    let mut t = String::new();
    for (k, p) in (first..).zip(points) {
        let _ = write!(
            t,
            "\n[[probe]]\nname = \"{body}{k}\"\nbody = \"{body}\"\npoint = [{:?}, {:?}, {:?}]\n",
            p[0], p[1], p[2]
        );
    }
    t
}

/// A cantilever 10 long and 1 square, as two halves whose meshes match at x = 5 tied
/// there, and as one box: clamped at x = 0 and loaded by 100 down at x = 10 in one static
/// increment, every probe along its top edge and its tip has the one box's displacement to
/// 1e-9 of the tip's. The tip is also CalculiX's (see below).
#[test]
fn a_tie_of_matching_meshes_is_one_body() {
    let beam = TwoBoxes {
        a_max: [5.0, 1.0, 1.0],
        b_min: [5.0, 0.0, 0.0],
        b_max: [10.0, 1.0, 1.0],
        na: [10, 2, 2],
        nb: [10, 2, 2],
        axis: 0,
    };
    let points: Vec<[f64; 3]> = (0..=10).map(|i| [i as f64, 0.5, 1.0]).collect();
    let (near, far): (Vec<_>, Vec<_>) = points.iter().partition(|p| p[0] <= 5.0);
    let clamp_and_load = |tie: bool| {
        let tip = if tie { "b" } else { "a" };
        let mut t = format!(
            "\n[[fix]]\nbody = \"a\"\nface = \"x-\"\ncomponents = [\"x\", \"y\", \"z\"]\n\n[[load]]\nbody = \"{tip}\"\nface = \"x+\"\nforce = [0.0, 0.0, {:?}]\n",
            -100.0 / 9.0
        );
        match tie {
            true => t += &(probes("a", &near, 0) + &probes("b", &far, 0)),
            false => t += &probes("a", &points, 0),
        }
        t
    };
    let (_, one) = run_completed("tie_one_beam", &beam.scene(false, &clamp_and_load(false)));
    let (_, tied) = run_completed("tie_two_beams", &beam.scene(true, &clamp_and_load(true)));
    let tip = one.last("a10.uz");
    assert!(tip < -1.6, "tip {tip}");
    for (k, p) in points.iter().enumerate() {
        let name = match p[0] <= 5.0 {
            true => format!("a{k}"),
            false => format!("b{}", k - near.len()),
        };
        for c in ["x", "y", "z"] {
            let (u1, u2) = (
                one.last(&format!("a{k}.u{c}")),
                tied.last(&format!("{name}.u{c}")),
            );
            assert!(
                (u1 - u2).abs() <= 1e-9 * tip.abs(),
                "x = {}: u{c} {u2} tied against {u1} in one body",
                p[0]
            );
        }
    }
}

/// A unit cube of 2 x 2 x 2 under a second of 4 x 4 x 3, the upper one's bottom tied to
/// the lower one's top, pulled 0.002 up by its top on symmetry planes: the upper mesh
/// refines the lower one, so the tie carries a uniform stress exactly, and every probe (the
/// upper cube's bottom nodes, which the tie sets, among them) has u = (-nu e x, -nu e y,
/// e z), e = 0.001, to 1e-6 of the top's (the static residual's tolerance).
#[test]
fn a_tie_of_nested_meshes_passes_the_patch_test() {
    let cubes = TwoBoxes {
        a_max: [1.0, 1.0, 1.0],
        b_min: [0.0, 0.0, 1.0],
        b_max: [1.0, 1.0, 2.0],
        na: [2, 2, 2],
        nb: [4, 4, 3],
        axis: 2,
    };
    let mut supports = String::new();
    for (face, c) in [("z-", "z"), ("x-", "x"), ("y-", "y")] {
        let _ = write!(
            supports,
            "\n[[fix]]\nbody = \"a\"\nface = \"{face}\"\ncomponents = [\"{c}\"]\n"
        );
    }
    supports += "\n[[fix]]\nbody = \"b\"\nface = \"z+\"\ncomponents = [\"z\"]\ndisplacement = [0.0, 0.0, 0.002]\n";
    let points: Vec<[f64; 3]> = (0..=4)
        .flat_map(|i| (0..=4).map(move |j| [0.25 * i as f64, 0.25 * j as f64, 1.0]))
        .chain([[0.5, 0.5, 0.5], [1.0, 1.0, 2.0], [0.25, 0.75, 4.0 / 3.0]])
        .collect();
    let (upper, lower) = (&points[..25], &points[25..26]);
    supports += &(probes("b", upper, 0) + &probes("a", lower, 0) + &probes("b", &points[26..], 25));
    let (_, h) = run_completed("tie_patch", &cubes.scene(true, &supports));
    let name = |k: usize| match k {
        25 => "a0".to_string(),
        k if k > 25 => format!("b{}", k - 1),
        k => format!("b{k}"),
    };
    let e = 0.001;
    for (k, p) in points.iter().enumerate() {
        let exact = [-NU * e * p[0], -NU * e * p[1], e * p[2]];
        for (a, c) in ["x", "y", "z"].iter().enumerate() {
            let u = h.last(&format!("{}.u{c}", name(k)));
            assert!(
                (u - exact[a]).abs() <= 1e-6 * 0.002,
                "{p:?}: u{c} {u} against {}",
                exact[a]
            );
        }
    }
}

/// A deck of two C3D8 blocks whose meshes differ, the second's face (`SLAVE`) tied to the
/// first's (`MASTER`) by `*TIE`, and a static `*STEP` that prints the slave block's nodes.
/// `patch`: two unit cubes stacked, 2 x 2 x 2 under 3 x 3 x 3, pulled by the top;
/// otherwise a cantilever of two halves, 10 x 2 x 2 and 7 x 3 x 3, loaded at its tip.
fn tied_deck(patch: bool) -> String {
    let block = |lo: [f64; 3], hi: [f64; 3], n: [usize; 3], node0: usize, elem0: usize| {
        let id = |i: usize, j: usize, k: usize| node0 + i + (n[0] + 1) * (j + (n[1] + 1) * k);
        let mut nodes = Vec::new();
        for k in 0..=n[2] {
            for j in 0..=n[1] {
                for i in 0..=n[0] {
                    let f = [i, j, k].map(|x| x as f64);
                    let x: [f64; 3] =
                        std::array::from_fn(|a| lo[a] + (hi[a] - lo[a]) * f[a] / n[a] as f64);
                    nodes.push((id(i, j, k), x));
                }
            }
        }
        let mut elements = Vec::new();
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
                    // the faces at the block's ends: x- S6, x+ S4, z- S1, z+ S2
                    let ends = [
                        (i == 0, "x-", "S6"),
                        (i + 1 == n[0], "x+", "S4"),
                        (k == 0, "z-", "S1"),
                        (k + 1 == n[2], "z+", "S2"),
                    ];
                    elements.push((elem0 + elements.len(), c, ends));
                }
            }
        }
        (nodes, elements)
    };
    let (a, b, master, slave) = match patch {
        true => (
            block([0.0; 3], [1.0; 3], [2, 2, 2], 1, 1),
            block([0.0, 0.0, 1.0], [1.0, 1.0, 2.0], [3, 3, 3], 1001, 1001),
            "z+",
            "z-",
        ),
        false => (
            block([0.0; 3], [5.0, 1.0, 1.0], [10, 2, 2], 1, 1),
            block([5.0, 0.0, 0.0], [10.0, 1.0, 1.0], [7, 3, 3], 1001, 1001),
            "x+",
            "x-",
        ),
    };
    let mut t = String::from("*HEADING\ntwo blocks of unlike meshes tied\n*NODE, NSET=NALL\n");
    for (id, x) in a.0.iter().chain(&b.0) {
        let _ = writeln!(t, "{id}, {:?}, {:?}, {:?}", x[0], x[1], x[2]);
    }
    for (name, blk) in [("EA", &a), ("EB", &b)] {
        let _ = writeln!(t, "*ELEMENT, TYPE=C3D8, ELSET={name}");
        for (e, c, _) in &blk.1 {
            let ids: Vec<String> = c.iter().map(|x| x.to_string()).collect();
            let _ = writeln!(t, "{e}, {}", ids.join(", "));
        }
    }
    for (name, blk, face) in [("MASTER", &a, master), ("SLAVE", &b, slave)] {
        let _ = writeln!(t, "*SURFACE, NAME={name}, TYPE=ELEMENT");
        for (e, _, ends) in &blk.1 {
            for (on, f, s) in ends {
                if *on && *f == face {
                    let _ = writeln!(t, "{e}, {s}");
                }
            }
        }
    }
    let set = |t: &mut String, name: &str, ids: Vec<usize>| {
        let _ = writeln!(t, "*NSET, NSET={name}");
        for chunk in ids.chunks(8) {
            let s: Vec<String> = chunk.iter().map(|x| x.to_string()).collect();
            let _ = writeln!(t, "{}", s.join(", "));
        }
    };
    let on = |nodes: &[(usize, [f64; 3])], a: usize, v: f64| -> Vec<usize> {
        (nodes.iter())
            .filter(|(_, x)| (x[a] - v).abs() < 1e-9)
            .map(|(i, _)| *i)
            .collect()
    };
    let tip = on(&b.0, 0, 10.0);
    let print: Vec<usize> = b.0.iter().map(|(i, _)| *i).collect();
    if patch {
        set(&mut t, "BOTTOM", on(&a.0, 2, 0.0));
        set(&mut t, "XSYM", on(&a.0, 0, 0.0));
        set(&mut t, "YSYM", on(&a.0, 1, 0.0));
        set(&mut t, "TOP", on(&b.0, 2, 2.0));
    } else {
        set(&mut t, "ROOT", on(&a.0, 0, 0.0));
        set(&mut t, "TIP", tip.clone());
    }
    set(&mut t, "PRINT", print);
    t += "*MATERIAL, NAME=STEEL\n*ELASTIC\n210000., 0.3\n*DENSITY\n7.85e-9\n";
    t += "*SOLID SECTION, ELSET=EA, MATERIAL=STEEL\n*SOLID SECTION, ELSET=EB, MATERIAL=STEEL\n";
    t += "*TIE, NAME=GLUE\nSLAVE, MASTER\n";
    t += &match patch {
        true => "*BOUNDARY\nBOTTOM, 3\nXSYM, 1\nYSYM, 2\n*STEP\n*STATIC\n1., 1.\n*BOUNDARY\nTOP, 3, 3, 0.002\n".to_string(),
        false => format!(
            "*BOUNDARY\nROOT, 1, 3\n*STEP\n*STATIC\n1., 1.\n*CLOAD\nTIP, 3, {:?}\n",
            -100.0 / tip.len() as f64
        ),
    };
    t + "*NODE PRINT, NSET=PRINT\nU\n*END STEP\n"
}

/// The largest difference of impact's probes from the displacements ccx prints, relative to
/// the largest printed value.
fn difference_from_ccx(dat: &str, deck: &Path, h: &History) -> f64 {
    let scene = impact::scene::Scene::load(deck).unwrap();
    let nodes = deck_nodes(&std::fs::read_to_string(deck).unwrap());
    let printed = reference_displacements(dat);
    let largest = (printed.iter().flat_map(|(_, v)| v.iter())).fold(0.0f64, |m, x| m.max(x.abs()));
    let mut worst = 0.0f64;
    for (n, v) in &printed {
        let x = nodes[n];
        let near = |p: &[f64; 3]| (0..3).all(|a| (p[a] - x[a]).abs() <= 1e-9 * (1.0 + x[a].abs()));
        let probe = (scene.probes.iter())
            .find(|p| near(&p.point))
            .expect("a probe on each printed node");
        for (a, c) in ["x", "y", "z"].iter().enumerate() {
            worst = worst.max((h.last(&format!("{}.u{c}", probe.name)) - v[a]).abs() / largest);
        }
    }
    worst
}

/// The two tied decks in impact and in ccx: every printed displacement within 1e-5 of the
/// largest (2.4e-7 and 2.8e-7 measured). Neither code's unlike meshes pass the patch test
/// (the slave nodes' forces reach the master nodes through the master's shape functions at
/// the slave nodes, which the 3 x 3 slave mesh cannot carry exactly), so the pulled cubes'
/// tie face is 3.7% off the uniform strain in both, the same way. The cantilever is taken in
/// one increment, where the static stabilisation's springs once held 6% of the tip load.
#[test]
fn tied_decks_of_unlike_meshes_match_calculix() {
    for (name, patch) in [("tie_patch", true), ("tie_beam", false)] {
        let deck = written_deck(name, &tied_deck(patch));
        let Some(dat) = ccx_output(&deck) else {
            return;
        };
        let (s, h) = run_scene_at(&deck, &out_dir(&format!("{name}_run")));
        let s = s.unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(s.status, "completed", "{name}: {:?}", s.warnings);
        let d = difference_from_ccx(&dat, &deck, &h);
        eprintln!("{name}: {d:e} of the largest printed displacement from ccx");
        assert!(
            d <= 1e-5,
            "{name}: {d:e} of the largest printed displacement"
        );
    }
}

/// A tie on the explicit path, a tie whose sides are apart by more than its tolerance, one
/// on a rigid body and one whose node another tie sets too are refused, each naming the tie.
#[test]
fn a_tie_is_refused_where_it_cannot_hold() {
    let cubes = TwoBoxes {
        a_max: [1.0, 1.0, 1.0],
        b_min: [0.0, 0.0, 1.0],
        b_max: [1.0, 1.0, 2.0],
        na: [2, 2, 2],
        nb: [3, 3, 3],
        axis: 2,
    };
    let held = "\n[[fix]]\nbody = \"a\"\nface = \"z-\"\ncomponents = [\"x\", \"y\", \"z\"]\n";
    let text = cubes.scene(true, held);
    let explicit = text
        .replace("method = \"static\"", "method = \"explicit\"")
        .replace("time_step = 1.0\n", "");
    let e = refusal_of("tie_explicit", &explicit);
    assert!(e.contains("tie[0]") && e.contains("explicit"), "{e}");
    let apart = text.replace("min = [0.0, 0.0, 1.0]", "min = [0.0, 0.0, 1.1]");
    let e = refusal_of("tie_apart", &apart);
    assert!(
        e.contains("tie[0]") && e.contains("no secondary node lies within"),
        "{e}"
    );
    let rigid = text.replace(
        "primary = { body = \"a\", face = \"z+\" }",
        "primary = { rigid_body = \"a\" }",
    );
    let e = refusal_of("tie_rigid", &rigid);
    assert!(e.contains("tie[0].primary.rigid_body"), "{e}");
    let twice = text.clone() + "\n[[tie]]\nname = \"again\"\nsecondary = { body = \"b\", face = \"z-\" }\nprimary = { body = \"a\", face = \"z+\" }\n";
    let e = refusal_of("tie_twice", &twice);
    assert!(
        e.contains("tie[1]") && e.contains("tied by an earlier tie"),
        "{e}"
    );
}
