//! Loading and running a scene given as JSON text, for the Python package.
//!
//! A run steps on a thread of its own (in a rayon pool of `threads` threads when given)
//! while the calling thread, which Python's signal handlers run on, waits without the GIL,
//! wakes every [`POLL`] to run Python's signal handlers (`py.check_signals()`) and to call
//! the progress callable with the last progress. A `KeyboardInterrupt` (Ctrl-C) or an
//! exception of the callable sets the run's stop flag (as SIGINT does on the command line):
//! the run stops after its step, writes its checkpoint and its summary, and the exception is
//! raised once it has returned.

use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use fdem_solver::driver::{self, Progress, RunOptions};
use fdem_solver::input::scene::Analysis;
use fdem_solver::output::FrameData;
use fdem_solver::{RunError, SceneError};

use crate::{arrays, errors};

/// How often the waiting thread runs Python's signal handlers and the progress callable.
const POLL: Duration = Duration::from_millis(100);

/// The stop flag's value for an interrupt (SIGINT's number, as the command line sets it).
const SIGINT: usize = 2;

/// The message of a panic's payload.
fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".into())
}

/// What [`load_check`] reports of a loaded scene (plain data, made without the GIL).
struct Checked {
    describe: String,
    report: Option<String>,
    analysis: Analysis,
    scheme: String,
    time_step: f64,
    time_step_limit: f64,
    steps: u64,
    duration: Option<f64>,
    nodes: usize,
    triangles: usize,
    free_dofs: usize,
    omega_max: f64,
    bodies: Vec<(Option<String>, String, usize, usize)>,
    /// The predicted accuracy indicators, as JSON.
    accuracy: String,
}

/// Loads the scene `text` as `fdem check` loads a file, with every check of the command line:
/// `file` names the scene in the messages and its folder resolves relative mesh paths (it
/// need not exist). Returns a dict: `describe` (the scene's description, as `fdem run`
/// prints it), `report` (with `report=True`: `fdem check`'s report, which times a force
/// evaluation; else None), `text` (both, as `fdem check` prints them), `analysis`, `scheme`,
/// `time_step`, `time_step_limit` [s], `steps`, `duration` [s], `nodes`, `triangles`,
/// `free_dofs`, `omega_max` [rad/s], `bodies` (a list of dicts: `name`, `mesh`, `nodes`,
/// `triangles`) and `accuracy` (the indicators `fdem check` predicts, as a JSON list). Raises `SceneError` as the command line refuses the scene.
#[pyfunction]
#[pyo3(signature = (text, file, report = false))]
pub fn load_check<'py>(
    py: Python<'py>,
    text: &str,
    file: PathBuf,
    report: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let checked = py.detach(|| {
        std::panic::catch_unwind(AssertUnwindSafe(|| {
            let l = driver::load_text(text, &file)?;
            Ok::<_, SceneError>(Checked {
                describe: l.describe(),
                report: report.then(|| {
                    let predicted = fdem_solver::run::accuracy::before_run(&l);
                    let block = fdem_solver::run::accuracy::check_block(&predicted);
                    format!("{}\n{block}", driver::check_report(&l))
                }),
                accuracy: serde_json::to_string(&fdem_solver::run::accuracy::before_run(&l))
                    .unwrap_or_else(|_| "[]".into()),
                analysis: l.scene.analysis,
                scheme: l.scheme.to_string(),
                time_step: l.dt,
                time_step_limit: l.dt_limit,
                steps: l.n_steps,
                duration: l.scene.duration,
                nodes: l.model.n_nodes(),
                triangles: l.model.triangles.len(),
                free_dofs: l.model.constrained.iter().filter(|c| !**c).count(),
                omega_max: l.omega_max(),
                bodies: l
                    .scene
                    .bodies
                    .iter()
                    .zip(&l.meshes)
                    .map(|(b, m)| {
                        (
                            b.name.clone(),
                            b.mesh.display().to_string(),
                            m.nodes.len(),
                            m.triangles.len(),
                        )
                    })
                    .collect(),
            })
        }))
    });
    let c = match checked {
        Ok(Ok(c)) => c,
        Ok(Err(e)) => return Err(errors::scene_error(py, &e)),
        Err(payload) => return Err(errors::internal_error(py, &panic_text(&*payload))),
    };
    let d = PyDict::new(py);
    let text = match &c.report {
        Some(r) => format!("{}\n{r}", c.describe),
        None => c.describe.clone(),
    };
    d.set_item("text", text)?;
    d.set_item("describe", c.describe)?;
    d.set_item("report", c.report)?;
    d.set_item("analysis", analysis_name(c.analysis))?;
    d.set_item("scheme", c.scheme)?;
    d.set_item("time_step", c.time_step)?;
    d.set_item("time_step_limit", c.time_step_limit)?;
    d.set_item("steps", c.steps)?;
    d.set_item("duration", c.duration)?;
    d.set_item("nodes", c.nodes)?;
    d.set_item("triangles", c.triangles)?;
    d.set_item("free_dofs", c.free_dofs)?;
    d.set_item("omega_max", c.omega_max)?;
    d.set_item("accuracy", c.accuracy)?;
    let bodies = pyo3::types::PyList::empty(py);
    for (name, mesh, nodes, triangles) in c.bodies {
        let b = PyDict::new(py);
        b.set_item("name", name)?;
        b.set_item("mesh", mesh)?;
        b.set_item("nodes", nodes)?;
        b.set_item("triangles", triangles)?;
        bodies.append(b)?;
    }
    d.set_item("bodies", bodies)?;
    Ok(d)
}

/// The scene's name of an analysis (`"dynamic"`, `"static"`, `"relaxation"`).
fn analysis_name(a: Analysis) -> &'static str {
    match a {
        Analysis::Dynamic => "dynamic",
        Analysis::Static => "static",
        Analysis::Relaxation => "relaxation",
    }
}

/// What a finished run hands back (plain data, made without the GIL).
struct Done {
    describe: String,
    summary: String,
    frame: FrameData,
    joint_state: Option<fdem_fracture::JointState>,
    not_converged: Option<RunError>,
}

/// Loads and runs the scene `text` into `out_dir` as `fdem run SCENE --out OUT_DIR` does
/// (`file` as in [`load_check`]), with the GIL released while it steps.
///
/// - `threads`: the rayon threads of this run (None: rayon's global pool, its default or
///   `RAYON_NUM_THREADS`);
/// - `raw`: also write each frame's arrays as JSON (`--raw`);
/// - `progress`: None, or a callable `f(step, steps, time)` called about ten times a second;
///   an exception it raises stops the run as Ctrl-C does, and is raised;
/// - `resume`: continue the run in `out_dir` from its checkpoint (`--resume`);
/// - `stop_after`: stop after this many steps in all, with a checkpoint (`--stop-after`):
///   raises `RunError` of kind `"interrupted"`.
///
/// Returns a dict: `describe`, `summary` (the JSON text of `summary.json`), `frame` (the last
/// frame's arrays), `joints` (the last frame's joints, None without a fracture section),
/// `joint_state` (the joints' history at the end, None without joints) and `error` (None, or
/// the `RunError` of a relaxation that did not converge: its output is written, the caller
/// raises it). Raises `SceneError` for a refused scene, `RunError` for a run that failed,
/// `KeyboardInterrupt` after a Ctrl-C (the folder holds the checkpoint and the interrupted
/// summary).
#[pyfunction]
#[pyo3(signature = (text, file, out_dir, threads = None, raw = false, progress = None, resume = false, stop_after = None))]
pub fn run<'py>(
    py: Python<'py>,
    text: String,
    file: PathBuf,
    out_dir: PathBuf,
    threads: Option<usize>,
    raw: bool,
    progress: Option<Bound<'py, PyAny>>,
    resume: bool,
    stop_after: Option<u64>,
) -> PyResult<Bound<'py, PyDict>> {
    let pool = match threads {
        None => None,
        Some(0) => {
            return Err(PyValueError::new_err(
                "threads = 0: a run needs at least one thread\n  fix: give threads >= 1, or None for rayon's default",
            ));
        }
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| {
                    errors::internal_error(py, &format!("cannot start {n} threads: {e}"))
                })?,
        ),
    };
    let stop = Arc::new(AtomicUsize::new(0));
    let (tx, mut rx) = mpsc::channel::<Progress>();
    let mut pending: Option<PyErr> = None;
    let joined = std::thread::scope(|s| {
        let run_stop = Arc::clone(&stop);
        let (text, file, out_dir) = (&text, &file, &out_dir);
        let handle = s.spawn(move || {
            let how = How {
                raw,
                resume,
                stop_after,
            };
            let work = || execute(text, file, out_dir, how, &run_stop, &tx);
            match &pool {
                Some(p) => p.install(work),
                None => work(),
            }
        });
        loop {
            // (the receiver is Send, not Sync: it goes into the GIL-free wait and back)
            let (got, back) = py.detach(move || (rx.recv_timeout(POLL), rx));
            rx = back;
            let mut last = match got {
                Ok(p) => Some(p),
                Err(RecvTimeoutError::Timeout) => None,
                Err(RecvTimeoutError::Disconnected) => break,
            };
            while let Ok(p) = rx.try_recv() {
                last = Some(p);
            }
            if pending.is_none()
                && let Err(e) = py.check_signals()
            {
                stop.store(SIGINT, Ordering::SeqCst);
                pending = Some(e);
            }
            if pending.is_none()
                && let (Some(f), Some(p)) = (&progress, last)
                && let Err(e) = f.call1((p.step, p.steps, p.time))
            {
                stop.store(SIGINT, Ordering::SeqCst);
                pending = Some(e);
            }
        }
        py.detach(|| handle.join())
    });
    // a Ctrl-C that came while the run ended is still Python's to raise
    if pending.is_none()
        && let Err(e) = py.check_signals()
    {
        pending = Some(e);
    }
    if let Some(e) = pending {
        return Err(e);
    }
    let done = match joined {
        Ok(Ok(done)) => done,
        Ok(Err(e)) => return Err(errors::run_error(py, &e)),
        Err(payload) => return Err(errors::internal_error(py, &panic_text(&*payload))),
    };
    let d = PyDict::new(py);
    d.set_item("describe", done.describe)?;
    d.set_item("summary", done.summary)?;
    d.set_item("frame", arrays::frame(py, &done.frame)?)?;
    match &done.frame.joints {
        Some(j) => d.set_item("joints", arrays::joints(py, j)?)?,
        None => d.set_item("joints", py.None())?,
    }
    match &done.joint_state {
        Some(j) => d.set_item("joint_state", arrays::joint_state(py, j)?)?,
        None => d.set_item("joint_state", py.None())?,
    }
    match &done.not_converged {
        Some(e) => d.set_item("error", errors::run_error(py, e).into_value(py))?,
        None => d.set_item("error", py.None())?,
    }
    Ok(d)
}

/// The options of [`run`] that go to the solver's [`RunOptions`].
#[derive(Clone, Copy)]
struct How {
    raw: bool,
    resume: bool,
    stop_after: Option<u64>,
}

/// The run itself, on its own thread: load, run, the summary as JSON text.
fn execute(
    text: &str,
    file: &Path,
    out_dir: &Path,
    how: How,
    stop: &Arc<AtomicUsize>,
    tx: &mpsc::Sender<Progress>,
) -> Result<Done, RunError> {
    let mut l = driver::load_text(text, file)?;
    let options = RunOptions {
        out_dir: out_dir.to_path_buf(),
        raw: how.raw,
        checkpoint_every: None,
        // a static solve is one step: nothing to stop, as on the command line
        stop: (l.scene.analysis != Analysis::Static).then(|| Arc::clone(stop)),
        stop_after: how.stop_after,
        resume: how.resume,
        // one process: nothing to partition
        rebalance: None,
    };
    let outcome = driver::run_outcome(&mut l, &options, &mut |p: &Progress| {
        // the receiver is gone only once the caller stopped waiting: nothing to tell
        let _ = tx.send(*p);
    })?;
    let summary = serde_json::to_string(&outcome.summary).map_err(|e| RunError::Output {
        file: out_dir.join("summary.json"),
        message: e.to_string(),
    })?;
    Ok(Done {
        describe: l.describe(),
        not_converged: fdem_solver::run::diagnosis::not_converged(&l.scene, &outcome.summary),
        summary,
        frame: outcome.last_frame,
        joint_state: outcome.joint_state,
    })
}
