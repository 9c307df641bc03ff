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
}

pub type Result<T, E = ImpactError> = std::result::Result<T, E>;
