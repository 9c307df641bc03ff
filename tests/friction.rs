//! Coulomb friction against the exact answers of rigid-body mechanics: a block sliding to rest
//! on a floor, a block on an incline (stuck below the friction angle, sliding above it), an
//! oblique impact that slides throughout. Every run also checks that the total energy
//! (kinetic + strain + gravity potential) never rises from one step to the next by more than
//! 1e-6 of its scale, and that the energy lost is the friction work reported.
//!
//! The block is 0.2 x 0.2 x 0.1 (2 x 2 x 1 hex8), stiff (E = 1e8, rho = 1000), resting on an
//! analytic floor z = 0; an incline is the same floor with gravity turned by theta.

mod common;
use common::*;

const G: f64 = 9.81;

fn block_scene(gravity: [f64; 3], velocity: [f64; 3], mu: f64, end: f64, dt: f64) -> String {
    format!(
        r#"title = "Block on a rigid floor"
gravity = [{}, {}, {}]

[run]
end_time = {end}
time_step = {dt}

[[material]]
name = "stiff"
density = 1000.0
youngs_modulus = 1.0e8
poissons_ratio = 0.25

[[body]]
name = "block"
material = "stiff"
box = {{ min = [0.0, 0.0, 0.0], max = [0.2, 0.2, 0.1], divisions = [2, 2, 1] }}
velocity = [{}, {}, {}]

[[rigid_plane]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
friction = {mu}

[[probe]]
name = "base"
body = "block"
point = [0.1, 0.1, 0.0]
"#,
        gravity[0], gravity[1], gravity[2], velocity[0], velocity[1], velocity[2]
    )
}

/// Largest rise of the total energy from one row to the next, and the energy balance error
/// |E_0 - E_end - W_friction|, both relative to `scale`.
fn energy_checks(h: &History, scale: f64) -> (f64, f64) {
    let e = h.col("total_energy");
    let rise = e.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max) / scale;
    let balance = (e[0] - e[e.len() - 1] - h.last("floor.friction_work")).abs() / scale;
    (rise, balance)
}

#[test]
fn block_sliding_on_a_floor_stops_at_v0_over_mu_g() {
    let (v0, mu, dt) = (2.0, 0.2, 1e-3);
    let text = block_scene([0.0, 0.0, -G], [v0, 0.0, 0.0], mu, 1.5, dt);
    let (s, h) = run_text("friction_slide", &text);
    let s = s.expect("run completes");
    // the implicit steps do not measure the normal impulses' share: NaN, and no balance
    assert!(h.col("floor.impact_loss").iter().all(|x| x.is_nan()));
    assert_eq!(s.energy_balance, None);
    let t = h.col("time");
    let vx = h.col("block.vx");
    let ux = h.col("base.ux");
    // stopped: the velocity is within one step's friction change of zero
    let stop = vx
        .iter()
        .position(|v| *v <= mu * G * dt)
        .expect("the block stops");
    let (t_stop, distance) = (t[stop], h.last("base.ux"));
    let (t_exact, d_exact) = (v0 / (mu * G), v0 * v0 / (2.0 * mu * G));
    let creep = ux[stop..].iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b))
        - ux[stop..].iter().fold(f64::INFINITY, |a, &b| a.min(b));
    let ringing = vx[stop..].iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let (rise, balance) = energy_checks(&h, h.col("total_energy")[0]);
    eprintln!(
        "slide: stop {t_stop:.4} (exact {t_exact:.4}), distance {distance:.5} (exact {d_exact:.5}), creep {creep:.2e}, velocity after stop <= {ringing:.2e}, energy rise {rise:.2e}, balance {balance:.2e}, {:.2} iterations/step",
        s.iterations_mean
    );
    assert!((t_stop / t_exact - 1.0).abs() <= 0.02, "stop time {t_stop}");
    assert!(
        (distance / d_exact - 1.0).abs() <= 0.02,
        "distance {distance}"
    );
    assert!(creep <= 1e-3 * d_exact, "creep {creep}");
    assert!(ringing <= mu * G * dt, "velocity after the stop {ringing}");
    assert!(rise <= 1e-6, "energy rise {rise}");
    assert!(
        balance <= 1e-3,
        "friction work against energy lost {balance}"
    );
    assert_eq!(s.unconverged_steps, 0);
}

/// Gravity turned by theta about y: the floor becomes an incline of angle theta.
fn incline(theta_deg: f64) -> (String, f64) {
    let th = theta_deg.to_radians();
    let text = block_scene([G * th.sin(), 0.0, -G * th.cos()], [0.0; 3], 0.2, 1.0, 1e-3);
    (text, th)
}

#[test]
fn block_on_an_incline_below_the_friction_angle_stays() {
    // tan(theta) = 0.15 < mu = 0.2
    let (text, th) = incline(0.15f64.atan().to_degrees());
    let (s, h) = run_text("friction_incline_stick", &text);
    s.expect("run completes");
    let free = 0.5 * G * th.sin() * 1.0f64.powi(2);
    let moved = h.col("base.ux").iter().fold(0.0f64, |a, b| a.max(b.abs()));
    // energy scale: m g h of the 4 kg block
    let (rise, _) = energy_checks(&h, 4.0 * G * 0.1);
    eprintln!(
        "incline tan 0.15: base moved {moved:.3e} (frictionless: {free:.3}), energy rise {rise:.2e}"
    );
    assert!(moved <= 1e-5 * free, "moved {moved}");
    assert!(rise <= 1e-6, "energy rise {rise}");
}

#[test]
fn block_on_an_incline_above_the_friction_angle_slides_at_g_sin_minus_mu_cos() {
    // tan(theta) = 0.3 > mu = 0.2
    let (text, th) = incline(0.3f64.atan().to_degrees());
    let (s, h) = run_text("friction_incline_slide", &text);
    let s = s.expect("run completes");
    let exact = G * (th.sin() - 0.2 * th.cos());
    // the mean acceleration over the second half (past the start's settling)
    let t = h.col("time");
    let vx = h.col("block.vx");
    let half = t.len() / 2;
    let a = (vx[t.len() - 1] - vx[half]) / (t[t.len() - 1] - t[half]);
    // energy scale: the work gravity does over the run
    let scale = 4.0 * G * th.sin() * h.last("base.ux");
    let (rise, balance) = energy_checks(&h, scale);
    eprintln!(
        "incline tan 0.3: acceleration {a:.5} (exact {exact:.5}), energy rise {rise:.2e}, balance {balance:.2e}, {:.2} iterations/step",
        s.iterations_mean
    );
    assert!((a / exact - 1.0).abs() <= 0.02, "acceleration {a}");
    assert!(rise <= 1e-6, "energy rise {rise}");
    assert!(balance <= 1e-3, "balance {balance}");
}

#[test]
fn oblique_impact_sliding_throughout_loses_mu_times_the_normal_impulse() {
    let mu = 0.3;
    let text = block_scene([0.0; 3], [3.0, 0.0, -1.0], mu, 0.015, 1e-4)
        .replace("youngs_modulus = 1.0e8", "youngs_modulus = 1.0e6");
    let (s, h) = run_text("friction_oblique", &text);
    let s = s.expect("run completes");
    let (vx, vz) = (h.col("block.vx"), h.col("block.vz"));
    let lost = vx[0] - h.last("block.vx");
    let normal = h.last("block.vz") - vz[0];
    let active = h.col("floor.active");
    let sliding = h.col("floor.sliding");
    let all_slide = active.iter().zip(&sliding).all(|(a, s)| a == s);
    let released = *active.last().unwrap() == 0.0;
    let (rise, _) = energy_checks(&h, h.col("total_energy")[0]);
    eprintln!(
        "oblique: tangential momentum lost / normal impulse = {:.5} (mu {mu}), rebound vz {:.4}, all contact nodes slide: {all_slide}, energy rise {rise:.2e}, {:.2} iterations/step",
        lost / normal,
        h.last("block.vz"),
        s.iterations_mean
    );
    assert!(released, "the block leaves the floor within the run");
    assert!(all_slide, "every contact node slides in every step");
    assert!(
        (lost / normal / mu - 1.0).abs() <= 0.02,
        "ratio {}",
        lost / normal
    );
    assert!(rise <= 1e-6, "energy rise {rise}");
}

/// When the contact stops sliding (the first step with contact nodes and none sliding) and
/// when it ends (the first step after contact with none active).
fn events(h: &History, name: &str) -> (Option<f64>, Option<f64>) {
    let t = h.col("time");
    let active = h.col(&format!("{name}.active"));
    let sliding = h.col(&format!("{name}.sliding"));
    let first = active.iter().position(|a| *a > 0.0).expect("contact");
    let stop = (first..t.len()).find(|&i| active[i] > 0.0 && sliding[i] == 0.0);
    let end = (first..t.len()).find(|&i| active[i] == 0.0);
    (stop.map(|i| t[i]), end.map(|i| t[i]))
}

/// The paper's example 2 as shipped: a regression pin on our own result (the contact slides
/// until it ends at 0.032 s; the paper reports that sliding stops at 0.026 s and contact ends
/// at 0.06 s, docs/validation.md and docs/method-notes.md say why they differ), plus the energy laws. A
/// run at dt / 8 without event sub-steps also slides throughout and ends at 0.032 s.
#[test]
fn cube_on_plate_events_are_pinned() {
    let (s, h) = run_text_on(
        "cube_on_plate",
        &scene_text("cube_on_plate.toml"),
        Some(impact::scene::DeviceChoice::Cpu),
    );
    let s = s.expect("run completes");
    let (stop, end) = events(&h, "impact");
    let e = h.col("total_energy");
    let rise = e.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max) / e[0];
    let lost = e[0] - e[e.len() - 1];
    let work = h.last("impact.friction_work");
    eprintln!(
        "cube on plate: sliding stops {stop:?}, contact ends {end:?}, energy lost {lost:.5} of which friction {work:.5}, rise {rise:.2e}, {:.2} iterations/step",
        s.iterations_mean
    );
    let dt = 0.002;
    let end = end.expect("contact ends");
    assert_eq!(stop, None, "the contact slides until it ends");
    assert!((end - 0.032).abs() <= 0.5 * dt, "contact ends at {end}");
    assert!(rise <= 1e-6, "energy rise {rise}");
    assert!(
        work > 0.0 && work <= lost * (1.0 + 1e-6),
        "friction work {work}, lost {lost}"
    );
    assert_eq!(s.unconverged_steps, 0);
}

/// The paper's example 2 at its dt = 0.002 against the same scene at dt / 8 (the reference):
/// taking the steps with contact events again in 4 sub-steps (the default) brings the
/// displacement of the centre of the cube's bottom face closer to the reference than the
/// plain steps do (measured: 10% against 16% of its largest value, uz; every step compared).
#[test]
fn event_substeps_bring_the_cube_on_plate_closer_to_a_fine_step() {
    let text = scene_text("cube_on_plate.toml");
    let cpu = Some(impact::scene::DeviceChoice::Cpu);
    let with = |extra: &str| format!("{text}\n[implicit]\n{extra}\n");
    let (s, refined) = run_text_on("cube_events", &text, cpu);
    assert!(s.expect("run completes").event_steps > 0);
    let (s, plain) = run_text_on("cube_plain", &with("event_substeps = 1"), cpu);
    assert_eq!(s.expect("run completes").event_steps, 0);
    let fine_text = edit(
        &with("event_substeps = 1"),
        "time_step = 0.002",
        "time_step = 0.00025",
    );
    let (s, fine) = run_text_on("cube_fine_step", &fine_text, cpu);
    s.expect("run completes");
    // the reference also slides until the contact ends, at 0.0315 (the events pinned above)
    let (stop, end) = events(&fine, "impact");
    assert_eq!(stop, None, "the reference slides until the contact ends");
    let end = end.expect("the reference's contact ends");
    assert!(
        (end - 0.032).abs() <= 0.001,
        "the reference's contact ends at {end}"
    );
    let reference: Vec<f64> = fine.col("bottom.uz").iter().step_by(8).copied().collect();
    let scale = reference.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let error = |h: &History| {
        let uz = h.col("bottom.uz");
        assert_eq!(uz.len(), reference.len());
        uz.iter()
            .zip(&reference)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            / scale
    };
    let (e_events, e_plain) = (error(&refined), error(&plain));
    eprintln!("cube on plate, bottom uz against dt / 8: events {e_events:.4}, plain {e_plain:.4}");
    assert!(
        e_events < 0.75 * e_plain,
        "event sub-steps {e_events} against plain steps {e_plain}"
    );
}

/// The short, hard slide of `docs/validation.md` (mu = 0.5, v0 = 1, g = 10: a rigid block
/// stops at 0.200): the elastic block's floor force rattles, but its impulse is m g t to 1%;
/// friction is mu times the normal impulse to 1e-3 while the block is fast (t < 0.1), and
/// the stop is late by at most the 6% the docs state as this model's bound.
#[test]
fn a_short_hard_slide_stops_late_within_the_documented_bound() {
    let (v0, mu, g, dt) = (1.0, 0.5, 10.0, 1e-3);
    let text = block_scene([0.0, 0.0, -g], [v0, 0.0, 0.0], mu, 0.4, dt);
    let (s, h) = run_text("friction_short_slide", &text);
    s.expect("run completes");
    let (t, vx) = (h.col("time"), h.col("block.vx"));
    let (fz, ft) = (h.col("floor.normal_force"), h.col("floor.tangential_force"));
    let stop = vx
        .iter()
        .position(|v| *v <= mu * g * dt)
        .expect("the block stops");
    let mg = 1000.0 * 0.2 * 0.2 * 0.1 * g;
    let normal: f64 = fz[1..=stop].iter().sum::<f64>() * dt;
    let fast = (0.1 / dt) as usize;
    let friction_fast = ft[1..fast].iter().sum::<f64>() / (mu * fz[1..fast].iter().sum::<f64>());
    let t_exact = v0 / (mu * g);
    eprintln!(
        "short slide: stop {:.4} (rigid {t_exact:.4}), normal impulse / (m g t) {:.4}, friction / (mu N) while fast {friction_fast:.5}",
        t[stop],
        normal / (mg * t[stop])
    );
    assert!((normal / (mg * t[stop]) - 1.0).abs() <= 0.01);
    assert!((friction_fast - 1.0).abs() <= 1e-3);
    assert!(
        t[stop] >= t_exact - dt && t[stop] <= 1.06 * t_exact,
        "stop {}",
        t[stop]
    );
}
