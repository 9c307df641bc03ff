//! Meshes from files: Gmsh `.msh` 4.1 (ASCII and binary) and Abaqus/CalculiX `.inp`, hex8
//! and tet4 bodies, named surfaces and node sets in `[[contact]]` and `[[fix]]`, and the
//! errors of malformed files and missing names.

mod common;
use common::*;

use impact::element::ElementKind;
use impact::mesh::import;
use impact::scene::Scene;

fn meshes() -> std::path::PathBuf {
    repo().join("scenes").join("meshes")
}

/// The impulse of a force column over the rows of a history ([`common::impulse`]).
fn impulse(h: &History, column: &str) -> f64 {
    let t = h.col("time");
    let f = h.col(column);
    common::impulse(&t, &f)
}

/// The same unit cube as 8 x 8 x 8 hex8 (`.inp`) and as 2740 tet4 (`.msh`) strikes a rigid
/// plane flat at 1: the rebound centre-of-mass velocities agree within 3%, each has left the
/// plane, and the plane's impulse equals each block's change of momentum (rho V = 0.01)
/// to 1e-9 of it.
#[test]
fn hex8_and_tet4_blocks_rebound_alike() {
    let mut rebound = Vec::new();
    for kind in ["hex", "tet"] {
        let name = format!("block_{kind}_drop");
        let (s, h) = run_scene_text(&name, &scene_text(&format!("{name}.toml")));
        let s = s.expect("run completes");
        let vz = h.last("block.vz");
        let f = h.col("ground.normal_force");
        let p = impulse(&h, "ground.normal_force");
        let dp = 0.01 * (vz - (-1.0));
        eprintln!(
            "{kind}: {} elements, {} steps, rebound {vz:.5}, impulse {p:.6e} vs m dv {dp:.6e}",
            s.elements, s.steps
        );
        assert!(vz > 0.5, "{kind}: rebound {vz}");
        assert_eq!(
            *f.last().unwrap(),
            0.0,
            "{kind}: still in contact at the end"
        );
        assert!((p - dp).abs() <= 1e-9 * dp, "{kind}: impulse {p} vs {dp}");
        rebound.push(vz);
    }
    let diff = (rebound[0] - rebound[1]).abs() / rebound[0];
    eprintln!(
        "hex8 {:.5} tet4 {:.5}: {:.3}% apart",
        rebound[0],
        rebound[1],
        100.0 * diff
    );
    assert!(
        diff <= 0.03,
        "hex8 {} and tet4 {} differ by {diff}",
        rebound[0],
        rebound[1]
    );
}

/// A tet4 block (`.msh`, secondary surface `bottom`) drops onto a hex8 block (`.inp`,
/// primary surface `TOP`) whose base is held by the node set `BASE`: contact forces
/// appear, the dropped block's vertical momentum changes by the contact's impulse (to 1e-3:
/// the impulse sums normal impulses, and the normals of the deforming primary face tilt by
/// a little), and the base nodes never move.
#[test]
fn named_surfaces_and_sets_drive_contact_and_fixes() {
    let text = r#"
title = "tet block on hex block"
[run]
end_time = 0.05
method = "explicit"
[[material]]
name = "elastic"
density = 0.01
youngs_modulus = 100.0
poissons_ratio = 0.3
[[body]]
name = "base"
material = "elastic"
mesh = "meshes/block_hex.inp"
[[body]]
name = "drop"
material = "elastic"
mesh = "meshes/block_tet.msh"
scale = 0.5
translate = [0.1, 0.0, 1.01]
velocity = [0.0, 0.0, -1.0]
[[contact]]
name = "stack"
secondary = { body = "drop", surface = "bottom" }
primary = { body = "base", surface = "TOP" }
[[fix]]
body = "base"
set = "BASE"
components = ["x", "y", "z"]
[[probe]]
name = "corner"
body = "base"
point = [-0.5, -0.5, 0.0]
"#;
    let (s, h) = run_scene_text("stacked_blocks", text);
    let s = s.expect("run completes");
    let f = h.col("stack.normal_force");
    let peak = f.iter().copied().fold(0.0, f64::max);
    let p = impulse(&h, "stack.normal_force");
    // the dropped block is a cube of side 0.5: mass 0.01 * 0.125
    let dp = 0.01 * 0.125 * (h.last("drop.vz") + 1.0);
    eprintln!(
        "{} steps: peak force {peak:.4}, impulse {p:.6e}, m dv {dp:.6e}, drop vz {:.4}",
        s.steps,
        h.last("drop.vz")
    );
    assert!(peak > 0.0 && p > 0.0);
    assert!(
        (p - dp).abs() <= 1e-3 * dp,
        "impulse {p} vs momentum change {dp}"
    );
    for c in ["corner.ux", "corner.uy", "corner.uz"] {
        assert!(h.col(c).iter().all(|&u| u == 0.0), "{c} moved");
    }
}

/// The binary copy of the block mesh reads to the ASCII one: the same elements, surfaces and
/// sets, and coordinates equal to the 16 digits the ASCII file keeps.
#[test]
fn ascii_and_binary_msh_read_alike() {
    let a = import(&meshes().join("block_tet.msh"), 1.0, [0.0; 3], None)
        .expect("ascii")
        .0;
    let b = import(&meshes().join("block_tet_binary.msh"), 1.0, [0.0; 3], None)
        .expect("binary")
        .0;
    assert_eq!(a.nodes.len(), b.nodes.len());
    let dx = a
        .nodes
        .iter()
        .zip(&b.nodes)
        .flat_map(|(p, q)| (0..3).map(move |k| (p[k] - q[k]).abs()))
        .fold(0.0, f64::max);
    assert!(dx <= 1e-15, "coordinates differ by {dx}");
    assert!(a.elements == b.elements, "elements differ");
    assert!(a.surfaces == b.surfaces, "surfaces differ");
    assert!(a.node_sets == b.node_sets, "node sets differ");
    assert_eq!(a.elements.count_of(ElementKind::Tet4), 2740);
    // the boundary of a unit cube: area 6, and the named surfaces cover it
    let area = |faces: &[impact::mesh::Face]| -> f64 {
        faces
            .iter()
            .map(|f| impact::geometry::quad::quad_area(&f.slots().map(|n| a.nodes[n as usize])))
            .sum()
    };
    assert!((area(&a.boundary) - 6.0).abs() < 1e-9);
    assert!((area(&a.surface("bottom").unwrap().faces) - 1.0).abs() < 1e-9);
    assert!((area(&a.surface("sides").unwrap().faces) - 4.0).abs() < 1e-9);
}

/// Scale, then translate: the `.inp` cube becomes [0, 2] x [0, 2] x [1, 3].
#[test]
fn scale_then_translate() {
    let m = import(&meshes().join("block_hex.inp"), 2.0, [1.0, 1.0, 1.0], None)
        .expect("deck")
        .0;
    let lo = [0, 1, 2].map(|a| m.nodes.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min));
    let hi = [0, 1, 2].map(|a| {
        m.nodes
            .iter()
            .map(|p| p[a])
            .fold(f64::NEG_INFINITY, f64::max)
    });
    assert_eq!((lo, hi), ([0.0, 0.0, 1.0], [2.0, 2.0, 3.0]));
    assert_eq!(m.elements.count_of(ElementKind::Hex8), 512);
    assert_eq!(m.node_set("BASE").unwrap().nodes.len(), 81);
}

/// Writes `contents` as `name` in a fresh folder with a scene that imports it, and returns
/// the error of reading that scene.
fn scene_error(name: &str, contents: &[u8], extra: &str) -> String {
    let dir = out_dir(&format!("bad_mesh_{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(name), contents).unwrap();
    let scene = format!(
        r#"
[run]
end_time = 1.0
time_step = 0.1
[[material]]
name = "m"
density = 1.0
youngs_modulus = 1.0
poissons_ratio = 0.0
[[body]]
name = "b"
material = "m"
mesh = "{name}"
{extra}"#
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let e = Scene::load(&path).expect_err("must be rejected");
    e.to_string()
}

#[test]
fn malformed_msh_names_the_file_and_line() {
    let text = std::fs::read_to_string(meshes().join("block_tet.msh")).unwrap();
    // break the 3rd line of the node coordinates block
    let lines: Vec<&str> = text.lines().collect();
    let at = lines.iter().position(|l| *l == "$Nodes").unwrap() + 4;
    let mut bad: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    bad[at] = "oops".into();
    let msg = scene_error("bad.msh", bad.join("\n").as_bytes(), "");
    eprintln!("{msg}");
    assert!(msg.contains(&format!("bad.msh:{}:", at + 1)), "{msg}");
    assert!(msg.contains("`oops`"), "{msg}");
}

#[test]
fn malformed_inp_names_the_file_and_line() {
    let text = std::fs::read_to_string(meshes().join("block_hex.inp")).unwrap();
    let bad = text.replacen(
        "2, -0.375000, -0.500000, 0.000000",
        "2, -0.375000, abc, 0.000000",
        1,
    );
    let msg = scene_error("bad.inp", bad.as_bytes(), "");
    eprintln!("{msg}");
    assert!(msg.contains("bad.inp:6:"), "{msg}");
    assert!(msg.contains("`abc`"), "{msg}");
}

#[test]
fn unsupported_element_type_is_named() {
    let text = std::fs::read_to_string(meshes().join("block_hex.inp")).unwrap();
    let bad = text.replace("TYPE=C3D8,", "TYPE=C3D8R,");
    let msg = scene_error("reduced.inp", bad.as_bytes(), "");
    assert!(
        msg.contains("C3D8R") && msg.contains("reduced.inp:"),
        "{msg}"
    );
}

#[test]
fn missing_surface_lists_the_surfaces() {
    let text = std::fs::read_to_string(meshes().join("block_tet.msh")).unwrap();
    let msg = scene_error(
        "block.msh",
        text.as_bytes(),
        r#"
[[rigid_plane]]
name = "p"
point = [0.0, 0.0, -1.0]
normal = [0.0, 0.0, 1.0]
[[body]]
name = "c"
material = "m"
box = { min = [0.0, 0.0, -1.0], max = [1.0, 1.0, -0.5], divisions = [1, 1, 1] }
[[contact]]
name = "k"
secondary = { body = "b", surface = "botom" }
primary = { body = "c", face = "z+" }
"#,
    );
    eprintln!("{msg}");
    assert!(msg.contains("contact[0].secondary.surface"), "{msg}");
    assert!(msg.contains("no surface named `botom`"), "{msg}");
    assert!(msg.contains("did you mean `bottom`"), "{msg}");
}

#[test]
fn missing_node_set_lists_the_sets() {
    let text = std::fs::read_to_string(meshes().join("block_hex.inp")).unwrap();
    let msg = scene_error(
        "block.inp",
        text.as_bytes(),
        r#"
[[fix]]
body = "b"
set = "BOTTOM_NODES"
components = ["z"]
"#,
    );
    eprintln!("{msg}");
    assert!(
        msg.contains("fix[0].set") && msg.contains("BOTTOM_NODES"),
        "{msg}"
    );
    assert!(msg.contains("\"BASE\""), "{msg}");
}

#[test]
fn a_missing_mesh_file_is_named() {
    let dir = out_dir("missing_mesh");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    let text = scene_text("block_tet_drop.toml").replace("meshes/block_tet.msh", "nowhere.msh");
    std::fs::write(&path, text).unwrap();
    let msg = Scene::load(&path)
        .expect_err("must be rejected")
        .to_string();
    assert!(
        msg.contains("nowhere.msh") && msg.contains("cannot read"),
        "{msg}"
    );
}

/// The block-drop deck with its elements given material axes by `*ORIENTATION` (through
/// `*SOLID SECTION, ORIENTATION=`), written next to a scene that imports it with a strongly
/// anisotropic material and `extra` body keys; returns the run's history.
fn oriented_block_drop(tag: &str, orientation: &str, extra: &str) -> History {
    let dir = out_dir(&format!("oriented_{tag}"));
    std::fs::create_dir_all(&dir).unwrap();
    let mut deck = std::fs::read_to_string(meshes().join("block_hex.inp")).unwrap();
    deck.push_str(orientation);
    std::fs::write(dir.join("block.inp"), deck).unwrap();
    let scene = scene_text("block_hex_drop.toml")
        .replace("meshes/block_hex.inp", "block.inp")
        .replace(
            "youngs_modulus = 100.0\npoissons_ratio = 0.3",
            "transversely_isotropic = { e1 = 1000.0, e2 = 50.0, nu12 = 0.3, nu23 = 0.4, g12 = 20.0 }",
        )
        .replace(
            "velocity = [0.0, 0.0, -1.0]",
            &format!("velocity = [0.0, 0.0, -1.0]\n{extra}"),
        )
        .replace("end_time = 0.06", "end_time = 0.02");
    assert!(scene.contains("transversely_isotropic") && scene.contains("block.inp"));
    let path = dir.join("scene.toml");
    std::fs::write(&path, &scene).unwrap();
    let (s, h) = run_scene_at(&path, &dir.join("out"));
    assert_eq!(s.expect("runs").status, "completed");
    h
}

/// Axes from the deck (`*ORIENTATION` by points a, b and the origin c, and a further turn
/// about local axis 3) give the history the same axes from the scene give: the same bits
/// for the same two vectors, and within 1e-12 of each column's scale for the turn (the
/// scene turns the global axes by 60 degrees about z; the deck turns its 45-degree axes by
/// 15 more). An unoriented run differs, so the axes do reach the elements.
#[test]
fn abaqus_orientations_give_the_scene_orientations_history() {
    let section = "*SOLID SECTION, ELSET=BLOCK, MATERIAL=CFRP, ORIENTATION=ORI\n";
    let deck =
        |lines: &str| format!("*ORIENTATION, NAME=ORI, SYSTEM=RECTANGULAR\n{lines}{section}");
    let from_deck = oriented_block_drop(
        "deck",
        &deck("2.0, 3.0, 0.0, 0.0, 3.0, 0.0, 1.0, 2.0, 0.0\n"),
        "",
    );
    let from_scene = oriented_block_drop(
        "scene",
        "",
        "orientation = { axes = [[1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]] }",
    );
    assert_eq!(
        from_deck.rows, from_scene.rows,
        "the same axes, the same bits"
    );
    let turned_deck = oriented_block_drop(
        "deck_turned",
        &deck("1.0, 1.0, 0.0, -1.0, 1.0, 0.0\n3, 15.0\n"),
        "",
    );
    let turned_scene = oriented_block_drop(
        "scene_turned",
        "",
        "orientation = { axis = [0.0, 0.0, 1.0], angle = 60.0 }",
    );
    let columns = [
        "ground.normal_force",
        "kinetic_energy",
        "strain_energy",
        "top.vx",
        "top.vy",
        "top.vz",
    ];
    let pairs = same_columns(&columns);
    let d = history_difference(&turned_deck, &turned_scene, &pairs);
    eprintln!("deck turn against scene turn: {d:.2e} of scale");
    assert!(d <= 1e-12, "{d:e}");
    let plain = oriented_block_drop("plain", "", "");
    let d = history_difference(&turned_deck, &plain, &pairs);
    assert!(d > 1e-3, "the axes changed nothing: {d:e}");
}

/// Orientations the reader does not take, or that clash with the scene, are named.
#[test]
fn bad_abaqus_orientations_are_named() {
    let text = std::fs::read_to_string(meshes().join("block_hex.inp")).unwrap();
    let with = |extra: &str| format!("{text}{extra}");
    let cases = [
        (with("*ORIENTATION, NAME=C, SYSTEM=CYLINDRICAL\n0, 0, 0, 0, 0, 1\n"), "", "SYSTEM=CYLINDRICAL is not supported"),
        (with("*SOLID SECTION, ELSET=BLOCK, MATERIAL=M, ORIENTATION=NONE\n"), "", "no *ORIENTATION named `NONE`"),
        (with("*ORIENTATION, NAME=P\n1, 0, 0, 2, 0, 0\n*SOLID SECTION, ELSET=BLOCK, MATERIAL=M, ORIENTATION=P\n"), "", "off one line"),
        (
            with("*ORIENTATION, NAME=Q\n1, 0, 0, 0, 1, 0\n*SOLID SECTION, ELSET=BLOCK, MATERIAL=M, ORIENTATION=Q\n"),
            "orientation = { axis = [0.0, 0.0, 1.0], angle = 30.0 }",
            "body[0].orientation",
        ),
    ];
    for (deck, extra, part) in cases {
        let msg = scene_error("oriented.inp", deck.as_bytes(), extra);
        assert!(msg.contains(part), "{msg:?} should contain {part:?}");
    }
}

/// `*INCLUDE`: the cube's deck split into a main deck that includes its nodes from a
/// subfolder, which in turn includes half of the elements' data lines from beside it, reads
/// as the whole deck (all 512 elements, the same nodes, sets and surfaces); the keywords it
/// does not read are named in one notice with their lines.
#[test]
fn an_included_deck_reads_as_the_whole_deck() {
    let whole_path = meshes().join("block_hex.inp");
    let text = std::fs::read_to_string(&whole_path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    // lines 4..=733: *NODE and its data; 734..: *ELEMENT and its 1,024 data lines
    let nodes = lines[3..733].join("\n") + "\n";
    let element_data = &lines[734..1758];
    let (first, second) = element_data.split_at(element_data.len() / 2);
    let dir = std::env::temp_dir().join(format!("impact_include_{}", std::process::id()));
    let sub = dir.join("parts");
    std::fs::create_dir_all(&sub).unwrap();
    std::fs::write(
        sub.join("nodes.inp"),
        nodes
            + "*ELEMENT, TYPE=C3D8, ELSET=BLOCK\n"
            + &first.join("\n")
            + "\n*INCLUDE, INPUT=\"more.inp\"\n",
    )
    .unwrap();
    // an editor's byte-order mark before the included data lines is passed over
    std::fs::write(
        sub.join("more.inp"),
        "\u{feff}".to_string() + &second.join("\n") + "\n",
    )
    .unwrap();
    let main = lines[..3].join("\n")
        + "\n*Include, input=parts/nodes.inp\n"
        + &lines[1758..].join("\n")
        + "\n";
    let main_path = dir.join("main.inp");
    std::fs::write(&main_path, main).unwrap();
    let (a, notices) = import(&main_path, 1.0, [0.0; 3], None).expect("the included deck");
    let (b, _) = import(&whole_path, 1.0, [0.0; 3], None).expect("the whole deck");
    assert_eq!(a.elements.count_of(ElementKind::Hex8), 512);
    assert!(
        a.nodes == b.nodes && a.elements == b.elements,
        "the meshes differ"
    );
    assert!(a.surfaces == b.surfaces && a.node_sets == b.node_sets);
    assert_eq!(notices.len(), 1, "{notices:?}");
    for k in [
        "*HEADING (line 2)",
        "*MATERIAL (line",
        "*ELASTIC",
        "*DENSITY",
    ] {
        assert!(notices[0].contains(k), "{k}: {}", notices[0]);
    }

    // a missing include names the including file and line; a file that includes itself
    // stops at the depth limit
    std::fs::write(sub.join("more.inp"), "*INCLUDE, INPUT=gone.inp\n").unwrap();
    let e = import(&main_path, 1.0, [0.0; 3], None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("more.inp:1") && e.contains("gone.inp"), "{e}");
    std::fs::write(sub.join("more.inp"), "*INCLUDE, INPUT=more.inp\n").unwrap();
    let e = import(&main_path, 1.0, [0.0; 3], None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("nested more than"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A mesh path that names a device is refused at once, not read until memory runs out.
#[test]
fn a_mesh_path_that_is_a_device_is_refused() {
    let dir = std::env::temp_dir().join(format!("impact_device_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let link = dir.join("zero.msh");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let e = import(&link, 1.0, [0.0; 3], None).unwrap_err().to_string();
    assert!(e.contains("not a regular file"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A byte-order mark before `$MeshFormat` (some editors write one) is passed over.
#[test]
fn a_byte_order_mark_is_passed_over() {
    let dir = std::env::temp_dir().join(format!("impact_bom_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut bytes = b"\xEF\xBB\xBF".to_vec();
    bytes.extend(std::fs::read(meshes().join("block_tet.msh")).unwrap());
    let path = dir.join("bom.msh");
    std::fs::write(&path, bytes).unwrap();
    let (a, _) = import(&path, 1.0, [0.0; 3], None).expect("read with its mark");
    let (b, _) = import(&meshes().join("block_tet.msh"), 1.0, [0.0; 3], None).unwrap();
    assert!(a.nodes == b.nodes && a.elements == b.elements);
    let _ = std::fs::remove_dir_all(&dir);
}
