//! When a run writes its checkpoints and when it stops ([`Checkpointing`]): the interval in
//! steps or wall-clock time, the stop asked for by a signal or by `--stop-after`.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use super::options::RunOptions;
use crate::checkpoint::{CheckpointWriter, DEFAULT_EVERY, Every};
use crate::problem::load::Problem;

/// In a distributed run, rank 0's wall-clock checkpoint interval and stop signal are taken up
/// by all ranks at the steps that are multiples of this (one message per such step).
pub const AGREE_EVERY: u64 = 16;

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
    /// The run's id (`crate::checkpoint::new_run_id`): drawn at the first checkpoint, or
    /// the checkpoint's when resumed.
    pub(super) run_id: Option<u64>,
    /// The checkpoint file's writer.
    pub writer: CheckpointWriter,
}

impl Checkpointing {
    /// The checkpoints of a run of `l` with `options`.
    pub fn new(l: &Problem, options: &RunOptions) -> Self {
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
            run_id: None,
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

    /// A distributed run's decision after step `step`, the same on every rank: why it stops
    /// and whether a checkpoint is due. The step count's checkpoints and `stop_after` are the
    /// same on every rank; the wall-clock interval and a signal are rank 0's, shared (through
    /// `share`, which gets `[due, signal]` and returns rank 0's) at the steps that are
    /// multiples of `agree_every`.
    pub(super) fn agreed(
        &self,
        step: u64,
        agree_every: u64,
        share: impl FnOnce(&mut [f64]),
    ) -> (Option<&'static str>, bool) {
        let after = self
            .stop_after
            .is_some_and(|n| step >= n)
            .then_some("stop_after");
        let (mut due, seconds) = match self.every {
            Every::Steps(n) => (step.is_multiple_of(n), false),
            Every::Seconds(_) => (false, true),
            Every::Off => (false, false),
        };
        let mut signal = None;
        if (seconds || self.stop.is_some()) && step.is_multiple_of(agree_every) {
            let mut flags = [
                f64::from(u8::from(seconds && self.due(step))),
                self.stop
                    .as_ref()
                    .map_or(0.0, |s| s.load(Ordering::Relaxed) as f64),
            ];
            share(&mut flags);
            due |= flags[0] != 0.0;
            signal = match flags[1] as usize {
                0 => None,
                2 => Some("SIGINT"),
                15 => Some("SIGTERM"),
                _ => Some("signal"),
            };
        }
        (signal.or(after), due)
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
