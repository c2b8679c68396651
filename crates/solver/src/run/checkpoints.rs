//! Checkpoints of a run and its graceful stop: when they are due ([`Checkpointing`]), what a
//! checkpoint holds ([`Run::encode`]: every part of the run in its own section), how a run
//! is rebuilt from one ([`Run::resume`]), and the stop of a run asked to stop
//! ([`Run::interrupt`]).
//!
//! A resumed run is the run a fresh start builds (stages attached, scheme, step control),
//! whose every part then takes up its saved state, without a force evaluation: each step
//! after it is the step the uninterrupted run took, bit for bit.

use std::path::Path;
use std::time::Instant;

use fdem_time::{Counters, SchemeState, State};

use super::checkpoint_policy::Checkpointing;
use super::frames::FrameClock;
use super::observer::Observer;
use super::options::RunOptions;
use super::step_control::StepControl;
use super::stepping::Run;
use crate::checkpoint::pack::{Dec, DecodeError, Enc, Pack};
use crate::checkpoint::{Checkpoint, CheckpointError, Header};
use crate::error::RunError;
use crate::problem::load::Problem;
use crate::problem::model::Model;
use crate::run::diagnosis::{Inversion, InversionWatch};
use crate::run::ledger::Books;
use crate::run::summary::{Interrupted, write_summary};
use crate::stages::system::SceneSystem;

/// The hash of what a run computes from its scene, leaving out what a resumed run may change:
/// the title, `duration`, `output` and `histories.every`; the meshes' paths (their content is
/// in [`mesh_hash`]).
pub fn scene_hash(l: &Problem) -> u64 {
    let mut v = serde_json::to_value(&l.scene).unwrap_or(serde_json::Value::Null);
    if let Some(o) = v.as_object_mut() {
        for key in ["title", "duration", "output"] {
            o.remove(key);
        }
        if let Some(h) = o.get_mut("histories").and_then(|h| h.as_object_mut()) {
            h.remove("every");
        }
        // the meshes by their content (`mesh_hash`), not by their paths
        for b in o
            .get_mut("bodies")
            .and_then(|b| b.as_array_mut())
            .into_iter()
            .flatten()
        {
            if let Some(b) = b.as_object_mut() {
                b.remove("mesh");
            }
        }
    }
    twox_hash::XxHash3_64::oneshot(v.to_string().as_bytes())
}

/// The hash of a model's mesh: node positions, triangles, bodies and nodal masses.
pub fn mesh_hash(m: &Model) -> u64 {
    let mut e = Enc::with_capacity(8 * (3 * m.x0.len() + 2 * m.triangles.len()));
    e.put(&m.x0);
    e.put(&m.triangles);
    e.put(&m.tri_body);
    e.put(&m.mass);
    twox_hash::XxHash3_64::oneshot(&e.buf)
}

/// The header of a checkpoint of `l` (its model `model`: during a run the system holds it)
/// at `step`, time `time`, of run `run_id` (no files listed).
pub fn header(l: &Problem, model: &Model, step: u64, time: f64, run_id: u64) -> Header {
    header_with(l, (scene_hash(l), mesh_hash(model)), step, time, run_id)
}

/// [`header`] with the scene's and the mesh's hashes already computed.
fn header_with(
    l: &Problem,
    (scene, mesh): (u64, u64),
    step: u64,
    time: f64,
    run_id: u64,
) -> Header {
    Header {
        version: env!("CARGO_PKG_VERSION").to_string(),
        scene,
        mesh,
        step,
        time,
        time_step: l.dt,
        scene_file: std::path::absolute(&l.file).unwrap_or_else(|_| l.file.clone()),
        run_id,
        files: Vec::new(),
    }
}

/// A resumed run keeps the time step of the run that wrote its checkpoint: with another
/// `duration` the loaded step (fitted to the duration) differs, so the step count is that of
/// the checkpoint's step up to the new end (the first step at or after it).
pub fn keep_time_step(l: &mut Problem, header: &Header) {
    if l.dt != header.time_step {
        l.dt = header.time_step;
        let duration = l.scene.duration.unwrap_or(0.0);
        l.n_steps = crate::problem::stable_step::step_count(duration, l.dt) as u64;
    }
}

/// Checks that the run of `l`, its time step kept ([`keep_time_step`]), has steps left after
/// the checkpoint `file` with `header`: its end (`duration`) is after the checkpoint's time.
pub fn check_end(l: &Problem, file: &Path, header: &Header) -> Result<(), CheckpointError> {
    let duration = l.scene.duration.unwrap_or(0.0);
    let done = match l.scene.integrator.time_step {
        crate::input::scene::TimeStep::Adaptive => header.time >= duration * (1.0 - 1e-12),
        _ => header.step >= l.n_steps,
    };
    if !done {
        return Ok(());
    }
    Err(CheckpointError::new(
        file,
        format!(
            "`duration` = {duration:e} s of {} ends at or before the checkpoint's time t = {:e} s (step {}): the resumed run would have no step left to take",
            l.file.display(),
            header.time,
            header.step
        ),
        format!(
            "resume with a scene whose `duration` is longer than {:e} s (its end extends the run), or start the run afresh",
            header.time
        ),
    ))
}

/// What a resumed run of `l` (its time step kept: [`keep_time_step`]) does from the checkpoint
/// with `header`, in one line: the step it goes on from, the step and the steps left.
pub fn describe_resume(l: &Problem, header: &Header) -> String {
    let duration = l.scene.duration.unwrap_or(0.0);
    let from = format!(
        "resuming from step {} (t = {:.4e} s)",
        header.step, header.time
    );
    match l.scene.integrator.time_step {
        crate::input::scene::TimeStep::Adaptive => format!(
            "{from}: adaptive steps (the last {:.4e} s) up to t = {duration:.4e} s",
            header.time_step
        ),
        _ => format!(
            "{from}: {}{} steps left of h = {:.4e} s, to step {} (t = {:.4e} s)",
            // a relaxation ends when it converges
            if l.scene.analysis == crate::input::scene::Analysis::Relaxation {
                "at most "
            } else {
                ""
            },
            l.n_steps.saturating_sub(header.step),
            l.dt,
            l.n_steps,
            l.n_steps as f64 * l.dt
        ),
    }
}

/// Checks that the checkpoint `file` with `header` belongs to the run of `l`.
pub fn check_belongs(l: &Problem, file: &Path, header: &Header) -> Result<(), CheckpointError> {
    if header.mesh != mesh_hash(&l.model) {
        return Err(CheckpointError::new(
            file,
            format!(
                "the checkpoint belongs to another mesh: the nodes, triangles or masses that {} gives differ from those of the run that wrote it",
                l.file.display()
            ),
            "resume with the scene and the meshes of the run that wrote the checkpoint",
        ));
    }
    if header.scene != scene_hash(l) {
        return Err(CheckpointError::new(
            file,
            format!(
                "the checkpoint belongs to another scene: {} differs from the scene of the run that wrote it in more than `duration`, `output`, `histories.every` or `title`",
                l.file.display()
            ),
            "resume with the scene of the run that wrote the checkpoint (only its end and its output may change), or start the run afresh",
        ));
    }
    Ok(())
}

impl Pack for SchemeState {
    fn pack(&self, e: &mut Enc) {
        e.put(&self.a);
        e.put(&self.a_time);
        e.put(&self.a_live);
        let c = self.counters;
        e.put(&[c.steps, c.forces, c.gradients]);
        e.put(&self.history);
        e.put(&self.scalars);
    }

    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        let a = d.get()?;
        let a_time = d.get()?;
        let a_live = d.get()?;
        let [steps, forces, gradients]: [u64; 3] = d.get()?;
        Ok(Self {
            a,
            a_time,
            a_live,
            counters: Counters {
                steps,
                forces,
                gradients,
            },
            history: d.get()?,
            scalars: d.get()?,
        })
    }
}

fn pack_inversion(e: &mut Enc, w: &InversionWatch) {
    e.put(&w.first.map(|i| (i.step, i.time, (i.tri, i.at))));
}

fn unpack_inversion(d: &mut Dec) -> Result<InversionWatch, DecodeError> {
    let first: Option<(u64, f64, (usize, [f64; 2]))> = d.get()?;
    Ok(InversionWatch {
        first: first.map(|(step, time, (tri, at))| Inversion {
            step,
            time,
            tri,
            at,
        }),
    })
}

/// A checkpoint error at `file` from a section that cannot be read.
fn unreadable(file: &Path, e: DecodeError) -> RunError {
    RunError::Checkpoint(CheckpointError::new(
        file,
        format!("the checkpoint cannot be resumed: {e}"),
        "resume with the fdem version that wrote it and the same scene, or start the run afresh",
    ))
}

/// The run's own numbers in a checkpoint.
struct RunPart {
    steps: u64,
    step_time: f64,
    wall: f64,
    next_frame: usize,
    ended: bool,
}

impl<'a> Run<'a> {
    /// Encodes the whole run (and its observers) as a checkpoint's state.
    pub(super) fn encode(
        &mut self,
        observers: &mut [&mut dyn Observer],
        scheme: &SchemeState,
    ) -> Result<Vec<u8>, RunError> {
        let mut e = Enc::with_capacity(64 * self.state.x.len());
        let wall = self.wall_before + self.wall.elapsed().as_secs_f64();
        e.section("run", |e| {
            e.put(&self.steps);
            e.put(&[self.step_time, wall]);
            e.put(&self.frames.next());
            e.put(&self.ended);
            pack_inversion(e, &self.inversions);
        });
        e.section("state", |e| {
            e.put(&self.state.t);
            e.put(&self.state.x);
            e.put(&self.state.v);
        });
        e.section("scheme", |e| e.put(scheme));
        e.section("control", |e| self.control.save(e));
        e.section("ledger", |e| self.ledger.save(e));
        e.section("system", |e| self.sys.save(e));
        if let Some(k) = &self.kinetic {
            e.section("kinetic", |e| k.save(e));
        }
        if let Some(a) = &self.adaptive {
            e.section("adaptive", |e| a.save(e));
        }
        if let Some(c) = &self.conjugate {
            e.section("conjugate-gradient", |e| c.save(e));
        }
        let sys = &mut *self.sys;
        for c in &mut sys.contributions {
            let name = c.name().to_string();
            let mut saved = Ok(());
            e.section(&name, |e| saved = c.save(e, &sys.events));
            saved.map_err(|err| RunError::Output {
                file: self.out_dir.to_path_buf(),
                message: format!("cannot save the {name} stage's files: {err}"),
            })?;
        }
        for o in observers.iter_mut() {
            let mut saved = Ok(());
            e.section("observer", |e| saved = o.save(e));
            saved?;
        }
        Ok(e.buf)
    }

    /// Writes a checkpoint of the run now (on the writer's thread; `wait`: and waits for it).
    pub(super) fn write_checkpoint(
        &mut self,
        observers: &mut [&mut dyn Observer],
        wait: bool,
    ) -> Result<(), RunError> {
        let s = Instant::now();
        let mut scheme = self.integrator.save_state();
        if let Some(d) = &mut self.sys.dist {
            // the scheme's cached acceleration of every DOF from its owner (each rank holds
            // its own DOFs' only); the rest of the state is whole at this step
            d.share_dofs(&mut scheme.a);
            if d.rank() != 0 {
                // rank 0 writes the checkpoint
                self.checkpoints.last = Instant::now();
                self.checkpoints.any = true;
                return Ok(());
            }
        }
        let state = self.encode(observers, &scheme)?;
        let (l, model) = (self.loaded, &self.sys.model);
        let hashes = *self
            .checkpoints
            .hashes
            .get_or_insert_with(|| (scene_hash(l), mesh_hash(model)));
        let run_id = self.run_id()?;
        let mut header = header_with(self.loaded, hashes, self.steps, self.state.t, run_id);
        for c in &self.sys.contributions {
            c.files(&mut header.files);
        }
        for o in observers.iter() {
            o.files(&mut header.files);
        }
        let file = crate::checkpoint::encode_file(&header, &state);
        let w = &mut self.checkpoints.writer;
        let path = w.path().to_path_buf();
        let failed = |e: std::io::Error| RunError::Output {
            file: path,
            message: format!("cannot write the checkpoint: {e}"),
        };
        let submitted = w.submit(file);
        let waited = if wait { w.wait() } else { Ok(()) };
        submitted.and(waited).map_err(failed)?;
        self.checkpoints.writer.encode_time += s.elapsed().as_secs_f64();
        self.checkpoints.last = Instant::now();
        self.checkpoints.any = true;
        self.sys.timers.output += s.elapsed().as_secs_f64();
        Ok(())
    }

    /// The run's id: drawn at its first checkpoint and written into the folder then (a resumed
    /// run keeps the checkpoint's).
    fn run_id(&mut self) -> Result<u64, RunError> {
        if let Some(id) = self.checkpoints.run_id {
            return Ok(id);
        }
        let id = crate::checkpoint::new_run_id(self.out_dir);
        crate::checkpoint::write_run_id(self.out_dir, id).map_err(|e| RunError::Output {
            file: self.out_dir.join(crate::checkpoint::RUN_ID_FILE),
            message: format!("cannot write the run's id: {e}"),
        })?;
        self.checkpoints.run_id = Some(id);
        Ok(id)
    }

    /// After step `steps` of the loop: a stop asked for (a checkpoint, an interrupted
    /// summary, [`RunError::Interrupted`]), or a checkpoint that is due.
    pub(super) fn between_steps(
        &mut self,
        observers: &mut [&mut dyn Observer],
    ) -> Result<(), RunError> {
        let (stop, due) = match &mut self.sys.dist {
            None => (
                self.checkpoints.stop_reason(self.steps),
                self.checkpoints.due(self.steps),
            ),
            Some(d) => {
                let decided = self.checkpoints.agreed(
                    self.steps,
                    super::checkpoint_policy::AGREE_EVERY,
                    |f| d.from_rank0(f),
                );
                if decided.0.is_some() || decided.1 {
                    // a checkpoint: every rank makes the whole state current
                    self.share_whole();
                }
                decided
            }
        };
        if let Some(reason) = stop {
            return Err(self.interrupt(reason, observers));
        }
        if due {
            self.write_checkpoint(observers, false)?;
        }
        Ok(())
    }

    /// Stops the run for `reason`: a checkpoint (waited for), the summary marked interrupted.
    fn interrupt(&mut self, reason: &str, observers: &mut [&mut dyn Observer]) -> RunError {
        if let Err(e) = self.write_checkpoint(observers, true) {
            return e;
        }
        if !self.writes() {
            // rank 0 wrote the checkpoint and writes the summary
            return RunError::Interrupted {
                reason: reason.to_string(),
                step: self.steps,
                time: self.state.t,
                checkpoint: self.checkpoints.writer.path().to_path_buf(),
            };
        }
        let energy = self.ledger.ledger(
            self.sys,
            &self.state,
            crate::stages::summed_report(self.sys, self.state.x_nodes()).as_ref(),
        );
        let mut summary = self.summary(energy);
        for o in observers.iter_mut() {
            o.stopped(&mut summary);
        }
        let checkpoint = self.checkpoints.writer.path().to_path_buf();
        summary.interrupted = Some(Interrupted {
            reason: reason.to_string(),
            checkpoint: checkpoint.display().to_string(),
        });
        if let Err(e) = write_summary(self.out_dir, &summary) {
            return e;
        }
        RunError::Interrupted {
            reason: reason.to_string(),
            step: self.steps,
            time: self.state.t,
            checkpoint,
        }
    }

    /// The run of `l` on `sys` rebuilt from checkpoint `cp` (read from `file`, checked to
    /// belong to `l`): stages attached to continue their files, every part restored, then the
    /// observers; no force is evaluated.
    pub fn resume(
        l: &'a Problem,
        sys: &'a mut SceneSystem,
        options: &RunOptions,
        out_dir: &'a Path,
        cp: &Checkpoint,
        observers: &mut [&mut dyn Observer],
    ) -> Result<Self, RunError> {
        let started = Instant::now();
        let file = out_dir.join(crate::checkpoint::FILE_NAME);
        let bad = |e: DecodeError| unreadable(&file, e);
        let stage_dir = super::stepping::stage_dir(sys, out_dir);
        crate::stages::attach_to(
            l,
            &mut *sys,
            l.dt,
            stage_dir,
            super::stepping::history_interval(l),
            true,
        )?;
        let n = sys.model.n_nodes();
        let mut integrator = l.scheme.build(2 * n);
        let mut control = StepControl::new(l);
        Books::prepare(&mut *sys, super::stepping::books_residuals(l));
        let mut d = Dec::new(&cp.state);
        let (part, inversions) = d
            .section("run", |d| {
                let steps = d.get()?;
                let [step_time, wall]: [f64; 2] = d.get()?;
                let next_frame = d.get()?;
                let ended = d.get()?;
                let part = RunPart {
                    steps,
                    step_time,
                    wall,
                    next_frame,
                    ended,
                };
                Ok((part, unpack_inversion(d)?))
            })
            .map_err(bad)?;
        let state = d
            .section("state", |d| {
                let t = d.get()?;
                let x = d.vec_of_len(2 * n, "positions")?;
                let v = d.vec_of_len(2 * n, "velocities")?;
                Ok(State::new(t, x, v))
            })
            .map_err(bad)?;
        d.section("scheme", |d| {
            let s: SchemeState = d.get()?;
            integrator.restore_state(&s).map_err(|e| d.error(e))
        })
        .map_err(bad)?;
        d.section("control", |d| control.restore(d)).map_err(bad)?;
        let ledger = d
            .section("ledger", |d| Books::restore(d, &sys.model))
            .map_err(bad)?;
        d.section("system", |d| sys.restore(d)).map_err(bad)?;
        let (kinetic, adaptive, conjugate) =
            restore_relaxation(l, &mut *sys, &state, &mut d).map_err(bad)?;
        for c in &mut sys.contributions {
            let name = c.name().to_string();
            d.section(&name, |d| c.restore(d, &mut sys.events))
                .map_err(bad)?;
        }
        // a run that had reached its last step ends at once, unless its end is later now
        let at_end = part.steps > 0 && control.is_last(part.steps, &state);
        let mut frames = FrameClock::new(l);
        frames.resume_at(part.next_frame);
        let mut run = Run {
            loaded: l,
            sys,
            state,
            integrator,
            control,
            ledger,
            inversions,
            frames,
            out_dir,
            steps: part.steps,
            step_time: part.step_time,
            wall: Instant::now(),
            wall_before: part.wall,
            ended: part.ended || at_end,
            checkpoints: Checkpointing::new(l, options),
            kinetic,
            adaptive,
            conjugate,
            resumed: None,
        };
        run.resumed = Some(crate::run::summary::Resumed {
            step: run.steps,
            time: run.state.t,
        });
        run.checkpoints.any = true;
        run.checkpoints.run_id = Some(cp.header.run_id);
        for o in observers.iter_mut() {
            let mut view = run.view(false, false);
            d.section("observer", |d| o.restore(&mut view, d))
                .map_err(bad)?;
        }
        if d.remaining() != 0 {
            return Err(bad(
                d.error(format!("{} bytes after the last section", d.remaining()))
            ));
        }
        // a distributed run's parts, from the whole restored state
        super::stepping::distribute_stages(run.sys, l.scene.damping.mass_proportional);
        // this process's set-up (the load and the restore), not the checkpointed run's
        run.sys.timers.setup = l.load_s + started.elapsed().as_secs_f64();
        Ok(run)
    }
}

/// The relaxation method's own state (kinetic damping's, adaptive damping's or the
/// conjugate-gradient iteration's), read from its section of a checkpoint.
#[allow(clippy::type_complexity)]
fn restore_relaxation(
    l: &Problem,
    sys: &mut SceneSystem,
    state: &State,
    d: &mut Dec,
) -> Result<
    (
        Option<super::kinetic::KineticDamping>,
        Option<super::adaptive::AdaptiveDamping>,
        Option<super::conjugate::ConjugateGradient>,
    ),
    DecodeError,
> {
    let n = sys.model.n_nodes();
    let method = super::stepping::relaxation_method(l);
    let mut kinetic = (method == Some(crate::input::scene::RelaxationMethod::Kinetic))
        .then(|| super::kinetic::KineticDamping::new(sys, state));
    if let Some(k) = &mut kinetic {
        d.section("kinetic", |d| k.restore(d, 2 * n))?;
    }
    let mut adaptive = (method == Some(crate::input::scene::RelaxationMethod::Adaptive))
        .then(|| super::adaptive::AdaptiveDamping::new(sys, state));
    if let Some(a) = &mut adaptive {
        d.section("adaptive", |d| a.restore(d, &mut *sys, 2 * n))?;
    }
    let mut conjugate = (method == Some(crate::input::scene::RelaxationMethod::ConjugateGradient))
        .then(|| super::conjugate::ConjugateGradient::sized(2 * n, l.dt));
    if let Some(c) = &mut conjugate {
        d.section("conjugate-gradient", |d| c.restore(d, 2 * n))?;
    }
    Ok((kinetic, adaptive, conjugate))
}
