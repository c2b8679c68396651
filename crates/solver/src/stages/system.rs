//! The composition: one [`SecondOrderSystem`] over the mesh, the loads, damping and any further
//! force contributions (contact, joints) a scene needs.
//!
//! The force on DOF `i` at time `t` is
//!
//! `f_i = f_int,i(x, v) + s(t) f_ext,i + m_i g - alpha m_i v_i + sum_c f_c,i(t, x, v)`
//!
//! with `f_int` the mesh crate's internal force (elastic + element viscosity), `s(t)` each
//! load's ramp or history, `alpha` the mass-proportional damping, and `f_c` the optional contributions.
//! A term the scene does not have costs nothing: no loads, no gravity, `alpha = 0`, no
//! viscosity (the mesh kernel then never reads `v`) and an empty contribution list are all
//! skipped. Constrained DOFs get zero acceleration and are moved by [`SceneSystem::prescribe`].

use std::time::Instant;

use fdem_mesh::{Elements, ForceScratch};
use fdem_time::SecondOrderSystem;
use rayon::prelude::*;

use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::output::FrameData;
use crate::problem::model::Model;

/// Below this many DOFs the element-wise loops of the system run serially.
const PAR_MIN_DOFS: usize = 1 << 16;
/// DOFs per rayon task in the element-wise loops.
const DOF_CHUNK: usize = 1 << 14;

/// The time now when `on` (the stage timers are on).
fn clock(on: bool) -> Option<Instant> {
    on.then(Instant::now)
}

/// Seconds since `s` (0 when the timers are off).
fn secs(s: Option<Instant>) -> f64 {
    s.map_or(0.0, |s| s.elapsed().as_secs_f64())
}

/// The forces of `stages` into `f`, in stage order; with `times`, each stage's wall time added
/// to its entry.
fn stage_forces(
    stages: &mut [Box<dyn Stage>],
    times: Option<&mut [f64]>,
    t: f64,
    x: &[[f64; 2]],
    v: &[[f64; 2]],
    f: &mut [[f64; 2]],
    events: &mut StepEvents,
) {
    match times {
        Some(times) => {
            for (c, ct) in stages.iter_mut().zip(times) {
                let sc = Instant::now();
                c.forces(t, x, v, f, events);
                *ct += sc.elapsed().as_secs_f64();
            }
        }
        None => {
            for c in stages {
                c.forces(t, x, v, f, events);
            }
        }
    }
}

/// A force term beyond the elements and the loads (contact, joints, ...): its forces, its
/// history at the end of a step and its frequency bounds, from the scene and the state. What
/// else a stage does lives in its own layer: [`StageOutput`] (energy books, reports, files,
/// frame fields), [`StageCheckpoint`] (the checkpoint), [`StageDistribution`] (a distributed
/// run). What one stage hands to another (the pairs a fracture releases to the contact) is
/// data of the step pipeline, [`StepEvents`], which [`SceneSystem`] owns and passes to every
/// stage in stage order.
pub trait ForceTerm: Send {
    /// Adds this term's nodal forces at `(t, x, v)` to `f`. Must not commit history; may take
    /// what earlier stages handed over in `events` (the contact stage takes the released
    /// pairs).
    fn forces(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        f: &mut [[f64; 2]],
        events: &mut StepEvents,
    );
    /// The next [`ForceTerm::forces`] call is the last of the step, and
    /// [`ForceTerm::end_of_step`] follows at its positions with `at_last` and no other call in
    /// between (the time crate's [`SecondOrderSystem::next_evaluation_ends_step`]): a term may
    /// advance its history in that call. Default: nothing.
    fn next_evaluation_ends_step(&mut self) {}
    /// For the first term of a system whose element forces it follows directly (no loads,
    /// gravity or mass damping in between, a whole run): runs the term's pass at `(t, x, v)`
    /// ahead of the element forces, in place of [`ForceTerm::forces`], and returns what adds
    /// its forces node range by node range, which the element pass calls while each range is
    /// in cache. The forces must be those of [`ForceTerm::forces`] bit for bit. `None` (the
    /// default): the term has no such split and did nothing; its `forces` follows as usual.
    fn forces_ahead(
        &mut self,
        _t: f64,
        _x: &[[f64; 2]],
        _v: &[[f64; 2]],
        _events: &mut StepEvents,
    ) -> Option<&dyn AheadForces> {
        None
    }
    /// Commits history at the end of an accepted step at `(t, x, v)`, and puts what it hands
    /// to the stages after it into `events` (the fracture stage: the released pairs and its
    /// fracture events). `at_last`: the step's last [`ForceTerm::forces`] call was at these
    /// positions `x`, bit for bit (the time crate's
    /// [`SecondOrderSystem::end_of_step_at_last_evaluation`]), so a term may reuse that
    /// evaluation's trial history without checking the positions. Default: nothing.
    fn end_of_step(
        &mut self,
        _t: f64,
        _x: &[[f64; 2]],
        _v: &[[f64; 2]],
        _at_last: bool,
        _events: &mut StepEvents,
    ) {
    }
    /// Whether [`ForceTerm::forces`] reads the velocities `v` (friction, damping). With
    /// `false` from every term (and no element viscosity or mass damping), the splitting
    /// schemes skip their velocity extrapolation pass and pass their velocity variable as it
    /// is ([`SecondOrderSystem::velocity_dependent`]). Default `true` (safe).
    fn reads_velocities(&self) -> bool {
        true
    }
    /// The term's frequency bound from what is engaged at positions `x` [rad/s]
    /// (`at`: what the last force evaluation engaged, its geometry at `x`, or what would be
    /// engaged at positions other than the last evaluation's, e.g. extrapolated ones): at most
    /// the term's a-priori bound in the problem's frequency terms
    /// ([`crate::problem::stable_step::FrequencyTerms`]), for what the state engages. `None`
    /// (the default): the term has no such bound, its a-priori one applies.
    fn active_frequency_bound(&mut self, _x: &[[f64; 2]], _at: Engaged) -> Option<f64> {
        None
    }
    /// The time step changed to `h` (an adaptive step; default: nothing).
    fn set_time_step(&mut self, _h: f64) {}
}

/// The nodal forces a term computed ahead of the element pass ([`ForceTerm::forces_ahead`]).
pub trait AheadForces: Sync {
    /// Adds the term's forces on nodes `i0..i0 + f.len()` to `f`.
    fn add(&self, i0: usize, f: &mut [[f64; 2]]);
}

/// What [`ForceTerm::active_frequency_bound`] counts as engaged at its positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Engaged {
    /// What the last force evaluation engaged (the positions are that evaluation's).
    LastEvaluation,
    /// What would be engaged at these positions, other than the last evaluation's (every
    /// candidate the term knows of).
    Elsewhere,
}

/// What a stage hands to the stages after it, as data of the step pipeline: filled by one
/// stage's [`ForceTerm::end_of_step`], read by a later stage's passes. [`SceneSystem`] owns it
/// and passes it to every stage in stage order.
#[derive(Debug, Clone, Default)]
pub struct StepEvents {
    /// Triangle pairs released from the bonded set (their joint softened or broke), in release
    /// order: appended by the fracture stage at the end of a step, taken and cleared by the
    /// contact stage at its next force evaluation (each pair once over the run). A checkpoint
    /// holds those not taken yet (in the fracture stage's section).
    pub released: Vec<[u32; 2]>,
    /// A stage takes [`StepEvents::released`] (the contact stage, given the bonded pairs at
    /// attach): without one, the releasing stage keeps none.
    pub released_taken: bool,
    /// The fracture events (breaks) of the last end of step, in joint order.
    pub fractures: Vec<fdem_fracture::FractureEvent>,
    /// The joints that softened (damage above 0) for the first time at the last end of step
    /// (global ids, increasing): filled by the fracture stage only when a later stage takes
    /// them ([`StepEvents::softened_taken`]: the fluid, `fluid.wet_damaged`).
    pub softened: Vec<u32>,
    /// A stage reads [`StepEvents::softened`].
    pub softened_taken: bool,
}

/// A stage's reports and output: its energy books for the run summary, the error that stops a
/// run, its arrays in the output frames and the files it writes. Every method has a default
/// (a stage without any of it).
pub trait StageOutput {
    /// Energies and state of this term at positions `x`, for the run summary (default: none).
    fn report(&self, _x: &[[f64; 2]]) -> StageReport {
        StageReport::default()
    }
    /// An error that should stop the run, checked every 100 steps (default none).
    fn error(&self) -> Option<String> {
        None
    }
    /// Adds this term's arrays to an output frame (`frame.extra_point_vectors`,
    /// `frame.extra_cell_scalars`, `frame.joints`) from its last force evaluation at
    /// positions `x` (default: nothing, so a scene without the term writes no such arrays).
    fn frame_fields(&self, _x: &[[f64; 2]], _frame: &mut FrameData) {}
    /// Adds to `files` the names of the files in the run's folder that this term appends to,
    /// which a run resumed from a checkpoint goes on from (default: none).
    fn files(&self, _files: &mut Vec<String>) {}
    /// Called once after the last step, or at a stop on an instability (flush files;
    /// default: nothing).
    fn finish(&mut self) {}
    /// The joints as the nodal stress recovery needs them (node ids, intact flags): a term
    /// with joints (the fracture stage) hands them out so that no patch crosses a broken
    /// joint (default: none).
    fn joint_links(&self) -> Option<crate::output::recovery::Links<'_>> {
        None
    }
}

/// A stage in a checkpoint.
pub trait StageCheckpoint {
    /// Appends to a checkpoint everything this term carries from one step to the next
    /// (committed histories, couples, detection state, counters, energy sums, the last
    /// evaluation's results that reports and frames read, the length of its CSV file, which
    /// it flushes; the part of `events` it hands over and a later stage has not taken yet),
    /// so that [`StageCheckpoint::restore`] on a term attached afresh for the same scene
    /// continues bit for bit.
    fn save(&mut self, e: &mut Enc, events: &StepEvents) -> std::io::Result<()>;
    /// Restores what [`StageCheckpoint::save`] wrote (its part of `events` included), on a
    /// term attached afresh (`resume`) for the same scene, and cuts its CSV file back to its
    /// length at the checkpoint. Sizes that do not match the scene are an error, never a
    /// panic.
    fn restore(&mut self, d: &mut Dec, events: &mut StepEvents) -> Result<(), DecodeError>;
    /// The joints' committed history, for a term that has one (the fracture stage): the
    /// driver hands it out with the run's outcome so that a later run can start from it
    /// (default: none).
    fn joint_state(&self) -> Option<&fdem_fracture::JointState> {
        None
    }
}

/// A stage in a distributed run ([`crate::distributed`]), and the modes of its force passes.
/// Every method has a default: the term runs whole on every rank, on the gathered state.
pub trait StageDistribution: ForceTerm {
    /// A distributed run starts on `layout`: a term that can evaluate only the part of this
    /// rank takes its part here (default: the term runs whole on every rank, on the gathered
    /// state).
    fn distribute(&mut self, _layout: &crate::distributed::Layout) {}
    /// With `on`, the next passes only look at a state (an output frame's force): the term
    /// changes nothing that carries over to the next step, so that what is written does not
    /// change the run. Default: nothing (a pass of the term changes nothing that carries).
    fn set_looking(&mut self, _on: bool) {}
    /// In a distributed run: evaluate this rank's part (`true`: the run's steps) or the whole
    /// term on the whole state (`false`: the observers, at the steps where the state is
    /// shared). Default: nothing (the term is whole anyway).
    fn set_partial(&mut self, _on: bool) {}
    /// The end-of-step hook of a distributed run, with the transport; `at_last` and `events`
    /// as for [`ForceTerm::end_of_step`]. Every rank calls it at every step. Default: the
    /// single-process hook.
    fn end_of_step_distributed(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        at_last: bool,
        events: &mut StepEvents,
        _comm: &mut dyn crate::distributed::Comm,
    ) {
        self.end_of_step(t, x, v, at_last, events);
    }
    /// In a distributed run, after the elements' ghosts are current and before the forces
    /// (`before_forces`) or the end-of-step hook (otherwise, when the state moved since the
    /// last evaluation or a term reads velocities): the term brings the nodes it reads beyond
    /// the elements' ghosts into `x` (and the velocities into `v` when it reads them) from
    /// their owners, takes what earlier stages handed over in `events` (before the forces),
    /// and takes its collective decisions. Every rank calls it. Default: nothing.
    fn exchange_distributed(
        &mut self,
        _t: f64,
        _x: &mut [[f64; 2]],
        _v: &mut [[f64; 2]],
        _before_forces: bool,
        _events: &mut StepEvents,
        _comm: &mut dyn crate::distributed::Comm,
    ) {
    }
    /// Adds the cost per step of the term's items to the triangles that lead them, in units of
    /// a triangle's element pass (`crate::distributed::balance`: what a repartition balances).
    /// Default: nothing.
    fn add_costs(&self, _tri_cost: &mut [f64]) {}
    /// In a distributed run, at each step whose state the observers read: makes the term's
    /// whole state current on every rank. Every rank calls it. Default: nothing.
    fn share(&mut self, _comm: &mut dyn crate::distributed::Comm) {}
}

/// A stage of the composition, plugged into [`SceneSystem::contributions`]: its name, and a
/// force term with its output, checkpoint and distribution layers. Each layer of the run
/// calls the trait of its layer (and the name, which every layer uses); [`std::any::Any`] lets
/// a caller that knows the stage's type (a test) get it back.
pub trait Stage:
    ForceTerm + StageOutput + StageCheckpoint + StageDistribution + std::any::Any
{
    /// Name in the summary's timers and stage details, and the checkpoint's section.
    fn name(&self) -> &str;
}

/// What a stage reports to the run summary ([`StageOutput::report`]).
#[derive(Debug, Clone, Default)]
pub struct StageReport {
    /// Energy stored by the term (contact potential, joint strain, friction springs) [J].
    pub stored: f64,
    /// Energy dissipated by friction slip [J].
    pub friction: f64,
    /// Energy dissipated by contact damping (the normal dashpots) [J].
    pub contact_damping: f64,
    /// Energy dissipated by the softening of joints [J].
    pub fracture: f64,
    /// Energy lost at the switches between joints and contact [J]: stored in joints when they
    /// broke, less the contact potential that released pairs brought in (negative when the
    /// contact brought in more).
    pub switch_loss: f64,
    /// Energy the term's forces removed from the bodies beyond what its books explain [J]:
    /// for contact, the work of the supplied energy (walls) less the change of the stored
    /// energy, the friction and damping dissipation and the work its forces did on the
    /// nodes (the contact potential is an exact potential for rigid relative motion only).
    pub contact_residual: f64,
    /// Work done on the bodies by boundaries the term moves (platens) [J].
    pub wall_work: f64,
    /// Work done on the bodies by the fluid's pressure on the crack faces [J].
    pub fluid_work: f64,
    /// An error that should stop the run (e.g. too deep a penetration).
    pub error: Option<String>,
    /// Free-form details for `summary.json`.
    pub details: serde_json::Value,
}

/// Wall time spent per stage [s].
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct StageTimers {
    /// Internal (element) forces; for the static analysis, the assembly and sparse solve.
    pub internal_forces: f64,
    /// External loads and gravity.
    pub external_loads: f64,
    /// Mass-proportional damping.
    pub mass_damping: f64,
    /// Further contributions (contact, joints).
    pub contributions: f64,
    /// Everything else inside the integrator's step (its update loops).
    pub integration: f64,
    /// History recording.
    pub histories: f64,
    /// Frame output (stresses, encoding, writing).
    pub output: f64,
    /// The set-up: the scene's load ([`crate::problem::load::load`]: meshes, explode, model, elements,
    /// time step) and the run's start until the first step (stages attached, first contact
    /// detection, first force evaluation, energy books). Not in a checkpoint: a resumed run
    /// reports its own set-up.
    pub setup: f64,
}

/// The scene as a second-order system for the time crate.
pub struct SceneSystem {
    /// The assembled scene (loads, constraints, groups).
    pub model: Model,
    /// The triangles prepared for the force kernels.
    pub elements: Elements,
    scratch: ForceScratch,
    inv_mass: Vec<f64>,
    constrained_dofs: Vec<usize>,
    x0: Vec<f64>,
    alpha: f64,
    /// Optional stages (contact, joints), in stage order: none by default.
    pub contributions: Vec<Box<dyn Stage>>,
    /// What the stages hand to each other in the step pipeline (the released pairs).
    pub events: StepEvents,
    /// Whether the first stage may run its pass ahead of the element forces and add its
    /// forces inside the element pass ([`ForceTerm::forces_ahead`]; on, off only to compare).
    pub(crate) ahead: bool,
    /// The evaluations whose first stage ran ahead of the element pass.
    pub(crate) ahead_evaluations: u64,
    /// Nodal force of the last evaluation (internal + external + damping + contributions).
    pub force: Vec<[f64; 2]>,
    /// The internal (element) part of [`SceneSystem::force`], kept only after
    /// [`SceneSystem::keep_internal_forces`] (for the energy ledger's work of the element
    /// forces); empty otherwise.
    pub internal_force: Vec<[f64; 2]>,
    /// Whether the last evaluation was at the positions that ended the last step (the time
    /// crate's `end_of_step_at_last_evaluation`; false after a plain `end_of_step`).
    pub evaluated_at_end: bool,
    /// Stage timers (accumulated).
    pub timers: StageTimers,
    /// Wall time of each contribution [s], aligned with [`SceneSystem::contributions`]:
    /// force passes and end-of-step hooks (filled while the stage timers are on).
    pub contribution_times: Vec<f64>,
    /// The part of [`SceneSystem::contribution_times`] spent in the end-of-step hooks [s].
    pub contribution_end_times: Vec<f64>,
    /// Time of the last evaluation's external loads [s].
    pub evaluations: u64,
    timing: bool,
    /// This system's part in a distributed run (`None`: the whole system on one process).
    pub dist: Option<Box<crate::distributed::Distribution>>,
    dist_scratch: ForceScratch,
}

impl SceneSystem {
    /// Composes the system; `alpha` is the mass-proportional damping [1/s].
    pub fn new(model: Model, elements: Elements, alpha: f64) -> Self {
        let n = model.n_nodes();
        let mut inv_mass = vec![0.0; 2 * n];
        for (i, m) in model.mass.iter().enumerate() {
            let im = if *m > 0.0 { 1.0 / m } else { 0.0 };
            inv_mass[2 * i] = im;
            inv_mass[2 * i + 1] = im;
        }
        let constrained_dofs: Vec<usize> = (0..2 * n).filter(|&d| model.constrained[d]).collect();
        for &d in &constrained_dofs {
            inv_mass[d] = 0.0;
        }
        let x0 = model.x0.as_flattened().to_vec();
        let scratch = ForceScratch::new(&elements);
        Self {
            model,
            elements,
            scratch,
            inv_mass,
            constrained_dofs,
            x0,
            alpha,
            contributions: Vec::new(),
            ahead: true,
            ahead_evaluations: 0,
            events: StepEvents::default(),
            force: vec![[0.0; 2]; n],
            internal_force: Vec::new(),
            evaluated_at_end: false,
            timers: StageTimers::default(),
            contribution_times: Vec::new(),
            contribution_end_times: Vec::new(),
            evaluations: 0,
            timing: true,
            dist: None,
            dist_scratch: ForceScratch::default(),
        }
    }

    /// Makes this system one rank's part of a distributed run: from now on it evaluates the
    /// forces of its part's triangles at positions whose ghost entries come from their owners,
    /// and the scheme moves only the DOFs of the nodes it owns
    /// ([`crate::distributed`]).
    pub fn distribute(&mut self, d: crate::distributed::Distribution) {
        self.dist_scratch = ForceScratch::new(&d.local);
        self.dist = Some(Box::new(d));
    }

    /// Takes a new distributed `layout` (a repartition at a step whose whole state every rank
    /// holds): the triangles evaluated, the exchanges and the stages' parts.
    pub fn repartition(&mut self, layout: crate::distributed::Layout) {
        if let Some(d) = &mut self.dist {
            d.repartition(layout, &self.elements);
            self.dist_scratch = ForceScratch::new(&d.local);
            for c in &mut self.contributions {
                c.distribute(&d.layout);
            }
        }
    }

    /// Sets the mass-proportional damping `alpha` [1/s] (an adaptive relaxation).
    pub fn set_alpha(&mut self, alpha: f64) {
        self.alpha = alpha;
    }

    /// Turns the per-stage timers on or off (they cost two clock reads per stage).
    pub fn set_timing(&mut self, on: bool) {
        self.timing = on;
    }

    /// From the next evaluation on, keeps a copy of the internal forces in
    /// [`SceneSystem::internal_force`] (one copy of the node array per evaluation).
    pub fn keep_internal_forces(&mut self) {
        self.internal_force = vec![[0.0; 2]; self.force.len()];
    }

    /// Recomputes [`SceneSystem::internal_force`] at `(x, v)` (node arrays), leaving
    /// [`SceneSystem::force`] alone: for a step whose last evaluation was elsewhere.
    pub fn refresh_internal_forces(&mut self, x: &[[f64; 2]], v: &[[f64; 2]]) {
        if !self.internal_force.is_empty() {
            self.elements
                .set_internal_forces(x, v, &mut self.internal_force, &mut self.scratch);
        }
    }

    /// Constrained DOFs (fixed or prescribed velocity).
    pub fn constrained(&self) -> &[usize] {
        &self.constrained_dofs
    }

    /// The acceleration at `(t, x, v)` into `a` (and the force into [`SceneSystem::force`])
    /// for a look at the state (an output frame): no stage changes what carries over to the
    /// next step ([`StageDistribution::set_looking`]).
    pub fn look(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        for c in &mut self.contributions {
            c.set_looking(true);
        }
        fdem_time::SecondOrderSystem::acceleration(self, t, x, v, a);
        for c in &mut self.contributions {
            c.set_looking(false);
        }
    }

    /// Total nodal force at `(t, x, v)` into [`SceneSystem::force`].
    pub fn evaluate(&mut self, t: f64, x: &[f64], v: &[f64]) {
        let xn = x.as_chunks::<2>().0;
        let vn = v.as_chunks::<2>().0;
        let s = clock(self.timing);
        let partial = self.dist.is_some();
        // the first stage's forces join the element pass when nothing comes in between
        let mut ahead_s = 0.0;
        let fused = self.ahead
            && self.dist.is_none()
            && self.model.loads.is_empty()
            && self.model.gravity.is_none()
            && self.alpha == 0.0
            && self.internal_force.is_empty()
            && self.elements.n_nodes == self.force.len();
        let ahead = match self.contributions.first_mut() {
            Some(c) if fused => {
                c.set_partial(false);
                let sa = clock(self.timing);
                let a = c.forces_ahead(t, xn, vn, &mut self.events);
                ahead_s = secs(sa);
                a
            }
            _ => None,
        };
        let n_ahead = usize::from(ahead.is_some());
        self.ahead_evaluations += n_ahead as u64;
        let (xn, vn) = match &mut self.dist {
            None => {
                match ahead {
                    Some(a) => self.elements.set_internal_forces_then(
                        xn,
                        vn,
                        &mut self.force,
                        &mut self.scratch,
                        |i0, fc| a.add(i0, fc),
                    ),
                    None => self.elements.set_internal_forces(
                        xn,
                        vn,
                        &mut self.force,
                        &mut self.scratch,
                    ),
                }
                (xn, vn)
            }
            Some(d) => {
                let with_v = self.elements.viscous
                    || self.alpha > 0.0
                    || self.contributions.iter().any(|c| c.reads_velocities());
                d.patch(x, v, with_v);
                let (xm, vm, comm) = d.parts();
                for c in &mut self.contributions {
                    c.exchange_distributed(t, xm, vm, true, &mut self.events, comm);
                }
                let xn = d.xp.as_chunks::<2>().0;
                let vn = if with_v { d.vp.as_chunks::<2>().0 } else { vn };
                d.local
                    .set_internal_forces(xn, vn, &mut self.force, &mut self.dist_scratch);
                (xn, vn)
            }
        };
        if !self.internal_force.is_empty() {
            self.internal_force.copy_from_slice(&self.force);
        }
        self.timers.internal_forces += secs(s) - ahead_s;
        if !self.model.loads.is_empty() || self.model.gravity.is_some() {
            let s = clock(self.timing);
            self.model.add_external(t, self.force.as_flattened_mut());
            self.timers.external_loads += secs(s);
        }
        if self.alpha > 0.0 {
            let s = clock(self.timing);
            let a = self.alpha;
            for ((f, vi), m) in self.force.iter_mut().zip(vn).zip(&self.model.mass) {
                f[0] -= a * m * vi[0];
                f[1] -= a * m * vi[1];
            }
            self.timers.mass_damping += secs(s);
        }
        if !self.contributions.is_empty() {
            for c in &mut self.contributions {
                c.set_partial(partial);
            }
            let s = clock(self.timing);
            if self.timing {
                self.contribution_times
                    .resize(self.contributions.len(), 0.0);
                if n_ahead > 0 {
                    self.contribution_times[0] += ahead_s;
                }
            }
            let times = (self.timing).then(|| &mut self.contribution_times[n_ahead..]);
            let stages = &mut self.contributions[n_ahead..];
            stage_forces(stages, times, t, xn, vn, &mut self.force, &mut self.events);
            self.timers.contributions += secs(s) + ahead_s;
        }
        self.evaluations += 1;
    }

    /// The round-off floor of the out-of-balance force at `(t, x, v)` (flat DOFs):
    /// `eps sqrt(sum_i S_i^2)` over the free DOFs, with `S_i` the sum of the magnitudes of
    /// the terms whose rounding makes up the force of DOF `i` (the triangles' contributions
    /// and their stiffness times the absolute positions,
    /// `fdem_mesh::Elements::add_round_off_terms`; the loads and gravity): a force summed from
    /// such terms is resolved to about `eps S_i`. The force terms of the stages (contact,
    /// joints) are not counted. `buf` is a DOF array (resized once).
    pub fn force_round_off(&self, t: f64, x: &[f64], v: &[f64], buf: &mut Vec<f64>) -> f64 {
        buf.clear();
        buf.resize(x.len(), 0.0);
        let xn = x.as_chunks::<2>().0;
        let vn = v.as_chunks::<2>().0;
        self.elements.add_round_off_terms(xn, vn, buf);
        for ld in &self.model.loads {
            let f = ld.factor(t);
            for &(d, val) in &ld.forces {
                buf[d as usize] += (f * val).abs();
            }
        }
        if let Some(g) = self.model.gravity {
            for (i, m) in self.model.mass.iter().enumerate() {
                buf[2 * i] += (m * g[0]).abs();
                buf[2 * i + 1] += (m * g[1]).abs();
            }
        }
        let mut s = 0.0;
        for (d, si) in buf.iter().enumerate() {
            if !self.model.constrained[d] {
                s += si * si;
            }
        }
        f64::EPSILON * s.sqrt()
    }

    /// Reaction at each DOF: the force the supports apply, `-f` at constrained DOFs (quasi-static
    /// reading), 0 elsewhere.
    pub fn reactions(&self) -> Vec<[f64; 2]> {
        let mut r = vec![[0.0; 2]; self.force.len()];
        let rf = r.as_flattened_mut();
        let f = self.force.as_flattened();
        for &d in &self.constrained_dofs {
            rf[d] = -f[d];
        }
        r
    }
}

impl SecondOrderSystem for SceneSystem {
    fn n_dofs(&self) -> usize {
        self.inv_mass.len()
    }

    fn inv_mass(&self) -> &[f64] {
        &self.inv_mass
    }

    fn acceleration(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        self.evaluate(t, x, v);
        // a = f / m, element-wise (in parallel for large systems: same result)
        let kernel = |a: &mut [f64], f: &[f64], im: &[f64]| {
            for ((ai, f), im) in a.iter_mut().zip(f).zip(im) {
                *ai = f * im;
            }
        };
        let f = self.force.as_flattened();
        if let Some(d) = &self.dist {
            // a distributed part: its own DOFs only (the scheme moves no others)
            for r in &d.layout.active {
                let r = r.clone();
                kernel(&mut a[r.clone()], &f[r.clone()], &self.inv_mass[r]);
            }
            return;
        }
        if a.len() >= PAR_MIN_DOFS {
            a.par_chunks_mut(DOF_CHUNK)
                .zip(f.par_chunks(DOF_CHUNK))
                .zip(self.inv_mass.par_chunks(DOF_CHUNK))
                .for_each(|((a, f), im)| kernel(a, f, im));
        } else {
            kernel(a, f, &self.inv_mass);
        }
    }

    fn velocity_dependent(&self) -> bool {
        // Element viscosity, mass-proportional damping, or a contribution (friction, contact
        // damping) read v.
        self.elements.viscous
            || self.alpha > 0.0
            || self.contributions.iter().any(|c| c.reads_velocities())
    }

    fn active_dofs(&self) -> Option<&[std::ops::Range<usize>]> {
        self.dist.as_ref().map(|d| d.layout.active.as_slice())
    }

    fn prescribed_dofs(&self) -> &[usize] {
        match &self.dist {
            Some(d) => &d.layout.held_dofs,
            None => &self.constrained_dofs,
        }
    }

    fn prescribe(&mut self, t: f64, x: &mut [f64], v: &mut [f64]) {
        for p in &self.model.prescribed {
            let d = p.dof as usize;
            let (u, vel) = p.motion(t);
            x[d] = self.x0[d] + u;
            v[d] = vel;
        }
    }

    fn next_evaluation_ends_step(&mut self) {
        for c in &mut self.contributions {
            c.next_evaluation_ends_step();
        }
    }

    fn end_of_step(&mut self, t: f64, x: &[f64], v: &[f64]) {
        self.evaluated_at_end = false;
        self.end_contributions(t, x, v, false);
    }

    fn end_of_step_at_last_evaluation(&mut self, t: f64, x: &[f64], v: &[f64]) {
        self.evaluated_at_end = true;
        self.end_contributions(t, x, v, true);
    }
}

impl SceneSystem {
    /// The contributions' end-of-step hooks; `at_last` when the last evaluation was at `x`.
    fn end_contributions(&mut self, t: f64, x: &[f64], v: &[f64], at_last: bool) {
        if self.contributions.is_empty() {
            return;
        }
        // a distributed run's stages see this rank's nodes and the ones they read, from their
        // owners, and get the transport
        if let Some(d) = &mut self.dist {
            // at the last evaluation's positions those are still current; the velocities are
            // brought when a stage reads them
            let with_v = self.contributions.iter().any(|c| c.reads_velocities());
            if !at_last || with_v {
                d.patch_owned(x, v, with_v);
                let (xm, vm, comm) = d.parts();
                for c in &mut self.contributions {
                    c.exchange_distributed(t, xm, vm, false, &mut self.events, comm);
                }
            }
            let (xp, vp, comm) = d.parts();
            let (xn, vn) = (&*xp, &*vp);
            let n = self.contributions.len();
            self.contribution_times.resize(n, 0.0);
            self.contribution_end_times.resize(n, 0.0);
            for (k, c) in self.contributions.iter_mut().enumerate() {
                let sc = Instant::now();
                c.end_of_step_distributed(t, xn, vn, at_last, &mut self.events, comm);
                let dt = sc.elapsed().as_secs_f64();
                self.contribution_times[k] += dt;
                self.contribution_end_times[k] += dt;
            }
            return;
        }
        let xn = x.as_chunks::<2>().0;
        let vn = v.as_chunks::<2>().0;
        let events = &mut self.events;
        if self.timing {
            let n = self.contributions.len();
            self.contribution_times.resize(n, 0.0);
            self.contribution_end_times.resize(n, 0.0);
            for ((c, ct), ce) in self
                .contributions
                .iter_mut()
                .zip(&mut self.contribution_times)
                .zip(&mut self.contribution_end_times)
            {
                let sc = Instant::now();
                c.end_of_step(t, xn, vn, at_last, events);
                let dt = sc.elapsed().as_secs_f64();
                *ct += dt;
                *ce += dt;
            }
        } else {
            for c in &mut self.contributions {
                c.end_of_step(t, xn, vn, at_last, events);
            }
        }
    }
}

impl crate::checkpoint::pack::Pack for StageTimers {
    fn pack(&self, e: &mut Enc) {
        e.put(&[
            self.internal_forces,
            self.external_loads,
            self.mass_damping,
            self.contributions,
            self.integration,
            self.histories,
            self.output,
        ]);
    }

    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        let t: [f64; 7] = d.get()?;
        Ok(Self {
            internal_forces: t[0],
            external_loads: t[1],
            mass_damping: t[2],
            contributions: t[3],
            integration: t[4],
            histories: t[5],
            output: t[6],
            setup: 0.0,
        })
    }
}

impl SceneSystem {
    /// Appends the system's own state to a checkpoint: the forces of the last evaluation (the
    /// reactions, the relaxation's residual and the energy books read them), the counters and
    /// timers (the stages save themselves: [`StageCheckpoint::save`]).
    pub fn save(&self, e: &mut Enc) {
        e.put(&self.force);
        e.put(&self.internal_force);
        e.put(&self.evaluated_at_end);
        e.put(&self.evaluations);
        e.put(&self.timers);
        e.put(&self.contribution_times);
        e.put(&self.contribution_end_times);
    }

    /// Takes up what [`SceneSystem::save`] wrote.
    pub fn restore(&mut self, d: &mut Dec) -> Result<(), DecodeError> {
        let n = self.force.len();
        self.force = d.vec_of_len(n, "nodal forces")?;
        let internal: Vec<[f64; 2]> = d.get()?;
        if internal.len() != self.internal_force.len() {
            return Err(d.error("the internal forces do not fit the scene's nodes"));
        }
        self.internal_force = internal;
        self.evaluated_at_end = d.get()?;
        self.evaluations = d.get()?;
        self.timers = d.get()?;
        self.contribution_times = d.get()?;
        self.contribution_end_times = d.get()?;
        Ok(())
    }
}
