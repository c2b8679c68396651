//! What a run is told besides its scene: where to write, in which forms, when to write
//! checkpoints, when to stop, and whether it continues a run from its checkpoint.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicUsize;

use crate::checkpoint::Every;

/// Options of a run.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Output folder (created).
    pub out_dir: PathBuf,
    /// Also write each frame's arrays as JSON (`frame_NNNN.json`).
    pub raw: bool,
    /// When to write checkpoints; `None`: the scene's `output.checkpoint_every`, else
    /// [`crate::checkpoint::DEFAULT_EVERY`].
    pub checkpoint_every: Option<Every>,
    /// Set to a signal number (2: SIGINT, 15: SIGTERM) by a signal handler: the run stops
    /// after its current step with a checkpoint and an interrupted summary
    /// ([`crate::RunError::Interrupted`]).
    pub stop: Option<Arc<AtomicUsize>>,
    /// Stop after this many steps in all, as if interrupted (a run split into parts).
    pub stop_after: Option<u64>,
    /// Continue the run in `out_dir` from its checkpoint instead of starting afresh.
    pub resume: bool,
    /// A distributed run repartitions when the largest part's cost exceeds this many times
    /// the mean (checked every 100 steps; infinite: never); `None`:
    /// [`crate::distributed::balance::DEFAULT_THRESHOLD`].
    pub rebalance: Option<f64>,
}
