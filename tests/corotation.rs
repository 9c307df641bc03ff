//! Corotational kinematics (`run.kinematics = "corotational"`): each element's forces in a
//! frame that turns with it. A rigid turn of any size strains nothing, a turned stretch
//! gives the stretch's forces turned and its strain energy, a swinging strip keeps its
//! energy, a stopped run resumes to the same bytes, and what the path cannot run is refused
//! by its key.

mod common;
use common::*;

use impact::backend::{CpuKernels, Kernels};
use impact::scene::Scene;

/// A hex8 block, a layered hex8i plate and a tet4 block, apart.
const BLOCKS: &str = r#"
title = "three element kinds"

[run]
method = "explicit"
end_time = 1e-6

[[material]]
name = "steel"
density = 7.85e-9
youngs_modulus = 210000.0
poissons_ratio = 0.3

[[material]]
name = "ply"
density = 1.57e-9
orthotropic = { e1 = 171420.0, e2 = 9080.0, e3 = 9080.0, nu12 = 0.32, nu13 = 0.32, nu23 = 0.52, g12 = 5290.0, g13 = 5290.0, g23 = 2987.0 }

[[body]]
name = "hexes"
material = "steel"
box = { min = [-3.0, -2.0, 1.0], max = [1.0, 2.0, 2.5], divisions = [3, 2, 2] }

[[body]]
name = "plate"
material = "ply"
box = { min = [2.0, -3.0, -1.0], max = [8.0, 3.0, 0.0], divisions = [3, 3, 2], element = "hex8i" }
plies = { normal = "z", layers = [{ angle = 30.0, thickness = 0.5 }, { angle = -60.0, thickness = 0.5 }] }

[[body]]
name = "tets"
material = "steel"
box = { min = [-4.0, 3.0, -2.0], max = [-2.0, 5.0, 0.0], divisions = [2, 2, 2], element = "tet4" }
"#;

/// The rotation by `angle` about `axis`, as rows.
fn rotation(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let n = {
        let l = axis.iter().map(|a| a * a).sum::<f64>().sqrt();
        axis.map(|a| a / l)
    };
    let (s, c) = angle.sin_cos();
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let cross = match (i, j) {
                (0, 1) => -n[2],
                (0, 2) => n[1],
                (1, 0) => n[2],
                (1, 2) => -n[0],
                (2, 0) => -n[1],
                (2, 1) => n[0],
                _ => 0.0,
            };
            let delta = if i == j { 1.0 } else { 0.0 };
            c * delta + s * cross + (1.0 - c) * n[i] * n[j]
        })
    })
}

fn apply(m: &[[f64; 3]; 3], x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| (0..3).map(|j| m[i][j] * x[j]).sum())
}

/// Every node's displacement that takes it from `x` to `map(x)`.
fn displacement(nodes: &[[f64; 3]], map: impl Fn([f64; 3]) -> [f64; 3]) -> Vec<f64> {
    nodes
        .iter()
        .flat_map(|&x| {
            let y = map(x);
            [y[0] - x[0], y[1] - x[1], y[2] - x[2]]
        })
        .collect()
}

fn largest(f: &[f64]) -> f64 {
    f.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}

/// Turned by 100 degrees about a skew axis, the three kinds' elements strain nothing (their
/// forces below 1e-9 of a 1e-3 stretch's, where the linear kernels give forces 100 times
/// the stretch's). A stretch turned so keeps the stretch's strain energy ($\tfrac12 u \cdot
/// f$ less the turn energy) to 1e-9 and gives the stretch's forces turned, but for the
/// frame's own turn, a part of the order of the strain (below 5e-3 of them); and the forces
/// are that energy's gradient: its central difference along a random direction is their
/// work to 1e-6.
#[test]
fn a_turn_strains_nothing_and_a_turned_stretch_keeps_its_energy_and_its_gradient() {
    let scene = Scene::parse(BLOCKS, std::path::Path::new("blocks.toml")).expect("scene");
    let model = impact::model::Model::from_scene(&scene).expect("model");
    let nodes = model.mesh.nodes.clone();
    let mut linear = CpuKernels::new(model.element_data());
    let mut turning = CpuKernels::new(model.element_data()).corotational(true);
    let r = rotation([0.4, -1.0, 0.7], 100f64.to_radians());
    let e = [
        [1.2e-3, 0.4e-3, -0.3e-3],
        [0.4e-3, -0.8e-3, 0.5e-3],
        [-0.3e-3, 0.5e-3, 0.6e-3],
    ];
    let stretch = |x: [f64; 3]| std::array::from_fn(|i| x[i] + apply(&e, x)[i]);
    let n = 3 * nodes.len();
    let (mut f_stretch, mut f) = (vec![0.0; n], vec![0.0; n]);
    let u_stretch = displacement(&nodes, stretch);
    linear
        .internal_forces_into(&u_stretch, &mut f_stretch)
        .unwrap();
    let scale = largest(&f_stretch);
    assert!(scale > 0.0);

    let u_turn = displacement(&nodes, |x| apply(&r, x));
    turning.internal_forces_into(&u_turn, &mut f).unwrap();
    eprintln!(
        "turned: {:.2e} of the stretch's forces",
        largest(&f) / scale
    );
    assert!(largest(&f) <= 1e-9 * scale, "{}", largest(&f) / scale);
    linear.internal_forces_into(&u_turn, &mut f).unwrap();
    assert!(
        largest(&f) > 100.0 * scale,
        "the linear kernels strain a turn"
    );

    let u = displacement(&nodes, |x| apply(&r, stretch(x)));
    turning.internal_forces_into(&u, &mut f).unwrap();
    let mut worst = 0.0f64;
    for (k, want) in f_stretch.chunks(3).enumerate() {
        let want = apply(&r, [want[0], want[1], want[2]]);
        for c in 0..3 {
            worst = worst.max((f[3 * k + c] - want[c]).abs());
        }
    }
    eprintln!(
        "turned stretch: forces within {:.2e} of the stretch's turned",
        worst / scale
    );
    assert!(worst <= 5e-3 * scale, "{}", worst / scale);
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let want = 0.5 * dot(&u_stretch, &f_stretch);
    let mut energy = |u: &[f64]| {
        let mut f = vec![0.0; u.len()];
        turning.internal_forces_into(u, &mut f).unwrap();
        0.5 * dot(u, &f) - turning.turn_energy()
    };
    let got = energy(&u);
    eprintln!("strain energy {got:.9e} against the stretch's {want:.9e}");
    assert!((got - want).abs() <= 1e-9 * want, "{got} {want}");
    // the gradient, along a direction of every node's own (a fixed pattern)
    let dir: Vec<f64> = (0..n)
        .map(|i| ((i * 7919) % 13) as f64 / 6.0 - 1.0)
        .collect();
    let h = 1e-6;
    let moved = |s: f64| -> Vec<f64> { u.iter().zip(&dir).map(|(a, b)| a + s * h * b).collect() };
    let difference = (energy(&moved(1.0)) - energy(&moved(-1.0))) / (2.0 * h);
    let work = dot(&f, &dir);
    eprintln!("energy's difference {difference:.9e}, forces' work {work:.9e}");
    assert!(
        (difference - work).abs() <= 1e-6 * work.abs(),
        "{difference} against {work}"
    );
}

/// The swinging strip keeps its energy to 1e-4 of it over its first swing out and back (1.2
/// ms, with its tip 16 mm out) and its tip's travel, the same as the linear strip's while
/// small, is shortened where it is large (the strip stretches as it bends).
#[test]
fn a_swinging_strip_keeps_its_energy() {
    let (s, h) = run_completed("corotation_swing", &swinging_strip("corotational", 1.2e-3));
    assert_eq!(s.engine, "cpu");
    let e = h.col("total_energy");
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max);
    let tip = h.col("tip.uz");
    let reach = tip.iter().fold(0.0f64, |a, v| a.max(*v));
    eprintln!(
        "swing: tip out {reach:.3} mm, energy within {:.2e} of its {:.3} mJ",
        drift / e[0],
        e[0]
    );
    assert!(reach > 10.0, "the tip travels {reach} mm");
    assert!(drift <= 1e-4 * e[0], "the energy drifts by {drift} mJ");
    let (_, linear) = run_completed("corotation_swing_linear", &swinging_strip("linear", 1.2e-3));
    let lin_tip = linear.col("tip.uz");
    let lin_reach = lin_tip.iter().fold(0.0f64, |a, v| a.max(*v));
    let early = tip.iter().position(|&v| v > 0.5).unwrap();
    eprintln!(
        "linear tip out {lin_reach:.3} mm; at {:.2} mm, the linear one is at {:.3} mm",
        tip[early], lin_tip[early]
    );
    assert!((tip[early] - lin_tip[early]).abs() <= 0.01 * tip[early]);
    assert!(reach < lin_reach, "{reach} against {lin_reach}");
}

/// Stopped mid-swing and resumed, the strip's history is the unbroken run's, byte for byte.
#[test]
fn a_swing_stopped_and_resumed_is_the_unbroken_swing() {
    let text = swinging_strip("corotational", 6e-4) + "\n[output]\ncheckpoint_every = 300\n";
    let early = text.replace("end_time = 6e-4", "end_time = 3e-4");
    assert_ne!(early, text);
    let whole = run_resumable("corotation_whole", "strip", &text, (false, None)).expect("whole");
    run_resumable("corotation_parts", "strip", &early, (false, None)).expect("first part");
    let resumed = run_resumable("corotation_parts", "strip", &text, (true, None)).expect("resumed");
    assert!(whole.status == "completed" && resumed.status == "completed");
    assert_eq!(
        history_text("corotation_whole"),
        history_text("corotation_parts"),
        "the resumed history differs"
    );
}

/// What the corotational path cannot run is refused by its key: the GPU, and the implicit
/// method.
#[test]
fn a_corotational_scene_on_the_gpu_or_implicit_is_refused_by_its_key() {
    let on_gpu = swinging_strip("corotational", 1e-4).replace(
        "kinematics = \"corotational\"",
        "kinematics = \"corotational\"\ndevice = \"gpu\"",
    );
    let why = refusal_of("corotation_gpu", &on_gpu);
    assert!(
        why.contains("run.kinematics") && why.contains("CPU"),
        "{why}"
    );
    let implicit = swinging_strip("corotational", 1e-4).replace(
        "method = \"explicit\"",
        "method = \"implicit\"\ntime_step = 1e-6",
    );
    let why = refusal_of("corotation_implicit", &implicit);
    assert!(
        why.contains("run.kinematics") && why.contains("explicit"),
        "{why}"
    );
    let unknown = swinging_strip("large", 1e-4);
    let why = refusal_of("corotation_unknown", &unknown);
    assert!(
        why.contains("run.kinematics") && why.contains("corotational"),
        "{why}"
    );
}
