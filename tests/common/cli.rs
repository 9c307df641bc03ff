//! The `impact` binary run as a user runs it: its exit status and what it printed.

use std::path::Path;
use std::process::{Command, Output};

/// Runs the binary with `args`.
pub fn impact(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_impact"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// The exit status of a process that exited (not killed by a signal).
pub fn code(o: &Output) -> i32 {
    o.status.code().expect("exited, not killed")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A path as an argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}
