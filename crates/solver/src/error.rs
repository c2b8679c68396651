//! Errors of the solver: each names the file, the place in it, and what to change.

use std::path::PathBuf;

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
    #[error("{}:{line}:{column}: at `{path}`: {message}\n  fix: {fix}", file.display())]
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
    #[error("{}: at `{path}`: {message}\n  fix: {fix}", file.display())]
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
    #[error("{}: at `{path}`: cannot load mesh {}: {message}\n  fix: check the path (relative to the scene file) and the mesh", file.display(), mesh.display())]
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
    /// The solution became unstable (NaN or infinite values).
    #[error(
        "the solution became unstable at step {step} (t = {time:e} s): {message}\n  fix: lower the time step or its safety factor, or check the materials"
    )]
    Unstable {
        /// Step number.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// What was found.
        message: String,
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
