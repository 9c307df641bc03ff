//! A study's output folder: one study writes a folder at a time, and an earlier study's files
//! are replaced only when asked (`--overwrite`), as a run's are.

use std::path::Path;

use crate::error::{ImpactError, Result};
use crate::run::FolderLock;

/// What a study writes into its folder (`runs` is the folder of its runs' own outputs).
pub const STUDY_FILES: [&str; 10] = [
    "study.csv",
    "atlas.md",
    "study.svg",
    "study.png",
    "atlas.svg",
    "atlas.png",
    "crack_band.csv",
    "crack_band.svg",
    "crack_band.png",
    "runs",
];

/// Takes `out` for a study: creates it, locks it (refused while another study or run holds
/// it), and refuses a folder holding an earlier study's files unless `overwrite`, which
/// removes them. The lock is held until the returned value is dropped.
pub fn claim(out: &Path, overwrite: bool) -> Result<FolderLock> {
    if out.exists() && !out.is_dir() {
        return Err(ImpactError::Usage {
            path: out.to_path_buf(),
            message: "is a file: --out names the folder a study writes into".into(),
        });
    }
    std::fs::create_dir_all(out).map_err(|source| ImpactError::Write {
        path: out.to_path_buf(),
        source,
    })?;
    let lock = FolderLock::acquire(out)?;
    let found: Vec<&str> = (STUDY_FILES.iter().copied())
        .filter(|f| out.join(f).exists())
        .collect();
    if found.is_empty() {
        return Ok(lock);
    }
    if !overwrite {
        return Err(ImpactError::Usage {
            path: out.to_path_buf(),
            message: format!(
                "holds the files of an earlier study ({}); pass --overwrite to replace them, or choose another --out",
                found.join(", ")
            ),
        });
    }
    for f in found {
        let path = out.join(f);
        let removed = match path.is_dir() {
            true => std::fs::remove_dir_all(&path),
            false => std::fs::remove_file(&path),
        };
        removed.map_err(|source| ImpactError::Write { path, source })?;
    }
    Ok(lock)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> std::path::PathBuf {
        let d =
            std::env::temp_dir().join(format!("impact_study_folder_{name}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn an_earlier_study_is_kept_without_overwrite_and_replaced_with_it() {
        let d = folder("earlier");
        drop(claim(&d, false).unwrap());
        std::fs::write(d.join("study.csv"), "old").unwrap();
        std::fs::create_dir_all(d.join("runs/a")).unwrap();
        let e = claim(&d, false).unwrap_err();
        assert_eq!(e.exit_code(), crate::error::exit::USAGE);
        assert!(e.to_string().contains("study.csv, runs"), "{e}");
        assert_eq!(std::fs::read_to_string(d.join("study.csv")).unwrap(), "old");
        drop(claim(&d, true).unwrap());
        assert!(!d.join("study.csv").exists() && !d.join("runs").exists());
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_study_into_a_locked_folder_or_onto_a_file_is_refused() {
        let d = folder("locked");
        let held = claim(&d, false).unwrap();
        let e = claim(&d, true).unwrap_err();
        assert!(matches!(e, ImpactError::Locked { .. }), "{e}");
        drop(held);
        let file = d.join("a_file");
        std::fs::write(&file, "").unwrap();
        let e = claim(&file, true).unwrap_err();
        assert_eq!(e.exit_code(), crate::error::exit::USAGE);
        assert!(e.to_string().contains("is a file"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }
}
