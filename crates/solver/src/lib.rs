//! fdem's solver: reads a JSON scene, composes the mesh and time crates into one system,
//! runs a dynamic, dynamic-relaxation or static analysis, and writes ParaView output.
//!
//! - [`scene`]: the JSON scene format (`docs/scene-format.md`), one file per part; it depends
//!   on nothing of the stages that read it.
//! - [`mesh_input`]: one body's mesh as the solver needs it (nodes, triangles, named groups).
//! - [`resolve`]: every name a scene refers to, resolved once against the bodies' meshes.
//! - [`limits`]: the derived quantities of a run (step, steps, frames, rows) checked.
//! - [`model`]: all bodies in one node numbering; constraints; consistent nodal loads.
//! - [`system`]: the composition as the time crate's `SecondOrderSystem`:
//!   `M a = f_int(x, v) + s(t) f_ext + M g - alpha M v + sum f_contrib`, constrained DOFs
//!   prescribed. Terms a scene lacks are skipped (cost nothing).
//! - [`driver`]: time step `h = safety (h omega)_scheme / omega_max (sqrt(1+z^2) - z)`, the
//!   dynamic and dynamic-relaxation loops, frames, histories, summary.
//! - [`ledger`]: the energy ledger (initial, supplied, present, dissipated, error) that the
//!   console, `summary.json` and `histories.csv` report.
//! - [`static_solve`]: `K u = f` with faer's sparse Cholesky (small strain).
//! - [`diagnosis`]: why a run stopped (instability, relaxation not converged), in the
//!   scene's terms, with the fix.
//! - [`output`]: `.pvd` + zlib `.vtu` frames, CSV histories, all written atomically.

pub mod contact_stage;
pub mod diagnosis;
pub mod driver;
pub mod error;
pub mod fracture_stage;
pub mod ledger;
pub mod limits;
pub mod mesh_adapter;
pub mod mesh_input;
pub mod model;
pub mod output;
pub mod resolve;
pub mod scene;
pub mod schemes;
pub mod stages;
pub mod star_bonds;
pub mod static_solve;
pub mod system;

pub use driver::{Loaded, RunOptions, Summary, load, run};
pub use error::{RunError, SceneError};
pub use fdem_mesh::{excerpt, shorten, shorten_to};
pub use scene::Scene;
