//! Errors of the library. The binary wraps them with `anyhow`.

use std::path::PathBuf;

/// Everything that can go wrong between reading a scene and writing its results.
#[derive(Debug, thiserror::Error)]
pub enum ImpactError {
    /// The scene file could not be read from disk.
    #[error("{path}: cannot read the scene file: {source}")]
    ReadScene {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A run's output (a history read back for charts) could not be read.
    #[error("{path}: cannot read: {source}")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The scene file is not valid TOML, or a key is unknown or has the wrong type.
    #[error("{path}: {message}")]
    SceneSyntax { path: PathBuf, message: String },
    /// A key has a value that is not allowed (named by its full path, e.g. `material[0].density`).
    #[error("{path}: key `{key}`: {message}")]
    SceneValue {
        path: PathBuf,
        key: String,
        message: String,
    },
    /// A feature that belongs to a later part of the project.
    #[error("{path}: key `{key}`: {message}")]
    Unsupported {
        path: PathBuf,
        key: String,
        message: String,
    },
    /// A mesh file (`.msh`, `.inp`) could not be read or is malformed; `line` is 1-based.
    #[error("{path}{}: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
    Mesh {
        path: PathBuf,
        line: Option<usize>,
        message: String,
    },
    /// A file the run wrote and a command reads back (`history.csv`) is not as written.
    #[error("{path}{}: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
    Malformed {
        path: PathBuf,
        line: Option<usize>,
        message: String,
    },
    /// The effective matrix could not be factorised (not positive definite: a body with no
    /// mass, or a NaN in the input).
    #[error("linear solver: {0}")]
    Solver(String),
    /// The time integration produced a non-finite or exploding state.
    #[error("the run diverged at step {step} (t = {time:.6e}): {reason}; the history written so far is kept in {dir}")]
    Diverged {
        step: usize,
        time: f64,
        reason: String,
        dir: PathBuf,
    },
    /// Writing results failed.
    #[error("{path}: cannot write: {source}")]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The GPU engine could not be used.
    #[error("gpu: {0}")]
    Gpu(String),
    /// A run decomposed over ranks cannot do what was asked (the message says what and why).
    #[error("ranks: {0}")]
    Ranks(String),
    /// A failed rank's own error in a stage the ranks of a decomposed run agree on: every
    /// rank stops there, none waits for another.
    #[error(transparent)]
    Agreed(Box<ImpactError>),
    /// A mesh file named by the scene could not be opened.
    #[error("{scene}: key `{key}`: cannot read the mesh file {}: {source}", path.display())]
    MeshFile {
        scene: PathBuf,
        key: String,
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The model would need more memory than the machine or the process may use.
    #[error("{path}: the model needs about {} ({what}), more than the {} this process may use ({limit_source}); use fewer elements or a machine with more memory", bytes(*estimate), bytes(*limit))]
    TooLarge {
        path: PathBuf,
        what: String,
        estimate: u64,
        limit: u64,
        limit_source: String,
    },
    /// The output folder holds an earlier run's files.
    #[error("{}: holds the files of an earlier run ({found}); pass --overwrite to replace them, or --resume to continue that run", dir.display())]
    OutputExists { dir: PathBuf, found: String },
    /// A command line that names a file it must not (the message says which and why).
    #[error("{}: {message}", path.display())]
    Usage { path: PathBuf, message: String },
    /// Another run holds the output folder's lock.
    #[error("{}: another impact run ({holder}) is writing to this folder; wait for it to end, or choose another --out", dir.display())]
    Locked { dir: PathBuf, holder: String },
    /// A run cannot be resumed from the folder (no checkpoint, another scene, ...).
    #[error("{}: cannot resume: {message}", dir.display())]
    Resume { dir: PathBuf, message: String },
    /// The run was stopped by a signal (SIGINT or SIGTERM) after writing a checkpoint.
    #[error("interrupted at step {step} (t = {time:.6e}); the checkpoint, the history so far and a summary are in {}; continue with --resume", dir.display())]
    Interrupted {
        step: usize,
        time: f64,
        dir: PathBuf,
    },
}

/// A byte count in the largest binary unit that keeps it at least 1.
pub fn bytes(n: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut x = n as f64;
    let mut u = 0;
    while x >= 1024.0 && u + 1 < UNITS.len() {
        x /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{n} B")
    } else {
        format!("{x:.1} {}", UNITS[u])
    }
}

/// The exit status of each outcome (documented in docs/scene-format.md, "Exit status").
pub mod exit {
    pub const SUCCESS: u8 = 0;
    /// A failure that is none of the below (the GPU driver, say).
    pub const OTHER: u8 = 1;
    pub const USAGE: u8 = 2;
    pub const INVALID_INPUT: u8 = 3;
    pub const DIVERGED: u8 = 4;
    pub const IO: u8 = 5;
    pub const WARNINGS_STRICT: u8 = 6;
    pub const INTERRUPTED: u8 = 130;
}

impl ImpactError {
    /// An error raised below the scene's level (a factor too large for the memory) with the
    /// scene's path.
    pub fn at_scene(self, scene: &std::path::Path) -> ImpactError {
        match self {
            ImpactError::TooLarge {
                path,
                what,
                estimate,
                limit,
                limit_source,
            } if path.as_os_str().is_empty() => ImpactError::TooLarge {
                path: scene.to_path_buf(),
                what,
                estimate,
                limit,
                limit_source,
            },
            e => e,
        }
    }

    /// The process exit status this error ends a command with.
    pub fn exit_code(&self) -> u8 {
        use ImpactError::*;
        match self {
            ReadScene { .. } | SceneSyntax { .. } | SceneValue { .. } | Unsupported { .. } => {
                exit::INVALID_INPUT
            }
            Mesh { .. } | MeshFile { .. } | TooLarge { .. } | Malformed { .. } => {
                exit::INVALID_INPUT
            }
            Solver(_) | Diverged { .. } => exit::DIVERGED,
            Read { .. } | Write { .. } => exit::IO,
            OutputExists { .. } | Resume { .. } | Locked { .. } | Usage { .. } => exit::USAGE,
            Interrupted { .. } => exit::INTERRUPTED,
            Gpu(_) | Ranks(_) => exit::OTHER,
            Agreed(e) => e.exit_code(),
        }
    }
}

pub type Result<T, E = ImpactError> = std::result::Result<T, E>;
