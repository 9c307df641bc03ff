//! VTU frames read back by an independent reader: `scripts/check_vtu.py` opens the `.pvd`
//! and every frame with meshio (PyPI) and compares the displacement at each probe's node
//! with the history, besides the arrays' presence and shapes and von Mises against the
//! stress components. `.ci/run` installs meshio; without it this test fails and says so.

mod common;
use common::*;

use std::process::Command;

use impact::model::Model;
use impact::scene::Scene;

fn check(tag: &str, text: &str, frames: usize) {
    // parsed as a file of scenes/, so that mesh paths resolve
    let path = repo().join("scenes").join(format!("{tag}.toml"));
    let scene = Scene::parse(text, &path).expect("valid scene");
    let (s, _) = run_scene_text(tag, text);
    s.expect("run completes");
    let model = Model::from_scene(&scene);
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
}

/// The paper's two bars (implicit), a frame every 10 of 40 steps and one at t = 0.
#[test]
fn implicit_frames_read_back_with_meshio() {
    let text = format!(
        "{}\n[output]\nvtu_every = 10\n",
        scene_text("two_bars.toml")
    );
    check("vtu_two_bars", &text, 5);
}

/// The cube on the plate on the explicit path (friction, two bodies, a surface contact):
/// frames every 20 steps.
#[test]
fn explicit_frames_read_back_with_meshio() {
    let text = format!(
        "{}\n[output]\nvtu_every = 20\n",
        scene_text("cube_on_plate.toml")
            .replace("[run]", "[run]\nmethod = \"explicit\"")
            .replace("end_time = 0.1", "end_time = 0.045")
    );
    check("vtu_cube_on_plate", &text, 2);
}

/// A tet4 body from a Gmsh file (VTK_TETRA cells, constant stress per cell), a frame every
/// 100 steps of the block drop.
#[test]
fn tet4_frames_read_back_with_meshio() {
    let text = format!(
        "{}\n[output]\nvtu_every = 100\n",
        scene_text("block_tet_drop.toml")
    );
    check("vtu_block_tet", &text, 4);
}
