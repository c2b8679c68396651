//! What a run is told besides its scene: where to write, and in which forms.

use std::path::PathBuf;

/// Options of a run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Output folder (created).
    pub out_dir: PathBuf,
    /// Also write each frame's arrays as JSON (`frame_NNNN.json`).
    pub raw: bool,
}
