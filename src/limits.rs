//! What this process may use: the host memory it may allocate, and input files read within
//! it.
//!
//! Every file the user names (a scene, a mesh, a deck and what it includes) is read through
//! [`read_input`]: only a regular file, and only one smaller than [`INPUT_SHARE`] of the
//! memory the process may use, so that `impact check /dev/zero` or a mesh path that names a
//! device is refused at once instead of reading until memory runs out. The files a run wrote
//! itself (its history, its checkpoint) are read through [`read_own`]: only a regular file,
//! of any size the run made.

use std::io::Read;
use std::path::Path;

use crate::error::bytes;

/// An input may take at most this share of the memory the process may use: a mesh's text
/// becomes a model several times its size.
pub(crate) const INPUT_SHARE: u64 = 8;

/// The most host memory this process may use, and where that figure comes from: the least of
/// the memory available now (plus `held`, what the process already holds of the model), the
/// address-space limit (`ulimit -v`) and the cgroup limit. `None` where none of them can be
/// read (not Linux).
pub fn host_limit(held: u64) -> Option<(u64, String)> {
    let mut best: Option<(u64, String)> = None;
    let mut offer = |bytes: u64, source: &str| {
        if best.as_ref().is_none_or(|b| bytes < b.0) {
            best = Some((bytes, source.to_string()));
        }
    };
    if let Some(kib) = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|t| field(&t, "MemAvailable:"))
    {
        offer(
            kib.saturating_mul(1024).saturating_add(held),
            "memory available now",
        );
    }
    if let Some(b) = std::fs::read_to_string("/proc/self/limits")
        .ok()
        .and_then(|t| field(&t, "Max address space"))
    {
        offer(b, "the address-space limit, ulimit -v");
    }
    if let Some(b) = std::fs::read_to_string("/sys/fs/cgroup/memory.max")
        .ok()
        .and_then(|t| t.trim().parse::<u64>().ok())
    {
        offer(b, "the cgroup's memory.max");
    }
    best
}

/// What this process holds now, as the limit named by `source` (from [`host_limit`]) counts
/// it: its address space (`VmSize`) against `ulimit -v`, its resident memory (`VmRSS`)
/// otherwise; 0 where it cannot be read.
pub fn process_bytes(source: &str) -> u64 {
    let label = match source.contains("ulimit -v") {
        true => "VmSize:",
        false => "VmRSS:",
    };
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|t| field(&t, label))
        .map_or(0, |kib| kib.saturating_mul(1024))
}

/// The first number after `label` on its line (`unlimited` is none).
pub(crate) fn field(text: &str, label: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(label))?;
    line[label.len()..].split_whitespace().next()?.parse().ok()
}

/// The largest input this process reads, and why.
pub(crate) fn input_limit() -> Option<(u64, String)> {
    host_limit(0).map(|(b, source)| {
        (
            b / INPUT_SHARE,
            format!(
                "1/{INPUT_SHARE} of the {} this process may use ({source})",
                bytes(b)
            ),
        )
    })
}

/// Reads a file the user named: refused (as an `InvalidInput` error saying why) when it is
/// not a regular file or is larger than [`input_limit`].
pub(crate) fn read_input(path: &Path) -> std::io::Result<Vec<u8>> {
    let meta = regular_file(path)?;
    let refuse = |m: String| std::io::Error::new(std::io::ErrorKind::InvalidInput, m);
    let limit = input_limit();
    if let Some((limit, why)) = limit.as_ref().filter(|(l, _)| meta.len() > *l) {
        return Err(refuse(format!(
            "it holds {}, more than the {} an input may take ({why})",
            bytes(meta.len()),
            bytes(*limit)
        )));
    }
    // a file that grows while it is read stops at the limit too
    let most = limit.map_or(u64::MAX, |(l, _)| l);
    let mut out = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)?
        .take(most.saturating_add(1))
        .read_to_end(&mut out)?;
    if out.len() as u64 > most {
        return Err(refuse(format!(
            "it grew past the {} an input may take while it was read",
            bytes(most)
        )));
    }
    Ok(out)
}

/// Reads a file a run wrote (a history, a checkpoint), which may be as large as the run
/// made it: refused only when it is not a regular file.
pub(crate) fn read_own(path: &Path) -> std::io::Result<Vec<u8>> {
    regular_file(path)?;
    std::fs::read(path)
}

/// [`read_own`] as UTF-8 text.
pub(crate) fn read_own_text(path: &Path) -> std::io::Result<String> {
    utf8(read_own(path)?)
}

/// [`read_input`] as UTF-8 text.
pub(crate) fn read_input_text(path: &Path) -> std::io::Result<String> {
    utf8(read_input(path)?)
}

/// The metadata of `path`, refused (`InvalidInput`, saying what it is) unless it is a regular
/// file.
fn regular_file(path: &Path) -> std::io::Result<std::fs::Metadata> {
    let meta = std::fs::metadata(path)?;
    if meta.is_file() {
        return Ok(meta);
    }
    let what = if meta.is_dir() {
        "a folder"
    } else {
        "a device, pipe or socket"
    };
    Err(std::io::Error::new(
        std::io::ErrorKind::InvalidInput,
        format!("it is {what}, not a regular file"),
    ))
}

/// `bytes` as text, or an `InvalidData` error saying where they are not UTF-8.
fn utf8(bytes: Vec<u8>) -> std::io::Result<String> {
    String::from_utf8(bytes).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("it is not UTF-8 text ({})", e.utf8_error()),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_parse_from_proc_text() {
        let limits = "Limit                     Soft Limit           Hard Limit           Units\nMax address space         4294967296           unlimited            bytes\n";
        assert_eq!(field(limits, "Max address space"), Some(4294967296));
        let unlimited =
            "Max address space         unlimited            unlimited            bytes\n";
        assert_eq!(field(unlimited, "Max address space"), None);
        assert_eq!(
            field(
                "MemTotal: 10 kB\nMemAvailable:   2048 kB\n",
                "MemAvailable:"
            ),
            Some(2048)
        );
    }

    #[test]
    fn a_device_and_a_folder_are_refused_without_reading() {
        let e = read_input(Path::new("/dev/zero")).unwrap_err();
        assert!(e.to_string().contains("not a regular file"), "{e}");
        let e = read_input(&std::env::temp_dir()).unwrap_err();
        assert!(e.to_string().contains("a folder"), "{e}");
    }

    #[test]
    fn a_regular_file_is_read_whole() {
        let path = std::env::temp_dir().join(format!("impact-limits-{}", std::process::id()));
        std::fs::write(&path, b"abc").unwrap();
        assert_eq!(read_input(&path).unwrap(), b"abc");
        std::fs::remove_file(&path).unwrap();
    }
}
