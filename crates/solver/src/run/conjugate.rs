//! Conjugate-gradient relaxation ([`ConjugateGradient`], `integrator.relaxation:
//! "conjugate-gradient"`): in place of the scheme's step, one iteration of a nonlinear
//! conjugate-gradient minimisation of the total potential energy, preconditioned by the
//! relaxation's lumped masses (Jacobi), with the velocities kept at zero.
//!
//! With `f` the force at the present state (free DOFs) and `z = M^-1 f` (zero at the
//! constrained DOFs), an iteration
//!
//! ```text
//! beta  = max(0, z . (f - f_prev) / (z_prev . f_prev))      (Polak-Ribiere+)
//! p     = z + beta p_prev          (p = z at the start, when beta <= 0, or when f . p <= 0)
//! f_1   = f(t, x + a_t p)          (trial, no history committed)
//! alpha = a_t (f . p) / (f . p - f_1 . p)                   (secant: exact for a quadratic)
//! x    <- x + alpha p,  t <- t + h
//! ```
//!
//! with `a_t` the last accepted `alpha` (at first `h^2`: for `p = M^-1 f` the move of the
//! pseudo-dynamics' step from rest). A denominator that is not positive (no positive
//! curvature along `p`) takes `alpha = a_t` and restarts with `p = z`. The new state's force
//! is evaluated at `t + h` (prescribed DOFs set there) and its history committed as at the
//! end of a step of the central difference; two force evaluations per iteration.
//!
//! The iteration is not dynamics: the energy it takes out (the ledger's error after the
//! iteration less the level the books hold) is booked as damping (`mass_damping`). For a
//! conservative scene that is the decrease of the total potential, which a minimiser's
//! iteration never raises: the largest rise of one iteration is kept (a round-off size rise
//! only). The dot products run over the DOFs in their order (no reduction that depends on the
//! threads); the buffers are allocated once.

use fdem_time::{SecondOrderSystem, State};

use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::run::ledger::Books;
use crate::stages::summed_report;
use crate::stages::system::SceneSystem;

/// The conjugate-gradient relaxation: the state it carries from iteration to iteration.
pub struct ConjugateGradient {
    /// The search direction (zero at the constrained DOFs).
    p: Vec<f64>,
    /// The force at the start of the last iteration (all DOFs).
    f_prev: Vec<f64>,
    /// `z_prev . f_prev` of the last iteration.
    zf_prev: f64,
    /// Trial positions (a buffer).
    trial: Vec<f64>,
    /// The last accepted step length (the next trial's).
    alpha: f64,
    /// The next direction is the steepest descent `z` (start, restart).
    fresh: bool,
    /// The ledger's error that the books hold (what each iteration's booking keeps).
    level: f64,
    /// Restarts so far (a direction reset to `z`).
    pub restarts: u64,
    /// Force evaluations of the iterations so far (two each: the trial and the new state).
    pub evaluations: u64,
    /// Energy taken out so far [J].
    pub removed: f64,
    /// The largest rise of the total potential in one iteration [J] (0: none rose).
    pub largest_rise: f64,
}

impl ConjugateGradient {
    /// The minimiser for a run at `state` with step `h`, whose force `sys` evaluated last and
    /// whose books `ledger` are open.
    pub fn new(sys: &SceneSystem, state: &State, ledger: &Books, h: f64) -> Self {
        let mut c = Self::sized(state.x.len(), h);
        c.level = ledger
            .ledger(sys, state, summed_report(sys, state.x_nodes()).as_ref())
            .error;
        c
    }

    /// The minimiser for `n` DOFs and step `h`, at its start, before the books' level is
    /// known (a resumed run restores it).
    pub fn sized(n: usize, h: f64) -> Self {
        Self {
            p: vec![0.0; n],
            f_prev: vec![0.0; n],
            zf_prev: 0.0,
            trial: vec![0.0; n],
            alpha: h * h,
            fresh: true,
            level: 0.0,
            restarts: 0,
            evaluations: 0,
            removed: 0.0,
            largest_rise: 0.0,
        }
    }

    /// One iteration from `state` (whose force `sys` holds) to the time `state.t + h`.
    pub fn iterate(&mut self, sys: &mut SceneSystem, state: &mut State, h: f64) {
        let constrained = &sys.model.constrained;
        for (v, c) in state.v.iter_mut().zip(constrained) {
            if !c {
                *v = 0.0;
            }
        }
        let s0 = self.direction(sys);
        let t = state.t;
        let mut step = 0.0;
        if s0 > 0.0 {
            let a_t = self.alpha;
            for ((y, x), p) in self.trial.iter_mut().zip(&state.x).zip(&self.p) {
                *y = x + a_t * p;
            }
            sys.evaluate(t, &self.trial, &state.v);
            self.evaluations += 1;
            let s1 = dot(sys.force.as_flattened(), &self.p);
            let den = s0 - s1;
            let curved = den > 0.0;
            step = if curved {
                a_t * (s0 / den)
            } else {
                // no positive curvature along p: the trial's length, and a restart
                a_t
            };
            if !curved || !step.is_finite() {
                self.fresh = true;
                self.restarts += 1;
            }
            if step.is_finite() && step > 0.0 {
                self.alpha = step;
            } else {
                step = 0.0;
            }
        }
        let constrained = &sys.model.constrained;
        for ((x, p), c) in state.x.iter_mut().zip(&self.p).zip(constrained) {
            if !c {
                *x += step * p;
            }
        }
        let t1 = t + h;
        sys.prescribe(t1, &mut state.x, &mut state.v);
        sys.next_evaluation_ends_step();
        sys.evaluate(t1, &state.x, &state.v);
        self.evaluations += 1;
        state.t = t1;
        sys.end_of_step_at_last_evaluation(t1, &state.x, &state.v);
    }

    /// The search direction at the present force (kept in `p`); returns `f . p`.
    fn direction(&mut self, sys: &SceneSystem) -> f64 {
        let f = sys.force.as_flattened();
        let im = sys.inv_mass();
        let mut zf = 0.0;
        let mut num = 0.0;
        for d in 0..f.len() {
            let z = im[d] * f[d];
            zf += z * f[d];
            num += z * (f[d] - self.f_prev[d]);
        }
        let beta = if self.fresh || self.zf_prev <= 0.0 {
            0.0
        } else {
            num / self.zf_prev
        };
        // Polak-Ribiere+: a beta that is not positive restarts
        let conjugate = beta > 0.0;
        let beta = if conjugate { beta } else { 0.0 };
        let mut s0 = 0.0;
        for d in 0..f.len() {
            self.p[d] = im[d] * f[d] + beta * self.p[d];
            s0 += f[d] * self.p[d];
        }
        let mut restarted = !self.fresh && !conjugate;
        let descent = s0 > 0.0;
        if conjugate && !descent {
            // not a descent direction
            for d in 0..f.len() {
                self.p[d] = im[d] * f[d];
            }
            s0 = zf;
            restarted = true;
        }
        if restarted {
            self.restarts += 1;
        }
        self.f_prev.copy_from_slice(f);
        self.zf_prev = zf;
        self.fresh = false;
        s0
    }

    /// After the iteration that ended at `state` (its step booked): the energy it took out
    /// booked as damping.
    pub fn book(&mut self, sys: &SceneSystem, state: &State, ledger: &mut Books) {
        let after = ledger
            .ledger(sys, state, summed_report(sys, state.x_nodes()).as_ref())
            .error;
        let removed = after - self.level;
        ledger.book_removed(removed);
        self.removed += removed;
        self.largest_rise = self.largest_rise.max(-removed);
    }

    /// Appends the state to a checkpoint.
    pub fn save(&self, e: &mut Enc) {
        e.put(&self.p);
        e.put(&self.f_prev);
        e.put(&[self.zf_prev, self.alpha, self.level]);
        e.put(&self.fresh);
        e.put(&[self.restarts, self.evaluations]);
        e.put(&[self.removed, self.largest_rise]);
    }

    /// Takes up what [`ConjugateGradient::save`] wrote, for `n_dofs` DOFs.
    pub fn restore(&mut self, d: &mut Dec, n_dofs: usize) -> Result<(), DecodeError> {
        self.p = d.vec_of_len(n_dofs, "conjugate-gradient direction")?;
        self.f_prev = d.vec_of_len(n_dofs, "conjugate-gradient forces")?;
        [self.zf_prev, self.alpha, self.level] = d.get()?;
        self.fresh = d.get()?;
        [self.restarts, self.evaluations] = d.get()?;
        [self.removed, self.largest_rise] = d.get()?;
        Ok(())
    }
}

/// `a . b` over the DOFs in their order.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut s = 0.0;
    for (x, y) in a.iter().zip(b) {
        s += x * y;
    }
    s
}
