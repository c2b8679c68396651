//! The time step of a run: the loaded fixed step, `n_steps` of them, or the adaptive step
//! ([`AdaptiveStep`]) up to the end time.

use fdem_time::{SchemeKind, State};

use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::input::scene::TimeStep;
use crate::problem::load::Problem;
use crate::problem::stable_step::{FrequencyTerms, stable_step};
use crate::stages::system::SceneSystem;

/// The step a run takes next, and when it has taken its last.
pub struct StepControl {
    /// The step before clipping to the end time [s].
    h: f64,
    /// Its stable limit [s].
    h_limit: f64,
    /// The step taken last [s].
    h_step: f64,
    /// The steps of a fixed-step run.
    n_steps: u64,
    /// `None`: a fixed step.
    adaptive: Option<AdaptiveStep>,
}

/// The adaptive step (`"time_step": "adaptive"`): every `every` steps the step becomes
/// `safety * h_limit(omega)` with `omega` the active bound (`stages::omega_active_ahead`:
/// the contact engaged now, or engaged at the positions extrapolated over twice the interval
/// to the next recomputation, with the elements and the joints); the last step ends at the
/// end time.
pub struct AdaptiveStep {
    every: u64,
    safety: f64,
    scheme: SchemeKind,
    z_high: f64,
    t_end: f64,
    /// The problem's frequency terms (the contact term is replaced by the stages' active ones).
    terms: FrequencyTerms,
    /// Scratch of the look-ahead positions.
    look_ahead: Vec<[f64; 2]>,
    /// The smallest and the largest step taken [s].
    h_min: f64,
    h_max: f64,
}

impl StepControl {
    /// The step of the run of `l`.
    pub fn new(l: &Problem) -> Self {
        let adaptive = (l.scene.integrator.time_step == TimeStep::Adaptive).then(|| AdaptiveStep {
            every: l.scene.integrator.adapt_every.max(1),
            safety: l.scene.integrator.safety,
            scheme: l.scheme,
            z_high: l.z_high,
            t_end: l.scene.duration.unwrap_or(0.0),
            terms: l.frequency,
            look_ahead: Vec::new(),
            h_min: f64::INFINITY,
            h_max: 0.0,
        });
        Self {
            h: l.dt,
            h_limit: l.dt_limit,
            h_step: l.dt,
            n_steps: l.n_steps,
            adaptive,
        }
    }

    /// No step is left after `steps` steps (a fixed step; an adaptive run ends on its last
    /// step, [`StepControl::is_last`]).
    pub fn done(&self, steps: u64) -> bool {
        self.adaptive.is_none() && steps >= self.n_steps
    }

    /// The step to take at `state` after `steps` steps.
    pub fn next(&mut self, sys: &mut SceneSystem, state: &State, steps: u64) -> f64 {
        let Some(a) = &mut self.adaptive else {
            return self.h;
        };
        if steps.is_multiple_of(a.every) {
            let ahead = 2.0 * a.every as f64 * self.h;
            let w = crate::stages::omega_active_ahead(
                sys,
                state.x_nodes(),
                state.v_nodes(),
                ahead,
                &a.terms,
                &mut a.look_ahead,
            );
            self.h_limit = stable_step(a.scheme, w, a.z_high);
            self.h = a.safety * self.h_limit;
            for c in &mut sys.contributions {
                c.set_time_step(self.h);
            }
        }
        self.h_step = self.h.min(a.t_end - state.t).max(f64::MIN_POSITIVE);
        a.h_min = a.h_min.min(self.h_step);
        a.h_max = a.h_max.max(self.h_step);
        self.h_step
    }

    /// The step `steps` just taken, ending at `state`, was the last: the step count, or
    /// (adaptive) the end time reached.
    pub fn is_last(&self, steps: u64, state: &State) -> bool {
        match &self.adaptive {
            Some(a) => state.t >= a.t_end * (1.0 - 1e-12),
            None => steps >= self.n_steps,
        }
    }

    /// The step taken last [s].
    pub fn h_step(&self) -> f64 {
        self.h_step
    }

    /// The stable limit of the step [s].
    pub fn h_limit(&self) -> f64 {
        self.h_limit
    }

    /// The steps planned, after `steps` steps up to time `t` (an adaptive step: estimated
    /// from the time reached).
    pub fn planned(&self, steps: u64, t: f64) -> u64 {
        match &self.adaptive {
            Some(a) => ((steps as f64) * a.t_end / t.max(f64::MIN_POSITIVE)).ceil() as u64,
            None => self.n_steps,
        }
    }

    /// An adaptive step: the smallest and the largest step taken [s].
    pub fn range(&self) -> Option<[f64; 2]> {
        self.adaptive.as_ref().map(|a| [a.h_min, a.h_max])
    }
}

impl StepControl {
    /// Appends the step's state to a checkpoint: the step, its limit, the step just taken and
    /// (adaptive) the range so far. What follows from the scene (the end, the scheme, the
    /// bounds' inputs) is not saved: a resumed run may have a later end.
    pub fn save(&self, e: &mut Enc) {
        e.put(&[self.h, self.h_limit, self.h_step]);
        e.put(&self.adaptive.as_ref().map(|a| [a.h_min, a.h_max]));
    }

    /// Takes up what [`StepControl::save`] wrote.
    pub fn restore(&mut self, d: &mut Dec) -> Result<(), DecodeError> {
        [self.h, self.h_limit, self.h_step] = d.get()?;
        let range: Option<[f64; 2]> = d.get()?;
        match (&mut self.adaptive, range) {
            (Some(a), Some([lo, hi])) => (a.h_min, a.h_max) = (lo, hi),
            (None, None) => {}
            _ => return Err(d.error("fixed and adaptive steps differ")),
        }
        Ok(())
    }

    /// The step the adaptive control chose last (what the stages were told).
    pub fn adaptive_step(&self) -> Option<f64> {
        self.adaptive.as_ref().map(|_| self.h)
    }
}
