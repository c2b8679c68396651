//! Errors of the solver: each names the file, the place in it, and what to change.

use std::path::{Path, PathBuf};

use fdem_mesh::shorten;

/// An error in a scene file or in what it refers to.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{}: cannot read the file: {message}", file.display())]
    Io {
        /// The file.
        file: PathBuf,
        /// The operating system's message.
        message: String,
    },
    /// The JSON is malformed, a field has the wrong type, is unknown or missing.
    #[error("{}:{line}:{column}: at `{}`: {}\n  fix: {}", file.display(), shorten(path), shorten(message), shorten(fix))]
    Parse {
        /// The scene file.
        file: PathBuf,
        /// JSON path of the offending field.
        path: String,
        /// Line (1-based).
        line: usize,
        /// Column (1-based).
        column: usize,
        /// What is wrong.
        message: String,
        /// What to change.
        fix: String,
    },
    /// A value is out of range or inconsistent.
    #[error("{}: at `{}`: {}\n  fix: {}", file.display(), shorten(path), shorten(message), shorten(fix))]
    Invalid {
        /// The scene file.
        file: PathBuf,
        /// JSON path of the offending field.
        path: String,
        /// What is wrong.
        message: String,
        /// What to change.
        fix: String,
    },
    /// The mesh a body names could not be loaded.
    #[error("{}: at `{}`: cannot load mesh {}: {}\n  fix: check the path (relative to the scene file) and the mesh", file.display(), shorten(path), mesh.display(), shorten(message))]
    Mesh {
        /// The scene file.
        file: PathBuf,
        /// JSON path of the body's mesh field.
        path: String,
        /// The mesh file.
        mesh: PathBuf,
        /// The mesh reader's message.
        message: String,
    },
}

impl SceneError {
    /// A value of `file` out of range or inconsistent at the JSON `path`, with the fix.
    pub fn invalid(
        file: &Path,
        path: impl Into<String>,
        message: impl Into<String>,
        fix: impl Into<String>,
    ) -> Self {
        SceneError::Invalid {
            file: file.to_path_buf(),
            path: path.into(),
            message: message.into(),
            fix: fix.into(),
        }
    }

    /// Checks that the value `v` of `file` at the JSON `path` (a `what`, e.g. "relaxation
    /// tolerance") lies in `range`; else the error names the path, the value, the range and
    /// the fix.
    pub fn check_range(
        file: &Path,
        path: impl Into<String>,
        what: &str,
        v: f64,
        range: Range,
        fix: impl Into<String>,
    ) -> Result<(), SceneError> {
        if range.contains(v) {
            Ok(())
        } else {
            Err(SceneError::invalid(
                file,
                path,
                format!("{what} {v} is outside its valid range {range}"),
                fix,
            ))
        }
    }
}

/// The valid range of a scene value (a tolerance, factor, ratio or rate): finite, above
/// `lo` (or equal to it when `lo_closed`) and below `hi` (or equal when `hi_closed`; an
/// infinite `hi` is no upper bound). Written as `(0, 1)`, `[0, inf)`, ...
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// The lower bound.
    pub lo: f64,
    /// The lower bound is valid.
    pub lo_closed: bool,
    /// The upper bound (infinite: none).
    pub hi: f64,
    /// The upper bound is valid.
    pub hi_closed: bool,
}

impl Range {
    /// `(lo, hi)`.
    pub const fn open(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            lo_closed: false,
            hi,
            hi_closed: false,
        }
    }
    /// `(lo, hi]`.
    pub const fn open_closed(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            lo_closed: false,
            hi,
            hi_closed: true,
        }
    }
    /// `[lo, hi)`.
    pub const fn closed_open(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            lo_closed: true,
            hi,
            hi_closed: false,
        }
    }
    /// `[lo, hi]`.
    pub const fn closed(lo: f64, hi: f64) -> Self {
        Self {
            lo,
            lo_closed: true,
            hi,
            hi_closed: true,
        }
    }
    /// `(lo, inf)`: above `lo`.
    pub const fn above(lo: f64) -> Self {
        Self::open(lo, f64::INFINITY)
    }
    /// `[lo, inf)`: at least `lo`.
    pub const fn at_least(lo: f64) -> Self {
        Self::closed_open(lo, f64::INFINITY)
    }

    /// Whether `v` is finite and in the range.
    pub fn contains(&self, v: f64) -> bool {
        v.is_finite()
            && (v > self.lo || (self.lo_closed && v == self.lo))
            && (v < self.hi || (self.hi_closed && v == self.hi))
    }
}

impl std::fmt::Display for Range {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let hi = if self.hi.is_finite() {
            format!("{}", self.hi)
        } else {
            "inf".into()
        };
        write!(
            f,
            "{}{}, {hi}{}",
            if self.lo_closed { "[" } else { "(" },
            self.lo,
            if self.hi_closed && self.hi.is_finite() {
                "]"
            } else {
                ")"
            }
        )
    }
}

/// An error while running a scene.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Writing output failed.
    #[error("cannot write {}: {message}", file.display())]
    Output {
        /// The file being written.
        file: PathBuf,
        /// The cause.
        message: String,
    },
    /// The solution became unstable (non-finite values, energy growth, triangles turned
    /// inside out, a stage's error) and the run was stopped (its output so far is written).
    #[error("the solution became unstable at step {step} (t = {time:e} s): {message}")]
    Unstable {
        /// Step number.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// What was found, its likely cause in the input, and (last line) the fix for that
        /// cause (`crate::run::diagnosis`).
        message: String,
    },
    /// A relaxation that did not reach its tolerance within the duration (its output and
    /// summary, with `converged: false`, are written).
    #[error(
        "the relaxation did not converge: relative residual {residual:.3e} at the end of the duration (t = {time:.4e} s, {steps} steps), above the tolerance {tolerance:e}\n  fix: {fix}"
    )]
    NotConverged {
        /// The residual reached: |out-of-balance force| / |load|.
        residual: f64,
        /// `integrator.relaxation_tolerance`.
        tolerance: f64,
        /// Steps run.
        steps: u64,
        /// Simulated time reached [s].
        time: f64,
        /// What to change.
        fix: String,
    },
    /// A checkpoint that cannot be resumed (damaged, of a newer format, of another scene).
    #[error("{}: {}\n  fix: {}", .0.file.display(), .0.message, .0.fix)]
    Checkpoint(crate::checkpoint::CheckpointError),
    /// The run was asked to stop (a signal, or its `stop_after` step): it wrote a checkpoint
    /// and its summary, marked interrupted.
    #[error(
        "the run was interrupted ({reason}) at step {step} (t = {time:.4e} s); its checkpoint is {}\n  to continue: fdem run --resume {}",
        checkpoint.display(),
        checkpoint.parent().map_or_else(|| ".".into(), |p| p.display().to_string())
    )]
    Interrupted {
        /// What stopped it: `SIGINT`, `SIGTERM`, `stop_after`.
        reason: String,
        /// Steps done.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// The checkpoint written.
        checkpoint: PathBuf,
    },
    /// The static solve failed.
    #[error("static solve failed: {message}\n  fix: {fix}")]
    Static {
        /// What went wrong.
        message: String,
        /// What to change.
        fix: String,
    },
}

impl From<crate::checkpoint::CheckpointError> for RunError {
    fn from(e: crate::checkpoint::CheckpointError) -> Self {
        RunError::Checkpoint(e)
    }
}
