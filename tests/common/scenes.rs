//! Scenes from the shipped files or from text, run into a fresh folder per test.

use std::path::PathBuf;

use impact::output::Summary;
use impact::run::{run, RunOptions};
use impact::scene::Scene;

use super::history::History;

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn scene_text(name: &str) -> String {
    std::fs::read_to_string(repo().join("scenes").join(name)).expect("shipped scene")
}

/// Replaces `from` (which must occur) by `to`.
pub fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "scene text lacks {from:?}");
    text.replacen(from, to, 1)
}

/// Where the run tagged `tag` writes.
pub fn out_path(tag: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(tag)
}

/// [`out_path`], emptied for a new run.
pub fn out_dir(tag: &str) -> PathBuf {
    let d = out_path(tag);
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs a scene given as text; returns the summary (or error) and the history written.
pub fn run_text(tag: &str, text: &str) -> (impact::Result<Summary>, History) {
    run_text_on(tag, text, None)
}

/// Runs a scene text, on the given device if one is named (else the scene's).
pub fn run_text_on(
    tag: &str,
    text: &str,
    device: Option<impact::scene::DeviceChoice>,
) -> (impact::Result<Summary>, History) {
    let dir = out_dir(tag);
    // as if it were the file scenes/<tag>.toml, so that mesh paths resolve against scenes/
    let path = repo().join("scenes").join(format!("{tag}.toml"));
    let scene = Scene::parse(text, &path).expect("valid scene");
    let opts = RunOptions {
        out: Some(dir.clone()),
        device,
        quiet: true,
        ..Default::default()
    };
    let s = run(&scene, &opts);
    if let Err(e) = &s {
        // a run that stops before its first row leaves no history to read
        eprintln!("{tag}: {e}");
    }
    (s, History::read(&dir.join("history.csv")))
}

/// [`run_text`]; the name says that the text's mesh paths resolve against `scenes/`.
pub fn run_scene_text(tag: &str, text: &str) -> (impact::Result<Summary>, History) {
    run_text(tag, text)
}
