//! What a run writes: field output (`.pvd` + `.vtu` frames) and history probes
//! (`histories.csv`).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::SceneError;

/// Field output.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// Number of frames over the run, besides the initial one (default 20; 0 turns output
    /// off except the summary).
    #[serde(default = "default_frames")]
    pub frames: usize,
    /// zlib level 0-9 of the `.vtu` files' blocks (default 1; 0 writes them uncompressed).
    #[serde(default = "default_level")]
    pub compression: u32,
    /// When the run writes a checkpoint (`checkpoint.fdem`): a number of steps, a wall-clock
    /// time (`"90s"`, `"30min"`, `"2h"`) or `"off"`; default every 10 minutes of wall-clock
    /// time. `fdem run --checkpoint-every` overrides it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checkpoint_every: Option<crate::checkpoint::Every>,
}

fn default_frames() -> usize {
    20
}
fn default_level() -> u32 {
    1
}

impl Default for Output {
    fn default() -> Self {
        Self {
            frames: default_frames(),
            compression: default_level(),
            checkpoint_every: None,
        }
    }
}

/// History probes.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Histories {
    /// Record every this many steps (default: 1000 rows over the run).
    #[serde(default)]
    pub every: Option<usize>,
    /// The probes (columns of `histories.csv`).
    #[serde(default)]
    pub probes: Vec<Probe>,
}

/// One history probe.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Probe {
    /// Mean displacement (x, y) of a group's nodes.
    Displacement(GroupProbe),
    /// Mean velocity (x, y) of a group's nodes.
    Velocity(GroupProbe),
    /// Total reaction force (x, y) on a group's constrained nodes.
    Reaction(GroupProbe),
    /// Kinetic, strain and external-work energies of the whole scene.
    Energy,
}

/// A probe on a named group.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GroupProbe {
    /// Group name.
    pub group: String,
    /// Body name (needed only when ambiguous).
    #[serde(default)]
    pub body: Option<String>,
}

impl Output {
    /// Checks the compression level; `file` names the scene in errors.
    pub(crate) fn validate(&self, file: &Path) -> Result<(), SceneError> {
        let bad = |path: String, message: String, fix: &str| {
            SceneError::invalid(file, path, message, fix)
        };

        if self.compression > 9 {
            return Err(bad(
                "output.compression".into(),
                format!("compression level {} is above 9", self.compression),
                "use a zlib level from 0 (none) to 9",
            ));
        }
        Ok(())
    }
}

impl Histories {
    /// Checks the interval; `file` names the scene in errors.
    pub(crate) fn validate(&self, file: &Path) -> Result<(), SceneError> {
        let bad = |path: String, message: String, fix: &str| {
            SceneError::invalid(file, path, message, fix)
        };

        if self.every == Some(0) {
            return Err(bad(
                "histories.every".into(),
                "history interval 0".into(),
                "record every 1 or more steps",
            ));
        }
        Ok(())
    }
}
