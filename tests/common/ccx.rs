//! CalculiX's test decks (Debian `calculix-ccx-test`) and CalculiX itself (`calculix-ccx`):
//! the decks' text, their nodes and their printed displacements.

use std::path::{Path, PathBuf};

use super::scenes::out_dir;

/// CalculiX's test decks (Debian `calculix-ccx-test`), where installed.
pub fn ccx_decks() -> Option<PathBuf> {
    let dir = PathBuf::from("/usr/share/doc/calculix-ccx-test/examples/test");
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(
        std::env::var_os("IMPACT_REQUIRE_CCX").is_none(),
        "IMPACT_REQUIRE_CCX is set and {} is missing",
        dir.display()
    );
    eprintln!(
        "skipped: CalculiX's test decks are not installed (apt-get install calculix-ccx-test)"
    );
    None
}

/// A deck's file, unpacked where the package gzipped it.
pub fn deck_text(dir: &Path, name: &str) -> String {
    let plain = dir.join(name);
    if plain.exists() {
        return std::fs::read_to_string(plain).unwrap();
    }
    let out = std::process::Command::new("gzip")
        .arg("-dc")
        .arg(dir.join(format!("{name}.gz")))
        .output()
        .expect("gzip runs");
    String::from_utf8(out.stdout).unwrap()
}

/// The last displacement block of a `.dat.ref`: node number -> (ux, uy, uz).
pub fn reference_displacements(text: &str) -> Vec<(u64, [f64; 3])> {
    let start = text
        .rfind("displacements (vx,vy,vz)")
        .expect("a displacement block");
    let mut out = Vec::new();
    for line in text[start..].lines().skip(2) {
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() != 4 {
            break;
        }
        let v = [1, 2, 3].map(|i| f[i].parse::<f64>().unwrap());
        out.push((f[0].parse().unwrap(), v));
    }
    out
}

/// The deck's node coordinates.
pub fn deck_nodes(text: &str) -> std::collections::HashMap<u64, [f64; 3]> {
    let mut out = std::collections::HashMap::new();
    let mut on = false;
    for line in text.lines() {
        let u = line.trim().to_ascii_uppercase();
        if u.starts_with('*') {
            on = u.starts_with("*NODE")
                && !u.starts_with("*NODE PRINT")
                && !u.starts_with("*NODE FILE");
            continue;
        }
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        if on && f.len() >= 4 {
            let x = [1, 2, 3].map(|i| f[i].parse::<f64>().unwrap());
            out.insert(f[0].parse().unwrap(), x);
        }
    }
    out
}

/// A printed block: node number -> (ux, uy, uz).
pub type Printed = Vec<(u64, [f64; 3])>;

/// Every displacement block of a `.dat.ref`, with its time.
pub fn reference_blocks(text: &str) -> Vec<(f64, Printed)> {
    let starts: Vec<usize> = (text.match_indices("displacements (vx,vy,vz) for set "))
        .map(|(at, _)| at)
        .collect();
    let ends = starts.iter().skip(1).copied().chain([text.len()]);
    (starts.iter().zip(ends))
        .map(|(&at, end)| {
            let line = text[at..].lines().next().unwrap();
            let time: f64 = line.split_whitespace().last().unwrap().parse().unwrap();
            // the block is the last one of the text up to the next
            (time, reference_displacements(&text[..end]))
        })
        .collect()
}

/// Writes `text` as `name.inp` in a folder of its own and returns its path.
pub fn written_deck(name: &str, text: &str) -> PathBuf {
    let dir = out_dir(&format!("ccx_{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.inp"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Runs CalculiX (`ccx`) on the deck at `path` and returns its `.dat` output; `None` (the
/// test skips) where ccx is not installed, unless `IMPACT_REQUIRE_CCX` is set.
pub fn ccx_output(path: &Path) -> Option<String> {
    let dir = path.parent().unwrap();
    let stem = path.file_stem().unwrap();
    let run = std::process::Command::new("ccx")
        .arg("-i")
        .arg(stem)
        .current_dir(dir)
        .output();
    match run {
        Ok(out) => {
            assert!(
                out.status.success(),
                "ccx on {}: {}",
                path.display(),
                String::from_utf8_lossy(&out.stdout)
            );
            Some(std::fs::read_to_string(path.with_extension("dat")).unwrap())
        }
        Err(e) => {
            assert!(
                std::env::var_os("IMPACT_REQUIRE_CCX").is_none(),
                "IMPACT_REQUIRE_CCX is set and ccx does not run: {e}"
            );
            eprintln!("skipped: CalculiX is not installed (apt-get install calculix-ccx)");
            None
        }
    }
}
