//! Scenes the benchmarks time, shared with the tests that check what the benchmarks
//! report (`benches/explicit_step.rs` and `benches/implicit_step.rs` include this file).

/// A block resting on a plate supported along its four bottom edges, pressed by gravity and
/// moving across it at (0.3, 0.2, -1): contact between meshed bodies with friction. About
/// 0.225 n^3 elements.
pub fn contact_scene(n: usize) -> String {
    let h = 1.0 / n as f64;
    let nz = (n / 10).max(2);
    let nb = (n / 2).max(2);
    format!(
        r#"
gravity = [0.0, 0.0, -9.8]

[run]
method = "explicit"
end_time = 1.0

[[material]]
name = "steel"
density = 7.8e-3
youngs_modulus = 200.0
poissons_ratio = 0.3

[[body]]
name = "plate"
material = "steel"
box = {{ min = [0.0, 0.0, {pz}], max = [1.0, 1.0, 0.0], divisions = [{n}, {n}, {nz}] }}

[[body]]
name = "block"
material = "steel"
box = {{ min = [0.25, 0.25, 0.0], max = [0.75, 0.75, 0.5], divisions = [{nb}, {nb}, {nb}] }}
velocity = [0.3, 0.2, -1.0]

[[contact]]
name = "impact"
secondary = {{ body = "block", face = "z-" }}
primary = {{ body = "plate", face = "z+" }}
friction = 0.2

[[fix]]
body = "plate"
region = {{ min = [0.0, 0.0, {pz}], max = [0.0, 1.0, {pz}] }}
components = ["z"]

[[fix]]
body = "plate"
region = {{ min = [1.0, 0.0, {pz}], max = [1.0, 1.0, {pz}] }}
components = ["x", "y", "z"]
"#,
        pz = -(nz as f64) * h,
    )
}

/// A steel-like block (E = 200, rho = 7.8e-3 in consistent units) of `n` cells, 1 wide,
/// dropped at 1 on a held rigid floor it touches at t = 0 with its bottom face, the contact
/// on that face; implicit at dt = h / c, the wave-resolving step, for `steps` steps;
/// `implicit` goes under `[implicit]`.
pub fn implicit_block_drop(n: [usize; 3], steps: usize, implicit: &str) -> String {
    let h = 1.0 / n[0] as f64;
    let dt = h / (200.0f64 / 7.8e-3).sqrt();
    format!(
        r#"
[run]
end_time = {end}
time_step = {dt}

[implicit]
{implicit}

[[material]]
name = "steel"
density = 7.8e-3
youngs_modulus = 200.0
poissons_ratio = 0.3

[[body]]
name = "block"
material = "steel"
box = {{ min = [0.0, 0.0, 0.0], max = [1.0, {ly}, {lz}], divisions = [{nx}, {ny}, {nz}] }}
velocity = [0.0, 0.0, -1.0]

[[rigid_body]]
name = "floor"
motion = "fixed"
position = [0.0, 0.0, 0.0]
shape = {{ plane = {{ normal = [0.0, 0.0, 1.0] }} }}

[[contact]]
name = "drop"
secondary = {{ body = "block", face = "z-" }}
primary = {{ rigid_body = "floor" }}
"#,
        end = (steps as f64 - 0.5) * dt,
        ly = n[1] as f64 * h,
        lz = n[2] as f64 * h,
        nx = n[0],
        ny = n[1],
        nz = n[2],
    )
}
