//! When a run writes its checkpoints and when it stops ([`Checkpointing`]): the interval in
//! steps or wall-clock time, the stop asked for by a signal or by `--stop-after`.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use super::options::RunOptions;
use crate::checkpoint::{CheckpointWriter, DEFAULT_EVERY, Every};
use crate::load::Loaded;

/// When a run writes checkpoints and when it stops.
#[derive(Debug)]
pub struct Checkpointing {
    pub(super) every: Every,
    /// Wall-clock time of the last checkpoint (or of the start).
    pub(super) last: Instant,
    pub(super) stop: Option<Arc<AtomicUsize>>,
    pub(super) stop_after: Option<u64>,
    /// A checkpoint was written (or resumed from): the run writes one at its end too, so that
    /// it can be extended.
    pub(super) any: bool,
    /// The scene's and the mesh's hashes, computed at the first checkpoint.
    pub(super) hashes: Option<(u64, u64)>,
    /// The checkpoint file's writer.
    pub writer: CheckpointWriter,
}

impl Checkpointing {
    /// The checkpoints of a run of `l` with `options`.
    pub fn new(l: &Loaded, options: &RunOptions) -> Self {
        let every = options
            .checkpoint_every
            .or(l.scene.output.checkpoint_every)
            .unwrap_or(DEFAULT_EVERY);
        Self {
            every,
            last: Instant::now(),
            stop: options.stop.clone(),
            stop_after: options.stop_after,
            any: false,
            hashes: None,
            writer: CheckpointWriter::new(&options.out_dir),
        }
    }

    /// A checkpoint is due after step `step`.
    pub(super) fn due(&self, step: u64) -> bool {
        match self.every {
            Every::Steps(n) => step.is_multiple_of(n),
            Every::Seconds(s) => self.last.elapsed().as_secs_f64() >= s,
            Every::Off => false,
        }
    }

    /// Why the run should stop after step `step`, if it should.
    pub(super) fn stop_reason(&self, step: u64) -> Option<&'static str> {
        match self.stop.as_ref().map(|s| s.load(Ordering::Relaxed)) {
            Some(2) => return Some("SIGINT"),
            Some(15) => return Some("SIGTERM"),
            Some(0) | None => {}
            Some(_) => return Some("signal"),
        }
        self.stop_after
            .is_some_and(|n| step >= n)
            .then_some("stop_after")
    }
}
