//! The stepping loop ([`Run::execute`]): the run's state, scheme and step control, the energy
//! books, and the observers called at the start, after each step, at each frame and at the
//! end.

use std::path::Path;
use std::time::Instant;

use fdem_time::{Integrator, SecondOrderSystem, State};

use super::adaptive::AdaptiveDamping;
use super::checkpoint_policy::Checkpointing;
use super::conjugate::ConjugateGradient;
use super::frames::{FrameClock, state_frame};
use super::kinetic::KineticDamping;
use super::observer::{Flow, Halt, Observer, RunView};
use super::options::RunOptions;
use super::step_control::StepControl;
use crate::error::RunError;
use crate::input::scene::{Probe, RelaxationMethod};
use crate::problem::load::Problem;
use crate::run::diagnosis::{self, InversionWatch};
use crate::run::ledger::{Books, Energies};
use crate::run::summary::{Outcome, Summary, write_summary};
use crate::stages::summed_report;
use crate::stages::system::SceneSystem;

/// A dynamic or relaxation run of a loaded scene on its system.
pub struct Run<'a> {
    pub(super) loaded: &'a Problem,
    pub(super) sys: &'a mut SceneSystem,
    pub(super) state: State,
    pub(super) integrator: Box<dyn Integrator>,
    pub(super) control: StepControl,
    /// The energy ledger's running books (`crate::run::ledger`).
    pub(super) ledger: Books,
    pub(super) inversions: InversionWatch,
    pub(super) frames: FrameClock,
    pub(super) out_dir: &'a Path,
    /// Steps done.
    pub(super) steps: u64,
    /// Wall time in the scheme's steps [s].
    pub(super) step_time: f64,
    /// When the run began (the summary's wall time).
    pub(super) wall: Instant,
    /// Wall time of the parts of the run before the checkpoint it resumed from [s].
    pub(super) wall_before: f64,
    /// The run reached its end (its last step, or a relaxation converged).
    pub(super) ended: bool,
    /// Checkpoints and stops.
    pub(super) checkpoints: Checkpointing,
    /// A kinetic relaxation's damping (`None` for any other run).
    pub(super) kinetic: Option<KineticDamping>,
    /// An adaptive relaxation's damping (`None` for any other run).
    pub(super) adaptive: Option<AdaptiveDamping>,
    /// A conjugate-gradient relaxation's minimiser (`None` for any other run): its
    /// iteration replaces the scheme's step.
    pub(super) conjugate: Option<ConjugateGradient>,
    /// Where a resumed run took up (`None` for a run from the start).
    pub(super) resumed: Option<crate::run::summary::Resumed>,
}

impl<'a> Run<'a> {
    /// The run of `l` at t = 0 on `sys` (which holds `l`'s model and elements): the stages
    /// attached, the initial state with the prescribed DOFs set, the force at t = 0 evaluated
    /// and the energy books opened on it.
    pub fn start(
        l: &'a Problem,
        sys: &'a mut SceneSystem,
        options: &RunOptions,
        out_dir: &'a Path,
        wall: Instant,
    ) -> Result<Self, RunError> {
        let stage_dir = stage_dir(sys, out_dir);
        crate::stages::attach_to(l, &mut *sys, l.dt, stage_dir, history_interval(l), false)?;
        let n = sys.model.n_nodes();
        let mut x0 = sys.model.x0.as_flattened().to_vec();
        let mut v0 = sys.model.v0.as_flattened().to_vec();
        for &d in sys.constrained() {
            v0[d] = 0.0;
        }
        sys.prescribe(0.0, &mut x0, &mut v0);
        let mut state = State::new(0.0, x0, v0);
        let integrator = l.scheme.build(2 * n);
        let control = StepControl::new(l);
        let book_residuals = books_residuals(l);
        Books::prepare(&mut *sys, book_residuals);
        let alpha = l.scene.damping.mass_proportional;
        distribute_stages(sys, alpha);
        let mut acc = vec![0.0; 2 * n];
        sys.acceleration(0.0, &state.x, &state.v, &mut acc);
        if let Some(d) = &mut sys.dist {
            let State { x, v, .. } = &mut state;
            d.sync(x, v, &mut sys.force, &mut sys.internal_force);
        }
        let ledger = Books::new(&mut *sys, &state, alpha, book_residuals);
        sys.timers.setup = l.load_s + wall.elapsed().as_secs_f64();
        let method = relaxation_method(l);
        let kinetic =
            (method == Some(RelaxationMethod::Kinetic)).then(|| KineticDamping::new(sys, &state));
        let adaptive =
            (method == Some(RelaxationMethod::Adaptive)).then(|| AdaptiveDamping::new(sys, &state));
        let conjugate = (method == Some(RelaxationMethod::ConjugateGradient))
            .then(|| ConjugateGradient::new(sys, &state, &ledger, l.dt));
        Ok(Self {
            loaded: l,
            sys,
            state,
            integrator,
            control,
            ledger,
            inversions: InversionWatch::default(),
            frames: FrameClock::new(l),
            out_dir,
            steps: 0,
            step_time: 0.0,
            wall,
            wall_before: 0.0,
            ended: false,
            checkpoints: Checkpointing::new(l, options),
            kinetic,
            adaptive,
            conjugate,
            resumed: None,
        })
    }

    /// The stepping loop: each step takes the step control's step with the scheme, books its
    /// energy, calls the observers (checks, histories, progress), writes a frame when one is
    /// due, and ends at the last step or when an observer says the goal is reached. An
    /// observer's `Halt` ends the run with its error.
    pub fn execute(mut self, observers: &mut [&mut dyn Observer]) -> Result<Outcome, RunError> {
        let started = self.notify(observers, false, |o, run| {
            o.start(run).map(|()| Flow::Continue)
        });
        if let Err(halt) = started {
            return Err(self.halt(halt, observers));
        }
        self.resume_loop(observers)
    }

    /// The loop of [`Run::execute`] from the run's present step (a resumed run enters here);
    /// checkpoints between steps, and one at the end of a run that wrote one before.
    pub fn resume_loop(mut self, observers: &mut [&mut dyn Observer]) -> Result<Outcome, RunError> {
        while !self.ended && !self.control.done(self.steps) {
            let h = self.control.next(self.sys, &self.state, self.steps);
            self.take_step(h);
            self.share_state();
            self.ledger.step(self.sys, &self.state);
            if let Some(k) = &mut self.kinetic {
                k.after_step(
                    self.sys,
                    &mut self.state,
                    &mut *self.integrator,
                    &mut self.ledger,
                );
            }
            if let Some(a) = &mut self.adaptive {
                a.after_step(self.sys, &self.state, &mut self.ledger, h);
            }
            if let Some(c) = &mut self.conjugate {
                c.book(self.sys, &self.state, &mut self.ledger);
            }
            let last = self.control.is_last(self.steps, &self.state);
            let end = match self.notify(observers, last, |o, run| o.after_step(run)) {
                Ok(end) => end,
                Err(halt) => return Err(self.halt(halt, observers)),
            };
            if self.frames.due(self.steps, self.state.t, end) {
                let written = self.notify(observers, end, |o, run| {
                    o.at_frame(run).map(|()| Flow::Continue)
                });
                if let Err(halt) = written {
                    return Err(self.halt(halt, observers));
                }
                self.frames.advance();
            }
            if end {
                // an observer's goal reached before the last step (a relaxation converged):
                // a resumed run does not go on, even with a later end
                self.ended = !last;
                break;
            }
            self.between_steps(observers)?;
        }
        if self.checkpoints.any {
            self.write_checkpoint(observers, false)?;
        }
        self.checkpoints
            .writer
            .wait()
            .map_err(|e| RunError::Output {
                file: self.checkpoints.writer.path().to_path_buf(),
                message: format!("cannot write the checkpoint: {e}"),
            })?;
        self.finish(observers)
    }

    /// One step of the scheme (or one conjugate-gradient iteration), timed.
    fn take_step(&mut self, h: f64) {
        let s = Instant::now();
        match &mut self.conjugate {
            Some(c) => c.iterate(self.sys, &mut self.state, h),
            None => self.integrator.step(&mut *self.sys, &mut self.state, h),
        }
        self.step_time += s.elapsed().as_secs_f64();
        self.steps += 1;
    }

    /// A distributed run's whole state on every rank now: the nodes' state and forces and the
    /// stages' (at a step the observers read, and before a checkpoint).
    pub(super) fn share_whole(&mut self) {
        let sys = &mut *self.sys;
        if let Some(d) = &mut sys.dist {
            let State { x, v, .. } = &mut self.state;
            d.sync(x, v, &mut sys.force, &mut sys.internal_force);
            for c in &mut sys.contributions {
                c.share(d.comm());
            }
        }
    }

    /// A distributed run after a step: the whole state shared when an observer reads it
    /// after this step (the checks, a history row, a frame, the last step) or the books
    /// need every node; otherwise the nodes of the loads and prescribed motions only.
    fn share_state(&mut self) {
        let sys = &mut *self.sys;
        let Some(d) = &mut sys.dist else {
            return;
        };
        let step = self.steps;
        let last = self.control.is_last(step, &self.state);
        let observed = d.every_step
            || last
            || step.is_multiple_of(super::stability::CHECK_EVERY)
            || step.is_multiple_of(history_interval(self.loaded))
            || self.frames.due(step, self.state.t, last);
        if observed {
            self.share_whole();
            if step.is_multiple_of(super::stability::CHECK_EVERY) {
                self.rebalance();
            }
        } else {
            let State { x, v, .. } = &mut self.state;
            d.sync_watched(x, v, &mut sys.force);
        }
    }

    /// A distributed run at a check, with the whole state on every rank: repartitions when
    /// the cost of the parts is unbalanced (`crate::distributed::balance`). Every rank takes
    /// the same decision from the same state; the results do not depend on the partition.
    fn rebalance(&mut self) {
        use crate::distributed::{Layout, balance};
        let sys = &mut *self.sys;
        let Some(d) = &mut sys.dist else {
            return;
        };
        let mut cost = vec![balance::TRIANGLE; sys.elements.len()];
        for c in &sys.contributions {
            c.add_costs(&mut cost);
        }
        let (size, tri_part) = (d.layout.size, &d.layout.tri_part);
        d.imbalance[0] = balance::imbalance(tri_part, &cost, size);
        let x = self.state.x_nodes();
        let Some(parts) =
            balance::repartition(&sys.elements, x, tri_part, &cost, size, d.rebalance)
        else {
            return;
        };
        d.imbalance[1] = balance::imbalance(&parts, &cost, size);
        // the scheme's cached acceleration of every DOF from its owner: the new owners read it
        let mut scheme = self.integrator.save_state();
        d.share_dofs(&mut scheme.a);
        if let Err(e) = self.integrator.restore_state(&scheme) {
            unreachable!("a scheme takes back its own state: {}", e.0);
        }
        let layout = Layout::with_parts(&sys.model, &sys.elements, d.rank(), size, parts);
        sys.repartition(layout);
    }

    /// Whether this process writes the run's files: always, except on the ranks other than
    /// 0 of a distributed run.
    pub(super) fn writes(&self) -> bool {
        self.sys.dist.as_ref().is_none_or(|d| d.rank() == 0)
    }

    /// Calls `hook` on every observer in order with a view of the run (`end`: the run ends
    /// after this step; an observer's [`Flow::Stop`] sets it for those after it); returns
    /// whether the run ends.
    fn notify(
        &mut self,
        observers: &mut [&mut dyn Observer],
        end: bool,
        mut hook: impl FnMut(&mut dyn Observer, &mut RunView) -> Result<Flow, Halt>,
    ) -> Result<bool, Halt> {
        let last = self.steps > 0 && self.control.is_last(self.steps, &self.state);
        // a distributed run's observers see the whole state (shared after the steps they
        // read) and evaluate on it as the single process does, with no exchange
        let dist = self.sys.dist.take();
        let mut run = self.view(last, end);
        let mut result = Ok(end);
        for o in observers.iter_mut() {
            match hook(&mut **o, &mut run) {
                Ok(Flow::Stop) => run.end = true,
                Ok(Flow::Continue) => {}
                Err(halt) => {
                    result = Err(halt);
                    break;
                }
            }
        }
        if result.is_ok() {
            result = Ok(run.end);
        }
        self.sys.dist = dist;
        result
    }

    pub(super) fn view(&mut self, last: bool, end: bool) -> RunView<'_> {
        RunView {
            loaded: self.loaded,
            sys: &mut *self.sys,
            state: &self.state,
            ledger: &self.ledger,
            inversions: &mut self.inversions,
            control: &self.control,
            step: self.steps,
            last,
            end,
        }
    }

    /// The end of a run stopped by an observer: an instability writes every file of the run
    /// up to the stop (the observers' `stopped`: frames, histories; the stages' CSV files)
    /// and the partial summary, and is diagnosed in the scene's terms.
    fn halt(self, halt: Halt, observers: &mut [&mut dyn Observer]) -> RunError {
        let found = match halt {
            Halt::Failed(e) => return e,
            Halt::Unstable(found) => found,
        };
        let energy = self.energies(summed_report(self.sys, self.state.x_nodes()).as_ref());
        let mut summary = self.summary(energy);
        for c in &mut self.sys.contributions {
            c.finish();
        }
        for o in observers.iter_mut() {
            o.stopped(&mut summary);
        }
        if self.writes() {
            let _ = write_summary(self.out_dir, &summary);
        }
        let (scene, model) = (&self.loaded.scene, &self.sys.model);
        diagnosis::unstable(
            scene,
            model,
            &self.inversions,
            self.steps,
            self.state.t,
            found,
        )
    }

    /// The end of a run that reached its last step: the stages' reports, the observers'
    /// parts of the summary, `summary.json`, and the last frame.
    fn finish(mut self, observers: &mut [&mut dyn Observer]) -> Result<Outcome, RunError> {
        let (report, details) = crate::stages::reports(self.sys, self.state.x_nodes());
        for c in &mut self.sys.contributions {
            c.finish();
        }
        let mut summary = self.summary(self.energies(Some(&report)));
        summary.force_evaluations = match &self.conjugate {
            Some(c) => c.evaluations,
            None => self.integrator.counters().forces,
        };
        summary.stages = details;
        summary.time_step_range = self.control.range();
        summary.kinetic_resets = self.kinetic.as_ref().map(|k| k.resets);
        summary.cg_restarts = self.conjugate.as_ref().map(|c| c.restarts);
        summary.cg_largest_rise = self.conjugate.as_ref().map(|c| c.largest_rise);
        summary.distributed = self.sys.dist.as_ref().map(|d| d.report());
        let last = self.control.is_last(self.steps, &self.state);
        let writes = self.writes();
        let dist = self.sys.dist.take();
        let mut run = self.view(last, true);
        for o in observers.iter_mut() {
            if let Err(e) = o.finish(&mut run, &mut summary) {
                self.sys.dist = dist;
                return Err(e);
            }
        }
        self.sys.dist = dist;
        summary.accuracy = crate::run::accuracy::assess(self.loaded, &summary, None);
        if writes {
            summary.result =
                crate::run::result::read(self.out_dir, &self.sys.model).map_err(|message| {
                    RunError::Output {
                        file: self.out_dir.to_path_buf(),
                        message,
                    }
                })?;
            write_summary(self.out_dir, &summary)?;
        }
        let mut last_frame = state_frame(self.sys, &self.state);
        for c in &self.sys.contributions {
            c.frame_fields(self.state.x_nodes(), &mut last_frame);
        }
        let joint_state = self
            .sys
            .contributions
            .iter()
            .find_map(|c| c.joint_state().cloned());
        Ok(Outcome {
            summary,
            last_frame,
            joint_state,
            checkpoints: self.checkpoints.writer.stats(),
        })
    }

    /// The energy ledger now, with the stages' report `stages`.
    fn energies(&self, stages: Option<&crate::stages::system::StageReport>) -> Energies {
        self.ledger.ledger(self.sys, &self.state, stages)
    }

    /// The summary of the run so far, with the ledger `energy` (the observers add their parts).
    pub(super) fn summary(&self, energy: Energies) -> Summary {
        let (l, sys, state) = (self.loaded, &*self.sys, &self.state);
        let mut timers = sys.timers;
        timers.integration = (self.step_time
            - timers.internal_forces
            - timers.external_loads
            - timers.mass_damping
            - timers.contributions)
            .max(0.0);
        let max_u = state
            .x_nodes()
            .iter()
            .zip(&sys.model.x0)
            .map(|(a, b)| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt())
            .fold(0.0, f64::max);
        Summary {
            scene: l.file.display().to_string(),
            analysis: format!("{:?}", l.scene.analysis).to_lowercase(),
            scheme: l.scheme.name().into(),
            nodes: sys.model.n_nodes(),
            triangles: sys.elements.len(),
            time_step: l.dt,
            time_step_limit: l.dt_limit,
            steps: self.steps,
            force_evaluations: sys.evaluations,
            simulated_time: state.t,
            wall_time: self.wall_before + self.wall.elapsed().as_secs_f64(),
            triangle_steps_per_second: if self.step_time > 0.0 {
                sys.elements.len() as f64 * self.steps as f64 / self.step_time
            } else {
                0.0
            },
            timers,
            energy,
            frames: 0,
            converged: None,
            relative_residual: None,
            relaxation: None,
            relaxation_reason: None,
            relaxation_masses: None,
            residual_floor: None,
            kinetic_to_strain: None,
            kinetic_resets: None,
            cg_restarts: None,
            cg_largest_rise: None,
            max_displacement: max_u,
            threads: rayon::current_num_threads(),
            stages: serde_json::Value::Null,
            time_step_range: None,
            mass_scaling_factor: sys.model.mass_scaling.as_ref().map(|m| m.0),
            loading_rate: l.scene.loading.as_ref().map(|x| x.rate),
            quasi_static: None,
            accuracy: Default::default(),
            result: None,
            resumed: self.resumed.clone(),
            interrupted: None,
            distributed: None,
        }
    }
}

/// Where the stages of `sys` write their files (walls.csv, fractures.csv): `out_dir`, except
/// on the ranks other than 0 of a distributed run, which write none.
pub(super) fn stage_dir<'p>(sys: &SceneSystem, out_dir: &'p Path) -> Option<&'p Path> {
    sys.dist
        .as_ref()
        .is_none_or(|d| d.rank() == 0)
        .then_some(out_dir)
}

/// A distributed system's stages take their parts, and
/// the whole state is shared after every step when the energy books sum over every node in
/// every step (mass damping `alpha`, element viscosity, the kept element forces).
pub(super) fn distribute_stages(sys: &mut SceneSystem, alpha: f64) {
    if let Some(d) = &mut sys.dist {
        for c in &mut sys.contributions {
            c.distribute(&d.layout);
        }
        d.every_step = alpha > 0.0 || sys.elements.viscous || !sys.internal_force.is_empty();
    }
}

/// The interval of the histories' rows (and of `walls.csv`): `histories.every`, else a
/// thousandth of the steps.
pub fn history_interval(l: &Problem) -> u64 {
    l.scene
        .histories
        .every
        .unwrap_or((l.n_steps / 1000).max(1) as usize) as u64
}

/// The relaxation method of `l` (`None`: not a relaxation).
pub fn relaxation_method(l: &Problem) -> Option<RelaxationMethod> {
    (l.scene.analysis == crate::input::scene::Analysis::Relaxation)
        .then(|| l.scene.relaxation_choice().0)
}

/// The residuals of the element law and the contact potential are booked when the run records
/// the ledger in histories.csv (they cost about a tenth of the step).
pub fn books_residuals(l: &Problem) -> bool {
    l.scene
        .histories
        .probes
        .iter()
        .any(|p| matches!(p, Probe::Energy))
}
