//! Adaptive damping of a relaxation ([`AdaptiveDamping`], `integrator.relaxation:
//! "adaptive"`): mass-proportional damping `alpha = 2 omega` set after every step from the
//! Rayleigh quotient of the secant stiffness on the present displacement (Underwood's
//! adaptive dynamic relaxation, with the scene's lumped masses):
//!
//! ```text
//! omega^2 = u . K u / (u . M u),    K u = g(x_0) - g(x),    g = f + alpha M v - f_ext(t)
//! ```
//!
//! with `u = x - x_0` over the free DOFs and `g` the force without the damping and the loads
//! (elements, gravity, contact, joints): for a linear system `K u` is exactly the stiffness
//! times the displacement, and as the run settles `u` tends to the static answer, whose
//! quotient is near the lowest frequency that the load excites; `alpha = 2 omega` damps that
//! mode critically. A quotient that is not positive (no displacement yet, a softening
//! secant) keeps the last `alpha`; `alpha` is capped at `0.5 / h` (the damping's own
//! explicit limit is `alpha h < 2`). The sums run over the DOFs in their order.

use fdem_time::{SecondOrderSystem, State};

use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::run::ledger::Books;
use crate::stages::system::SceneSystem;

/// The adaptive damping of a relaxation run: the state it carries from step to step.
pub struct AdaptiveDamping {
    /// `g(x_0)` (flat DOFs).
    g0: Vec<f64>,
    /// The loads at the present time (a buffer).
    fext: Vec<f64>,
    /// The damping now [1/s].
    pub alpha: f64,
}

impl AdaptiveDamping {
    /// Adaptive damping from the initial state `state`, whose force `sys` evaluated last
    /// (undamped: the run starts with `alpha = 0`).
    pub fn new(sys: &SceneSystem, state: &State) -> Self {
        let mut fext = vec![0.0; state.x.len()];
        sys.model.add_external(state.t, &mut fext);
        let g0 = sys
            .force
            .as_flattened()
            .iter()
            .zip(&fext)
            .map(|(f, e)| f - e)
            .collect();
        Self {
            g0,
            fext,
            alpha: 0.0,
        }
    }

    /// After the step of length `h` that ended at `state` (its energy booked): the damping
    /// for the next step, set in the system and the books.
    pub fn after_step(&mut self, sys: &mut SceneSystem, state: &State, ledger: &mut Books, h: f64) {
        self.fext.fill(0.0);
        sys.model.add_external(state.t, &mut self.fext);
        let f = sys.force.as_flattened();
        let (x0, im) = (sys.model.x0.as_flattened(), sys.inv_mass());
        let (mut num, mut den) = (0.0, 0.0);
        for d in 0..f.len() {
            if im[d] > 0.0 {
                let m = 1.0 / im[d];
                let u = state.x[d] - x0[d];
                let g = f[d] + self.alpha * m * state.v[d] - self.fext[d];
                num += u * (self.g0[d] - g);
                den += m * u * u;
            }
        }
        if num > 0.0 && den > 0.0 {
            let alpha = (2.0 * (num / den).sqrt()).min(0.5 / h);
            if alpha != self.alpha {
                self.alpha = alpha;
                sys.set_alpha(alpha);
                ledger.set_alpha(alpha, &state.v);
            }
        }
    }

    /// Appends the state to a checkpoint.
    pub fn save(&self, e: &mut Enc) {
        e.put(&self.g0);
        e.put(&self.alpha);
    }

    /// Takes up what [`AdaptiveDamping::save`] wrote, for `n_dofs` DOFs, and sets the
    /// damping in `sys`.
    pub fn restore(
        &mut self,
        d: &mut Dec,
        sys: &mut SceneSystem,
        n_dofs: usize,
    ) -> Result<(), DecodeError> {
        self.g0 = d.vec_of_len(n_dofs, "adaptive damping forces")?;
        self.alpha = d.get()?;
        sys.set_alpha(self.alpha);
        Ok(())
    }
}
