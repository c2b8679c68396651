//! The extension module `fdem._core` of fdem's Python package (`import fdem`): the scene
//! checks and the run of the solver crate, called with a scene's JSON text.
//!
//! - [`load_check`]: a scene loaded as `fdem check` loads it (every check of the command
//!   line, the same messages), and its report;
//! - [`run`]: a scene run into an output folder as `fdem run` runs it, with the GIL
//!   released while it steps; returns the summary and the last frame's arrays as numpy
//!   arrays;
//! - [`SceneError`] (a `ValueError`) and [`RunError`] (a `RuntimeError`): the solver's errors
//!   with their file, JSON path and fix as attributes ([`errors`]).
//!
//! The Python side (`python/fdem/`) holds the scene as a dict and passes its JSON text here;
//! `file` names the scene in the messages and its folder resolves the relative mesh paths.

mod arrays;
mod errors;
mod running;

use pyo3::prelude::*;

pub use errors::{RunError, SceneError};
pub use running::{load_check, run};

/// The module `fdem._core`.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("RunError", py.get_type::<RunError>())?;
    m.add_function(wrap_pyfunction!(load_check, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    Ok(())
}
