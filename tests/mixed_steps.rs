//! Steps of different methods in one run (`[[step]] method`, `time_step`): a static preload,
//! then an impact; an impact, then a static settling. Each stage goes on from the last one's
//! state, the total energy going on where it ended. Checked against exact answers: a
//! preloaded bar stays at rest on either dynamic path, St Venant's rigid mass strikes after
//! waiting through a static step, and a bar left ringing by a sudden load settles statically
//! at F L / (E A); a run stopped inside the dynamic stage resumes to the unbroken history.

mod common;
use common::*;

/// A bar 10 long (E 100, density 1, Poisson 0; c = 10), held at x = 0, pulled at x = 10 by
/// a total force `force` with amplitude `amplitude`; `run` is its `[run]` table's body and
/// `steps` is appended.
fn pulled_bar(run: &str, force: f64, amplitude: &str, steps: &str) -> String {
    format!(
        r#"title = "a bar pulled at its end"
[run]
{run}

[[material]]
name = "soft"
density = 1.0
youngs_modulus = 100.0
poissons_ratio = 0.0

[[body]]
name = "bar"
material = "soft"
box = {{ min = [0.0, 0.0, 0.0], max = [10.0, 1.0, 1.0], divisions = [10, 1, 1], element = "hex8" }}

[[fix]]
body = "bar"
face = "x-"
components = ["x", "y", "z"]

[[load]]
body = "bar"
face = "x+"
force = [{:?}, 0.0, 0.0]
{amplitude}

[[probe]]
name = "tip"
body = "bar"
point = [10.0, 0.5, 0.5]
{steps}"#,
        force / 4.0
    )
}

/// The largest change of the total energy from one row to the next.
fn largest_jump(h: &History) -> f64 {
    let e = h.col("total_energy");
    (1..e.len())
        .map(|i| (e[i] - e[i - 1]).abs())
        .fold(0.0, f64::max)
}

/// A bar pulled by 10 over a static step (four increments to t = 1), then held by the same
/// load on the explicit and on the implicit path to t = 3: it stays where the static step
/// left it, at F L / (E A) = 1, to 1e-8, and at rest (its kinetic energy below 1e-12 of
/// the strain energy); the total energy goes on through the change (no row moves it by
/// more than 1e-8 of the strain energy).
#[test]
fn a_preloaded_bar_stays_at_rest_on_either_dynamic_path() {
    let amplitude = "amplitude = [[0.0, 0.0], [1.0, 1.0], [3.0, 1.0]]";
    for (method, dt) in [("explicit", ""), ("implicit", "time_step = 0.05\n")] {
        let step = format!("\n[[step]]\nstart = 1.0\nmethod = \"{method}\"\n{dt}");
        let run = "method = \"static\"\nend_time = 3.0\ntime_step = 0.25";
        let tag = format!("mixed_rest_{method}");
        let (s, h) = run_completed(&tag, &pulled_bar(run, 10.0, amplitude, &step));
        let (t, u) = (h.col("time"), h.col("tip.ux"));
        let strain = h.last("strain_energy");
        assert!(
            t.iter().filter(|&&x| x > 1.0).count() > 10,
            "{method}: the dynamic stage's rows"
        );
        for (x, y) in t.iter().zip(&u).filter(|(x, _)| **x >= 1.0) {
            assert!((y - 1.0).abs() <= 1e-8, "{method}: t = {x}: tip {y}");
        }
        let kinetic = h
            .col("kinetic_energy")
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(
            kinetic <= 1e-12 * strain,
            "{method}: kinetic energy {kinetic}"
        );
        let jump = largest_jump(&h);
        assert!(jump <= 1e-8 * strain, "{method}: the total moved by {jump}");
        assert!((s.end_time - 3.0).abs() < 1e-12);
    }
}

/// The bar pulled by a sudden load of 10 on the explicit path rings between 0 and twice
/// the static stretch; a static step from t = 2.5 (its increments 0.25) then settles it at
/// F L / (E A) = 1 to 1e-8. The static step starts at rest, its kinetic energy dropped into
/// the balance; settling from a state out of equilibrium then loses energy (half the
/// stiffness times the jump squared, for one spring), and the total never rises.
#[test]
fn a_ringing_bar_settles_in_a_static_step() {
    let step = "\n[[step]]\nstart = 2.5\nmethod = \"static\"\ntime_step = 0.25\n";
    let run = "method = \"explicit\"\nend_time = 3.0";
    let (_, h) = run_completed("mixed_settle", &pulled_bar(run, 10.0, "", step));
    let (t, u) = (h.col("time"), h.col("tip.ux"));
    let ringing = (t.iter().zip(&u))
        .filter(|(x, _)| **x < 2.5)
        .map(|(_, y)| *y)
        .fold(0.0, f64::max);
    assert!(ringing > 1.8, "the sudden load rings the bar to {ringing}");
    let last = h.last("tip.ux");
    assert!((last - 1.0).abs() <= 1e-8, "settled at {last}");
    assert_eq!(h.last("kinetic_energy"), 0.0);
    let e = h.col("total_energy");
    let rise = (1..e.len()).map(|i| e[i] - e[i - 1]).fold(0.0, f64::max);
    assert!(
        rise <= 1e-8 * h.last("strain_energy"),
        "the total rose by {rise}"
    );
}

/// St Venant's rigid mass (`tests/rigid_bodies.rs`: the bar's mass, at v0 = 1 onto a bar of
/// impedance Z = 1 held at its far end) waits through a static step in which a small load
/// presses the bar's struck end 1e-6 away from it, then strikes at the explicit step from
/// t = 0.05: the mass starts at v0 (its kinetic energy counted as work done on the model),
/// the contact force follows Z v0 exp(-Z (t - t1) / M) within 2% of Z v0 until the
/// reflected wave returns, the impulse is the mass's loss of momentum to 1e-9, and the
/// total energy goes on through the change and never rises (1e-9 of the 0.05 given).
#[test]
fn a_rigid_mass_waits_through_a_static_step_then_strikes_as_st_venant() {
    let text = r#"title = "St Venant after a static step"
[run]
method = "static"
end_time = 0.3
time_step = 0.025

[[material]]
name = "elastic"
density = 0.01
youngs_modulus = 100.0
poissons_ratio = 0.0

[[body]]
name = "bar"
material = "elastic"
box = { min = [0.0, 0.0, 0.0], max = [10.0, 1.0, 1.0], divisions = [40, 1, 1] }

[[fix]]
body = "bar"
face = "x+"
components = ["x", "y", "z"]

[[load]]
body = "bar"
face = "x-"
force = [2.5e-6, 0.0, 0.0]
amplitude = [[0.0, 0.0], [0.05, 1.0], [1.0, 1.0]]

[[rigid_body]]
name = "tup"
mass = 0.1
position = [0.0, 0.5, 0.5]
velocity = [1.0, 0.0, 0.0]
shape = { plane = { normal = [1.0, 0.0, 0.0] } }

[[contact]]
name = "strike"
secondary = { body = "bar", face = "x-" }
primary = { rigid_body = "tup" }

[[probe]]
name = "end"
body = "bar"
point = [0.0, 0.5, 0.5]

[[step]]
start = 0.05
method = "explicit"
time_step = 0.0025
"#;
    let (_, h) = run_completed("mixed_st_venant", text);
    let (t, f, v) = (h.col("time"), h.col("strike.normal_force"), h.col("tup.vx"));
    let t1 = 0.05;
    let at = t
        .iter()
        .position(|&x| (x - t1).abs() < 1e-12)
        .expect("a row at the change");
    assert_eq!(v[at], 0.0, "the mass waits through the static step");
    assert!((h.col("end.ux")[at] - 1e-6).abs() <= 1e-12, "the preload");
    let (m, dt) = (0.1, 0.0025);
    let exact = |s: f64| m * ((-(s - dt) / m).exp() - (-s / m).exp()) / dt;
    let mut worst = 0.0f64;
    for i in at + 9..t.len() {
        let s = t[i] - t1;
        if s > 0.9 * 0.2 {
            break;
        }
        worst = worst.max((f[i] - exact(s)).abs());
    }
    eprintln!("St Venant after a static step: force error {worst:.4} Z v0");
    assert!(worst <= 0.02, "force error {worst} Z v0");
    let impulse = impulse_from(&t, &f, at + 1);
    let lost = m * (1.0 - v[v.len() - 1]);
    assert!(
        (impulse - lost).abs() <= 1e-9 * m,
        "impulse {impulse} against the lost momentum {lost}"
    );
    let given = 0.5 * m;
    let work = h.col("external_work");
    assert!(
        (work[at + 1] - work[at] - given).abs() <= 1e-6 * given,
        "the kinetic energy given: {} against {given}",
        work[at + 1] - work[at]
    );
    let e = h.col("total_energy");
    let rise = (at..e.len()).map(|i| e[i] - e[at]).fold(0.0, f64::max);
    assert!(rise <= 1e-9 * given, "the total rises by {rise}");
}

/// The preload-then-explicit bar stopped inside its explicit stage and resumed gives the
/// unbroken history, byte for byte.
#[test]
fn a_run_stopped_inside_its_dynamic_stage_resumes_to_the_unbroken_history() {
    let amplitude = "amplitude = [[0.0, 0.0], [1.0, 2.0], [3.0, 0.5]]";
    let step = "\n[[step]]\nstart = 1.0\nmethod = \"explicit\"\n\n[output]\ncheckpoint_every = 7\n";
    let text = |end: f64| {
        let run = format!("method = \"static\"\nend_time = {end:?}\ntime_step = 0.25");
        pulled_bar(&run, 10.0, amplitude, step)
    };
    let (_, whole) = run_completed("mixed_whole", &text(3.0));
    let dir = out_dir("mixed_resumed");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    let out = out_dir("mixed_resumed_run");
    std::fs::write(&path, text(2.0)).unwrap();
    let (s, _) = run_scene_at(&path, &out);
    assert_eq!(s.expect("the first part runs").status, "completed");
    std::fs::write(&path, text(3.0)).unwrap();
    let scene = impact::scene::Scene::load(&path).unwrap();
    let opts = impact::run::RunOptions {
        out: Some(out.clone()),
        quiet: true,
        resume: true,
        ..Default::default()
    };
    let s = impact::run::run(&scene, &opts).expect("the resumed run");
    assert_eq!(s.status, "completed");
    let a = std::fs::read_to_string(out_path("mixed_whole_run").join("history.csv")).unwrap();
    let b = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert!(a == b, "the resumed history differs from the unbroken one");
    assert!(whole.col("time").len() > 20);
}

/// A step's method "auto", and a static step without a time step in an explicit run, are
/// refused, naming the step's key.
#[test]
fn a_steps_method_is_refused_where_it_cannot_step() {
    let run = "method = \"explicit\"\nend_time = 2.0";
    for (step, key) in [
        (
            "\n[[step]]\nstart = 1.0\nmethod = \"auto\"\n",
            "step[0].method",
        ),
        (
            "\n[[step]]\nstart = 1.0\nmethod = \"static\"\n",
            "step[0].time_step",
        ),
    ] {
        let dir = out_dir("mixed_refused");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("scene.toml");
        std::fs::write(&path, pulled_bar(run, 10.0, "", step)).unwrap();
        let e = impact::scene::Scene::load(&path)
            .expect_err("refused")
            .to_string();
        assert!(e.contains(key), "{e}");
    }
}

/// A CalculiX deck: a bar of 10 C3D8 (10 x 1 x 1, E 100, density 1, Poisson 0) held at
/// x = 0, its end stretched to 0.1 in a `*STATIC` step of 4 increments, then let go in a
/// `*DYNAMIC, DIRECT, ALPHA=0.` step (`*BOUNDARY, OP=NEW` keeping only the held end) of 40
/// increments of 0.05, its end's displacement printed at every increment.
fn let_go_deck() -> String {
    let mut t =
        String::from("*HEADING\na bar stretched statically, then let go\n*NODE, NSET=NALL\n");
    let id = |i: usize, j: usize, k: usize| 1 + i + 11 * (j + 2 * k);
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..11 {
                t += &format!("{}, {}., {}., {}.\n", id(i, j, k), i, j, k);
            }
        }
    }
    t += "*ELEMENT, TYPE=C3D8, ELSET=BAR\n";
    for i in 0..10 {
        let c = [
            id(i, 0, 0),
            id(i + 1, 0, 0),
            id(i + 1, 1, 0),
            id(i, 1, 0),
            id(i, 0, 1),
            id(i + 1, 0, 1),
            id(i + 1, 1, 1),
            id(i, 1, 1),
        ];
        let c: Vec<String> = c.iter().map(|x| x.to_string()).collect();
        t += &format!("{}, {}\n", i + 1, c.join(", "));
    }
    let set = |i: usize| {
        format!(
            "{}, {}, {}, {}\n",
            id(i, 0, 0),
            id(i, 1, 0),
            id(i, 0, 1),
            id(i, 1, 1)
        )
    };
    t += &format!("*NSET, NSET=HELD\n{}*NSET, NSET=END\n{}", set(0), set(10));
    t += "*MATERIAL, NAME=SOFT\n*ELASTIC\n100., 0.\n*DENSITY\n1.\n";
    t += "*SOLID SECTION, ELSET=BAR, MATERIAL=SOFT\n*BOUNDARY\nHELD, 1, 3\n";
    // (ccx asks for the energy in the first step of a run whose later step is dynamic)
    t += "*STEP\n*STATIC\n0.25, 1.\n*BOUNDARY\nEND, 1, 1, 0.1\n*NODE PRINT, NSET=END\nU\n";
    t += "*EL PRINT, ELSET=BAR, TOTALS=ONLY\nELSE\n*END STEP\n";
    t += "*STEP\n*DYNAMIC, DIRECT, ALPHA=0.\n0.05, 2.\n*BOUNDARY, OP=NEW\nHELD, 1, 3\n*NODE PRINT, NSET=END\nU\n*END STEP\n";
    t
}

/// The deck above in impact and in CalculiX 2.20: the static step stretches the bar
/// (its end at 0.1 after each of its increments' share), and in the dynamic step the end
/// swings back through 0 towards -0.1 as the bar rings (a quarter period is L / c = 1).
/// Every printed displacement, at every printed time, within 1e-3 of the stretch (8.7e-5
/// measured; the two codes' implicit steps are both the trapezoidal rule here).
#[test]
fn a_calculix_deck_stretched_statically_then_let_go_rings_as_ccx() {
    let deck = written_deck("let_go", &let_go_deck());
    let (s, h) = run_scene_at(&deck, &out_dir("let_go_run"));
    let s = s.unwrap_or_else(|e| panic!("let_go: {e}"));
    assert_eq!(s.status, "completed", "{:?}", s.warnings);
    let (t, u) = (h.col("time"), h.col("END_1.ux"));
    let at = |x: f64| u[t.iter().position(|y| (y - x).abs() < 1e-9).unwrap()];
    assert!((at(1.0) - 0.1).abs() <= 1e-9, "stretched to {}", at(1.0));
    let least = u.iter().fold(f64::MAX, |m, &x| m.min(x));
    assert!(least < -0.08, "the end swings to {least}");
    let Some(dat) = ccx_output(&deck) else {
        return;
    };
    let nodes = deck_nodes(&std::fs::read_to_string(&deck).unwrap());
    let scene = impact::scene::Scene::load(&deck).unwrap();
    let blocks = reference_blocks(&dat);
    let mut worst = 0.0f64;
    let mut compared = 0;
    for (time, block) in &blocks {
        let Some(row) = t.iter().position(|x| (x - time).abs() <= 1e-9 * time) else {
            continue;
        };
        compared += 1;
        for (n, v) in block {
            let x = nodes[n];
            let near = |p: &[f64; 3]| (0..3).all(|a| (p[a] - x[a]).abs() <= 1e-9);
            let probe = (scene.probes.iter()).find(|p| near(&p.point)).unwrap();
            let ux = h.col(&format!("{}.ux", probe.name))[row];
            worst = worst.max((ux - v[0]).abs() / 0.1);
        }
    }
    eprintln!("let go: {worst:e} of the stretch from ccx over {compared} printed times");
    assert!(compared >= 40, "{compared} printed times compared");
    assert!(worst <= 1e-3, "{worst:e} of the stretch");
}
