//! Running a loaded scene: the static solve, or the dynamic and relaxation runs.
//!
//! A dynamic run is a [`Run`] (the system, its state, the scheme and the [`StepControl`],
//! the energy books) whose loop ([`Run::execute`]) takes one step at a time and calls a
//! list of [`Observer`]s at defined points: `start` (t = 0), `after_step`, `at_frame`, and
//! `finish` (or `stopped` when an observer halts the run on an instability). The
//! observers of a run, in the order they are called:
//!
//! - [`StabilityGuard`]: every [`CHECK_EVERY`] steps, a stage's error, non-finite values,
//!   energy growth ([`energy_growth`]); scans for inverted triangles;
//! - [`Relaxation`] (relaxation only): the residual; ends the run when it converged;
//! - [`FrameWriter`]: the frames (`results.pvd`) when the [`FrameClock`] says one is due;
//! - [`Histories`]: the probes' rows of `histories.csv`;
//! - [`ProgressReport`]: the caller's progress callback.
//!
//! A relaxation without `damping.mass_proportional` takes the energy out after every step,
//! before the observers: kinetic damping (`kinetic.rs`: velocities zeroed at a peak of the
//! kinetic energy, positions moved back to it) or adaptive damping (`adaptive.rs`: the
//! mass-proportional damping set from a Rayleigh quotient), each saved in the checkpoint. A
//! conjugate-gradient relaxation (`conjugate.rs`) replaces the scheme's step by one
//! iteration of a preconditioned nonlinear conjugate-gradient minimisation (velocities
//! zero), and books the energy it takes out after each.
//!
//! The run's own parts are the step control ([`StepControl`], with the [`AdaptiveStep`]),
//! the energy ledger's books (`crate::run::ledger::Books`, booked after every step, read by the
//! observers), and the summary (`summary.json`, written by the run after the observers have
//! added their parts).
//!
//! Checkpoints (`checkpoints.rs`, `checkpoint_policy.rs`): between two steps the run may
//! write a checkpoint (its interval, a signal's stop, `--stop-after`): every part of the run
//! and every observer saves itself (`Observer::save`); [`Run::resume`] builds the run from a
//! checkpoint in place of [`Run::start`] (each part restored, no force evaluated) and enters
//! the same loop ([`Run::resume_loop`]). A distributed run would reduce its checks' sums
//! inside its observers' `after_step`. Every hook gets the same [`RunView`].

pub mod accuracy;
mod adaptive;
mod checkpoint_policy;
mod checkpoints;
mod conjugate;
pub mod diagnosis;
pub mod distributed;
pub mod estimate;
mod frames;
mod histories;
mod kinetic;
pub mod ledger;
mod observer;
mod options;
mod progress;
mod relaxation;
pub mod result;
mod stability;
pub mod static_solve;
mod step_control;
mod stepping;
pub mod summary;

use std::time::Instant;

pub use checkpoint_policy::{AGREE_EVERY, Checkpointing};
pub use checkpoints::{
    check_belongs, check_end, describe_resume, header, keep_time_step, mesh_hash, scene_hash,
};
pub use frames::{FrameClock, FrameWriter, state_frame};
pub use histories::Histories;
pub use observer::{Flow, Halt, Observer, RunView};
pub use options::RunOptions;
pub use progress::{Progress, ProgressReport};
pub use relaxation::{ROUND_OFF_FACTOR, Relaxation};
pub use stability::{CHECK_EVERY, ENERGY_GROWTH_BOUND, StabilityGuard, energy_growth, indicator};
pub use step_control::{AdaptiveStep, StepControl};
pub use stepping::{Run, books_residuals, history_interval};

use crate::checkpoint::Checkpoint;
use crate::error::RunError;
use crate::input::scene::Analysis;
use crate::problem::load::Problem;
use crate::run::ledger::Energies;
use crate::run::summary::{Outcome, Summary, write_summary};
use crate::stages::system::SceneSystem;

/// Runs a loaded scene, writing output under `options.out_dir`.
pub fn run(
    l: &mut Problem,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Summary, RunError> {
    run_outcome(l, options, progress).map(|o| o.summary)
}

/// Runs a loaded scene and returns the summary with the last frame.
pub fn run_outcome(
    l: &mut Problem,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Outcome, RunError> {
    let wall = Instant::now();
    if l.scene.analysis == Analysis::Static {
        if options.resume {
            let file = options.out_dir.join(crate::checkpoint::FILE_NAME);
            return Err(crate::checkpoint::CheckpointError::new(
                &file,
                "a static analysis has no checkpoint to resume (it is one solve)",
                "run the scene afresh: fdem run SCENE --out DIR",
            )
            .into());
        }
        return static_run(l, options, progress, wall);
    }
    // the stages' own input, checked before the folder is claimed
    let n_joints = l.fracturing.n_joints();
    crate::problem::joints::check_initial_state(l.initial_joint_state.as_ref(), n_joints, &l.file)?;
    if options.resume {
        let cp = open_checkpoint(l, &options.out_dir)?;
        let writer = FrameWriter::resume(options, &l.scene.output);
        return dynamic(l, options, progress, writer, wall, Some(&cp));
    }
    let writer = FrameWriter::new(options, &l.scene.output)?;
    dynamic(l, options, progress, writer, wall, None)
}

/// The checkpoint of the run in `dir` that `l` resumes, read and checked before anything in
/// the folder changes: of `l`'s scene and mesh ([`check_belongs`]), with `l`'s end after it
/// once the checkpoint's time step is kept ([`keep_time_step`], [`check_end`]), in the folder
/// its run wrote (`crate::checkpoint::check_folder`: the run's id, the frames before it).
pub fn open_checkpoint(l: &mut Problem, dir: &std::path::Path) -> Result<Checkpoint, RunError> {
    let file = dir.join(crate::checkpoint::FILE_NAME);
    let cp = crate::checkpoint::read(&file)?;
    check_belongs(l, &file, &cp.header)?;
    keep_time_step(l, &cp.header);
    check_end(l, &file, &cp.header)?;
    crate::checkpoint::check_folder(dir, &file, &cp.header)?;
    Ok(cp)
}

/// The static solve, written as a run of one frame.
fn static_run(
    l: &mut Problem,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
    wall: Instant,
) -> Result<Outcome, RunError> {
    // Solved (and checked: a singular stiffness is bad input) before the folder is touched.
    let (frame, mut summary) = crate::run::static_solve::solve(l)?;
    let finite = |v: &[[f64; 2]]| v.iter().flatten().all(|x| x.is_finite());
    let all_finite = finite(&frame.points)
        && finite(&frame.displacement)
        && frame.stress.iter().flatten().all(|s| s.is_finite())
        && frame.energy_density.iter().all(|e| e.is_finite());
    if !all_finite {
        // bad input, as a singular stiffness: nothing written
        let largest = crate::problem::strains::input_strains(&l.scene, &l.model);
        return Err(RunError::Static {
            message: "the solution overflows the floating-point range (non-finite displacements, stresses or energy densities)".into(),
            fix: match largest.first() {
                Some(i) => format!(
                    "check the magnitude and units of `{}` ({}) against the material",
                    i.path, i.what
                ),
                None => "check the magnitudes and units of the loads and the materials".into(),
            },
        });
    }
    // the static terms as a ledger (gravity's work `1/2 sum m g . u` taken apart)
    let gravity = l.model.gravity.map_or(0.0, |g| {
        0.5 * l
            .model
            .weight_mass()
            .iter()
            .zip(&frame.displacement)
            .map(|(m, u)| m * (g[0] * u[0] + g[1] * u[1]))
            .sum::<f64>()
    });
    summary.energy = Energies::from_static(&summary.energy, gravity);
    let mut writer = FrameWriter::new(options, &l.scene.output)?;
    let s = Instant::now();
    if l.scene.output.frames > 0 {
        writer.write(frame.clone())?;
        writer.flush()?;
    }
    summary.timers.output = s.elapsed().as_secs_f64();
    summary.frames = writer.frames();
    summary.wall_time = wall.elapsed().as_secs_f64();
    if let Some(h) = &mut Histories::new(l, &l.model, &options.out_dir) {
        let x: Vec<[f64; 2]> = frame.points.clone();
        h.record(
            l,
            &l.model.x0,
            0.0,
            &x,
            &frame.velocity,
            &frame.reaction,
            &summary.energy,
            0.0,
            None,
        );
        h.flush()?;
    }
    let strain = accuracy::largest_strain(&l.elements, frame.displacement.as_flattened());
    summary.accuracy = accuracy::assess(l, &summary, Some(strain));
    write_summary(&options.out_dir, &summary)?;
    progress(&Progress {
        step: 1,
        steps: 1,
        time: 0.0,
    });
    Ok(Outcome {
        summary,
        last_frame: frame,
        joint_state: None,
        checkpoints: Default::default(),
    })
}

/// A dynamic run. The model and elements are moved out of `l` into the run's system (no
/// copy: the run only reads them) and put back when it ends, on the error paths too; the
/// contact and fracture stages attached for the run are dropped (a second run attaches fresh
/// stages). Only a panic inside the run leaves `l`
/// without its model.
fn dynamic(
    l: &mut Problem,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
    writer: FrameWriter,
    wall: Instant,
    resume: Option<&Checkpoint>,
) -> Result<Outcome, RunError> {
    let alpha = l.scene.damping.mass_proportional;
    let model = std::mem::take(&mut l.model);
    let elements = std::mem::take(&mut l.elements);
    let mut sys = SceneSystem::new(model, elements, alpha);
    let outcome = dynamic_run(l, &mut sys, options, progress, writer, wall, resume);
    l.model = std::mem::take(&mut sys.model);
    l.elements = std::mem::take(&mut sys.elements);
    outcome
}

/// The body of [`dynamic`], on the system `sys` that holds the model and elements of `l`:
/// the run and its observers.
fn dynamic_run(
    l: &Problem,
    sys: &mut SceneSystem,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
    mut writer: FrameWriter,
    wall: Instant,
    resume: Option<&Checkpoint>,
) -> Result<Outcome, RunError> {
    let mut histories = Histories::new(l, &sys.model, &options.out_dir);
    let method = l.scene.relaxation_choice().0.name();
    let mut relaxation = (l.scene.analysis == Analysis::Relaxation)
        .then(|| Relaxation::new(l.scene.integrator.relaxation_tolerance, method));
    let mut guard = StabilityGuard::new();
    let mut progress = ProgressReport::new(progress);
    let observers: &mut [&mut dyn Observer] = &mut [
        &mut guard,
        &mut relaxation,
        &mut writer,
        &mut histories,
        &mut progress,
    ];
    match resume {
        Some(cp) => {
            Run::resume(l, sys, options, &options.out_dir, cp, observers)?.resume_loop(observers)
        }
        None => Run::start(l, sys, options, &options.out_dir, wall)?.execute(observers),
    }
}

/// Runs a loaded dynamic scene as rank `comm.rank()` of `comm.size()` processes
/// ([`crate::distributed`]): every rank takes its part of the work, and rank 0 writes the
/// output (frames, histories, summary, checkpoints), identical to the single-process run's but
/// for the summary's timings. Scenes a distributed run does not support are refused before
/// anything is written ([`distributed::check`]). Checkpoints are the single-process run's,
/// written by rank 0 at a step where every rank holds the whole state; `options.resume`
/// continues from one on any number of ranks. A wall-clock checkpoint interval and a stop
/// signal (`options.stop`) are rank 0's, taken up by all ranks at the next step that is a
/// multiple of [`AGREE_EVERY`]. Returns the outcome on every rank (the last frame is the
/// whole state on each).
pub fn run_distributed(
    l: &mut Problem,
    options: &RunOptions,
    comm: Box<dyn crate::distributed::Comm>,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Outcome, RunError> {
    use crate::distributed::{Distribution, Layout};
    distributed::check(l, comm.size())?;
    let wall = Instant::now();
    let (rank, size) = (comm.rank(), comm.size());
    let resume = if options.resume {
        Some(open_checkpoint(l, &options.out_dir)?)
    } else {
        None
    };
    let mut writer = match (rank, &resume) {
        (0, Some(_)) => Some(FrameWriter::resume(options, &l.scene.output)),
        (0, None) => Some(FrameWriter::new(options, &l.scene.output)?),
        _ => None,
    };
    let alpha = l.scene.damping.mass_proportional;
    let model = std::mem::take(&mut l.model);
    let elements = std::mem::take(&mut l.elements);
    let mut sys = SceneSystem::new(model, elements, alpha);
    let layout = Layout::new(&sys.model, &sys.elements, rank, size);
    let mut part = Distribution::new(layout, comm, &sys.elements);
    if let Some(r) = options.rebalance {
        part.rebalance = r;
    }
    sys.distribute(part);
    let outcome = {
        let mut histories = if rank == 0 {
            Histories::new(l, &sys.model, &options.out_dir)
        } else {
            None
        };
        let mut guard = StabilityGuard::new();
        let mut relaxation = None::<Relaxation>;
        let mut progress = ProgressReport::new(progress);
        let [mut a, mut b, mut c, mut d] = [
            observer::Absent,
            observer::Absent,
            observer::Absent,
            observer::Absent,
        ];
        // the single process's list on rank 0, the same places on the others
        let observers: &mut [&mut dyn Observer] = match writer.as_mut() {
            Some(w) => &mut [
                &mut guard,
                &mut relaxation,
                w,
                &mut histories,
                &mut progress,
            ],
            None => &mut [&mut guard, &mut a, &mut b, &mut c, &mut d],
        };
        match &resume {
            Some(cp) => Run::resume(l, &mut sys, options, &options.out_dir, cp, observers)
                .and_then(|run| run.resume_loop(observers)),
            None => Run::start(l, &mut sys, options, &options.out_dir, wall)
                .and_then(|run| run.execute(observers)),
        }
    };
    l.model = std::mem::take(&mut sys.model);
    l.elements = std::mem::take(&mut sys.elements);
    outcome
}
