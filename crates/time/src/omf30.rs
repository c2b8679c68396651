//! OMF30 (seed eq 5.112): Omelyan, Mryglod and Folk's optimised second-order
//! velocity-form splitting, two forces per step (FSAL).
//!
//! ```text
//! lambda = 1/2 - (36 + 2 sqrt(326))^(1/3) / 12 + 1 / (6 (36 + 2 sqrt(326))^(1/3))  (~0.19318)
//! v1 = v  + lambda h a(t, x)
//! x1 = x  + h/2 v1
//! v2 = v1 + (1 - 2 lambda) h a(t + h/2, x1, v1)
//! x' = x1 + h/2 v2
//! v' = v2 + lambda h a(t + h, x', v2)
//! ```
//!
//! Velocity passed to `a` for damping: the velocity after the preceding kick extrapolated
//! to the stage time with the latest acceleration, `v1 + (1/2 - lambda) h a(x)` and
//! `v2 + lambda h a(x1)` (second order with damping; see `SecondOrderSystem`).
//! Memory traffic per DOF-step: two fused kick-drift passes (5 arrays each) and one kick
//! (3 arrays): 13 x 8 = 104 B.

use crate::integrator::Core;
use crate::{Counters, Integrator, SchemeKind, SecondOrderSystem, State, kernels};

/// `lambda` of OMF30, `1/2 - c/12 + 1/(6c)` with `c = (36 + 2 sqrt(326))^(1/3)`.
pub fn omf30_lambda() -> f64 {
    let c = (36.0 + 2.0 * 326.0_f64.sqrt()).cbrt();
    0.5 - c / 12.0 + 1.0 / (6.0 * c)
}

/// The OMF30 scheme.
#[derive(Clone, Debug)]
pub struct Omf30 {
    core: Core,
    lambda: f64,
}

impl Omf30 {
    /// A scheme for `n` DOFs (allocates its buffers once).
    pub fn new(n: usize) -> Self {
        Self {
            core: Core::new(n),
            lambda: omf30_lambda(),
        }
    }
}

impl Integrator for Omf30 {
    fn kind(&self) -> SchemeKind {
        SchemeKind::Omf30
    }

    fn n_dofs(&self) -> usize {
        self.core.a.len()
    }

    fn step(&mut self, system: &mut dyn SecondOrderSystem, state: &mut State, h: f64) {
        let l = self.lambda;
        let c = &mut self.core;
        c.begin(system, state);
        c.ensure_start_acceleration(system, state);
        let (th, t1) = (state.t + 0.5 * h, state.t + h);
        let State { x, v, .. } = state;
        kernels::kick_drift(v, x, &c.a, l * h, 0.5 * h);
        c.constrain(system, th, x, v);
        c.eval_lead(system, th, x, v, (0.5 - l) * h);
        kernels::kick_drift(v, x, &c.a, (1.0 - 2.0 * l) * h, 0.5 * h);
        c.constrain(system, t1, x, v);
        c.eval_lead(system, t1, x, v, l * h);
        kernels::kick(v, &c.a, l * h);
        c.constrain(system, t1, x, v);
        c.finish(system, state, t1, true);
    }

    core_bookkeeping!();
}
