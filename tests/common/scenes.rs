//! Scenes from the shipped files or from text, run into a fresh folder per test.

use std::path::PathBuf;

use impact::output::Summary;
use impact::run::{run, RunOptions};
use impact::scene::Scene;

use super::history::History;

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn scene_text(name: &str) -> String {
    std::fs::read_to_string(repo().join("scenes").join(name)).expect("shipped scene")
}

/// Replaces `from` (which must occur) by `to`.
pub fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "scene text lacks {from:?}");
    text.replacen(from, to, 1)
}

/// Where the run tagged `tag` writes.
pub fn out_path(tag: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(tag)
}

/// [`out_path`], emptied for a new run.
pub fn out_dir(tag: &str) -> PathBuf {
    let d = out_path(tag);
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs a scene given as text; returns the summary (or error) and the history written.
pub fn run_text(tag: &str, text: &str) -> (impact::Result<Summary>, History) {
    run_text_on(tag, text, None)
}

/// The device a test runs a scene on: the one named, else the scene's, where the scene
/// names one; a scene left to `device = "auto"` runs on the CPU in f64, so that its f64
/// tolerances hold on machines with a GPU too (auto would take a real GPU, in f32, for
/// 20,000 elements and more, and lavapipe never).
fn test_device(
    device: Option<impact::scene::DeviceChoice>,
    scene: &Scene,
) -> Option<impact::scene::DeviceChoice> {
    use impact::scene::DeviceChoice;
    match (device, scene.run.device) {
        (Some(d), _) => Some(d),
        (None, DeviceChoice::Auto) => Some(DeviceChoice::Cpu),
        (None, _) => None,
    }
}

/// Runs a scene text, on the given device if one is named (else as [`test_device`]).
pub fn run_text_on(
    tag: &str,
    text: &str,
    device: Option<impact::scene::DeviceChoice>,
) -> (impact::Result<Summary>, History) {
    let dir = out_dir(tag);
    // as if it were the file scenes/<tag>.toml, so that mesh paths resolve against scenes/
    let path = repo().join("scenes").join(format!("{tag}.toml"));
    let scene = Scene::parse(text, &path).expect("valid scene");
    let opts = RunOptions {
        out: Some(dir.clone()),
        device: test_device(device, &scene),
        quiet: true,
        ..Default::default()
    };
    let s = run(&scene, &opts);
    if let Err(e) = &s {
        // a run that stops before its first row leaves no history to read
        eprintln!("{tag}: {e}");
    }
    (s, History::read(&dir.join("history.csv")))
}

/// Runs `text`, as if it were the file `scenes/<stem>.toml`, into `tag`'s folder: a fresh
/// one, or (`resume`) the one it ran in before, from its latest checkpoint; on the device
/// named, else as [`test_device`] picks it.
pub fn run_resumable(
    tag: &str,
    stem: &str,
    text: &str,
    (resume, device): (bool, Option<impact::scene::DeviceChoice>),
) -> impact::Result<Summary> {
    let path = repo().join("scenes").join(format!("{stem}.toml"));
    let scene = Scene::parse(text, &path).expect("valid scene");
    let opts = RunOptions {
        out: Some(if resume { out_path(tag) } else { out_dir(tag) }),
        device: test_device(device, &scene),
        quiet: true,
        resume,
        ..Default::default()
    };
    run(&scene, &opts)
}

/// The history the run tagged `tag` wrote, as text.
pub fn history_text(tag: &str) -> String {
    std::fs::read_to_string(out_path(tag).join("history.csv")).expect("a history")
}

/// Runs the scene file `path` into `out`.
pub fn run_scene_at(
    path: &std::path::Path,
    out: &std::path::Path,
) -> (impact::Result<Summary>, History) {
    let scene = Scene::load(path).expect("valid scene");
    let opts = RunOptions {
        out: Some(out.to_path_buf()),
        device: test_device(None, &scene),
        quiet: true,
        ..Default::default()
    };
    let s = run(&scene, &opts);
    (s, History::read(&out.join("history.csv")))
}

/// Writes `text` as the scene file of `tag`'s folder, runs it into `<tag>_run` and asserts
/// that it completed without warnings; returns its summary and history.
pub fn run_completed(tag: &str, text: &str) -> (Summary, History) {
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let (s, h) = run_scene_at(&path, &out_dir(&format!("{tag}_run")));
    let s = s.unwrap_or_else(|e| panic!("{tag}: {e}"));
    assert_eq!(s.status, "completed", "{tag}: {:?}", s.warnings);
    (s, h)
}

/// The refusal of the scene `text` (the scene file of `tag`'s folder), by its reading or by
/// its run, as text.
pub fn refusal_of(tag: &str, text: &str) -> String {
    let dir = out_dir(tag);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let scene = match Scene::load(&path) {
        Ok(scene) => scene,
        Err(e) => return e.to_string(),
    };
    let opts = RunOptions {
        out: Some(dir.join("out")),
        quiet: true,
        ..Default::default()
    };
    run(&scene, &opts).expect_err("refused").to_string()
}

/// [`run_text`]; the name says that the text's mesh paths resolve against `scenes/`.
pub fn run_scene_text(tag: &str, text: &str) -> (impact::Result<Summary>, History) {
    run_text(tag, text)
}

/// The fine two bars (`two_bars_fine.toml`) with both boxes meshed as tet4 (each cell cut
/// into six tetrahedra), bar A with `a` x `a` cells across and bar B with `b` x `b`, so that
/// the primary surface, B's `x-`, is made of triangles (and, for a != b, A's nodes meet them
/// inside, not at their corners).
pub fn tet4_two_bars(a: usize, b: usize) -> String {
    let text = scene_text("two_bars_fine.toml");
    let at = text.find("name = \"B\"").expect("bar B");
    let cut = |part: &str, n: usize| {
        part.replace(
            "divisions = [40, 1, 1] }",
            &format!("divisions = [40, {n}, {n}], element = \"tet4\" }}"),
        )
    };
    let tets = cut(&text[..at], a) + &cut(&text[at..], b);
    assert_eq!(tets.matches("\"tet4\"").count(), 2, "both boxes are tet4");
    tets
}

/// The paper's two bars (`two_bars.toml`) with bar B in half cubes (`divisions = [20, 2,
/// 2]`) and bar A in unit cubes: one material, one element shape at two sizes, so B's
/// elements set a stable step half of A's (5e-3 against 1e-2 for c = 100).
pub fn two_bars_at_two_sizes() -> String {
    let text = scene_text("two_bars.toml");
    let at = text.find("name = \"B\"").expect("bar B");
    let b = text[at..].replacen("divisions = [10, 1, 1]", "divisions = [20, 2, 2]", 1);
    assert_ne!(b, text[at..], "bar B's divisions");
    text[..at].to_string() + &b
}

/// The cube on the plate (`cube_on_plate.toml`, friction 0.3) with both boxes meshed as
/// tet4: the plate's contact face is triangles, and the cube's nodes lie exactly over the
/// plate's vertices and edges.
pub fn tet4_cube_on_plate() -> String {
    let text = scene_text("cube_on_plate.toml")
        .replace(
            "divisions = [4, 4, 4] }",
            "divisions = [4, 4, 4], element = \"tet4\" }",
        )
        .replace(
            "divisions = [16, 4, 4] }",
            "divisions = [16, 4, 4], element = \"tet4\" }",
        );
    assert_eq!(text.matches("\"tet4\"").count(), 2, "both boxes are tet4");
    text
}

/// `text` run explicit at the default step (0.9 of the stable bound): its `method` and
/// `time_step` lines replaced by `method = "explicit"`.
pub fn explicit_at_default_step(text: &str) -> String {
    let text: String = (text.lines())
        .filter(|l| !l.starts_with("time_step") && !l.starts_with("method"))
        .collect::<Vec<_>>()
        .join("\n");
    edit(&text, "[run]", "[run]\nmethod = \"explicit\"")
}

/// `text` with a small rigid sphere far above everything, spinning in place and in no
/// contact: the physics of `text`, but a model with a rotating rigid body, which ranks on
/// GPUs run with their element forces on the device and the rest on the host (the "gpu
/// kernels, decomposed over mpi ranks" engine) rather than resident.
#[allow(dead_code)]
pub fn with_idle_rigid_body(text: &str) -> String {
    text.to_string()
        + r#"
[[rigid_body]]
name = "idle"
motion = "prescribed"
position = [0.0, 0.0, 50.0]
angular_velocity = [0.0, 0.0, 1.0]
shape = { sphere = { radius = 0.1 } }
"#
}

/// A rigid ball (0.01, radius 0.3) dropped at 1 on a unit block of 6 x 6 x 6 hex8 clamped
/// at its base, friction 0.2, a probe on the block's top: a small scene with a free rigid
/// body in contact with a meshed one.
#[allow(dead_code)]
pub fn rigid_ball_on_block() -> String {
    r#"title = "A rigid ball dropped on a clamped block"

[run]
end_time = 0.04
method = "explicit"

[[material]]
name = "elastic"
density = 0.01
youngs_modulus = 100.0
poissons_ratio = 0.3

[[body]]
name = "block"
material = "elastic"
box = { min = [-0.5, -0.5, 0.0], max = [0.5, 0.5, 1.0], divisions = [6, 6, 6] }

[[fix]]
body = "block"
region = { min = [-0.5, -0.5, 0.0], max = [0.5, 0.5, 0.0] }
components = ["x", "y", "z"]

[[rigid_body]]
name = "ball"
mass = 0.01
position = [0.05, 0.0, 1.301]
velocity = [0.0, 0.0, -1.0]
shape = { sphere = { radius = 0.3 } }

[[contact]]
name = "hit"
secondary = { body = "block", face = "z+" }
primary = { rigid_body = "ball" }
friction = 0.2

[[probe]]
name = "top"
body = "block"
point = [0.0, 0.0, 1.0]
"#
    .to_string()
}

/// `text` without its VTU frames: the tests read the history.
pub fn without_frames(text: &str) -> String {
    let lines = text.lines().filter(|l| !l.starts_with("vtu_every"));
    lines.collect::<Vec<_>>().join("\n")
}

/// The shipped damaged drop weight (`drop_weight_d7136.toml`: the plies damaging in their
/// plane, the two ply-change interfaces delaminating) on 5 mm cells without the refinement,
/// through its first `end` seconds: the load's climb, the first delaminations and the load
/// drop.
pub fn damaged_coarse(end: f64) -> String {
    let text = edit(
        &scene_text("drop_weight_d7136.toml"),
        "divisions = [38, 25, 4], element = \"hex8i\", refine = { min = [-10.0, -10.0, 0.0], max = [10.0, 10.0, 4.56], size = [1.0, 1.0, 1.14] } }",
        "divisions = [30, 20, 4], element = \"hex8i\" }",
    );
    // the law's strengths: in 5 mm cells, 14 times matrix compression's snap-back width,
    // the shipped scene's lowering would start the matrix modes at 0.23-0.51 of theirs
    let text = edit(&text, "snap_back = \"lower_strength\"\n", "");
    without_frames(&edit(
        &text,
        "end_time = 6e-3",
        &format!("end_time = {end:e}"),
    ))
}

/// [`damaged_coarse`] with its plies' damage regularised in time: a Duvaut-Lions viscosity
/// (`damage_viscosity`) of 50 us, a twentieth of the time to the peak, over which a point's
/// damage follows its softening instead of at once. The 5 mm cells, four to twenty times
/// the matrix modes' snap-back widths, then no longer fail each in one step, and which
/// cell goes first no longer turns on the last digits: run to 2.1 ms on the CPU with the
/// tup's speed moved by 1e-7, 1e-6 or 1e-5 of itself, its force filtered over 0.05 ms
/// peaks within 0.01% of the unmoved run's and it delaminates the same 400 mm^2 (without
/// the viscosity, to 1.2 ms, 1e-7 moves the peak by 3% and 1e-6 adds a 25 mm^2 pair; the
/// pairs' times still spread, the last of the 400 mm^2 coming at 1.36-1.90 ms). This is
/// the copy that sets one computation of the drop weight beside another.
pub fn damaged_coarse_viscous(end: f64) -> String {
    edit(
        &damaged_coarse(end),
        "damage_stresses = \"in_plane\"\n",
        "damage_stresses = \"in_plane\"\ndamage_viscosity = 5e-5\n",
    )
}

/// The largest contact force of a history, and its last row's delaminated area.
pub fn peak_and_area(h: &History) -> (f64, f64) {
    let peak = h
        .col("impact.normal_force")
        .iter()
        .copied()
        .fold(0.0, f64::max);
    (peak, h.last("plies.delaminated_area"))
}

/// Two 8 x 8 x 1 mm blocks (4 x 4 hex8i each) bonded by a mode II interface with friction
/// `mu` (`crack`, G_IIc 0.788 N/mm, shear strength 90 MPa, K 1e5 N/mm^3): the lower block's
/// base held, the upper pressed by `p` on its top (ramped over the first 0.1 ms) and its top
/// moved along x by the named fix `push`, still to 0.2 ms, then 0.1 mm by 1.2 ms: the
/// interface breaks in shear under the pressure and then slides. Runs to `end`.
pub fn sheared_blocks(mu: f64, p: f64, end: f64) -> String {
    format!(
        r#"title = "sheared blocks"
[run]
end_time = {end:e}
method = "explicit"
[[material]]
name = "steel"
density = 7.8e-9
youngs_modulus = 2.1e5
poissons_ratio = 0.3
[[body]]
name = "upper"
material = "steel"
box = {{ min = [0.0, 0.0, 1.0], max = [8.0, 8.0, 2.0], divisions = [4, 4, 1], element = "hex8i" }}
[[body]]
name = "lower"
material = "steel"
box = {{ min = [0.0, 0.0, 0.0], max = [8.0, 8.0, 1.0], divisions = [4, 4, 1], element = "hex8i" }}
[[cohesive]]
name = "crack"
between = [{{ body = "upper", face = "z-" }}, {{ body = "lower", face = "z+" }}]
stiffness = 1e5
strength = {{ normal = 60.0, shear = 90.0 }}
toughness = {{ normal = 0.277, shear = 0.788, bk = 2.1 }}
friction = {mu}
[[fix]]
body = "lower"
face = "z-"
components = ["x", "y", "z"]
[[fix]]
name = "push"
body = "upper"
face = "z+"
components = ["x"]
displacement = [0.1, 0.0, 0.0]
amplitude = [[0.0, 0.0], [2e-4, 0.0], [1.2e-3, 1.0]]
[[load]]
body = "upper"
face = "z+"
pressure = {p}
amplitude = [[0.0, 0.0], [1e-4, 1.0]]
"#
    )
}

/// A strip clamped at one end, 40 x 8 x 1 mm of aluminium in 20 x 2 x 1 hex8i, set swinging
/// by 32 m/s so that its tip travels about 16 mm (two fifths of its length; its end turns
/// by about 0.5 rad).
pub fn swinging_strip(kinematics: &str, end: f64) -> String {
    format!(
        r#"
title = "a swinging strip"

[run]
method = "explicit"
end_time = {end:e}
kinematics = "{kinematics}"

[[material]]
name = "aluminium"
density = 2.7e-9
youngs_modulus = 70000.0
poissons_ratio = 0.33

[[body]]
name = "strip"
material = "aluminium"
box = {{ min = [0.0, 0.0, 0.0], max = [40.0, 8.0, 1.0], divisions = [20, 2, 1], element = "hex8i" }}
velocity = [0.0, 0.0, 32000.0]

[[fix]]
name = "root"
body = "strip"
face = "x-"
components = ["x", "y", "z"]

[[probe]]
name = "tip"
body = "strip"
point = [40.0, 4.0, 0.5]
"#
    )
}
