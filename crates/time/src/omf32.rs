//! OMF32 (seed eq 5.113): Omelyan, Mryglod and Folk's eleven-stage fourth-order
//! force-gradient splitting, five forces and two gradients per step (position first, so
//! no force is shared between steps).
//!
//! ```text
//! rho = 0.6419108866816235e-01   theta  = 0.1919807940455741
//! vth = 0.1518179640276466       lambda = 0.2158369476787619
//! xi  = 0.9628905212024874e-03   s = (1 - 2 (theta + rho)) / 2
//! x1 = x  + rho h v
//! v1 = v  + vth h a(x1)
//! x2 = x1 + theta h v1
//! v2 = v1 + lambda h a(x2) + xi h^3 G(x2)
//! x3 = x2 + s h v2
//! v3 = v2 + (1 - 2 (lambda + vth)) h a(x3)
//! x4 = x3 + s h v3
//! v4 = v3 + lambda h a(x4) + xi h^3 G(x4)
//! x5 = x4 + theta h v4
//! v' = v4 + vth h a(x5)
//! x' = x5 + rho h v'
//! ```
//!
//! with `G = 2 M^-1 J M^-1 f` ([`SecondOrderSystem::force_gradient`]). Stage times:
//! `t + rho h`, `t + (rho + theta) h`, `t + h/2`, `t + (1 - rho - theta) h`, `t + (1 - rho) h`.
//! Velocity passed to `a` for damping: the velocity before the kick that uses the force
//! (`v`, `v1`, ..., `v4`) extrapolated to the stage's position time with the latest
//! acceleration (for the first stage, the last one of the previous step; none on the very
//! first step): leads `rho`, `rho + theta - vth`, `1/2 - vth - lambda`,
//! `lambda + vth - rho - theta`, `vth - rho` times `h` (second order with damping).
//! Memory traffic per DOF-step: one drift (3 arrays), three fused kick-drifts (5 each) and
//! two fused gradient-kick-drifts (6 each): 30 x 8 = 240 B, plus the gradient products.

use crate::integrator::Core;
use crate::{Counters, GradientWork, Integrator, SchemeKind, SecondOrderSystem, State, kernels};

/// `rho` of OMF32.
pub const OMF32_RHO: f64 = 0.6419108866816235e-01;
/// `theta` of OMF32.
pub const OMF32_THETA: f64 = 0.1919807940455741;
/// `vartheta` of OMF32.
pub const OMF32_VTH: f64 = 0.1518179640276466;
/// `lambda` of OMF32.
pub const OMF32_LAMBDA: f64 = 0.2158369476787619;
/// `xi` of OMF32.
pub const OMF32_XI: f64 = 0.9628905212024874e-03;

/// The OMF32 scheme.
#[derive(Clone, Debug)]
pub struct Omf32 {
    core: Core,
    g: Vec<f64>,
    work: GradientWork,
}

impl Omf32 {
    /// A scheme for `n` DOFs (allocates its buffers once).
    pub fn new(n: usize) -> Self {
        Self {
            core: Core::new(n),
            g: vec![0.0; n],
            work: GradientWork::new(n),
        }
    }
}

impl Integrator for Omf32 {
    fn kind(&self) -> SchemeKind {
        SchemeKind::Omf32
    }

    fn n_dofs(&self) -> usize {
        self.core.a.len()
    }

    fn step(&mut self, system: &mut dyn SecondOrderSystem, state: &mut State, h: f64) {
        let (rho, th, vth, lam, xi) = (OMF32_RHO, OMF32_THETA, OMF32_VTH, OMF32_LAMBDA, OMF32_XI);
        let s = 0.5 * (1.0 - 2.0 * (th + rho));
        let mid = 1.0 - 2.0 * (lam + vth);
        let c = &mut self.core;
        c.begin(system, state);
        let t = state.t;
        let times = [
            t + rho * h,
            t + (rho + th) * h,
            t + 0.5 * h,
            t + (1.0 - rho - th) * h,
            t + (1.0 - rho) * h,
            t + h,
        ];
        let State { x, v, .. } = state;
        kernels::drift(x, v, rho * h);
        c.constrain(system, times[0], x, v);
        c.eval_lead(system, times[0], x, v, rho * h);
        kernels::kick_drift(v, x, &c.a, vth * h, th * h);
        c.constrain(system, times[1], x, v);
        c.eval_lead(system, times[1], x, v, (rho + th - vth) * h);
        c.gradient(system, times[1], x, v, &mut self.g, &mut self.work);
        kernels::kick2_drift(v, x, &c.a, &self.g, lam * h, xi * h * h * h, s * h);
        c.constrain(system, times[2], x, v);
        c.eval_lead(system, times[2], x, v, (0.5 - vth - lam) * h);
        kernels::kick_drift(v, x, &c.a, mid * h, s * h);
        c.constrain(system, times[3], x, v);
        c.eval_lead(system, times[3], x, v, (lam + vth - rho - th) * h);
        c.gradient(system, times[3], x, v, &mut self.g, &mut self.work);
        kernels::kick2_drift(v, x, &c.a, &self.g, lam * h, xi * h * h * h, th * h);
        c.constrain(system, times[4], x, v);
        c.eval_lead(system, times[4], x, v, (vth - rho) * h);
        kernels::kick_drift(v, x, &c.a, vth * h, rho * h);
        c.constrain(system, times[5], x, v);
        c.finish(system, state, times[5], false);
    }

    core_bookkeeping!(keep_invalidate);

    fn invalidate(&mut self) {
        self.core.a_time = None;
        self.core.a_live = false;
    }
}
