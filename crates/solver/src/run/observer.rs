//! The points at which a run calls its observers ([`Observer`]), and what they see of the
//! run there ([`RunView`]).

use fdem_time::State;

use super::step_control::StepControl;
use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::error::RunError;
use crate::problem::load::Problem;
use crate::run::diagnosis::{Found, InversionWatch};
use crate::run::ledger::Books;
use crate::run::summary::Summary;
use crate::stages::system::SceneSystem;

/// What an observer sees of the run at a hook.
pub struct RunView<'r> {
    /// The loaded scene. During a dynamic run its model and elements are in `sys`.
    pub loaded: &'r Problem,
    /// The system: model, elements, stages, the forces of its last evaluation, timers.
    pub sys: &'r mut SceneSystem,
    /// The state (at the end of the step, after a step).
    pub state: &'r State,
    /// The energy ledger's running books, booked up to this step.
    pub ledger: &'r Books,
    /// The first triangle seen turned inside out (the stability checks scan for it).
    pub inversions: &'r mut InversionWatch,
    /// The time step: the step just taken, its stable limit, the steps planned.
    pub control: &'r StepControl,
    /// Steps done.
    pub step: u64,
    /// This is the last step: the step count is done, or (adaptive step) the end time reached.
    pub last: bool,
    /// The run ends after this step: `last`, or an observer before this one said
    /// [`Flow::Stop`] (a relaxation that converged).
    pub end: bool,
}

/// What an observer asks of the run after a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    /// Go on.
    Continue,
    /// The run reached its goal (a relaxation converged): this step is its last.
    Stop,
}

/// Why an observer stopped the run.
#[derive(Debug)]
pub enum Halt {
    /// An instability: the run writes its partial summary and diagnoses the cause
    /// ([`crate::run::diagnosis::unstable`]).
    Unstable(Found),
    /// Any other error, returned as it is.
    Failed(RunError),
}

/// Something that follows a run: called at the start, after every step, at every frame and at
/// the end, in the order of the run's observer list, and asked to save and restore what it
/// carries from step to step when the run writes or resumes a checkpoint. The hooks are where
/// a run can be entered from outside the loop: a distributed run would reduce its checks'
/// sums at `after_step`.
pub trait Observer {
    /// Once, at the initial state: stages attached, the force at t = 0 evaluated, books open.
    fn start(&mut self, _run: &mut RunView) -> Result<(), Halt> {
        Ok(())
    }

    /// After each step, once its energy is booked.
    fn after_step(&mut self, _run: &mut RunView) -> Result<Flow, Halt> {
        Ok(Flow::Continue)
    }

    /// At each output frame after the initial one, after every observer's `after_step`.
    fn at_frame(&mut self, _run: &mut RunView) -> Result<(), Halt> {
        Ok(())
    }

    /// At the end of a run that reached its last step: adds its part to the summary and
    /// closes its files (the run writes `summary.json` after every observer's `finish`).
    fn finish(&mut self, _run: &mut RunView, _summary: &mut Summary) -> Result<(), RunError> {
        Ok(())
    }

    /// The run stopped on an instability: adds its part to the partial summary the run writes.
    fn stopped(&mut self, _summary: &mut Summary) {}

    /// Appends what this observer carries from step to step to a checkpoint (flushing its
    /// files first where a resumed run reads them back).
    fn save(&mut self, e: &mut Enc) -> Result<(), RunError>;

    /// Takes up what [`Observer::save`] wrote, in place of [`Observer::start`], on a run
    /// resumed from a checkpoint (the run's state is restored; no force was evaluated).
    fn restore(&mut self, run: &mut RunView, d: &mut Dec) -> Result<(), DecodeError>;

    /// Adds to `files` the names of the files in the run's folder that a run resumed from a
    /// checkpoint written now goes on from, and that [`Observer::restore`] does not write
    /// again (called after [`Observer::save`]; default: none).
    fn files(&self, _files: &mut Vec<String>) {}
}

/// An observer a scene may lack (no histories, not a relaxation) is an `Option`.
impl<O: Observer> Observer for Option<O> {
    fn start(&mut self, run: &mut RunView) -> Result<(), Halt> {
        self.as_mut().map_or(Ok(()), |o| o.start(run))
    }

    fn after_step(&mut self, run: &mut RunView) -> Result<Flow, Halt> {
        self.as_mut()
            .map_or(Ok(Flow::Continue), |o| o.after_step(run))
    }

    fn at_frame(&mut self, run: &mut RunView) -> Result<(), Halt> {
        self.as_mut().map_or(Ok(()), |o| o.at_frame(run))
    }

    fn finish(&mut self, run: &mut RunView, summary: &mut Summary) -> Result<(), RunError> {
        self.as_mut().map_or(Ok(()), |o| o.finish(run, summary))
    }

    fn stopped(&mut self, summary: &mut Summary) {
        if let Some(o) = self {
            o.stopped(summary);
        }
    }

    fn save(&mut self, e: &mut Enc) -> Result<(), RunError> {
        e.put(&self.is_some());
        self.as_mut().map_or(Ok(()), |o| o.save(e))
    }

    fn files(&self, files: &mut Vec<String>) {
        if let Some(o) = self {
            o.files(files);
        }
    }

    fn restore(&mut self, run: &mut RunView, d: &mut Dec) -> Result<(), DecodeError> {
        if d.get::<bool>()? != self.is_some() {
            return Err(d.error("an observer of the run is missing or extra"));
        }
        self.as_mut().map_or(Ok(()), |o| o.restore(run, d))
    }
}

/// The place of an observer that only rank 0 of a distributed run has (those that write
/// files): the other ranks keep the run's observer list in step with rank 0's, and a resumed
/// run passes over that observer's part of the checkpoint. Only rank 0 writes checkpoints, so
/// it saves nothing.
pub struct Absent;

impl Observer for Absent {
    fn save(&mut self, _e: &mut Enc) -> Result<(), RunError> {
        Ok(())
    }

    fn restore(&mut self, _run: &mut RunView, d: &mut Dec) -> Result<(), DecodeError> {
        d.skip_rest();
        Ok(())
    }
}
