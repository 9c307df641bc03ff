//! `[[fix]] displacement`: held components moved along a path in time, against the exact
//! path, the static stiffness and the energy balance; what cannot be asked is refused.

mod common;
use common::*;

/// Pushed in by 0.1 over 4 (ten times the bar's period 4 l / c): the end follows the ramp
/// at every step, the push's reaction is the bar's static stiffness E A / l times the
/// displacement, and the work the push does is the strain energy it leaves.
#[test]
fn a_slow_push_follows_its_path_to_the_static_reaction() {
    let (s, h) = run_text(
        "push_ramp",
        &pushed_bar(4.0, "displacement = [-0.1, 0.0, 0.0]\n"),
    );
    assert_eq!(s.expect("runs").status, "completed");
    for (&t, u) in h.col("time").iter().zip(h.col("tip.ux")) {
        assert!((u + 0.1 * t / 4.0).abs() < 1e-12, "tip at {u} at {t}");
    }
    // the ramp's start rings the bar: its mean force is the static one, E A u / l = 1
    let (t, f) = (h.col("time"), h.col("push.fx"));
    let last: Vec<f64> = (t.iter().zip(&f))
        .filter(|(&t, _)| t >= 3.6)
        .map(|(_, &f)| f)
        .collect();
    let mean = last.iter().sum::<f64>() / last.len() as f64;
    // the support pushes against the bar's end: along -x
    assert!(
        (mean + 0.95).abs() < 0.02 * 0.95,
        "mean reaction {mean} against -0.95"
    );
    let strain = h.last("strain_energy");
    assert!(
        (strain - 0.5 * 1.0 * 0.1 * 0.1 / 10.0 * 100.0).abs() < 0.03 * 0.05,
        "strain {strain}"
    );
    let drift = h
        .col("total_energy")
        .iter()
        .fold(0.0f64, |m, e| m.max(e.abs()));
    assert!(drift < 1e-6 * 0.05, "total energy moved by {drift}");
}

/// An amplitude table: out, held, back; the end is on the path at every step.
#[test]
fn a_displacement_follows_its_amplitude_table() {
    let motion = "displacement = [-0.05, 0.0, 0.0]\namplitude = [[0.0, 0.0], [0.1, 1.0], [0.2, 1.0], [0.3, 0.0]]\n";
    let (s, h) = run_text("push_table", &pushed_bar(0.4, motion));
    assert_eq!(s.expect("runs").status, "completed");
    let path = |t: f64| {
        -0.05
            * if t < 0.1 {
                t / 0.1
            } else if t < 0.2 {
                1.0
            } else {
                (0.3 - t).max(0.0) / 0.1
            }
    };
    for (&t, u) in h.col("time").iter().zip(h.col("tip.ux")) {
        assert!(
            (u - path(t)).abs() < 1e-12,
            "tip at {u} at {t}, path {}",
            path(t)
        );
    }
    let drift = h
        .col("total_energy")
        .iter()
        .fold(0.0f64, |m, e| m.max(e.abs()));
    let most = h.col("strain_energy").into_iter().fold(0.0, f64::max);
    assert!(
        drift < 1e-9 * most,
        "total energy moved by {drift} of {most}"
    );
}

#[test]
fn a_displacement_that_cannot_be_followed_is_refused_by_its_key() {
    let bad = |motion: &str, parts: &[&str]| {
        let msg = refusal("bad_push", &pushed_bar(0.4, motion));
        for p in parts {
            assert!(msg.contains(p), "{msg:?} should contain {p:?}");
        }
    };
    bad(
        "displacement = [-0.1, 0.0, 0.0]\nvelocity = [-1.0, 0.0, 0.0]\n",
        &["fix[1].displacement", "not both"],
    );
    bad(
        "amplitude = [[0.0, 0.0], [1.0, 1.0]]\n",
        &["fix[1].amplitude", "scales a `displacement`"],
    );
    bad(
        "displacement = [-0.1, 0.2, 0.0]\n",
        &[
            "fix[1].displacement",
            "moves y but the fix does not hold it",
        ],
    );
    bad(
        "displacement = [-0.1, 0.0, 0.0]\namplitude = [[0.0, 0.0], [0.0, 1.0]]\n",
        &["fix[1].amplitude", "times must increase"],
    );
    bad(
        "displacement = [-0.1, 0.0, 0.0]\n\n[[fix]]\nbody = \"bar\"\nregion = { min = [9.9, -1.0, -1.0], max = [11.0, 0.5, 2.0] }\ncomponents = [\"x\"]\n",
        &["fix[2].displacement", "fix[1] holds node", "that fix's alone"],
    );
    let implicit = pushed_bar(0.4, "displacement = [-0.1, 0.0, 0.0]\n")
        .replace("method = \"explicit\"", "method = \"implicit\"");
    let e = refusal("bad_push_implicit", &implicit);
    assert!(
        e.contains("run.method") && e.contains("velocity or displacement"),
        "{e}"
    );
}

/// Stopped part way along its path and resumed: the unbroken history, byte for byte; and
/// on one MPI rank the single process's history.
#[test]
fn a_pushed_run_resumes_to_the_unbroken_history() {
    let motion = "displacement = [-0.05, 0.0, 0.0]\namplitude = [[0.0, 0.0], [0.1, 1.0], [0.3, 0.0]]\n\n[output]\ncheckpoint_every = 100\n";
    let text = pushed_bar(0.4, motion);
    let s = run_resumable("push_whole", "pushed", &text, (false, None)).expect("whole");
    assert_eq!(s.status, "completed");
    let early = pushed_bar(0.15, motion);
    run_resumable("push_parts", "pushed", &early, (false, None)).expect("first part");
    let r = run_resumable("push_parts", "pushed", &text, (true, None)).expect("resumed");
    assert_eq!(r.status, "completed");
    assert_eq!(history_text("push_whole"), history_text("push_parts"));
}
