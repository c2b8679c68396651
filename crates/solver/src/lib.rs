//! fdem's solver: reads a JSON scene, composes the mesh and time crates into one system,
//! runs a dynamic, dynamic-relaxation or static analysis, and writes ParaView output.
//!
//! See `docs/scene-format.md` for the scene format.

pub mod error;
pub mod model;
pub mod output;
pub mod scene;
pub mod schemes;

pub use error::{RunError, SceneError};
pub use scene::Scene;
