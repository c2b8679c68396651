//! What a run writes: field output (`.pvd` + `.vtu` frames) and history probes
//! (`histories.csv`).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::SceneError;
use crate::input::arrays::{ArraySet, Offer};

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
    /// The arrays the frames carry: `"all"` (default: every array the scene offers) or a
    /// list of names ([`crate::output::arrays`]); names the scene cannot give are an error.
    #[serde(default, skip_serializing_if = "Arrays::is_all")]
    pub arrays: Arrays,
    /// Frames compressed and written on a background thread while the run steps on
    /// (default true); false writes each frame before the next step.
    #[serde(default = "default_true", skip_serializing_if = "is_true")]
    pub writer_thread: bool,
}

/// `output.arrays`: `"all"` or a list of array names.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(untagged)]
pub enum Arrays {
    /// A word: only `"all"` is valid.
    Word(String),
    /// The names of the arrays to write.
    List(Vec<String>),
}

impl Default for Arrays {
    fn default() -> Self {
        Arrays::Word("all".into())
    }
}

impl Arrays {
    /// True for `"all"`.
    pub fn is_all(&self) -> bool {
        matches!(self, Arrays::Word(w) if w == "all")
    }

    /// The set of arrays a run writes (checked by [`Output::validate`]).
    pub fn set(&self) -> ArraySet {
        match self {
            Arrays::List(names) => ArraySet::only(names.iter().cloned()),
            Arrays::Word(_) => ArraySet::all(),
        }
    }
}

fn default_true() -> bool {
    true
}
fn is_true(b: &bool) -> bool {
    *b
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
            arrays: Arrays::default(),
            writer_thread: true,
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
    /// The fluid's volume books, the pressure at the first injection and the channels
    /// (scenes with a `"fluid"` section).
    Fluid,
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
    /// Checks the compression level and the array names against what the scene `offer`s;
    /// `file` names the scene in errors.
    pub(crate) fn validate(&self, offer: &Offer, file: &Path) -> Result<(), SceneError> {
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
        let valid = || {
            format!(
                "\"all\" or a list of this scene's arrays: {}",
                offer.names().join(", ")
            )
        };
        let names = match &self.arrays {
            Arrays::Word(w) if w == "all" => return Ok(()),
            Arrays::Word(w) => {
                return Err(bad(
                    "output.arrays".into(),
                    format!("\"{w}\" is neither \"all\" nor a list of arrays"),
                    &format!("give {}", valid()),
                ));
            }
            Arrays::List(names) => names,
        };
        let offered = offer.names();
        for (i, name) in names.iter().enumerate() {
            let path = format!("output.arrays[{i}]");
            if !offered.contains(&name.as_str()) {
                return Err(bad(
                    path,
                    offer.missing(name),
                    &format!("list only {}", valid()),
                ));
            }
            if names[..i].contains(name) {
                return Err(bad(
                    path,
                    format!("'{name}' is listed twice"),
                    "list each array once",
                ));
            }
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
