//! The trait every scheme implements, its counters, and the bookkeeping the
//! schemes share (cached acceleration, prescribed DOFs, counters).

use crate::{SchemeKind, SecondOrderSystem, State, StepCost};

/// What a scheme has done since construction or [`Integrator::reset_counters`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Accepted steps.
    pub steps: u64,
    /// Calls of [`SecondOrderSystem::acceleration`], including those of the start-up, of
    /// re-evaluations after [`Integrator::invalidate`], and of the finite-difference
    /// gradient default (two per gradient).
    pub forces: u64,
    /// Calls of [`SecondOrderSystem::force_gradient`].
    pub gradients: u64,
}

/// What a scheme carries from one step to the next, as plain data: the cached acceleration
/// and its time, the counters, and a scheme's own history (Gear PC's scaled derivatives).
/// [`Integrator::save_state`] gives it; [`Integrator::restore_state`] on a scheme of the same
/// kind and size continues bit for bit (a checkpoint holds it).
#[derive(Clone, Debug, PartialEq)]
pub struct SchemeState {
    /// The acceleration buffer (for FSAL schemes the acceleration at `a_time`; for the others
    /// the last evaluation's, which the velocity extrapolation of the next step reads).
    pub a: Vec<f64>,
    /// Time at which `a` holds the acceleration of the current state, if it does.
    pub a_time: Option<f64>,
    /// Whether `a` holds an acceleration of this run.
    pub a_live: bool,
    /// The counters.
    pub counters: Counters,
    /// The scheme's own arrays (Gear PC: its scaled derivatives `r_2..r_Q`); empty for the
    /// others.
    pub history: Vec<f64>,
    /// The scheme's own numbers (Gear PC: the step `r` is scaled with, and the time at which
    /// `r` holds the derivatives of the state, NaN for none).
    pub scalars: Vec<f64>,
}

/// Why a [`SchemeState`] does not fit a scheme.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the scheme's saved state {0}")]
pub struct SchemeStateError(pub String);

/// An explicit one-step scheme for a [`SecondOrderSystem`].
///
/// The last acceleration evaluation of a step is at the final state `(t + h, x')` for
/// central difference, CHIN, OMF30 and Forest & Ruth (so a system can read its final
/// forces, e.g. platen reactions, there); for OMF32 it is at the last stage `x5` and for
/// Gear PC at the predicted state. Acceleration entries at prescribed DOFs are set to zero
/// by the scheme after every evaluation (a system can still record the reaction forces it
/// computed there).
///
/// Each implementation owns its scratch buffers, allocated once at construction for
/// `n_dofs` DOFs: a step allocates nothing. Update loops run on rayon above
/// [`crate::kernels::PAR_MIN_DOFS`] DOFs and give bit-identical results for any number of
/// threads.
///
/// Schemes that reuse the last force of a step as the first of the next one cache the
/// acceleration at `state.t`. The cache is dropped automatically when `state.t` is not the
/// time it was computed at; if anything else changes the forces between two steps
/// (positions edited by hand, a new contact list, changed material state), call
/// [`invalidate`](Self::invalidate) and the next step re-evaluates it (one extra force).
/// The cached force at the accepted state is evaluated before
/// [`SecondOrderSystem::end_of_step`] commits history; a consistent model gives the same
/// force at the same state after the commit, otherwise call `invalidate` there too.
pub trait Integrator: Send {
    /// Which scheme this is.
    fn kind(&self) -> SchemeKind;

    /// Number of DOFs the scratch buffers were sized for.
    fn n_dofs(&self) -> usize;

    /// Advances `state` from `state.t` to `state.t + h`, calling
    /// [`SecondOrderSystem::end_of_step`] once at the end.
    ///
    /// `h` must be positive and finite, and may change from one step to the next (every
    /// scheme here accepts a variable step); `state` must have [`n_dofs`](Self::n_dofs)
    /// DOFs. These are checked by the caller (the solver checks its settings once), not
    /// here: `step` is the inner loop and panics on a wrong length.
    fn step(&mut self, system: &mut dyn SecondOrderSystem, state: &mut State, h: f64);

    /// Force and gradient evaluations per step, in steady state.
    fn cost(&self) -> StepCost {
        self.kind().cost()
    }

    /// Counts since construction or the last [`reset_counters`](Self::reset_counters).
    fn counters(&self) -> Counters;

    /// Sets the counters to zero.
    fn reset_counters(&mut self);

    /// Forgets cached forces (and, for Gear PC, the higher derivatives) so that the next
    /// step starts afresh from `state`.
    fn invalidate(&mut self);

    /// What the scheme carries to its next step ([`SchemeState`]).
    fn save_state(&self) -> SchemeState;

    /// Takes up a state saved by [`save_state`](Self::save_state) on a scheme of the same
    /// kind and size: the next step is the one the saved scheme would have taken, bit for
    /// bit. A state of another size or shape is an error (the scheme is left as it was).
    fn restore_state(&mut self, s: &SchemeState) -> Result<(), SchemeStateError>;

    /// The largest stable `h omega` on the undamped oscillator (computed from the spectral
    /// radius of the one-step operator; see [`crate::stability`]).
    fn stability_limit(&self) -> f64 {
        self.kind().stability_limit()
    }
}

/// Bookkeeping shared by the schemes: cached acceleration, counters, prescribed DOFs.
#[derive(Clone, Debug)]
pub(crate) struct Core {
    /// Acceleration buffer (for FSAL schemes: the acceleration at `a_time`).
    pub a: Vec<f64>,
    /// Time at which `a` holds the acceleration of the current state, if it does.
    pub a_time: Option<f64>,
    pub counters: Counters,
    /// Whether `a` holds an acceleration of this run (for velocity extrapolation).
    pub a_live: bool,
    /// Extrapolated velocities passed to velocity-dependent forces.
    v_est: Vec<f64>,
    prescribed: Vec<usize>,
    px: Vec<f64>,
    pv: Vec<f64>,
    /// The DOFs the system moves ([`SecondOrderSystem::active_dofs`]), recorded by
    /// [`begin`](Self::begin): every DOF unless the system gives ranges.
    pub active: Vec<std::ops::Range<usize>>,
}

impl Core {
    /// The core's part of a [`SchemeState`] (the scheme adds its own history).
    pub fn save(&self) -> SchemeState {
        SchemeState {
            a: self.a.clone(),
            a_time: self.a_time,
            a_live: self.a_live,
            counters: self.counters,
            history: Vec::new(),
            scalars: Vec::new(),
        }
    }

    /// Checks that `s` fits a scheme with `history` own values and `scalars` own numbers.
    pub fn check(
        &self,
        s: &SchemeState,
        history: usize,
        scalars: usize,
    ) -> Result<(), SchemeStateError> {
        let n = self.a.len();
        if s.a.len() != n || s.history.len() != history || s.scalars.len() != scalars {
            return Err(SchemeStateError(format!(
                "has {} DOFs, {} history values and {} numbers where this scheme has {n}, {history} and {scalars}",
                s.a.len(),
                s.history.len(),
                s.scalars.len()
            )));
        }
        Ok(())
    }

    /// Takes up the core's part of `s` (checked by [`check`](Self::check)).
    pub fn restore(&mut self, s: &SchemeState) {
        self.a.copy_from_slice(&s.a);
        self.a_time = s.a_time;
        self.a_live = s.a_live;
        self.counters = s.counters;
    }

    pub fn new(n: usize) -> Self {
        Self {
            a: vec![0.0; n],
            a_time: None,
            counters: Counters::default(),
            a_live: false,
            v_est: vec![0.0; n],
            prescribed: Vec::new(),
            px: Vec::new(),
            pv: Vec::new(),
            active: std::iter::once(0..n).collect(),
        }
    }

    /// Checks sizes, records the prescribed DOFs and their values at the start of the step.
    pub fn begin(&mut self, system: &dyn SecondOrderSystem, state: &State) {
        let n = self.a.len();
        assert!(
            state.x.len() == n && state.v.len() == n && system.n_dofs() == n,
            "scheme built for {n} DOFs got a state of {} / {} and a system of {}",
            state.x.len(),
            state.v.len(),
            system.n_dofs()
        );
        self.prescribed.clear();
        self.prescribed.extend_from_slice(system.prescribed_dofs());
        self.active.clear();
        match system.active_dofs() {
            Some(r) => self.active.extend_from_slice(r),
            None => self.active.push(0..n),
        }
        self.px.clear();
        self.pv.clear();
        for &i in &self.prescribed {
            self.px.push(state.x[i]);
            self.pv.push(state.v[i]);
        }
    }

    /// Prescribed DOFs back to their values at the start of the step, then the system's
    /// prescribed motion at stage time `t`.
    pub fn constrain(
        &self,
        system: &mut dyn SecondOrderSystem,
        t: f64,
        x: &mut [f64],
        v: &mut [f64],
    ) {
        for (k, &i) in self.prescribed.iter().enumerate() {
            x[i] = self.px[k];
            v[i] = self.pv[k];
        }
        system.prescribe(t, x, v);
    }

    /// The prescribed DOF indices recorded by [`begin`](Self::begin).
    pub fn prescribed(&self) -> &[usize] {
        &self.prescribed
    }

    /// Makes sure `a` holds the acceleration at the start of the step (FSAL schemes).
    pub fn ensure_start_acceleration(
        &mut self,
        system: &mut dyn SecondOrderSystem,
        state: &mut State,
    ) {
        if self.a_time != Some(state.t) {
            self.constrain(system, state.t, &mut state.x, &mut state.v);
            self.eval(system, state.t, &state.x, &state.v);
        }
    }

    /// `a = a(t, x, v)` into the core buffer, then zero at prescribed DOFs (they do not
    /// accelerate: this also keeps them out of the finite-difference gradient's probe).
    pub fn eval(&mut self, system: &mut dyn SecondOrderSystem, t: f64, x: &[f64], v: &[f64]) {
        system.acceleration(t, x, v, &mut self.a);
        for &i in &self.prescribed {
            self.a[i] = 0.0;
        }
        self.counters.forces += 1;
        self.a_live = true;
    }

    /// Like [`eval`](Self::eval) at a stage whose position time leads the velocity
    /// variable's time by `lead` (s): a velocity-dependent system gets
    /// `v + lead a_last` (an `O(h^2)` estimate of the velocity at the stage time).
    pub fn eval_lead(
        &mut self,
        system: &mut dyn SecondOrderSystem,
        t: f64,
        x: &[f64],
        v: &[f64],
        lead: f64,
    ) {
        if lead != 0.0 && self.a_live && system.velocity_dependent() {
            for r in &self.active {
                let r = r.clone();
                crate::kernels::axpy_into(
                    &mut self.v_est[r.clone()],
                    &v[r.clone()],
                    lead,
                    &self.a[r],
                );
            }
            for &i in &self.prescribed {
                self.v_est[i] = v[i];
            }
            let v_est = std::mem::take(&mut self.v_est);
            self.eval(system, t, x, &v_est);
            self.v_est = v_est;
        } else {
            self.eval(system, t, x, v);
        }
    }

    /// `g = G(x)` given `self.a = a(t, x, v)`.
    pub fn gradient(
        &mut self,
        system: &mut dyn SecondOrderSystem,
        t: f64,
        x: &[f64],
        v: &[f64],
        g: &mut [f64],
        work: &mut crate::GradientWork,
    ) {
        system.force_gradient(t, x, v, &self.a, g, work);
        self.counters.gradients += 1;
        if !system.has_exact_gradient() {
            self.counters.forces += 2;
        }
    }

    /// Ends an accepted step: time, end-of-step hook, counters, cache time.
    pub fn finish(
        &mut self,
        system: &mut dyn SecondOrderSystem,
        state: &mut State,
        t_new: f64,
        fsal: bool,
    ) {
        state.t = t_new;
        // an FSAL step's last evaluation is at the final positions (the last constrain puts
        // the prescribed DOFs back to the same values: `prescribe` is a function of `t`)
        if fsal {
            system.end_of_step_at_last_evaluation(state.t, &state.x, &state.v);
        } else {
            system.end_of_step(state.t, &state.x, &state.v);
        }
        self.counters.steps += 1;
        self.a_time = if fsal { Some(t_new) } else { None };
    }
}
