//! The solver's errors as Python exceptions: [`SceneError`] (bad input, a `ValueError`) and
//! [`RunError`] (a run that failed, a `RuntimeError`), whose `str()` is the command line's
//! message and whose attributes carry its parts: `file`, `path` (the JSON path), `fix`,
//! `message`, and `kind` (which error it is).

use pyo3::IntoPyObjectExt;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use fdem_solver::{RunError as SolverRunError, SceneError as SolverSceneError};

create_exception!(
    fdem._core,
    SceneError,
    PyValueError,
    "A scene that fdem refuses: str(e) is the command line's message; e.file, e.path (the JSON path, or None), e.fix and e.message its parts."
);
create_exception!(
    fdem._core,
    RunError,
    PyRuntimeError,
    "A run that failed (instability, a relaxation that did not converge, output that could not be written, ...): str(e) is the command line's message; e.kind, e.message, e.fix and, where known, e.file, e.step and e.time its parts."
);

/// Sets the attributes `names[i] = values[i]` on the exception of `err`.
fn set_attrs<'py>(
    py: Python<'py>,
    err: &PyErr,
    attrs: Vec<(&str, Bound<'py, PyAny>)>,
) -> PyResult<()> {
    let value = err.value(py);
    for (k, v) in attrs {
        value.setattr(k, v)?;
    }
    Ok(())
}

/// `x` as a Python object.
fn obj<'py, T: IntoPyObjectExt<'py>>(py: Python<'py>, x: T) -> Bound<'py, PyAny> {
    x.into_bound_py_any(py)
        .unwrap_or_else(|_| py.None().into_bound(py))
}

/// The Python exception of a scene error: a [`SceneError`] with `kind`, `file`, `path`,
/// `message`, `fix` (and `line`, `column` of a parse error, `mesh` of a mesh that could not
/// be read).
pub fn scene_error(py: Python<'_>, e: &SolverSceneError) -> PyErr {
    let err = SceneError::new_err(e.to_string());
    let none = || py.None().into_bound(py);
    let attrs = match e {
        SolverSceneError::Io { file, message } => vec![
            ("kind", obj(py, "io")),
            ("file", obj(py, file.display().to_string())),
            ("path", none()),
            (
                "message",
                obj(py, format!("cannot read the file: {message}")),
            ),
            ("fix", obj(py, "check the file's path")),
        ],
        SolverSceneError::Parse {
            file,
            path,
            line,
            column,
            message,
            fix,
        } => vec![
            ("kind", obj(py, "parse")),
            ("file", obj(py, file.display().to_string())),
            ("path", obj(py, path.as_str())),
            ("message", obj(py, message.as_str())),
            ("fix", obj(py, fix.as_str())),
            ("line", obj(py, *line)),
            ("column", obj(py, *column)),
        ],
        SolverSceneError::Invalid {
            file,
            path,
            message,
            fix,
        } => vec![
            ("kind", obj(py, "invalid")),
            ("file", obj(py, file.display().to_string())),
            ("path", obj(py, path.as_str())),
            ("message", obj(py, message.as_str())),
            ("fix", obj(py, fix.as_str())),
        ],
        SolverSceneError::Mesh {
            file,
            path,
            mesh,
            message,
        } => vec![
            ("kind", obj(py, "mesh")),
            ("file", obj(py, file.display().to_string())),
            ("path", obj(py, path.as_str())),
            ("mesh", obj(py, mesh.display().to_string())),
            (
                "message",
                obj(
                    py,
                    format!("cannot load mesh {}: {message}", mesh.display()),
                ),
            ),
            (
                "fix",
                obj(
                    py,
                    "check the path (relative to the scene file) and the mesh",
                ),
            ),
        ],
    };
    match set_attrs(py, &err, attrs) {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// The Python exception of a run error: a [`SceneError`] for a scene error, else a
/// [`RunError`] with `kind` (`"output"`, `"unstable"`, `"not_converged"`, `"checkpoint"`,
/// `"interrupted"`, `"static"`), `message`, `fix` and, where the error has them, `file`,
/// `step`, `time`, `checkpoint`.
pub fn run_error(py: Python<'_>, e: &SolverRunError) -> PyErr {
    let text = e.to_string();
    let none = || py.None().into_bound(py);
    let attrs = match e {
        SolverRunError::Scene(s) => return scene_error(py, s),
        SolverRunError::Output { file, message } => vec![
            ("kind", obj(py, "output")),
            ("file", obj(py, file.display().to_string())),
            ("message", obj(py, message.as_str())),
            (
                "fix",
                obj(
                    py,
                    "check that the output folder can be written (space, permissions)",
                ),
            ),
        ],
        SolverRunError::Unstable {
            step,
            time,
            message,
        } => {
            // the diagnosis' last line is the fix
            let fix = message
                .lines()
                .rev()
                .find_map(|l| l.trim_start().strip_prefix("fix: "))
                .map_or_else(none, |f| obj(py, f));
            vec![
                ("kind", obj(py, "unstable")),
                ("step", obj(py, *step)),
                ("time", obj(py, *time)),
                ("message", obj(py, message.as_str())),
                ("fix", fix),
            ]
        }
        SolverRunError::NotConverged {
            residual,
            tolerance,
            steps,
            time,
            fix,
        } => vec![
            ("kind", obj(py, "not_converged")),
            ("residual", obj(py, *residual)),
            ("tolerance", obj(py, *tolerance)),
            ("step", obj(py, *steps)),
            ("time", obj(py, *time)),
            ("message", obj(py, text.lines().next().unwrap_or_default())),
            ("fix", obj(py, fix.as_str())),
        ],
        SolverRunError::Checkpoint(c) => vec![
            ("kind", obj(py, "checkpoint")),
            ("file", obj(py, c.file.display().to_string())),
            ("message", obj(py, c.message.as_str())),
            ("fix", obj(py, c.fix.as_str())),
        ],
        SolverRunError::Interrupted {
            reason,
            step,
            time,
            checkpoint,
        } => vec![
            ("kind", obj(py, "interrupted")),
            ("reason", obj(py, reason.as_str())),
            ("step", obj(py, *step)),
            ("time", obj(py, *time)),
            ("checkpoint", obj(py, checkpoint.display().to_string())),
            ("message", obj(py, text.lines().next().unwrap_or_default())),
            (
                "fix",
                obj(
                    py,
                    "continue it with fdem.run(scene, out=FOLDER, resume=True)",
                ),
            ),
        ],
        SolverRunError::Static { message, fix } => vec![
            ("kind", obj(py, "static")),
            ("message", obj(py, message.as_str())),
            ("fix", obj(py, fix.as_str())),
        ],
    };
    let err = RunError::new_err(text);
    let mut all = vec![("file", none()), ("step", none()), ("time", none())];
    all.extend(attrs);
    match set_attrs(py, &err, all) {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// A [`RunError`] of kind `"internal"`: a panic of the solver (a bug), caught at the thread
/// that ran it.
pub fn internal_error(py: Python<'_>, what: &str) -> PyErr {
    let message = format!("internal error in fdem (a bug): {what}");
    let err = RunError::new_err(message.clone());
    let none = || py.None().into_bound(py);
    let attrs = vec![
        ("kind", obj(py, "internal")),
        ("file", none()),
        ("step", none()),
        ("time", none()),
        ("message", obj(py, message)),
        (
            "fix",
            obj(py, "please report it with the scene that caused it"),
        ),
    ];
    match set_attrs(py, &err, attrs) {
        Ok(()) => err,
        Err(e) => e,
    }
}
