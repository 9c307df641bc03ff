//! VTU frames read back by an independent reader: `scripts/check_vtu.py` opens the `.pvd`
//! and every frame with meshio (PyPI) and compares the displacement at each probe's node
//! with the history, besides the arrays' presence and shapes and von Mises against the
//! stress components. `.ci/run` installs meshio and sets `IMPACT_REQUIRE_MESHIO=1`, under
//! which a missing meshio fails these tests; elsewhere (a fresh machine with only the README's
//! setup) they print why and pass without reading the frames.
//! The cell arrays `body` and `material` are read back with meshio too and checked against the
//! scene: each cell's corners are nodes of the body its `body` names, whose material it carries.

mod common;
use common::*;

use std::process::Command;

use impact::model::Model;
use impact::scene::Scene;

fn check(tag: &str, text: &str, frames: usize) {
    if !meshio_available(tag) {
        return;
    }
    // parsed as a file of scenes/, so that mesh paths resolve
    let path = repo().join("scenes").join(format!("{tag}.toml"));
    let scene = Scene::parse(text, &path).expect("valid scene");
    let (s, _) = run_scene_text(tag, text);
    s.expect("run completes");
    let model = Model::from_scene(&scene).expect("model builds");
    let dir = out_path(tag);
    let mut cmd = Command::new("python3");
    cmd.arg(repo().join("scripts/check_vtu.py"))
        .arg(&dir)
        .arg(tag);
    for p in &model.probes {
        cmd.arg(format!("{}={}", p.name, p.node));
    }
    let out = cmd.output().expect("python3 runs");
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    eprintln!("{text}");
    assert!(
        !text.contains("No module named 'meshio'"),
        "meshio is missing: python3 -m pip install meshio"
    );
    assert!(
        out.status.success(),
        "{tag}: the frames do not check out:\n{text}"
    );
    assert!(text.contains(&format!("{frames} frames ok")), "{text}");
    check_cell_ids(tag, &scene, frames);
}

/// Prints, for every frame of the `.pvd`, the dtypes of the `body` and `material` cell arrays
/// of each cell block and then one line per cell: type, body, material, corner nodes.
const DUMP_CELL_IDS: &str = r#"
import sys, xml.etree.ElementTree as ET
import meshio
run_dir, stem = sys.argv[1], sys.argv[2]
for d in ET.parse(f"{run_dir}/{stem}.pvd").getroot().iter("DataSet"):
    mesh = meshio.read(f"{run_dir}/{d.get('file')}")
    print("frame", d.get("file"))
    for block, body, material in zip(mesh.cells, mesh.cell_data["body"], mesh.cell_data["material"]):
        print("dtype", block.type, body.dtype, material.dtype)
        for cell, b, m in zip(block.data, body, material):
            print(block.type, b, m, *cell)
"#;

/// Every frame's `body` and `material` cell arrays against the scene: a body's nodes are a
/// block of the numbering in the scene's order of bodies, so a cell belongs to the body that
/// owns its corners; it carries that body's material, and each body has as many cells as its
/// mesh has elements.
fn check_cell_ids(tag: &str, scene: &Scene, frames: usize) {
    let mut first = 0;
    let bodies: Vec<(std::ops::Range<usize>, usize, usize)> = scene
        .bodies
        .iter()
        .map(|b| {
            let parts = b.parts();
            let nodes = first..first + parts.nodes.len();
            first = nodes.end;
            (nodes, b.material, parts.element_count())
        })
        .collect();
    let out = Command::new("python3")
        .arg("-c")
        .arg(DUMP_CELL_IDS)
        .arg(out_path(tag))
        .arg(tag)
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "{tag}: reading the cell arrays failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let mut counts: Vec<Vec<usize>> = Vec::new();
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        match f[0] {
            "frame" => counts.push(vec![0; bodies.len()]),
            "dtype" => assert_eq!(f[2..], ["int32", "int32"], "{tag}: {line}"),
            kind => {
                let ids: Vec<usize> = f[1..].iter().map(|v| v.parse().unwrap()).collect();
                let (b, m, corners) = (ids[0], ids[1], &ids[2..]);
                let expected = if kind == "hexahedron" { 8 } else { 4 };
                assert_eq!(corners.len(), expected, "{tag}: {line}");
                let (nodes, material, _) = &bodies[b];
                assert!(
                    corners.iter().all(|n| nodes.contains(n)),
                    "{tag}: a cell of body {b} has corners outside its nodes {nodes:?}: {line}"
                );
                assert_eq!(m, *material, "{tag}: body {b}'s material: {line}");
                counts.last_mut().expect("a frame line first")[b] += 1;
            }
        }
    }
    assert_eq!(counts.len(), frames, "{tag}: frames with cell arrays");
    let elements: Vec<usize> = bodies.iter().map(|b| b.2).collect();
    for c in &counts {
        assert_eq!(*c, elements, "{tag}: cells per body");
    }
}

/// The paper's two bars (implicit), a frame every 10 of 40 steps and one at t = 0. B's
/// material is a copy of A's listed before it, so that the `material` of a cell differs from
/// its `body`.
#[test]
fn implicit_frames_read_back_with_meshio() {
    let text = scene_text("two_bars.toml");
    let text = edit(
        &text,
        "[[material]]\nname = \"elastic\"",
        "[[material]]\nname = \"elastic_b\"\ndensity = 0.01\nyoungs_modulus = 100.0\n\
         poissons_ratio = 0.0\n\n[[material]]\nname = \"elastic\"",
    );
    let text = edit(
        &text,
        "name = \"B\"\nmaterial = \"elastic\"",
        "name = \"B\"\nmaterial = \"elastic_b\"",
    );
    let text = format!("{text}\n[output]\nvtu_every = 10\n");
    check("vtu_two_bars", &text, 5);
}

/// The cube on the plate on the explicit path (friction, two bodies, a surface contact):
/// frames every 20 steps, and one at the last step (the 23rd).
#[test]
fn explicit_frames_read_back_with_meshio() {
    let text = format!(
        "{}\n[output]\nvtu_every = 20\n",
        scene_text("cube_on_plate.toml")
            .replace("[run]", "[run]\nmethod = \"explicit\"")
            .replace("end_time = 0.1", "end_time = 0.045")
    );
    check("vtu_cube_on_plate", &text, 3);
}

/// A tet4 body from a Gmsh file (VTK_TETRA cells, constant stress per cell), a frame every
/// 100 steps of the block drop and one at its last step (392).
#[test]
fn tet4_frames_read_back_with_meshio() {
    let text = format!(
        "{}\n[output]\nvtu_every = 100\n",
        scene_text("block_tet_drop.toml")
    );
    check("vtu_block_tet", &text, 5);
}

/// Hex8 and tet4 cells in one frame, the tet body first in the scene: the writer puts every
/// hex8 before every tet4, so the cells' order is not the bodies' order and `body` must follow
/// each cell. A free hex8 box of its own material (listed first) floats above the tet block
/// drop; 131 steps, a frame every 50 and one at the last step.
#[test]
fn mixed_cells_carry_their_body_and_material() {
    let text = scene_text("block_tet_drop.toml");
    let text = edit(&text, "end_time = 0.06", "end_time = 0.02");
    let text = edit(
        &text,
        "[[material]]",
        "[[material]]\nname = \"stiff\"\ndensity = 0.01\nyoungs_modulus = 200.0\n\
         poissons_ratio = 0.25\n\n[[material]]",
    );
    let text = edit(
        &text,
        "[[rigid_plane]]",
        "[[body]]\nname = \"box\"\nmaterial = \"stiff\"\n\
         box = { min = [3.0, 0.0, 3.0], max = [4.0, 1.0, 4.0], divisions = [2, 2, 2] }\n\n\
         [[rigid_plane]]",
    );
    let text = format!("{text}\n[output]\nvtu_every = 50\n");
    check("vtu_mixed_cells", &text, 4);
}

/// Recomputes Hashin's four indices and the maximum stress index of every cell of the last
/// frame of material `ply` from its `material_stress` (an independent implementation of the
/// formulas of `material::failure`; the other cells' indices must be zero) and prints the
/// largest difference from the frame's `failure_index`, and the largest index.
const CHECK_FAILURE: &str = r#"
import sys, xml.etree.ElementTree as ET
import meshio
run_dir, stem = sys.argv[1], sys.argv[2]
xt, xc, yt, yc, s12, s23 = map(float, sys.argv[3:9])
last = list(ET.parse(f"{run_dir}/{stem}.pvd").getroot().iter("DataSet"))[-1]
mesh = meshio.read(f"{run_dir}/{last.get('file')}")
worst, largest, cells = 0.0, 0.0, 0
ply = int(sys.argv[9])
data = zip(mesh.cell_data["material_stress"], mesh.cell_data["failure_index"], mesh.cell_data["material"])
for s, f, m in data:
    for (a, b, c, d, e, g), got, material in zip(s, f, m):
        if material != ply:
            # a material without strengths: zeros
            worst = max(worst, max(abs(x) for x in got))
            continue
        lt = (d * d + g * g) / s12**2
        tt = (e * e - b * c) / s23**2
        i1 = b + c
        want = [
            (a / xt) ** 2 + lt if a >= 0 else 0.0,
            (a / xc) ** 2 if a < 0 else 0.0,
            (i1 / yt) ** 2 + tt + lt if i1 >= 0 else 0.0,
            ((yc / (2 * s23)) ** 2 - 1) * i1 / yc + (i1 / (2 * s23)) ** 2 + tt + lt if i1 < 0 else 0.0,
            max(a / xt if a >= 0 else -a / xc, b / yt if b >= 0 else -b / yc,
                c / yt if c >= 0 else -c / yc, abs(d) / s12, abs(g) / s12, abs(e) / s23),
        ]
        worst = max(worst, max(abs(x - y) / max(1.0, abs(y)) for x, y in zip(got, want)))
        largest = max(largest, max(want))
        cells += 1
print("cells", cells, "difference", worst, "largest", largest)
"#;

/// The laminate's frames carry each cell's failure indices (`strength` on its ply material):
/// the last frame's `failure_index` equals the indices recomputed from its
/// `material_stress` by an independent implementation, within 1e-12 relative, and is zero
/// in the steel ball (no strengths).
#[test]
fn laminate_frames_carry_the_failure_indices_of_their_ply_stresses() {
    let tag = "laminate_failure_indices";
    if !meshio_available(tag) {
        return;
    }
    let text = edit(
        &scene_text("sphere_on_laminate.toml"),
        "end_time = 1.4e-4",
        "end_time = 1.2e-5",
    )
    .replace("vtu_every = 20", "vtu_every = 12");
    let (s, _) = run_scene_text(tag, &text);
    s.expect("run completes");
    let out = Command::new("python3")
        .args(["-c", CHECK_FAILURE])
        .arg(out_path(tag))
        .arg(tag)
        // the strengths of carbon_epoxy, the scene's second material
        .args(["1500", "1500", "40", "246", "68", "68", "1"])
        .output()
        .expect("python3 runs");
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    eprintln!("{text}");
    assert!(out.status.success(), "{text}");
    let field = |name: &str| -> f64 {
        let words: Vec<&str> = text.split_whitespace().collect();
        let at = words.iter().position(|w| *w == name).expect(name);
        words[at + 1].parse().expect("a number")
    };
    assert!(field("cells") > 0.0);
    assert!(field("difference") < 1e-12, "{text}");
    assert!(
        field("largest") > 0.0,
        "the impact must load the plies: {text}"
    );
}

/// Prints `step m1 .. m5` for each frame of the run: the largest of each failure index over
/// its cells.
const FRAME_FAILURE_MAXIMA: &str = r#"
import sys, re, xml.etree.ElementTree as ET
import meshio
run_dir, stem = sys.argv[1], sys.argv[2]
for d in ET.parse(f"{run_dir}/{stem}.pvd").getroot().iter("DataSet"):
    name = d.get("file")
    step = int(re.search(r"_(\d+)\.vtu$", name).group(1))
    fi = meshio.read(f"{run_dir}/{name}").cell_data["failure_index"][0]
    print(step, *(repr(float(v)) for v in fi.max(axis=0)))
"#;

/// The history's failure index columns are, at each frame's step, the largest of the
/// frame's cells' indices (a layered laminate: the drop-weight coupon on a coarse mesh), and
/// the summary's first failure is the first row where one reaches 1.
#[test]
fn the_history_carries_the_largest_failure_indices_of_the_frames() {
    let tag = "failure_history";
    if !meshio_available(tag) {
        return;
    }
    let text = edit(
        &scene_text("drop_weight_d7136_elastic.toml"),
        "divisions = [50, 34, 4]",
        "divisions = [30, 20, 2]",
    );
    let text = edit(&text, "end_time = 4.5e-3", "end_time = 2.0e-3");
    let text = edit(&text, "vtu_every = 500", "vtu_every = 1000");
    let (s, h) = run_scene_text(tag, &text);
    let s = s.expect("run completes");
    let out = Command::new("python3")
        .args(["-c", FRAME_FAILURE_MAXIMA])
        .arg(out_path(tag))
        .arg(tag)
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let names = impact::material::failure::INDICES.map(|n| format!("failure_index.{n}"));
    let columns: Vec<Vec<f64>> = names.iter().map(|n| h.col(n)).collect();
    let mut frames = 0;
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let v: Vec<f64> = line
            .split_whitespace()
            .map(|w| w.parse().unwrap())
            .collect();
        let step = v[0] as usize;
        for k in 0..5 {
            let (frame, row) = (v[1 + k], columns[k][step]);
            assert!(
                (frame - row).abs() <= 1e-9 * frame.abs().max(1e-6),
                "step {step}, {}: frame {frame}, history {row}",
                names[k]
            );
        }
        frames += 1;
    }
    assert!(frames >= 3, "{frames} frames");
    // the first row where an index reaches 1, and the index largest there
    let first = (0..h.rows.len()).find(|&i| columns.iter().any(|c| c[i] >= 1.0));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_path(tag).join("summary.json")).unwrap())
            .unwrap();
    let reported = &summary["first_failure"];
    match first {
        Some(i) => {
            let largest = (0..5)
                .max_by(|&a, &b| columns[a][i].total_cmp(&columns[b][i]))
                .unwrap();
            assert_eq!(reported["step"].as_u64(), Some(i as u64), "{reported}");
            assert_eq!(
                reported["index"].as_str(),
                Some(impact::material::failure::INDICES[largest])
            );
            assert_eq!(reported["body"].as_str(), Some("coupon"));
            assert!(
                reported["ply"].as_u64().is_some_and(|p| p < 24),
                "{reported}"
            );
        }
        None => assert!(reported.is_null(), "{reported}"),
    }
    assert_eq!(s.status, "completed");
    eprintln!("{frames} frames; first failure {reported}");
}
