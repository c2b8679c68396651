//! fdem's solver: reads a JSON scene, composes the mesh and time crates into one system,
//! runs a dynamic, dynamic-relaxation or static analysis, and writes ParaView output.
//!
//! - [`scene`]: the JSON scene format (`docs/scene-format.md`), one file per part; it depends
//!   on nothing of the stages that read it.
//! - [`mesh_input`]: one body's mesh as the solver needs it (nodes, triangles, named groups).
//! - [`resolve`]: every name a scene refers to, resolved once against the bodies' meshes.
//! - [`cracks`]: pre-existing cracks resolved to joints, and the joint state they start from.
//! - [`limits`]: the derived quantities of a run (step, steps, frames, rows) checked.
//! - [`model`]: all bodies in one node numbering; constraints; consistent nodal loads.
//! - [`time_history`]: the factor of a load, prescribed motion or wall in time (its ramp or
//!   history), its integral and its rate.
//! - [`system`]: the composition as the time crate's `SecondOrderSystem`:
//!   `M a = f_int(x, v) + s(t) f_ext + M g - alpha M v + sum f_contrib`, constrained DOFs
//!   prescribed. Terms a scene lacks are skipped (cost nothing).
//! - [`load`](mod@load): a scene loaded: meshes, model, elements, time step
//!   `h = safety (h omega)_scheme / omega_max (sqrt(1+z^2) - z)`.
//! - [`run`](mod@run): the static solve, and the dynamic and dynamic-relaxation runs: the
//!   stepping loop and its observers (stability checks, frames, histories, progress).
//! - [`summary`]: the run summary (`summary.json`) and outcome.
//! - [`estimate`]: `fdem check`'s report: stable steps and the estimated run time.
//! - [`driver`]: the entry points under their earlier paths (`driver::load`, `driver::run`).
//! - [`ledger`]: the energy ledger (initial, supplied, present, dissipated, error) that the
//!   console, `summary.json` and `histories.csv` report.
//! - [`static_solve`]: `K u = f` with faer's sparse Cholesky (small strain);
//!   [`static_checks`]: what a static analysis needs of the scene (sections, supports).
//! - [`diagnosis`]: why a run stopped (instability, relaxation not converged), in the
//!   scene's terms, with the fix.
//! - [`output`]: `.pvd` + zlib `.vtu` frames, CSV histories, all written atomically.

pub mod checkpoint;
pub mod distributed;
pub mod error;
pub mod input;
pub mod output;
pub mod problem;
pub mod run;
pub mod stages;

pub use driver::{Problem, RunOptions, Summary, load, run};

/// The entry points of a run under the paths callers have used: loading a scene, running it,
/// `fdem check`'s report. Each item lives in [`load`](mod@crate::problem::load),
/// [`run`](mod@crate::run), [`summary`](crate::run::summary), [`estimate`](crate::run::estimate) or
/// [`limits`](crate::problem::limits).
pub mod driver {
    pub use crate::output::{frame_from_parts, make_frame};
    pub use crate::problem::load::{Problem, load, load_text, step_count};
    pub use crate::problem::stable_step::stable_step;
    pub use crate::run::estimate::{
        RELEASED_FLOOR, RELEASED_FRACTION, ReleasedContact, RunTimeEstimate, StepSample,
        check_report, expected_steps, run_time_estimate,
    };
    pub use crate::run::ledger::Energies;
    pub use crate::run::summary::{Outcome, Summary};
    pub use crate::run::{
        ENERGY_GROWTH_BOUND, Progress, RunOptions, describe_resume, energy_growth, open_checkpoint,
        run, run_distributed, run_outcome,
    };
}
pub use error::{RunError, SceneError};
pub use fdem_mesh::{excerpt, shorten, shorten_to};
pub use input::scene::Scene;
