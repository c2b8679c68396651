//! CHIN (seed eq 5.111): Chin's fourth-order force-gradient splitting, two forces and one
//! gradient per step (FSAL).
//!
//! ```text
//! v1 = v  + h/6 a(t, x)
//! x1 = x  + h/2 v1
//! v2 = v1 + 2h/3 (a(t + h/2, x1, v1) + h^2/48 G(x1))
//! x' = x1 + h/2 v2
//! v' = v2 + h/6 a(t + h, x', v2)
//! ```
//!
//! with `G = 2 M^-1 J M^-1 f` ([`SecondOrderSystem::force_gradient`]).
//! Velocity passed to `a` for damping: the velocity after the preceding kick extrapolated
//! to the stage time with the latest acceleration, `v1 + h/3 a(x)` and `v2 + h/6 a(x1)`
//! (second order with damping; see `SecondOrderSystem`).
//! Memory traffic per DOF-step: fused kick-drift (5 arrays), fused gradient-kick-drift
//! (6 arrays), kick (3 arrays): 14 x 8 = 112 B, plus the gradient product.

use crate::integrator::Core;
use crate::{Counters, GradientWork, Integrator, SchemeKind, SecondOrderSystem, State, kernels};

/// The CHIN scheme.
#[derive(Clone, Debug)]
pub struct Chin {
    core: Core,
    g: Vec<f64>,
    work: GradientWork,
}

impl Chin {
    /// A scheme for `n` DOFs (allocates its buffers once).
    pub fn new(n: usize) -> Self {
        Self {
            core: Core::new(n),
            g: vec![0.0; n],
            work: GradientWork::new(n),
        }
    }
}

impl Integrator for Chin {
    fn kind(&self) -> SchemeKind {
        SchemeKind::Chin
    }

    fn n_dofs(&self) -> usize {
        self.core.a.len()
    }

    fn step(&mut self, system: &mut dyn SecondOrderSystem, state: &mut State, h: f64) {
        let c = &mut self.core;
        c.begin(system, state);
        c.ensure_start_acceleration(system, state);
        let (th, t1) = (state.t + 0.5 * h, state.t + h);
        let State { x, v, .. } = state;
        kernels::kick_drift(v, x, &c.a, h / 6.0, 0.5 * h);
        c.constrain(system, th, x, v);
        c.eval_lead(system, th, x, v, h / 3.0);
        c.gradient(system, th, x, v, &mut self.g, &mut self.work);
        let w = 2.0 * h / 3.0;
        kernels::kick2_drift(v, x, &c.a, &self.g, w, w * h * h / 48.0, 0.5 * h);
        c.constrain(system, t1, x, v);
        c.eval_lead(system, t1, x, v, h / 6.0);
        kernels::kick(v, &c.a, h / 6.0);
        c.constrain(system, t1, x, v);
        c.finish(system, state, t1, true);
    }

    core_bookkeeping!();
}
