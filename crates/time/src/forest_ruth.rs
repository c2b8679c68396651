//! Forest & Ruth (seed eqs 5.114-5.115): the fourth-order symplectic splitting, three
//! forces per step (FSAL).
//!
//! ```text
//! lambda = (2^(1/3) + 2^(-1/3) - 1) / 6
//! c1 = c4 = lambda + 1/2,  c2 = c3 = -lambda
//! d1 = d3 = 2 lambda + 1,  d2 = -4 lambda - 1
//! v1 = v  + c1 h a(t, x);                   x1 = x  + d1 h v1
//! v2 = v1 + c2 h a(t + d1 h, x1, v1);       x2 = x1 + d2 h v2
//! v3 = v2 + c3 h a(t + (d1 + d2) h, x2, v2); x' = x2 + d3 h v3
//! v' = v3 + c4 h a(t + h, x', v3)
//! ```
//!
//! The stage times `t + d1 h ~ t + 1.35 h` and `t + (d1 + d2) h ~ t - 0.35 h` lie outside
//! the step; the system's prescribed motion and time-dependent loads are evaluated there.
//! Velocity passed to `a` for damping: the velocity after the preceding kick extrapolated
//! to the stage's position time with the latest acceleration, `v_k + (tau_x - tau_v) h a`
//! with `tau_x = d1, d1 + d2, 1` and `tau_v = c1, c1 + c2, c1 + c2 + c3` (second order with
//! damping; see `SecondOrderSystem`).
//! Memory traffic per DOF-step: three fused kick-drift passes and one kick: 18 x 8 = 144 B.

use crate::integrator::Core;
use crate::{Counters, Integrator, SchemeKind, SecondOrderSystem, State, kernels};

/// The coefficients `(c1, c2, c3, c4, d1, d2, d3)` of Forest & Ruth.
pub fn forest_ruth_coefficients() -> [f64; 7] {
    let l = (2.0_f64.cbrt() + 1.0 / 2.0_f64.cbrt() - 1.0) / 6.0;
    [
        l + 0.5,
        -l,
        -l,
        l + 0.5,
        2.0 * l + 1.0,
        -4.0 * l - 1.0,
        2.0 * l + 1.0,
    ]
}

/// The Forest & Ruth scheme.
#[derive(Clone, Debug)]
pub struct ForestRuth {
    core: Core,
    coef: [f64; 7],
}

impl ForestRuth {
    /// A scheme for `n` DOFs (allocates its buffers once).
    pub fn new(n: usize) -> Self {
        Self {
            core: Core::new(n),
            coef: forest_ruth_coefficients(),
        }
    }
}

impl Integrator for ForestRuth {
    fn kind(&self) -> SchemeKind {
        SchemeKind::ForestRuth
    }

    fn n_dofs(&self) -> usize {
        self.core.a.len()
    }

    fn step(&mut self, system: &mut dyn SecondOrderSystem, state: &mut State, h: f64) {
        let [c1, c2, c3, c4, d1, d2, d3] = self.coef;
        let c = &mut self.core;
        c.begin(system, state);
        c.ensure_start_acceleration(system, state);
        let t = state.t;
        let (ta, tb, t1) = (t + d1 * h, t + (d1 + d2) * h, t + h);
        let State { x, v, .. } = state;
        kernels::kick_drift(v, x, &c.a, c1 * h, d1 * h);
        c.constrain(system, ta, x, v);
        c.eval_lead(system, ta, x, v, (d1 - c1) * h);
        kernels::kick_drift(v, x, &c.a, c2 * h, d2 * h);
        c.constrain(system, tb, x, v);
        c.eval_lead(system, tb, x, v, (d1 + d2 - c1 - c2) * h);
        kernels::kick_drift(v, x, &c.a, c3 * h, d3 * h);
        c.constrain(system, t1, x, v);
        c.eval_lead(system, t1, x, v, (1.0 - c1 - c2 - c3) * h);
        kernels::kick(v, &c.a, c4 * h);
        c.constrain(system, t1, x, v);
        c.finish(system, state, t1, true);
    }

    core_bookkeeping!();
}
