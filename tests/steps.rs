//! Steps in sequence (`[[step]]`) and `[[equation]]`s on the implicit path: a block tied
//! node for node to a twin moves as one body of twice the mass and stiffness under the
//! same load (so as the block alone under half of it); a step that removes the equations
//! releases the twin with the momentum it had; a run of steps resumed before and inside the
//! second step gives the unbroken history; and CalculiX's equrem decks (dynamic steps whose
//! second removes the equations) against their reference output, where the Debian package
//! `calculix-ccx-test` is installed.

mod common;
use common::*;

use impact::scene::Scene;

/// Block `a` on [0, 1]^3 held on its bottom, a pressure on its x+ face; with `twin`, block
/// `b` on [2, 3] x [0, 1]^2 whose every node's every component follows a's matching node
/// (b's bottom thus held by a's). `extra`: appended (steps, output).
fn tied_blocks(pressure: f64, twin: bool, extra: &str) -> String {
    let mut t = format!(
        r#"title = "a block and its tied twin"
[run]
method = "implicit"
end_time = 1.0
time_step = 0.005

[[material]]
name = "soft"
youngs_modulus = 1000.0
poissons_ratio = 0.0
density = 1.0

[[body]]
name = "a"
material = "soft"
box = {{ min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], divisions = [1, 1, 1] }}

[[fix]]
body = "a"
face = "z-"
components = ["x", "y", "z"]

[[load]]
body = "a"
face = "x+"
pressure = {pressure}

[[probe]]
name = "a_tip"
body = "a"
point = [1.0, 1.0, 1.0]
"#
    );
    if twin {
        t += "\n[[body]]\nname = \"b\"\nmaterial = \"soft\"\nbox = { min = [2.0, 0.0, 0.0], max = [3.0, 1.0, 1.0], divisions = [1, 1, 1] }\n";
        let at = |x: f64, y: f64, z: f64| {
            format!(
                "region = {{ min = [{}, {}, {}], max = [{}, {}, {}] }}",
                x - 0.01,
                y - 0.01,
                z - 0.01,
                x + 0.01,
                y + 0.01,
                z + 0.01
            )
        };
        for k in 0..8 {
            let (x, y, z) = ((k & 1) as f64, ((k >> 1) & 1) as f64, (k >> 2) as f64);
            for c in ["x", "y", "z"] {
                t += &format!(
                    "\n[[equation]]\nterms = [{{ body = \"b\", {}, component = \"{c}\", coefficient = 1.0 }}, {{ body = \"a\", {}, component = \"{c}\", coefficient = -1.0 }}]\n",
                    at(x + 2.0, y, z),
                    at(x, y, z)
                );
            }
        }
    }
    t + extra
}

fn run_tagged(tag: &str, text: &str) -> History {
    let s =
        run_resumable(tag, "tied", text, (false, None)).unwrap_or_else(|e| panic!("{tag}: {e}"));
    assert_eq!(s.status, "completed", "{tag}: {:?}", s.warnings);
    History::parse(&history_text(tag))
}

/// [M, K] twice over under F is [M, K] under F / 2: the tied pair's a moves as a alone
/// under half the pressure, to round-off, at every step.
#[test]
fn a_block_tied_to_its_twin_moves_as_itself_under_half_the_load() {
    let pair = run_tagged("tied_pair", &tied_blocks(2.0, true, ""));
    let alone = run_tagged("tied_alone", &tied_blocks(1.0, false, ""));
    let (x, y) = (pair.col("a_tip.ux"), alone.col("a_tip.ux"));
    let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 1e-4, "the tip moves: {scale}");
    for (k, (p, q)) in x.iter().zip(&y).enumerate() {
        assert!((p - q).abs() <= 1e-9 * scale, "row {k}: {p} against {q}");
    }
}

/// A step at t = 0.5 removes every equation: b, free of fixes and loads, keeps the
/// momentum it had then, to round-off, while a goes on.
#[test]
fn a_step_that_removes_the_equations_releases_the_twin_with_its_momentum() {
    let step = "\n[[step]]\nstart = 0.5\nremove_equations = \"all\"\n";
    let h = run_tagged("tied_released", &tied_blocks(2.0, true, step));
    let (t, v) = (h.col("time"), h.col("b.vx"));
    let scale = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let at = t
        .iter()
        .position(|&x| (x - 0.5).abs() < 1e-9)
        .expect("a row at 0.5");
    assert!(
        v[at].abs() > 1e-3 * scale,
        "b moves at the release: {}",
        v[at]
    );
    for (k, x) in v.iter().enumerate().skip(at) {
        assert!(
            (x - v[at]).abs() <= 1e-9 * scale,
            "row {k}: {x} against {}",
            v[at]
        );
    }
    // before the release b followed a: it did not keep its momentum then
    assert!((v[at / 2] - v[at]).abs() > 1e-3 * scale);
}

/// Stopped before the second step and inside it, and resumed: the unbroken history, byte
/// for byte.
#[test]
fn a_run_of_steps_resumes_to_the_unbroken_history() {
    let extra =
        "\n[[step]]\nstart = 0.5\nremove_equations = \"all\"\n\n[output]\ncheckpoint_every = 10\n";
    let whole = tied_blocks(2.0, true, extra);
    run_tagged("steps_whole", &whole);
    for (tag, stop) in [("steps_before", "0.3"), ("steps_inside", "0.7")] {
        let early = whole.replace("end_time = 1.0", &format!("end_time = {stop}"));
        run_tagged(tag, &early);
        let r = run_resumable(tag, "tied", &whole, (true, None)).expect("resumed");
        assert_eq!(r.status, "completed");
        assert_eq!(history_text("steps_whole"), history_text(tag), "{tag}");
    }
}

#[test]
fn a_step_off_the_time_steps_or_removing_what_no_body_holds_is_refused() {
    let refused = |extra: &str, words: &[&str]| {
        let text = tied_blocks(2.0, true, extra);
        let e = Scene::parse(&text, &repo().join("scenes/tied.toml"))
            .expect_err("refused")
            .to_string();
        for w in words {
            assert!(e.contains(w), "`{w}` in: {e}");
        }
    };
    refused(
        "\n[[step]]\nstart = 0.5012\n",
        &["step[0].start", "whole number"],
    );
    refused(
        "\n[[step]]\nstart = 0.5\nremove_equations = \"some\"\n",
        &["step[0].remove_equations", "\"all\""],
    );
    refused(
        "\n[[step]]\nstart = 0.5\nremove_equations = [{ body = \"c\", set = \"n\", component = \"x\" }]\n",
        &["step[0].remove_equations[0].body"],
    );
    refused(
        "\n[[step]]\nstart = 0.5\n\n[[step]]\nstart = 0.25\n",
        &["step[1].start", "after the one before"],
    );
}
