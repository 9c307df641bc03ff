//! Every run draws its contact forces and energies (SVG and PNG), with the scene's exact
//! curves beside them; `impact plot` draws any columns. The PNGs are checked without a
//! screenshot: they decode, have the chart's size, and hold more than one colour (the
//! curve's, black, white).

mod common;
use common::*;

use std::collections::HashSet;
use std::path::Path;
use std::process::Command;

/// Decodes a PNG: (width, height, distinct RGB colours).
fn png_colours(path: &Path) -> (u32, u32, HashSet<[u8; 3]>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buf).expect("one frame");
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let colours = buf[..info.buffer_size()]
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    (info.width, info.height, colours)
}

#[test]
fn a_run_draws_its_forces_with_the_exact_curve_and_its_energies() {
    let (s, _) = run_text("plots_two_bars", &scene_text("two_bars.toml"));
    s.expect("run completes");
    let dir = out_path("plots_two_bars");
    for name in ["forces", "energies"] {
        let (w, h, colours) = png_colours(&dir.join(format!("{name}.png")));
        assert_eq!((w, h), (800, 480));
        assert!(
            colours.len() > 2,
            "{name}.png has {} colours",
            colours.len()
        );
        assert!(colours.contains(&[31, 119, 180]), "{name}.png: no curve");
        assert!(colours.contains(&[0, 0, 0]) && colours.contains(&[255, 255, 255]));
    }
    let svg = std::fs::read_to_string(dir.join("forces.svg")).expect("forces.svg");
    assert!(
        svg.contains("impact.normal_force (1D wave theory)"),
        "exact curve in the legend"
    );
    assert_eq!(
        svg.matches("<polyline").count(),
        2,
        "computed and exact curves"
    );
    assert!(
        svg.contains("stroke-dasharray"),
        "the exact curve is dashed"
    );
}

#[test]
fn plot_command_draws_named_columns_and_names_a_missing_one() {
    let (s, _) = run_text("plots_command", &scene_text("two_bars.toml"));
    s.expect("run completes");
    let dir = out_path("plots_command");
    let bin = env!("CARGO_BIN_EXE_impact");
    let out = Command::new(bin)
        .args([
            "plot",
            dir.to_str().unwrap(),
            "--columns",
            "A.vx,B.vx",
            "--name",
            "velocities",
        ])
        .output()
        .expect("impact plot runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (w, h, colours) = png_colours(&dir.join("velocities.png"));
    assert_eq!((w, h), (800, 480));
    // two curves in two palette colours
    assert!(colours.contains(&[31, 119, 180]) && colours.contains(&[214, 39, 40]));
    let svg = std::fs::read_to_string(dir.join("velocities.svg")).expect("svg");
    assert_eq!(svg.matches("<polyline").count(), 2);

    let out = Command::new(bin)
        .args(["plot", dir.to_str().unwrap(), "--columns", "A.vq"])
        .output()
        .expect("impact plot runs");
    // a column the history lacks is a usage error, like a bad flag
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no column \"A.vq\"") && err.contains("history.csv"),
        "{err}"
    );
    // an empty or hidden name, and the run's own charts' names, are refused: the run's
    // energies chart is left as it was
    let energies = std::fs::read(dir.join("energies.svg")).expect("the run's chart");
    for (name, words) in [
        ("", "not empty"),
        (".hidden", "hidden"),
        ("a/b", "holds '/'"),
        ("energies", "writes a chart of that name"),
        ("impact_force_displacement", "writes a chart of that name"),
    ] {
        let out = Command::new(bin)
            .args([
                "plot",
                dir.to_str().unwrap(),
                "--columns",
                "A.vx",
                "--name",
                name,
            ])
            .output()
            .expect("impact plot runs");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name:?}: {err}");
        assert!(err.contains(words), "{name:?}: {err}");
    }
    assert_eq!(std::fs::read(dir.join("energies.svg")).unwrap(), energies);
}
