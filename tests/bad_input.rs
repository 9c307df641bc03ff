//! Bad input gives an error that names the file and the key (and the line where TOML gives
//! one), never a panic. One test per case.

mod common;
use common::*;
use impact::scene::Scene;
use std::path::Path;

fn error_of(text: &str) -> String {
    let e = Scene::parse(text, Path::new("bad.toml")).expect_err("must be rejected");
    let msg = e.to_string();
    assert!(msg.starts_with("bad.toml:"), "names the file: {msg}");
    msg
}

fn base() -> String {
    scene_text("two_bars.toml")
}

fn expect(text: &str, parts: &[&str]) {
    let msg = error_of(text);
    for p in parts {
        assert!(msg.contains(p), "{msg:?} should contain {p:?}");
    }
}

#[test]
fn malformed_toml_names_the_line() {
    let text = edit(&base(), "end_time = 0.4", "end_time = = 0.4");
    expect(&text, &["line 7"]);
}

#[test]
fn unknown_key_is_named_with_a_suggestion() {
    let text = edit(&base(), "density = 0.01", "densty = 0.01");
    expect(&text, &["densty", "did you mean `density`?", "line"]);
}

#[test]
fn missing_material_is_named() {
    let text = edit(&base(), "material = \"elastic\"", "material = \"steel\"");
    expect(&text, &["body[0].material", "steel"]);
}

#[test]
fn non_positive_density() {
    expect(
        &edit(&base(), "density = 0.01", "density = 0.0"),
        &["density", "> 0"],
    );
}

#[test]
fn non_positive_modulus() {
    expect(
        &edit(&base(), "youngs_modulus = 100.0", "youngs_modulus = -1.0"),
        &["youngs_modulus"],
    );
}

#[test]
fn poissons_ratio_out_of_range() {
    expect(
        &edit(&base(), "poissons_ratio = 0.0", "poissons_ratio = 0.5"),
        &["poissons_ratio", "(-1, 0.5)"],
    );
    expect(
        &edit(&base(), "poissons_ratio = 0.0", "poissons_ratio = -1.0"),
        &["poissons_ratio"],
    );
}

#[test]
fn contact_face_that_does_not_exist() {
    expect(
        &edit(&base(), "face = \"x+\"", "face = \"x*\""),
        &["contact[0].secondary.face", "x*"],
    );
}

#[test]
fn contact_body_that_does_not_exist() {
    expect(
        &edit(
            &base(),
            "primary = { body = \"B\"",
            "primary = { body = \"C\"",
        ),
        &["contact[0].primary.body", "`C`"],
    );
}

#[test]
fn unknown_box_element() {
    expect(
        &edit(
            &base(),
            "divisions = [10, 1, 1] }",
            "divisions = [10, 1, 1], element = \"hex20\" }",
        ),
        &["body[0].box.element", "hex20", "did you mean `hex8`?"],
    );
}

#[test]
fn zero_divisions() {
    expect(
        &edit(&base(), "divisions = [10, 1, 1]", "divisions = [10, 0, 1]"),
        &["body[0].box.divisions", ">= 1"],
    );
}

#[test]
fn non_positive_end_time() {
    expect(
        &edit(&base(), "end_time = 0.4", "end_time = 0.0"),
        &["run.end_time"],
    );
}

#[test]
fn implicit_without_time_step() {
    expect(
        &edit(&base(), "time_step = 0.01\n", ""),
        &["run.time_step", "required"],
    );
}

#[test]
fn negative_friction() {
    expect(
        &edit(&base(), "friction = 0.0", "friction = -0.1"),
        &["contact[0].friction", ">= 0"],
    );
}

#[test]
fn rigid_plane_with_zero_normal() {
    let text = edit(
        &scene_text("bar_on_wall.toml"),
        "normal = [-1.0, 0.0, 0.0]",
        "normal = [0.0, 0.0, 0.0]",
    );
    expect(&text, &["rigid_plane[0].normal", "zero"]);
}

/// The same rigid plane given twice for a body is refused (the two would share its force,
/// each reporting part of it); the same plane for other bodies, or a parallel one, is not.
#[test]
fn the_same_rigid_plane_twice_is_refused() {
    let text = scene_text("bar_on_wall.toml");
    let twice = text.clone()
        + "\n[[rigid_plane]]\nname = \"again\"\npoint = [0.0, 5.0, 0.0]\nnormal = [-1.0, 0.0, 0.0]\n";
    expect(
        &twice,
        &[
            "rigid_plane[1].point",
            "same plane as rigid_plane[0] (`wall`)",
        ],
    );
    let parallel = twice.replace("point = [0.0, 5.0, 0.0]", "point = [1.0, 5.0, 0.0]");
    Scene::parse(&parallel, Path::new("ok.toml")).expect("a parallel plane");
}

#[test]
fn unknown_choice_suggests_the_closest() {
    expect(
        &edit(
            &base(),
            "constraint = \"gap_rate\"",
            "constraint = \"gaprate\"",
        ),
        &["implicit.constraint", "did you mean `gap_rate`?"],
    );
}

/// An explicit step above the stable bound is refused with both numbers.
#[test]
fn explicit_step_above_the_stable_step() {
    let text = edit(&base(), "method = \"implicit\"", "method = \"explicit\"")
        .replace("time_step = 0.01", "time_step = 0.011");
    let scene = Scene::parse(&text, Path::new("bad.toml")).expect("valid scene");
    let opts = impact::run::RunOptions {
        out: Some(out_dir("explicit_step_too_long")),
        device: None,
        quiet: true,
        ..Default::default()
    };
    let msg = impact::run::run(&scene, &opts)
        .expect_err("refused")
        .to_string();
    for part in [
        "run.time_step",
        "1.1000e-2",
        "above the stable explicit step 1.0000e-2",
    ] {
        assert!(msg.contains(part), "{msg:?} should contain {part:?}");
    }
}

#[test]
fn explicit_safety_factor_out_of_range() {
    expect(
        &format!("{}\n[explicit]\nsafety_factor = 1.5\n", base()),
        &["explicit.safety_factor", "(0, 1]"],
    );
}

#[test]
fn missing_scene_file() {
    let e = Scene::load("no/such/scene.toml").expect_err("missing file");
    assert!(e.to_string().contains("no/such/scene.toml"));
}

#[test]
fn negative_friction_on_a_rigid_plane() {
    let text = edit(
        &scene_text("bar_on_wall.toml"),
        "friction = 0.0",
        "friction = -0.3",
    );
    expect(&text, &["rigid_plane[0].friction", ">= 0", "-0.3"]);
}

#[test]
fn unknown_acceleration_is_named() {
    expect(
        &edit(
            &base(),
            "penalty = \"adaptive\"",
            "penalty = \"adaptive\"\nacceleration = \"aitken\"",
        ),
        &["implicit.acceleration", "aitken", "anderson"],
    );
}

#[test]
fn non_positive_tangential_penalty() {
    expect(
        &edit(
            &base(),
            "penalty = \"adaptive\"",
            "penalty = \"adaptive\"\npenalty_tangential = 0.0",
        ),
        &["implicit.penalty_tangential"],
    );
}

#[test]
fn event_substeps_out_of_range() {
    expect(
        &edit(
            &base(),
            "penalty = \"adaptive\"",
            "penalty = \"adaptive\"\nevent_substeps = 0",
        ),
        &["implicit.event_substeps", "from 1 (off) to 1000", "got 0"],
    );
}

#[test]
fn non_positive_event_force_change() {
    expect(
        &edit(
            &base(),
            "penalty = \"adaptive\"",
            "penalty = \"adaptive\"\nevent_force_change = -0.2",
        ),
        &["implicit.event_force_change", "> 0"],
    );
}

#[test]
fn vtu_every_must_be_positive() {
    expect(
        &format!("{}\n[output]\nvtu_every = 0\n", base()),
        &["output.vtu_every", ">= 1"],
    );
}

#[test]
fn exact_curve_needs_two_points() {
    // the scene's own [[exact]] table comes last: replace it by one with a single point
    let head = base().split("[[exact]]").next().unwrap().to_string();
    expect(
        &format!("{head}[[exact]]\ncolumn = \"impact.normal_force\"\npoints = [[0.0, 0.5]]\n"),
        &["exact[0].points", "at least two"],
    );
}

/// An exact curve for a column the history does not have is refused before the run.
#[test]
fn exact_curve_of_an_unknown_column() {
    let text = base().replace(
        "column = \"impact.normal_force\"",
        "column = \"impact.force\"",
    );
    let scene = Scene::parse(&text, Path::new("bad.toml")).expect("parses");
    let opts = impact::run::RunOptions {
        out: Some(out_dir("exact_unknown_column")),
        device: None,
        quiet: true,
        ..Default::default()
    };
    let msg = impact::run::run(&scene, &opts)
        .expect_err("refused")
        .to_string();
    for part in [
        "exact[0].column",
        "\"impact.force\" is not a history column",
    ] {
        assert!(msg.contains(part), "{msg:?} should contain {part:?}");
    }
}

/// The two bars' material as orthotropic constants `c` in place of E and nu.
fn orthotropic(c: &str) -> String {
    edit(
        &base(),
        "youngs_modulus = 100.0\npoissons_ratio = 0.0",
        &format!("orthotropic = {{ {c} }}"),
    )
}

const PLY: &str = "e1 = 100.0, e2 = 10.0, e3 = 10.0, nu12 = 0.3, nu13 = 0.3, nu23 = 0.4, g12 = 5.0, g13 = 5.0, g23 = 4.0";

#[test]
fn orthotropic_constants_that_are_not_positive_definite_are_named() {
    // nu12^2 must stay below E1 / E2 = 10
    let text = orthotropic(&PLY.replace("nu12 = 0.3", "nu12 = 3.5"));
    expect(
        &text,
        &["material[0].orthotropic", "nu12", "positive definite"],
    );
    let text = orthotropic(&PLY.replace("g23 = 4.0", "g23 = 0.0"));
    expect(&text, &["material[0].orthotropic", "g23", "positive"]);
    let together = "e1 = 1.0, e2 = 1.0, e3 = 1.0, nu12 = 0.9, nu13 = 0.9, nu23 = 0.9, g12 = 1.0, g13 = 1.0, g23 = 1.0";
    expect(&orthotropic(together), &["nu12, nu13, nu23", "determinant"]);
}

#[test]
fn an_orthotropic_material_with_isotropic_constants_too_is_refused() {
    let text = edit(
        &base(),
        "poissons_ratio = 0.0",
        &format!("poissons_ratio = 0.0\northotropic = {{ {PLY} }}"),
    );
    expect(&text, &["material[0].orthotropic", "one law"]);
}

#[test]
fn an_orientation_of_two_parallel_vectors_is_named() {
    let text = edit(
        &orthotropic(PLY),
        "velocity = [1.0, 0.0, 0.0]",
        "velocity = [1.0, 0.0, 0.0]\norientation = { axes = [[1.0, 1.0, 0.0], [2.0, 2.0, 0.0]] }",
    );
    expect(&text, &["body[0].orientation.axes", "parallel"]);
}

#[test]
fn plies_thinner_or_thicker_than_the_body_are_named() {
    // the bars are 1 thick along z
    for (layers, total) in [("0.25", "0.5"), ("0.75", "1.5")] {
        let plies = format!(
            "plies = {{ normal = \"z\", layers = [{{ angle = 0.0, thickness = {layers} }}, {{ angle = 90.0, thickness = {layers} }}] }}"
        );
        let text = edit(
            &orthotropic(PLY),
            "velocity = [1.0, 0.0, 0.0]",
            &format!("velocity = [1.0, 0.0, 0.0]\n{plies}"),
        );
        expect(
            &text,
            &["body[0].plies.layers", &format!("{total} thick"), "along z"],
        );
    }
}

#[test]
fn a_ply_normal_that_is_no_axis_is_named() {
    let text = edit(
        &orthotropic(PLY),
        "velocity = [1.0, 0.0, 0.0]",
        "velocity = [1.0, 0.0, 0.0]\nplies = { normal = \"w\", layers = [{ angle = 0.0, thickness = 1.0 }] }",
    );
    expect(&text, &["body[0].plies.normal", "\"w\""]);
}

/// Names head history columns (`bar.vx`) and go into CSV, XML and file names: a comma, a
/// quote, a newline or nothing at all is refused naming the key.
#[test]
fn names_that_would_break_the_history_are_refused() {
    let wall = scene_text("bar_on_wall.toml");
    for (bad, what) in [
        ("\"bar,A\"", "','"),
        ("\"\\\"bar\"", "'\"'"),
        ("\"bar\\nA\"", "'\\n'"),
        ("\"\"", "must not be empty"),
        ("\"bar A\"", "' '"),
    ] {
        let text = edit(&wall, "name = \"bar\"", &format!("name = {bad}"));
        expect(&text, &["body[0].name", what]);
    }
    let text = edit(&wall, "name = \"elastic\"", "name = \"el&astic\"");
    expect(&text, &["material[0].name", "'&'"]);
}

/// Bodies, contacts, planes and probes share one set of names: a probe named like a body
/// would give two `bar.vx` columns.
#[test]
fn a_probe_named_like_a_body_is_refused() {
    let wall = scene_text("bar_on_wall.toml");
    let text = edit(&wall, "name = \"tip\"", "name = \"bar\"");
    expect(&text, &["probe[0].name", "body[0]", "history columns"]);
    let text = edit(&wall, "name = \"wall\"", "name = \"tip\"");
    expect(&text, &["probe[0].name", "rigid_plane[0]"]);
}

/// A normal is scaled before it is normalised: `[-1e200, 0, 0]` and `[-1e-13, 0, 0]` are the
/// unit normal `[-1, 0, 0]`, and only a zero or non-finite one is refused.
#[test]
fn a_huge_or_tiny_normal_is_the_unit_normal() {
    let wall = scene_text("bar_on_wall.toml");
    for n in ["-1e200", "-1e-13", "-1e-300", "-1.7e308"] {
        let text = edit(
            &wall,
            "normal = [-1.0, 0.0, 0.0]",
            &format!("normal = [{n}, 0.0, 0.0]"),
        );
        let scene = Scene::parse(&text, Path::new("wall.toml")).expect("a valid normal");
        assert_eq!(scene.planes[0].normal, [-1.0, 0.0, 0.0], "{n}");
    }
    let text = edit(
        &wall,
        "normal = [-1.0, 0.0, 0.0]",
        "normal = [0.0, 0.0, 0.0]",
    );
    expect(&text, &["rigid_plane[0].normal", "zero vector"]);
}

/// The same contact pair declared twice would halve each reported force: refused.
#[test]
fn a_contact_pair_declared_twice_is_refused() {
    let text = base();
    let start = text.find("[[contact]]").unwrap();
    let end = start + text[start..].find("[[probe]]").unwrap();
    let twice = text[start..end].replace("name = \"impact\"", "name = \"impact2\"");
    let text = format!("{}{twice}{}", &text[..end], &text[end..]);
    expect(&text, &["contact[1].secondary", "contact[0] (`impact`)"]);
}

/// "`nu23 = nan` is reported as a problem with `g23`": each constant is checked by its own key.
#[test]
fn a_nan_elastic_constant_is_named_by_its_own_key() {
    let text = edit(
        &scene_text("sphere_on_laminate.toml"),
        "nu23 = 0.45",
        "nu23 = nan",
    );
    expect(&text, &["transversely_isotropic.nu23", "finite"]);
}

/// A ply strength that is not positive is named by its key in the `strength` table; a key
/// that is not a strength is named as unknown.
#[test]
fn a_strength_that_is_not_positive_is_named() {
    let with = |s: &str| {
        edit(
            &base(),
            "density = 0.01",
            &format!("density = 0.01\nstrength = {{ {s} }}"),
        )
    };
    expect(
        &with("xt = 1500.0, xc = 1500.0, yt = 40.0, yc = -246.0, s12 = 68.0, s23 = 68.0"),
        &["material[0].strength.yc", "> 0", "-246"],
    );
    expect(
        &with("xt = 1500.0, xc = 1500.0, yt = 40.0, yc = 246.0, s12 = 68.0, s13 = 68.0"),
        &["s13"],
    );
}

/// The St Venant bar struck by the rigid body `tup`, whose keys are `tup`.
fn rigid(tup: &str) -> String {
    format!(
        r#"[run]
end_time = 0.1
time_step = 0.0025
method = "explicit"

[[material]]
name = "elastic"
density = 0.01
youngs_modulus = 100.0
poissons_ratio = 0.0

[[body]]
name = "bar"
material = "elastic"
box = {{ min = [0.0, 0.0, 0.0], max = [10.0, 1.0, 1.0], divisions = [4, 1, 1] }}

[[rigid_body]]
name = "tup"
position = [0.0, 0.5, 0.5]
{tup}

[[contact]]
name = "strike"
secondary = {{ body = "bar", face = "x-" }}
primary = {{ rigid_body = "tup" }}
"#
    )
}

const SPHERE: &str = "shape = { sphere = { radius = 1.0 } }";

#[test]
fn a_free_rigid_body_needs_its_mass() {
    expect(&rigid(SPHERE), &["rigid_body[0].mass", "required", "free"]);
    let fixed = rigid(&format!("{SPHERE}\nmotion = \"fixed\""));
    Scene::parse(&fixed, Path::new("ok.toml")).expect("a held body needs no mass");
}

#[test]
fn a_rigid_body_rotates_only_as_its_motion_allows() {
    let inertia = |i: &str| format!("mass = 1.0\n{SPHERE}\ninertia = {i}");
    let ok = rigid(&inertia(
        "[[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]]",
    ));
    Scene::parse(&ok, Path::new("ok.toml")).expect("a free body with an inertia rotates");
    // not symmetric, not positive definite
    let text = rigid(&inertia(
        "[[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]",
    ));
    expect(&text, &["rigid_body[0].inertia", "symmetric"]);
    let text = rigid(&inertia(
        "[[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]",
    ));
    expect(&text, &["rigid_body[0].inertia", "positive definite"]);
    // too small to invert in f64, moments 1e12 apart, or no body's (the triangle inequality)
    for (i, words) in [
        (
            "[[1e-105, 0.0, 0.0], [0.0, 1e-105, 0.0], [0.0, 0.0, 1e-105]]",
            "too small to invert",
        ),
        (
            "[[1e-13, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]",
            "1e12 apart",
        ),
        (
            "[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.5]]",
            "sum of the other two",
        ),
    ] {
        expect(&rigid(&inertia(i)), &["rigid_body[0].inertia", words]);
    }
    // a free body without inertia only translates; a fixed one does not spin
    let spin = "angular_velocity = [0.0, 0.0, 1.0]";
    let text = rigid(&format!("mass = 1.0\n{SPHERE}\n{spin}"));
    expect(&text, &["rigid_body[0].angular_velocity", "inertia"]);
    let text = rigid(&format!("{SPHERE}\nmotion = \"fixed\"\n{spin}"));
    expect(&text, &["rigid_body[0].angular_velocity", "prescribed"]);
    let text = rigid(&format!("{SPHERE}\nmotion = \"prescribed\"\n{spin}"));
    Scene::parse(&text, Path::new("ok.toml")).expect("a prescribed body spins");
    // inertia is a free body's
    let text = rigid(&format!(
        "{SPHERE}\nmotion = \"prescribed\"\ninertia = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]"
    ));
    expect(&text, &["rigid_body[0].inertia", "free body"]);
    // the implicit path rotates bodies too
    let text = rigid(&inertia(
        "[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]",
    ))
    .replace("method = \"explicit\"", "method = \"implicit\"");
    Scene::parse(&text, Path::new("ok.toml")).expect("an implicit run rotates its bodies");
}

#[test]
fn a_rigid_shape_is_exactly_one_shape() {
    let two =
        "mass = 1.0\nshape = { sphere = { radius = 1.0 }, plane = { normal = [1.0, 0.0, 0.0] } }";
    expect(
        &rigid(two),
        &["rigid_body[0].shape", "exactly one", "sphere, plane"],
    );
    let meshed = "mass = 1.0\nshape = { mesh = \"tup.msh\", surface = \"face\" }";
    expect(&rigid(meshed), &["rigid_body[0].shape.mesh", "tup.msh"]);
    let half = "mass = 1.0\nshape = { mesh = \"tup.msh\" }";
    expect(&rigid(half), &["rigid_body[0].shape.surface", "both"]);
    let bad_ends =
        "mass = 1.0\nshape = { cylinder = { radius = 1.0, axis = [1.0, 0.0, 0.0], length = 2.0, ends = \"domed\" } }";
    expect(&rigid(bad_ends), &["shape.cylinder.ends", "domed", "round"]);
    let zero_axis =
        "mass = 1.0\nshape = { cylinder = { radius = 1.0, axis = [0.0, 0.0, 0.0], length = 2.0 } }";
    expect(&rigid(zero_axis), &["shape.cylinder.axis", "zero"]);
}

#[test]
fn a_plate_window_must_fit_inside_the_plate() {
    let text = "motion = \"fixed\"\nshape = { plate = { normal = [1.0, 0.0, 0.0], size = [4.0, 2.0], opening = [1.0, 2.0] } }";
    expect(
        &rigid(text),
        &["rigid_body[0].shape.plate.opening", "smaller than"],
    );
}

#[test]
fn a_held_rigid_body_does_not_move() {
    let text = format!("motion = \"fixed\"\nvelocity = [1.0, 0.0, 0.0]\n{SPHERE}");
    expect(&rigid(&text), &["rigid_body[0].velocity", "prescribed"]);
}

#[test]
fn a_contact_names_an_existing_rigid_body_on_its_primary_side_only() {
    let base = rigid(&format!("mass = 1.0\n{SPHERE}"));
    expect(
        &edit(
            &base,
            "primary = { rigid_body = \"tup\" }",
            "primary = { rigid_body = \"tupp\" }",
        ),
        &["contact[0].primary.rigid_body", "did you mean `tup`?"],
    );
    expect(
        &edit(
            &base,
            "primary = { rigid_body = \"tup\" }",
            "primary = { body = \"bar\", face = \"x+\", rigid_body = \"tup\" }",
        ),
        &["contact[0].primary.rigid_body", "not both"],
    );
    expect(
        &edit(
            &base,
            "secondary = { body = \"bar\", face = \"x-\" }",
            "secondary = { rigid_body = \"tup\" }",
        ),
        &["contact[0].secondary.body", "required"],
    );
    expect(
        &edit(
            &base,
            "primary = { rigid_body = \"tup\" }",
            "primary = { rigid_body = \"tup\", face = \"x+\" }",
        ),
        &["contact[0].primary.rigid_body", "leave out `face`"],
    );
}

#[test]
fn a_fix_of_a_rigid_body_holds_it_whole() {
    let text = format!(
        "{}\n[[fix]]\nbody = \"tup\"\nface = \"x-\"\ncomponents = [\"y\"]\n",
        rigid(&format!("mass = 1.0\n{SPHERE}"))
    );
    expect(&text, &["fix[0].face", "rigid body", "leave out"]);
}

#[test]
fn a_rigid_body_named_like_a_body_is_refused() {
    let text = edit(
        &rigid(&format!("mass = 1.0\n{SPHERE}")),
        "name = \"tup\"",
        "name = \"bar\"",
    );
    expect(&text, &["rigid_body[0].name", "body[0]"]);
}

#[test]
fn a_meshed_rigid_shape_names_a_surface_of_its_file() {
    // parsed as if in scenes/, where meshes/sphere.msh is
    let text = rigid("mass = 1.0\nshape = { mesh = \"meshes/sphere.msh\", surface = \"skn\" }");
    let e =
        Scene::parse(&text, &repo().join("scenes").join("bad.toml")).expect_err("no such surface");
    let msg = e.to_string();
    for part in ["rigid_body[0].shape.surface", "skn", "did you mean `skin`?"] {
        assert!(msg.contains(part), "{msg:?} should contain {part:?}");
    }
}

/// The two bars' material as a transversely isotropic ply with strengths, `extra` after it.
fn ply_bars(extra: &str) -> String {
    edit(
        &base(),
        "youngs_modulus = 100.0\npoissons_ratio = 0.0",
        &format!(
            "transversely_isotropic = {{ e1 = 100.0, e2 = 10.0, nu12 = 0.3, nu23 = 0.4, g12 = 5.0 }}\nstrength = {{ xt = 1.0, xc = 1.0, yt = 0.1, yc = 0.3, s12 = 0.2, s23 = 0.15 }}\n{extra}"
        ),
    )
}

#[test]
fn fracture_energy_needs_strengths_and_an_orthotropic_law() {
    let energies = "fracture_energy = { ft = 1.0, fc = 1.0, mt = 0.1, mc = 0.2 }";
    let no_strength = ply_bars(energies).replace(
        "strength = { xt = 1.0, xc = 1.0, yt = 0.1, yc = 0.3, s12 = 0.2, s23 = 0.15 }\n",
        "",
    );
    expect(&no_strength, &["material[0].fracture_energy", "strength"]);
    let isotropic = edit(
        &base(),
        "poissons_ratio = 0.0",
        &format!("poissons_ratio = 0.0\nstrength = {{ xt = 1.0, xc = 1.0, yt = 0.1, yc = 0.3, s12 = 0.2, s23 = 0.15 }}\n{energies}"),
    );
    expect(
        &isotropic,
        &[
            "material[0].fracture_energy",
            "orthotropic or transversely_isotropic",
        ],
    );
    expect(
        &ply_bars("fracture_energy = { ft = 1.0, fc = -1.0, mt = 0.1, mc = 0.2 }"),
        &["material[0].fracture_energy.fc", "> 0"],
    );
    expect(
        &ply_bars(&format!("{energies}\ndamage_viscosity = -1e-3")),
        &["material[0].damage_viscosity", "at least 0"],
    );
    expect(
        &ply_bars("damage_viscosity = 1e-3"),
        &["material[0].damage_viscosity", "fracture_energy"],
    );
    expect(
        &ply_bars(&format!("{energies}\ndamage_stresses = \"planar\"")),
        &["material[0].damage_stresses", "\"in_plane\"", "planar"],
    );
    expect(
        &ply_bars("damage_stresses = \"in_plane\""),
        &["material[0].damage_stresses", "fracture_energy"],
    );
    expect(
        &ply_bars(&format!("{energies}\nsnap_back = \"lower\"")),
        &["material[0].snap_back", "\"lower_strength\"", "lower"],
    );
    expect(
        &ply_bars("snap_back = \"lower_strength\""),
        &["material[0].snap_back", "fracture_energy"],
    );
}

/// A damaging material runs explicit: `method = "implicit"` is refused naming the method
/// to use.
#[test]
fn an_implicit_run_of_a_damaging_material_is_refused() {
    let text = ply_bars("fracture_energy = { ft = 1.0, fc = 1.0, mt = 0.1, mc = 0.2 }");
    let scene = Scene::parse(&text, Path::new("bad.toml")).expect("valid scene");
    let opts = impact::run::RunOptions {
        out: Some(out_dir("implicit_damage_refused")),
        quiet: true,
        ..Default::default()
    };
    let msg = impact::run::run(&scene, &opts)
        .expect_err("refused")
        .to_string();
    for part in ["run.method", "method = \"explicit\"", "fracture_energy"] {
        assert!(msg.contains(part), "{msg:?} should contain {part:?}");
    }
}

#[test]
fn a_fix_velocity_moves_only_held_components_at_one_velocity() {
    let fix = |extra: &str| {
        base() + &format!("\n[[fix]]\nbody = \"B\"\nface = \"x+\"\ncomponents = [\"x\"]\n{extra}\n")
    };
    expect(
        &fix("velocity = [0.0, 1.0, 0.0]"),
        &["fix[0].velocity", "moves y but the fix does not hold it"],
    );
    expect(&fix("velocity = [1.0, 0.0]"), &["velocity"]);
    expect(
        &fix("name = \"A\""),
        &["fix[0].name", "also the name of body[0]"],
    );
    // two fixes holding one node's x at two velocities, found when the model is built
    let two = fix("velocity = [1.0, 0.0, 0.0]")
        + "\n[[fix]]\nbody = \"B\"\nregion = { min = [10.0, 0.0, 0.0], max = [10.0, 1.0, 1.0] }\ncomponents = [\"x\"]\n";
    let scene = Scene::parse(&two, Path::new("bad.toml")).expect("valid scene");
    let msg = impact::model::Model::from_scene(&scene)
        .expect_err("refused")
        .to_string();
    assert!(
        msg.contains("fix[1].velocity") && msg.contains("fix[0] holds node"),
        "{msg}"
    );
}

#[test]
fn a_refined_zone_is_checked() {
    let refine = |r: &str| {
        edit(
            &base(),
            "divisions = [10, 1, 1] }\nvelocity",
            &format!("divisions = [10, 1, 1], refine = {r} }}\nvelocity"),
        )
    };
    expect(
        &refine("{ min = [-5.0, 0.0, 0.0], max = [-6.0, 1.0, 1.0], size = [0.1, 1.0, 1.0] }"),
        &["body[0].box.refine.max", "must exceed box.refine.min"],
    );
    expect(
        &refine("{ min = [-5.0, 0.0, 0.0], max = [-4.0, 1.0, 1.0], size = [0.0, 1.0, 1.0] }"),
        &["body[0].box.refine.size", "> 0"],
    );
    expect(
        &refine("{ min = [-5.0, 0.0, 0.0], max = [-4.0, 1.0, 1.0], size = [1e-9, 1e-9, 1e-9] }"),
        &["body[0].box.refine.size", "32-bit"],
    );
}

/// A `[[fix]]` holding a component along which its rigid body was given a velocity is
/// refused (the body would keep still along it without a word), naming the component.
#[test]
fn a_fix_on_a_moving_rigid_bodys_component_is_refused() {
    let text = rigid(&format!(
        "mass = 1.0\n{SPHERE}\nvelocity = [0.5, 0.0, -1.0]"
    )) + "\n[[fix]]\nbody = \"tup\"\ncomponents = [\"x\", \"y\"]\n";
    expect(&text, &["fix[0].components", "holds x", "0.5"]);
    let held = rigid(&format!(
        "mass = 1.0\n{SPHERE}\nvelocity = [0.0, 0.0, -1.0]"
    )) + "\n[[fix]]\nbody = \"tup\"\ncomponents = [\"x\", \"y\"]\n";
    Scene::parse(&held, Path::new("ok.toml")).expect("held where it does not move");
}

/// An array with more components than its key takes (the TOML reader takes the first ones
/// and passed over the rest) is refused by its key.
#[test]
fn an_array_with_extra_components_is_refused() {
    let text = edit(
        &base(),
        "divisions = [10, 1, 1]",
        "divisions = [10, 1, 1, 4]",
    );
    expect(
        &text,
        &[
            "key `body[0].box.divisions`",
            "has 4 components; it takes 3",
        ],
    );
    let text = base()
        + "\n[[rigid_body]]\nname = \"plate\"\nmass = 1.0\nposition = [0.0, 0.0, -2.0]\nmotion = \"fixed\"\nshape = { plate = { normal = [0.0, 0.0, 1.0], size = [2.0, 2.0, 3.0] } }\n";
    expect(
        &text,
        &[
            "key `rigid_body[0].shape.plate.size`",
            "has 3 components; it takes 2",
        ],
    );
}
