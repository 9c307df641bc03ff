//! What a run writes and reads back, checked as an adversary would: a checkpoint with a
//! flipped byte or a tally that disagrees with its state, a history cut or edited before a
//! resume, two runs into one folder, a write that fails after the run started, and an output
//! folder that is a dangling link. Each is refused (exit 2) or ends `failed` (exit 5), and
//! nothing the earlier run wrote is touched.

mod common;
use common::*;
use std::path::{Path, PathBuf};
use std::process::Output;

/// The two bars to t = `end` (of 0.4), checkpointed every 10 steps, as `dir/scene_<end>.toml`.
fn two_bars(dir: &Path, end: &str) -> PathBuf {
    let text = edit(
        &scene_text("two_bars.toml"),
        "end_time = 0.4",
        &format!("end_time = {end}"),
    ) + "\n[output]\ncheckpoint_every = 10\n";
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join(format!("scene_{end}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

fn run_into(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "run",
        s(scene),
        "--out",
        s(out),
        "--quiet",
        "--device",
        "cpu",
    ];
    args.extend_from_slice(extra);
    impact(&args)
}

/// A folder holding the two bars run to t = 0.2 (a checkpoint at step 20), and the scene
/// that continues it to 0.4.
fn half_run(tag: &str) -> (PathBuf, PathBuf) {
    let dir = out_dir(tag);
    let first = two_bars(&dir, "0.2");
    let out = dir.join("run");
    let o = run_into(&first, &out, &[]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(out.join("checkpoint.bin").exists());
    (two_bars(&dir, "0.4"), out)
}

fn status(out: &Path) -> String {
    let text = std::fs::read_to_string(out.join("summary.json")).expect("a summary");
    let v: serde_json::Value = serde_json::from_str(&text).expect("the summary is JSON");
    v["status"].as_str().unwrap_or_default().to_string()
}

/// One byte flipped anywhere in the checkpoint (every 7th byte here, and the last), or the
/// file cut short, and the resume is refused before anything in the folder changes.
#[test]
fn a_damaged_checkpoint_is_refused_and_the_folder_left_as_it_was() {
    let (scene, out) = half_run("files_flipped");
    let path = out.join("checkpoint.bin");
    let whole = std::fs::read(&path).unwrap();
    let history = std::fs::read(out.join("history.csv")).unwrap();
    let mut places: Vec<usize> = (0..whole.len()).step_by(7).collect();
    places.push(whole.len() - 1);
    let mut cases: Vec<Vec<u8>> = places
        .iter()
        .map(|&i| {
            let mut b = whole.clone();
            b[i] ^= 0x10;
            b
        })
        .collect();
    cases.push(whole[..whole.len() / 2].to_vec());
    cases.push(whole[..whole.len() - 4].to_vec());
    for (k, bytes) in cases.iter().enumerate() {
        std::fs::write(&path, bytes).unwrap();
        let o = run_into(&scene, &out, &["--resume"]);
        assert_eq!(code(&o), 2, "case {k} resumed: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains("checksum") || e.contains("format") || e.contains("cut short"),
            "case {k}: {e}"
        );
        assert_eq!(std::fs::read(out.join("history.csv")).unwrap(), history);
    }
    println!("{} damaged checkpoints refused", cases.len());
    // the whole file still resumes to the unbroken run
    std::fs::write(&path, &whole).unwrap();
    let o = run_into(&scene, &out, &["--resume"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert_eq!(status(&out), "completed");
    let unbroken = out_dir("files_flipped_whole");
    let o = run_into(&scene, &unbroken, &[]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert_eq!(
        std::fs::read(out.join("history.csv")).unwrap(),
        std::fs::read(unbroken.join("history.csv")).unwrap()
    );
}

/// A checkpoint whose tally counts other steps than its state (written whole, with a
/// correct checksum) is refused.
#[test]
fn a_checkpoint_whose_tally_disagrees_with_its_state_is_refused() {
    let (scene_path, out) = half_run("files_tally");
    let scene = impact::scene::Scene::load(&scene_path).unwrap();
    let mut c = impact::checkpoint::Checkpoint::read(&out, &scene).unwrap();
    c.tally.steps = 4;
    c.write(&out).unwrap();
    let o = run_into(&scene_path, &out, &["--resume"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("tally counts 4 steps"),
        "{}",
        stderr(&o)
    );
}

/// Rows deleted and text appended, a row cut short, or a row of another step: the resume
/// is refused naming the row, and the history is not touched.
#[test]
fn a_history_edited_before_a_resume_is_refused_untouched() {
    let (scene, out) = half_run("files_history");
    let path = out.join("history.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let mut deleted = lines.clone();
    deleted.drain(5..8);
    let deleted = deleted.join("\n") + "\nsome text\nmore text\n";
    let cut_row = lines[..12].join("\n")
        + "\n"
        + &lines[12][..lines[12].len() / 2]
        + "\n"
        + &lines[13..].join("\n")
        + "\n";
    let mut other = lines.clone();
    other[21] = lines[20];
    let other = other.join("\n") + "\n";
    for (what, edited) in [("deleted", deleted), ("cut", cut_row), ("other", other)] {
        std::fs::write(&path, &edited).unwrap();
        let o = run_into(&scene, &out, &["--resume"]);
        assert_eq!(code(&o), 2, "{what}: {}", stderr(&o));
        assert!(stderr(&o).contains("history.csv"), "{what}: {}", stderr(&o));
        assert_eq!(std::fs::read_to_string(&path).unwrap(), edited, "{what}");
    }
}

/// While a run holds the folder, another run, `--overwrite` and `--resume` into it are
/// refused with exit 2 and its files are left alone.
#[test]
fn a_locked_folder_refuses_a_second_run() {
    let (scene, out) = half_run("files_lock");
    let before = std::fs::read(out.join("history.csv")).unwrap();
    let lock = impact::run::FolderLock::acquire(&out).unwrap();
    for extra in [&[][..], &["--overwrite"], &["--resume"]] {
        let o = run_into(&scene, &out, extra);
        assert_eq!(code(&o), 2, "{extra:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("another impact run"), "{}", stderr(&o));
        assert_eq!(std::fs::read(out.join("history.csv")).unwrap(), before);
    }
    drop(lock);
    let o = run_into(&scene, &out, &["--resume"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(
        !out.join(".impact.lock").exists(),
        "the lock outlived the run"
    );
}

/// A checkpoint or a chart that cannot be written after the run started ends the run
/// `failed` with the reason in the summary, exit 5.
#[test]
fn a_write_that_fails_mid_run_leaves_a_failed_summary() {
    let dir = out_dir("files_unwritable");
    let scene = two_bars(&dir, "0.4");
    for blocked in [".checkpoint.bin.tmp", ".forces.svg.tmp"] {
        let out = dir.join(blocked.trim_start_matches('.'));
        // a folder where the temporary file must go
        std::fs::create_dir_all(out.join(blocked)).unwrap();
        let o = run_into(&scene, &out, &[]);
        assert_eq!(code(&o), 5, "{blocked}: {}", stderr(&o));
        assert_eq!(status(&out), "failed", "{blocked}");
        let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
        let file = blocked.trim_start_matches('.').trim_end_matches(".tmp");
        assert!(summary.contains(file), "{blocked}: {summary}");
    }
}

/// `--out` naming a link to nowhere says so; `--resume` into a missing folder refuses
/// without creating it.
#[test]
fn a_dangling_link_and_a_missing_resume_folder_are_named() {
    let dir = out_dir("files_dangling");
    let scene = two_bars(&dir, "0.4");
    let link = dir.join("link");
    std::os::unix::fs::symlink(dir.join("nowhere"), &link).unwrap();
    let o = run_into(&scene, &link, &[]);
    assert_eq!(code(&o), 5, "{}", stderr(&o));
    assert!(stderr(&o).contains("symbolic link"), "{}", stderr(&o));
    let missing = dir.join("missing");
    let o = run_into(&scene, &missing, &["--resume"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("does not exist"), "{}", stderr(&o));
    assert!(!missing.exists());
}

/// A scene named `R&D.toml` writes a frame collection whose file names are escaped XML.
#[test]
fn the_frame_collection_escapes_its_file_names() {
    let dir = out_dir("files_xml");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("R&D.toml");
    std::fs::write(
        &scene,
        edit(
            &scene_text("bar_on_wall.toml"),
            "end_time = 0.4",
            "end_time = 0.05",
        ) + "\n[output]\nvtu_every = 2\n",
    )
    .unwrap();
    let out = dir.join("run");
    let o = run_into(&scene, &out, &[]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let pvd = std::fs::read_to_string(out.join("R&D.pvd")).unwrap();
    assert!(pvd.contains("file=\"R&amp;D_000000.vtu\""), "{pvd}");
    assert!(!pvd.contains("\"R&D"), "{pvd}");
    assert!(out.join("R&D_000000.vtu").exists());
}

/// `impact check /dev/zero` is refused at once as no regular file (exit 3).
#[test]
fn a_device_as_the_scene_is_refused_at_once() {
    let t0 = std::time::Instant::now();
    let o = impact(&["check", "/dev/zero"]);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    assert!(stderr(&o).contains("not a regular file"), "{}", stderr(&o));
    assert!(t0.elapsed().as_secs() < 30);
}

/// `impact plot` on a history whose last row was cut short (a full disk), or that holds a
/// header only, names the file and the line (exit 3) instead of drawing.
#[test]
fn plot_refuses_a_cut_or_empty_history() {
    let (_, out) = half_run("files_plot");
    let path = out.join("history.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let cut = &text[..text.len() - 20];
    let rows = cut.lines().count();
    std::fs::write(&path, cut).unwrap();
    let o = impact(&["plot", s(&out), "--columns", "impact.normal_force"]);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    assert!(
        stderr(&o).contains(&format!("history.csv:{rows}")),
        "{}",
        stderr(&o)
    );
    let header = text.lines().next().unwrap().to_string() + "\n";
    std::fs::write(&path, header).unwrap();
    let o = impact(&["plot", s(&out)]);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    assert!(stderr(&o).contains("no rows"), "{}", stderr(&o));
}
