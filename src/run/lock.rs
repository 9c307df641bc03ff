//! The output folder's lock: one run writes a folder at a time.
//!
//! A run holds an advisory lock (`flock`) on `DIR/.impact.lock`, which names its process, from
//! before it touches the folder's files until it ends. A second run, `--overwrite` or
//! `--resume` into a locked folder is refused. The kernel drops the lock when the process
//! dies however it dies, so a crashed run leaves no stale lock; the file is removed when the
//! run ends.

use std::fs::File;
use std::path::{Path, PathBuf};

use crate::error::{ImpactError, Result};

/// The lock file's name inside the folder.
pub(crate) const FILE: &str = ".impact.lock";

/// A held lock on an output folder, released when dropped.
#[derive(Debug)]
pub struct FolderLock {
    path: PathBuf,
    // the open file holds the lock
    _file: File,
}

impl FolderLock {
    /// Takes the lock on `dir` (which must exist), or refuses naming the process that holds
    /// it.
    pub fn acquire(dir: &Path) -> Result<FolderLock> {
        let path = dir.join(FILE);
        let write_err = |source| ImpactError::Write {
            path: path.clone(),
            source,
        };
        loop {
            let file = std::fs::OpenOptions::new()
                .create(true)
                .truncate(false)
                .read(true)
                .write(true)
                .open(&path)
                .map_err(write_err)?;
            if !try_lock(&file).map_err(write_err)? {
                let holder = std::fs::read_to_string(&path).unwrap_or_default();
                return Err(ImpactError::Locked {
                    dir: dir.to_path_buf(),
                    holder: holder.trim().to_string(),
                });
            }
            // a run that ended between our open and our lock removed the file we locked:
            // take the lock again on the file now at the path
            if !same_file(&file, &path) {
                continue;
            }
            if let Err(source) = name_holder(&file) {
                return Err(ImpactError::Write { path, source });
            }
            return Ok(FolderLock { path, _file: file });
        }
    }
}

/// Writes `process <pid>` into the held lock file.
fn name_holder(mut f: &File) -> std::io::Result<()> {
    use std::io::{Seek, Write};
    f.set_len(0)?;
    f.seek(std::io::SeekFrom::Start(0))?;
    writeln!(f, "process {}", std::process::id())
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        // removed while still locked, so no other run can lock this file in between
        let _ = std::fs::remove_file(&self.path);
    }
}

#[cfg(unix)]
fn try_lock(file: &File) -> std::io::Result<bool> {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock on a file descriptor this process owns for the duration of the call
    let r = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
    if r == 0 {
        return Ok(true);
    }
    let e = std::io::Error::last_os_error();
    match e.raw_os_error() {
        Some(libc::EWOULDBLOCK) => Ok(false),
        _ => Err(e),
    }
}

/// Elsewhere the standard library's lock (Rust 1.89 or later there).
#[cfg(not(unix))]
fn try_lock(file: &File) -> std::io::Result<bool> {
    match file.try_lock() {
        Ok(()) => Ok(true),
        Err(std::fs::TryLockError::WouldBlock) => Ok(false),
        Err(std::fs::TryLockError::Error(e)) => Err(e),
    }
}

/// Whether `path` still names the open `file`.
#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_file: &File, path: &Path) -> bool {
    path.exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_held_lock_refuses_a_second_and_is_released_on_drop() {
        let dir = std::env::temp_dir().join(format!("impact-lock-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let first = FolderLock::acquire(&dir).unwrap();
        let text = std::fs::read_to_string(dir.join(FILE)).unwrap();
        assert_eq!(text.trim(), format!("process {}", std::process::id()));
        match FolderLock::acquire(&dir) {
            Err(ImpactError::Locked { holder, .. }) => assert!(holder.contains("process")),
            other => panic!("a second lock was not refused: {other:?}"),
        }
        drop(first);
        assert!(!dir.join(FILE).exists());
        let again = FolderLock::acquire(&dir).unwrap();
        drop(again);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
