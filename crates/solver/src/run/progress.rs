//! Progress of a run, reported to the caller about five times a second and at the end.

use std::time::Instant;

use super::observer::{Flow, Halt, Observer, RunView};
use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::error::RunError;

/// Progress of a run, passed to the caller's callback.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    /// Steps done.
    pub step: u64,
    /// Steps planned.
    pub steps: u64,
    /// Simulated time [s].
    pub time: f64,
}

impl Progress {
    /// Fraction done, 0 to 1.
    pub fn fraction(&self) -> f64 {
        if self.steps == 0 {
            1.0
        } else {
            self.step as f64 / self.steps as f64
        }
    }
}

/// Calls the caller's progress callback at most every 0.2 s of wall time and after the last
/// step.
pub struct ProgressReport<'p> {
    callback: &'p mut dyn FnMut(&Progress),
    last: Instant,
}

impl<'p> ProgressReport<'p> {
    /// Reports to `callback`.
    pub fn new(callback: &'p mut dyn FnMut(&Progress)) -> Self {
        Self {
            callback,
            last: Instant::now(),
        }
    }
}

impl Observer for ProgressReport<'_> {
    fn after_step(&mut self, run: &mut RunView) -> Result<Flow, Halt> {
        if self.last.elapsed().as_secs_f64() > 0.2 || run.last {
            self.last = Instant::now();
            (self.callback)(&Progress {
                step: run.step,
                steps: run.control.planned(run.step, run.state.t),
                time: run.state.t,
            });
        }
        Ok(Flow::Continue)
    }

    /// Nothing to carry: the next report comes after the next step.
    fn save(&mut self, _e: &mut Enc) -> Result<(), RunError> {
        Ok(())
    }

    fn restore(&mut self, _run: &mut RunView, _d: &mut Dec) -> Result<(), DecodeError> {
        Ok(())
    }
}
