//! Layered hex8i: the shipped [0/90]s plate (`sphere_on_laminate.toml`'s, a quarter, clamped
//! edges) bent statically by its weight. One hex8i layer per half ply (16 x 16 x 8), and two
//! element layers each spanning two plies (16 x 16 x 2, each ply integrated over its own part
//! of the element), against the same element converged (32 x 32 x 16); the plain hex8 on
//! 16 x 16 x 8 for scale. The figures are in docs/validation.md.

use impact::linalg::{assemble, Ordering, SpdSolver};
use impact::model::Model;
use impact::scene::{MassKind, Scene};
use std::path::Path;

/// The quarter plate meshed `n` x `n` x `layers` with `element`, under gravity along -z.
fn plate(n: usize, layers: usize, element: &str) -> String {
    format!(
        r#"gravity = [0.0, 0.0, -9.81e3]
[run]
end_time = 1.0
time_step = 1.0

[[material]]
name = "carbon_epoxy"
density = 1.6e-9
transversely_isotropic = {{ e1 = 1.35e5, e2 = 1.0e4, nu12 = 0.3, nu23 = 0.45, g12 = 5.0e3 }}

[[body]]
name = "plate"
material = "carbon_epoxy"
box = {{ min = [0.0, 0.0, -2.0], max = [25.0, 25.0, 0.0], divisions = [{n}, {n}, {layers}], element = "{element}" }}
plies = {{ normal = "z", layers = [
  {{ angle = 0.0, thickness = 0.5 }},
  {{ angle = 90.0, thickness = 0.5 }},
  {{ angle = 90.0, thickness = 0.5 }},
  {{ angle = 0.0, thickness = 0.5 }},
] }}

[[fix]]
body = "plate"
face = "x-"
components = ["x"]

[[fix]]
body = "plate"
face = "y-"
components = ["y"]

[[fix]]
body = "plate"
face = "x+"
components = ["x", "y", "z"]

[[fix]]
body = "plate"
face = "y+"
components = ["x", "y", "z"]
"#
    )
}

/// The static deflection at the plate's centre (top face) under its weight, and how many
/// layered sections the model holds.
fn centre_deflection(text: &str) -> (f64, usize) {
    let scene = Scene::parse(text, Path::new("plate.toml")).expect("valid scene");
    let model = Model::from_scene(&scene).expect("model");
    let asm = assemble(&model, MassKind::Lumped, 0.0);
    let mut f: Vec<f64> = (asm.dof_of.iter())
        .map(|&d| asm.nodal_mass[d as usize / 3] * model.gravity[d as usize % 3])
        .collect();
    let solver = SpdSolver::new(&asm.effective, Ordering::NestedDissection).expect("factor");
    solver.solve_in_place(&mut f);
    let centre = (model.mesh.nodes.iter())
        .position(|p| p[0] == 0.0 && p[1] == 0.0 && p[2] == 0.0)
        .expect("a node at the centre of the top face");
    let eq = asm.equation[3 * centre + 2] as usize;
    (-f[eq], model.layups.iter().flatten().count())
}

#[test]
fn a_laminate_meshed_coarser_than_its_plies_bends_like_the_fine_mesh() {
    let (reference, _) = centre_deflection(&plate(32, 16, "hex8i"));
    let ratio = |n: usize, layers: usize, element: &str| {
        let (w, layups) = centre_deflection(&plate(n, layers, element));
        (w / reference, layups)
    };
    let (fine, none) = ratio(16, 8, "hex8i");
    let (per_ply, none_either) = ratio(16, 4, "hex8i");
    let (coarse, two) = ratio(16, 2, "hex8i");
    let (single, one) = ratio(16, 1, "hex8i");
    let (plain, _) = ratio(16, 8, "hex8");
    eprintln!(
        "centre deflection over hex8i 32x32x16's ({reference:.6e}): hex8i 16x16x8 {fine:.4}, 16x16x4 {per_ply:.4}, 16x16x2 layered {coarse:.4}, 16x16x1 layered {single:.4}; hex8 16x16x8 {plain:.4}"
    );
    // an element of half a ply or of one ply holds one ply; the coarse meshes' layers span
    // two plies and four, one layered section per element layer
    assert_eq!((none, none_either, two, one), (0, 0, 2, 1));
    assert!((fine - 1.0).abs() <= 0.01, "16 x 16 x 8: {fine}");
    assert!((per_ply - 1.0).abs() <= 0.01, "16 x 16 x 4: {per_ply}");
    // one or two elements through the thickness: the plies are integrated exactly
    // (`element::hex8i` tests), but a brick's transverse shear strain is constant through
    // its thickness, stiffer than the plate's parabolic one (the shear correction factor
    // that a plate theory applies, 5/6): 2.4% stiff on a plate of all 0 degree plies too
    for (r, what) in [(coarse, "16 x 16 x 2"), (single, "16 x 16 x 1")] {
        assert!((r - 1.0).abs() <= 0.04, "{what}: {r}");
    }
    assert!(plain < fine, "the hex8 locks");
}
