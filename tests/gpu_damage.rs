//! The damage kernels (`hex8_damage`, `hex8i_damage`, `tet4_damage`, `damage_reduce`) on the
//! device in f32 against their CPU twins in f64, on random distorted inputs: jittered boxes
//! of IM7/8552 far from the origin (a layered hex8i body of three plies at 0, 45 and 90
//! degrees, a hex8 body whose plies damage by their in-plane stresses alone, with their
//! strengths lowered where the cells are wider than a snap-back width, and a tet4
//! body, each turned), random strains around the matrix's
//! initiation (some points start to damage, some do not, the sieve passes some elements and
//! skips others), random mid-step velocities, and a random old state (some elements already
//! damaged, in every mode). The step's forces, new state, first damages and dissipation
//! (and its fibre modes' share) agree within f32's reach; so do the forces of the state as
//! it is (no step).

mod common;
use common::*;

use impact::backend::{CpuKernels, Kernels};
use impact::gpu::engine::GpuKernels;
use impact::kernels::damage_data::{DamageData, DamageState};
use impact::material::damage::POINT_STATE;
use impact::model::Model;
use impact::scene::Scene;
use rand::{rngs::StdRng, Rng, SeedableRng};

const SCENE: &str = r#"
[run]
method = "explicit"
end_time = 1e-6

[[material]]
name = "im7"
density = 1.57e-9
transversely_isotropic = { e1 = 171420.0, e2 = 9080.0, nu12 = 0.32, nu23 = 0.52, g12 = 5290.0 }
strength = { xt = 2326.2, xc = 1200.1, yt = 62.3, yc = 199.8, s12 = 92.3, s23 = 75.3 }
fracture_energy = { ft = 133.3, fc = 47.5, mt = 0.277, mc = 0.788 }
damage_viscosity = 2e-8

[[material]]
name = "im7_in_plane"
density = 1.57e-9
transversely_isotropic = { e1 = 171420.0, e2 = 9080.0, nu12 = 0.32, nu23 = 0.52, g12 = 5290.0 }
strength = { xt = 2326.2, xc = 1200.1, yt = 62.3, yc = 199.8, s12 = 92.3, s23 = 75.3 }
fracture_energy = { ft = 133.3, fc = 47.5, mt = 0.277, mc = 0.788 }
damage_stresses = "in_plane"
snap_back = "lower_strength"

[[body]]
name = "layered"
material = "im7"
box = { min = [120.0, -64.0, 30.0], max = [123.0, -61.0, 30.6], divisions = [6, 6, 1], element = "hex8i" }
plies = { normal = "z", layers = [
  { angle = 0.0, thickness = 0.2 }, { angle = 45.0, thickness = 0.2 }, { angle = 90.0, thickness = 0.2 },
] }

[[body]]
name = "bricks"
material = "im7_in_plane"
box = { min = [125.0, -64.0, 30.0], max = [128.0, -61.0, 31.5], divisions = [6, 6, 3], element = "hex8" }
orientation = { axis = [0.3, 0.2, 1.0], angle = 30.0 }

[[body]]
name = "tets"
material = "im7"
box = { min = [130.0, -64.0, 30.0], max = [132.0, -62.0, 31.0], divisions = [4, 4, 2], element = "tet4" }
orientation = { axis = [1.0, 0.0, 0.2], angle = -20.0 }
"#;

/// The model, its nodes jittered by up to 0.15 of the cells.
fn model(rng: &mut StdRng) -> Model {
    let scene = Scene::parse(SCENE, std::path::Path::new("damage_twins.toml")).expect("scene");
    let mut model = Model::from_scene(&scene).expect("model");
    for x in &mut model.mesh.nodes {
        for c in x.iter_mut() {
            *c += rng.random_range(-0.075..0.075);
        }
    }
    model
}

/// A random old state: a third of the damageable elements damaged (every point's
/// variables up to 0.6, the acting ones up to them), with first damages.
fn old_state(rng: &mut StdRng, data: &DamageData) -> DamageState {
    let mut s = DamageState::new(data);
    s.steps = 40;
    for (k, b) in data.blocks.iter().enumerate() {
        for i in 0..b.len() {
            if rng.random_range(0.0..1.0) > 0.33 {
                continue;
            }
            for p in s.points[k][b.state_range(i)].chunks_exact_mut(POINT_STATE) {
                for m in 0..4 {
                    let d: f64 = if rng.random_range(0.0..1.0) < 0.5 {
                        rng.random_range(0.0..0.6)
                    } else {
                        0.0
                    };
                    p[m] = d;
                    p[4 + m] = d * rng.random_range(0.5..1.0);
                }
            }
            s.damaged[k][i] = true;
            s.first[k][i] = [rng.random_range(1..40), 0];
        }
    }
    s
}

/// Random displacements of strains up to about twice the matrix's initiation strain (a
/// rotation about the origin and a translation besides, which strain nothing) and mid-step
/// velocities of a step's change of a tenth of that.
fn motion(rng: &mut StdRng, model: &Model, dt: f64) -> (Vec<f64>, Vec<f64>) {
    let grad: [[f64; 3]; 3] =
        std::array::from_fn(|_| std::array::from_fn(|_| rng.random_range(-0.012..0.012)));
    let (mut u, mut v) = (Vec::new(), Vec::new());
    for x in &model.mesh.nodes {
        for row in &grad {
            let h: f64 = (0..3).map(|b| row[b] * (x[b] - 125.0)).sum();
            u.push(h + rng.random_range(-2e-3..2e-3) + 0.3);
            v.push((0.1 * h + rng.random_range(-2e-4..2e-4)) / dt);
        }
    }
    (u, v)
}

#[test]
fn damage_kernels_match_their_cpu_twins() {
    let Some(ctx) = gpu_context("damage kernels") else {
        return;
    };
    let seed = seed("damage_kernels");
    let mut rng = StdRng::seed_from_u64(seed);
    let model = model(&mut rng);
    let data = model.damage_data().expect("damage");
    let dt = 2e-8;
    let (mut damaged_now, mut fibre_seen) = (0, false);
    for round in 0..4 {
        let old = old_state(&mut rng, &data);
        let (u, v) = motion(&mut rng, &model, dt);
        let mut cpu = CpuKernels::new(model.element_data()).with_damage(Some(data.clone()));
        let mut gpu = GpuKernels::new(ctx.clone(), &model.element_data())
            .unwrap()
            .with_damage(Some(data.clone()))
            .unwrap();
        cpu.restore_damage(&old.flat()).unwrap();
        gpu.restore_damage(&old.flat()).unwrap();
        let n = u.len();
        // the forces of the state as it is
        let (mut fc, mut fg) = (vec![0.0; n], vec![0.0; n]);
        cpu.internal_forces_into(&u, &mut fc).unwrap();
        gpu.internal_forces_into(&u, &mut fg).unwrap();
        let still = rel_err(&fg, &fc);
        // a step
        let dc = cpu.step_forces_into((&u, &v), dt, &mut fc).unwrap();
        let dg = gpu.step_forces_into((&u, &v), dt, &mut fg).unwrap();
        let step = rel_err(&fg, &fc);
        let (sc, sg) = (cpu.damage_values().unwrap(), gpu.damage_values().unwrap());
        let mut cs = DamageState::new(&data);
        cs.restore(&data, &sc).unwrap();
        let mut gs = DamageState::new(&data);
        gs.restore(&data, &sg).unwrap();
        let worst_state = (cs.points.iter().flatten().zip(gs.points.iter().flatten()))
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let flags = |s: &DamageState| s.damaged.iter().flatten().filter(|&&d| d).count();
        let differing: Vec<_> = (cs.first.iter().flatten().zip(gs.first.iter().flatten()))
            .filter(|(a, b)| a != b)
            .collect();
        let firsts = differing.len();
        if firsts > 0 {
            eprintln!("differing first damages (cpu, gpu): {differing:?}");
        }
        damaged_now += flags(&cs) - flags(&old);
        eprintln!(
            "round {round}: forces (no step) {still:.2e}, step forces {step:.2e}, state {worst_state:.2e}, dissipation cpu {:.6e} gpu {:.6e} (fibre {:.6e} {:.6e}), newly damaged {}, first damages differing {firsts}",
            dc.total,
            dg.total,
            dc.fibre,
            dg.fibre,
            flags(&cs) - flags(&old)
        );
        assert!(
            still <= 1e-5,
            "seed {seed}: forces of the state {still:.3e}"
        );
        assert!(step <= 2e-5, "seed {seed}: step forces {step:.3e}");
        assert!(worst_state <= 1e-4, "seed {seed}: state {worst_state:.3e}");
        let tolerance = 1e-3 * dc.total.abs().max(1e-12);
        assert!(
            (dg.total - dc.total).abs() <= tolerance,
            "seed {seed}: dissipation"
        );
        assert!(
            (dg.fibre - dc.fibre).abs() <= tolerance,
            "seed {seed}: the fibre modes' share"
        );
        assert!((0.0..=dc.total).contains(&dc.fibre) || dc.total == 0.0);
        fibre_seen |= dc.fibre > 0.0 && dc.fibre < dc.total;
        assert_eq!(flags(&cs), flags(&gs), "seed {seed}: damaged elements");
        assert_eq!(firsts, 0, "seed {seed}: first damages");
        assert_eq!((cs.steps, gs.steps), (old.steps + 1, old.steps + 1));
    }
    assert!(damaged_now > 0, "some elements start to damage");
    assert!(fibre_seen, "both kinds grow on some step");
}
