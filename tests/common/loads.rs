//! Scenes with `[[load]]`s: a bar held at one end, loaded at the other; and what a scene is
//! refused for.

/// A bar along x, 10 long, c = 100, held at x = 0 (x only; Poisson 0, so it stays 1D), with
/// `load` appended; `method` and `dt` given.
pub fn held_bar(method: &str, dt: f64, cells: usize, load: &str) -> String {
    format!(
        r#"title = "held bar under an end load"
[run]
end_time = 0.4
time_step = {dt}
method = "{method}"
device = "auto"

[[material]]
name = "elastic"
density = 0.01
youngs_modulus = 100.0
poissons_ratio = 0.0

[[body]]
name = "bar"
material = "elastic"
box = {{ min = [0.0, 0.0, 0.0], max = [10.0, 1.0, 1.0], divisions = [{cells}, 1, 1] }}

[[fix]]
body = "bar"
face = "x-"
components = ["x"]

[[probe]]
name = "tip"
body = "bar"
point = [10.0, 0.5, 0.5]

{load}"#
    )
}

/// A step pressure of 2 on the bar's free end.
pub const PRESSURE: &str = "[[load]]\nbody = \"bar\"\nface = \"x+\"\npressure = 2.0\n";

/// A ramped pressure and a sine-like table of nodal forces on the held bar (both
/// amplitudes change within the run, so a resumed run must take them up at its time).
pub fn loaded_bar(method: &str, dt: f64, end: f64) -> String {
    held_bar(method, dt, 40, &format!(
        "{PRESSURE}amplitude = [[0.0, 0.0], [0.05, 1.0], [0.3, 0.5]]\n\n[[load]]\nbody = \"bar\"\nregion = {{ min = [4.0, -1.0, -1.0], max = [6.0, 2.0, 2.0] }}\nforce = [0.01, 0.02, 0.0]\namplitude = [[0.0, 0.0], [0.1, 1.0], [0.2, -1.0], [0.3, 0.0]]\n\n[output]\ncheckpoint_every = 100\n"
    ))
    .replace("end_time = 0.4", &format!("end_time = {end}"))
}

/// The held bar of `tests/loads.rs` (10 long, E = 100, A = 1, c = 100), its free end pushed
/// by a named fix `push` with `motion` appended (the `displacement` and its amplitude).
pub fn pushed_bar(end: f64, motion: &str) -> String {
    held_bar(
        "explicit",
        0.0009,
        10,
        &format!("[[fix]]\nname = \"push\"\nbody = \"bar\"\nface = \"x+\"\ncomponents = [\"x\"]\n{motion}"),
    )
    .replace("end_time = 0.4", &format!("end_time = {end}"))
}

/// The refusal of `text` as the scene `scenes/<stem>.toml`: when it is read, or else when
/// its model is built (a run into `stem`'s folder, which must fail).
pub fn refusal(stem: &str, text: &str) -> String {
    use impact::run::{run, RunOptions};
    let path = super::repo().join("scenes").join(format!("{stem}.toml"));
    match impact::scene::Scene::parse(text, &path) {
        Err(e) => e.to_string(),
        Ok(scene) => {
            let opts = RunOptions {
                out: Some(super::out_dir(stem)),
                quiet: true,
                ..Default::default()
            };
            run(&scene, &opts).expect_err("must be refused").to_string()
        }
    }
}
