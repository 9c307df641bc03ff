//! The numbers of `history.csv` in their shortest round-trip form (`docs/scene-format.md`,
//! "What a run writes"): a shipped scene's history has no field over 24 characters, every
//! field is a number `str::parse::<f64>` reads (or `NaN`), counts are plain integers, and the
//! t = 0 and last rows' `total_energy` are bit for bit the `energy_initial` and `energy_final`
//! of the summary, both as `run` returns it and as `summary.json` writes it.

mod common;
use common::*;

use impact::output::history::shortest;
use impact::run::{run, RunOptions};
use impact::scene::Scene;

/// The longest text of a finite f64: `-d.ddddddddddddddddde-ddd`.
const LONGEST: usize = 24;

/// The number `"key": <number>` of a JSON text, parsed from its text (serde_json's own float
/// parser is best-effort unless its `float_roundtrip` feature is on; `str::parse` is exact).
fn json_number(json: &str, key: &str) -> f64 {
    let pat = format!("\"{key}\": ");
    let start = json
        .find(&pat)
        .unwrap_or_else(|| panic!("no {key} in {json}"))
        + pat.len();
    let rest = &json[start..];
    let end = rest.find([',', '\n', '}']).unwrap_or(rest.len());
    rest[..end]
        .trim()
        .parse()
        .unwrap_or_else(|e| panic!("{key}: {:?}: {e}", &rest[..end]))
}

/// The paper's two bars, 40 implicit steps.
#[test]
fn two_bars_history_is_short_and_exact() {
    let tag = "history_format_two_bars";
    let dir = out_dir(tag);
    let path = repo().join("scenes").join("two_bars.toml");
    let scene = Scene::parse(&scene_text("two_bars.toml"), &path).expect("valid scene");
    let opts = RunOptions {
        out: Some(dir.clone()),
        quiet: true,
        ..Default::default()
    };
    let summary = run(&scene, &opts).expect("run completes");

    let text = std::fs::read_to_string(dir.join("history.csv")).expect("history.csv");
    let mut lines = text.lines();
    let columns: Vec<&str> = lines.next().expect("header").split(',').collect();
    let integer = |c: &str| c == "step" || c.ends_with(".active") || c.ends_with(".sliding");
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for (r, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), columns.len(), "row {r}: {line}");
        let mut row = Vec::with_capacity(fields.len());
        for (c, f) in columns.iter().zip(&fields) {
            assert!(
                f.len() <= LONGEST,
                "row {r}, {c}: {f} has {} characters",
                f.len()
            );
            if integer(c) {
                f.parse::<u64>()
                    .unwrap_or_else(|e| panic!("row {r}, {c}: {f} is no integer: {e}"));
            }
            let x: f64 = f
                .parse()
                .unwrap_or_else(|e| panic!("row {r}, {c}: {f} is no number: {e}"));
            if !x.is_nan() && !integer(c) {
                // written in the shortest form, and that form reads back to its bits
                let mut s = String::new();
                shortest(x, &mut s);
                assert_eq!(*f, s, "row {r}, {c}");
            }
            row.push(x);
        }
        rows.push(row);
    }
    assert_eq!(
        rows.len(),
        summary.steps + 1,
        "the t = 0 row and one per step"
    );
    let col = |name: &str| columns.iter().position(|c| *c == name).expect(name);
    let (time, step, total) = (col("time"), col("step"), col("total_energy"));
    for (r, row) in rows.iter().enumerate() {
        assert_eq!(row[step], r as f64);
    }
    let (first, last) = (&rows[0], rows.last().expect("rows"));
    assert_eq!(first[time].to_bits(), 0f64.to_bits());

    let json = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    for (name, row, reported, written) in [
        (
            "energy_initial",
            first,
            summary.energy_initial,
            json_number(&json, "energy_initial"),
        ),
        (
            "energy_final",
            last,
            summary.energy_final,
            json_number(&json, "energy_final"),
        ),
    ] {
        assert_eq!(row[total].to_bits(), reported.to_bits(), "{name}: {row:?}");
        assert_eq!(
            row[total].to_bits(),
            written.to_bits(),
            "{name} of summary.json"
        );
    }
}
