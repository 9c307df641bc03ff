//! Files written whole or not at all, and text made safe for XML.
//!
//! A run's summary, collections, charts and checkpoints are each written to a temporary file
//! beside their place and renamed over it, so that a crash, a full disk or a second reader
//! never sees half a file: the old file stays until the new one is complete. A run's summary
//! may also be written over the room its first one reserved ([`write_over`]), so that a
//! full disk still gets the run's ending.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{ImpactError, Result};

/// Writes `bytes` to `path` through `.<name>.tmp` in the same folder and a rename. On a
/// failure the temporary file is removed and `path` is as it was.
pub(crate) fn write_whole(path: &Path, bytes: &[u8]) -> Result<()> {
    write_whole_with(path, |w| w.write_all(bytes))
}

/// [`write_whole`] for a file `write` streams out.
pub(crate) fn write_whole_with(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let tmp = temporary(path);
    let written = std::fs::File::create(&tmp)
        .and_then(|f| {
            let mut out = std::io::BufWriter::new(f);
            write(&mut out)?;
            // on the disk before it replaces the old file, so that not even a power loss
            // leaves an empty file where a whole one was
            out.into_inner().map_err(|e| e.into_error())?.sync_all()
        })
        .and_then(|()| std::fs::rename(&tmp, path));
    written.map_err(|source| {
        let _ = std::fs::remove_file(&tmp);
        ImpactError::Write {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// Writes `bytes` over the start of the existing file at `path`, the rest of its length
/// blanks, without growing it (the file's own blocks, where a full disk has none for a
/// new file). Refused where `bytes` is longer than the file.
pub(crate) fn write_over(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut f = std::fs::OpenOptions::new().write(true).open(path)?;
    let room = f.metadata()?.len() as usize;
    if bytes.len() > room {
        return Err(std::io::Error::other("longer than the room the file holds"));
    }
    f.write_all(bytes)?;
    f.write_all(&vec![b' '; room - bytes.len()])?;
    f.sync_all()
}

/// `dir/.name.tmp` for `dir/name`.
fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp"))
}

/// `s` with the five characters XML reserves escaped, for text and attribute values.
pub(crate) fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_every_reserved_character() {
        assert_eq!(
            xml_escape(r#"R&D <"a">'b'"#),
            "R&amp;D &lt;&quot;a&quot;&gt;&apos;b&apos;"
        );
        assert_eq!(xml_escape("plain_name-1.2"), "plain_name-1.2");
    }

    #[test]
    fn a_failed_write_leaves_the_old_file() {
        let dir = std::env::temp_dir().join(format!("impact-whole-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("summary.json");
        write_whole(&path, b"old").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        // a folder where the temporary file must go makes the write fail
        std::fs::create_dir_all(temporary(&path)).unwrap();
        assert!(write_whole(&path, b"new").is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
