//! Orthotropic bodies against exact answers.
//!
//! A bar of an orthotropic material strikes a rigid wall at v0 = 1, held laterally (y and z
//! fixed at every node): the force is S v0 sqrt(rho C11') for 2 L sqrt(rho / C11'), then the
//! bar rebounds at -v0, where C11' is the turned stiffness along the bar, provided the turn
//! couples no x-shear to the axial strain (C15' = C16' = 0): turns about z by 0 and 90
//! degrees (C11' = C11, then C22), and turns about x by any angle (C11' = C11, the couplings
//! C12' ... C44' all taken by the lateral supports). A turn about z by 30 or 45 degrees
//! couples the axial strain to the x-y shear (C16' != 0): the bar's free faces then shear,
//! a mode 1D theory does not hold (`a_turned_scene_gives_the_turned_history` covers it). C'
//! is computed here from the compliance with nalgebra and the rotation formula about z,
//! independently of the library.

mod common;
use common::*;

const L: f64 = 10.0;
const RHO: f64 = 0.01;
const ELEMENTS: usize = 40;

/// E1, E2, E3, nu12, nu13, nu23, G12, G13, G23.
const PLY: [f64; 9] = [100.0, 20.0, 15.0, 0.25, 0.2, 0.3, 12.0, 10.0, 8.0];

/// C11' of the material turned by `deg` about `axis` ("z": the formula; "x": C11).
fn axial_modulus(axis: &str, deg: f64) -> f64 {
    let [e1, e2, e3, n12, n13, n23, g12, _, _] = PLY;
    let s = nalgebra::Matrix3::new(
        1.0 / e1,
        -n12 / e1,
        -n13 / e1,
        -n12 / e1,
        1.0 / e2,
        -n23 / e2,
        -n13 / e1,
        -n23 / e2,
        1.0 / e3,
    );
    let c = s.try_inverse().expect("compliance inverts");
    let (c11, c12, c22, c66) = (c[(0, 0)], c[(0, 1)], c[(1, 1)], g12);
    if axis == "x" {
        return c11;
    }
    let (m, n) = (deg.to_radians().cos(), deg.to_radians().sin());
    let c16 = (c11 - c12 - 2.0 * c66) * m.powi(3) * n + (c12 - c22 + 2.0 * c66) * m * n.powi(3);
    assert!(
        c16.abs() < 1e-9 * c11,
        "{deg} degrees about z couple the x-y shear"
    );
    c11 * m.powi(4) + 2.0 * (c12 + 2.0 * c66) * m * m * n * n + c22 * n.powi(4)
}

fn bar_scene(axis: [f64; 3], deg: f64, method: &str, dt: f64, end: f64) -> String {
    let [e1, e2, e3, n12, n13, n23, g12, g13, g23] = PLY;
    format!(
        r#"title = "orthotropic bar at {deg} degrees on a rigid wall"
[run]
method = "{method}"
end_time = {end:?}
time_step = {dt:?}

[[material]]
name = "ply"
density = {RHO:?}
orthotropic = {{ e1 = {e1:?}, e2 = {e2:?}, e3 = {e3:?}, nu12 = {n12:?}, nu13 = {n13:?}, nu23 = {n23:?}, g12 = {g12:?}, g13 = {g13:?}, g23 = {g23:?} }}

[[body]]
name = "bar"
material = "ply"
box = {{ min = [-{L:?}, 0.0, 0.0], max = [0.0, 1.0, 1.0], divisions = [{ELEMENTS}, 1, 1] }}
velocity = [1.0, 0.0, 0.0]
orientation = {{ axis = {axis:?}, angle = {deg:?} }}

[[fix]]
body = "bar"
region = {{ min = [-{L:?}, 0.0, 0.0], max = [0.0, 1.0, 1.0] }}
components = ["y", "z"]

[[rigid_plane]]
name = "wall"
point = [0.0, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
"#
    )
}

/// Runs the bar turned by `deg` about `axis` and checks the plateau (1%) and the rebound
/// (3%).
fn bar_matches_wave_theory(axis: &str, deg: f64, method: &str) {
    let c_mod = axial_modulus(axis, deg);
    let vector = if axis == "x" {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    let c = (c_mod / RHO).sqrt();
    let duration = 2.0 * L / c;
    let force = (RHO * c_mod).sqrt();
    let dt = L / ELEMENTS as f64 / c;
    let mut text = bar_scene(vector, deg, method, dt, 2.0 * duration);
    if method == "explicit" {
        // the stable step of the 3D elements is a little below h / c
        text = text.replace(&format!("time_step = {dt:?}\n"), "");
    }
    let (s, h) = run_text(&format!("orthotropic_bar_{method}_{axis}{deg:?}"), &text);
    let s = s.expect("run completes");
    assert_eq!(s.status, "completed", "{:?}", s.warnings);
    let (t, f) = (h.col("time"), h.col("wall.normal_force"));
    let plateau: Vec<f64> = (t.iter().zip(&f))
        .filter(|(t, _)| **t >= 0.1 * duration && **t <= 0.9 * duration)
        .map(|(_, f)| *f)
        .collect();
    let mean = plateau.iter().sum::<f64>() / plateau.len() as f64;
    let rebound = h.last("bar.vx");
    eprintln!(
        "{method} {deg:?} deg about {axis}: C11 {c_mod:.4}, force {mean:.5} of {force:.5} ({:+.2e}), rebound {rebound:.5}",
        mean / force - 1.0
    );
    assert!(
        (mean - force).abs() <= 0.01 * force,
        "{deg:?}: plateau {mean} against {force}"
    );
    assert!((rebound + 1.0).abs() <= 0.03, "{deg:?}: rebound {rebound}");
}

const TURNS: [(&str, f64); 4] = [("z", 0.0), ("z", 90.0), ("x", 30.0), ("x", 45.0)];

#[test]
fn a_turned_orthotropic_bar_matches_wave_theory_implicit() {
    for (axis, deg) in TURNS {
        bar_matches_wave_theory(axis, deg, "implicit");
    }
}

#[test]
fn a_turned_orthotropic_bar_matches_wave_theory_explicit() {
    for (axis, deg) in TURNS {
        bar_matches_wave_theory(axis, deg, "explicit");
    }
}

/// An isotropic material entered as orthotropic constants (E, nu, G = E / 2 (1 + nu) on every
/// axis) runs the block drop of the shipped scene (a 3D state with Poisson's effect) with the
/// same history as the isotropic one, to 1e-10 of each column's scale, implicit and explicit.
#[test]
fn isotropic_constants_entered_as_orthotropic_give_the_isotropic_history() {
    let iso = scene_text("block_hex_drop.toml").replace(
        "mesh = \"meshes/",
        &format!("mesh = \"{}/scenes/meshes/", repo().display()),
    );
    let g = 100.0 / (2.0 * 1.3);
    let ortho = edit(
        &iso,
        "youngs_modulus = 100.0\npoissons_ratio = 0.3",
        &format!("orthotropic = {{ e1 = 100.0, e2 = 100.0, e3 = 100.0, nu12 = 0.3, nu13 = 0.3, nu23 = 0.3, g12 = {g:?}, g13 = {g:?}, g23 = {g:?} }}"),
    );
    for method in ["explicit", "implicit"] {
        // the implicit contact iteration converged to round-off, so that the two
        // stiffnesses' last-digit differences do not move it by its tolerance
        let set = |t: &str| {
            let run = format!("method = \"{method}\"\ntime_step = 5e-4");
            edit(t, "method = \"explicit\"", &run)
                + "\n[implicit]\ntolerance = 1e-12\nmax_iterations = 600\n"
        };
        let (sa, a) = run_text(&format!("iso_{method}"), &set(&iso));
        let (sb, b) = run_text(&format!("iso_as_ortho_{method}"), &set(&ortho));
        assert_eq!(sa.expect("isotropic run").status, "completed");
        assert_eq!(sb.expect("orthotropic run").status, "completed");
        let columns: Vec<(&str, &str, f64)> = a
            .columns
            .iter()
            .map(|c| (c.as_str(), c.as_str(), 1.0))
            .collect();
        let d = history_difference(&a, &b, &columns);
        eprintln!("{method}: largest difference {d:.2e} of a column's scale");
        assert!(d <= 1e-10, "{method}: {d:e}");
    }
}

/// The orthotropic bar turned 30 degrees about z (its axial strain coupled to the x-y shear)
/// and the same scene turned a quarter turn about z, bar, wall, supports and material axes
/// (120 degrees) together: the histories agree, x of the first being y of the second, to
/// 1e-9 of each column's scale.
#[test]
fn a_turned_scene_gives_the_turned_history() {
    let c = (axial_modulus("z", 0.0) / RHO).sqrt();
    let dt = L / ELEMENTS as f64 / c;
    // one step for both (the Gershgorin bound of the stable step is not invariant under
    // turns of the mesh): half the 1D step of the stiffest direction
    let along_x = bar_scene([0.0, 0.0, 1.0], 30.0, "explicit", 0.5 * dt, 4.0 * L / c);
    let along_y = along_x
        .replace("angle = 30.0", "angle = 120.0")
        .replace(
            &format!("min = [-{L:?}, 0.0, 0.0], max = [0.0, 1.0, 1.0]"),
            &format!("min = [0.0, -{L:?}, 0.0], max = [1.0, 0.0, 1.0]"),
        )
        .replace("divisions = [40, 1, 1]", "divisions = [1, 40, 1]")
        .replace("velocity = [1.0, 0.0, 0.0]", "velocity = [0.0, 1.0, 0.0]")
        .replace("components = [\"y\", \"z\"]", "components = [\"x\", \"z\"]")
        .replace("normal = [-1.0, 0.0, 0.0]", "normal = [0.0, -1.0, 0.0]");
    assert_eq!(along_y.matches("[0.0, -10.0, 0.0]").count(), 2, "{along_y}");
    assert_eq!(along_y.matches("[1, 40, 1]").count(), 1, "{along_y}");
    let (sa, a) = run_text("turned_scene_x", &along_x);
    let (sb, b) = run_text("turned_scene_y", &along_y);
    let (sa, sb) = (sa.expect("run along x"), sb.expect("run along y"));
    assert_eq!(sa.status, "completed", "{:?}", sa.warnings);
    assert_eq!(sb.status, "completed", "{:?}", sb.warnings);
    let pairs = [
        ("wall.normal_force", "wall.normal_force", 1.0),
        ("bar.vx", "bar.vy", 1.0),
        ("kinetic_energy", "kinetic_energy", 1.0),
        ("strain_energy", "strain_energy", 1.0),
    ];
    let d = history_difference(&a, &b, &pairs);
    eprintln!("turned scene: largest difference {d:.2e} of a column's scale");
    assert!(d <= 1e-9, "{d:e}");
}

/// The columns the laminate's device comparisons check: the contact force, the energies and
/// both bodies' velocities.
const LAMINATE_COLUMNS: [&str; 5] = [
    "impact.normal_force",
    "strain_energy",
    "kinetic_energy",
    "ball.vz",
    "plate.vz",
];

/// The shipped laminate scene cut to its first 12 us, with one frame at the end.
fn laminate_first_12us() -> String {
    edit(
        &scene_text("sphere_on_laminate.toml"),
        "end_time = 1.4e-4",
        "end_time = 1.2e-5",
    )
    .replace("vtu_every = 20", "vtu_every = 12")
}

/// The shipped laminate scene's first 12 us (the ball's first contact with the [0/90]s
/// plate) on the CPU and with the kernels on the GPU: every column, the contact force
/// included, agrees within the GPU runs' tolerance (`tests/gpu_runs.rs`: 1e-4 of each
/// quantity's scale), and the total energy never rises in a step by more than 1e-5 of the
/// initial.
#[test]
fn the_laminate_scene_agrees_on_cpu_and_gpu_and_loses_energy() {
    let text = laminate_first_12us();
    let (sc, hc) = run_text_on(
        "laminate_cpu",
        &text,
        Some(impact::scene::DeviceChoice::Cpu),
    );
    let sc = sc.expect("cpu run");
    assert_eq!(sc.status, "completed", "{:?}", sc.warnings);
    assert!(
        hc.last("impact.normal_force") > 0.0,
        "the ball is in contact"
    );
    let e = hc.col("total_energy");
    let rise = e.windows(2).map(|w| w[1] - w[0]).fold(f64::MIN, f64::max) / e[0];
    eprintln!("laminate: largest energy rise in a step {rise:.2e} of the initial");
    assert!(rise <= 1e-5, "energy rises by {rise:e} in a step");
    if skip_gpu("laminate") {
        return;
    }
    let (sg, hg) = run_text_on(
        "laminate_gpu",
        &text,
        Some(impact::scene::DeviceChoice::Gpu),
    );
    let sg = sg.expect("gpu run");
    assert_ne!(sg.device, "cpu");
    assert_eq!(sg.status, "completed", "{:?}", sg.warnings);
    let d = history_difference(&hc, &hg, &same_columns(&LAMINATE_COLUMNS));
    eprintln!(
        "laminate: the devices differ by {d:.2e} of scale on {}",
        sg.device
    );
    assert!(d <= 1e-4, "gpu and cpu differ by {d:e}");
}

/// The laminate's first 12 us without event sub-steps (`event_substeps = 1`) on the CPU and
/// with the kernels on the GPU: every column, the contact force included, within the GPU
/// runs' tolerance of 1e-4 of its scale (1.3e-5 measured on llvmpipe).
#[test]
fn the_laminate_without_substeps_agrees_on_cpu_and_gpu() {
    if skip_gpu("laminate_plain_steps") {
        return;
    }
    let text = laminate_first_12us().replace(
        "max_iterations = 300",
        "max_iterations = 300\nevent_substeps = 1",
    );
    assert!(text.contains("event_substeps = 1"));
    let run = |tag: &str, device| {
        let (s, h) = run_text_on(tag, &text, Some(device));
        assert_eq!(s.expect("runs").status, "completed");
        h
    };
    let hc = run("laminate_plain_cpu", impact::scene::DeviceChoice::Cpu);
    let hg = run("laminate_plain_gpu", impact::scene::DeviceChoice::Gpu);
    assert!(
        hc.last("impact.normal_force") > 0.0,
        "the ball is in contact"
    );
    let d = history_difference(&hc, &hg, &same_columns(&LAMINATE_COLUMNS));
    eprintln!("laminate without sub-steps: devices differ by {d:.2e} of scale");
    assert!(d <= 1e-4, "gpu and cpu differ by {d:e}");
}
