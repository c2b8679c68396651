//! Central difference (seed eqs 5.12-5.13), with a constant or a variable step.
//!
//! The seed's form, with the velocity living at half steps, is
//!
//! ```text
//! v_{n+1/2} = v_{n-1/2} + (h_{n-1} + h_n)/2 a(x_n)        (figure 5.1: variable step)
//! x_{n+1}   = x_n + h_n v_{n+1/2}
//! ```
//!
//! which for a constant step is eqs 5.12-5.13, `v' = v + h a(x)`, `x' = x + h v'`.
//! fdem keeps velocities synchronised with positions (so that every scheme has the same
//! [`State`]), which splits the kick in two halves ("kick-drift-kick"):
//!
//! ```text
//! v_{n+1/2} = v_n + h_n/2 a(t_n, x_n, .)
//! x_{n+1}   = x_n + h_n v_{n+1/2}
//! a_{n+1}   = a(t_n + h_n, x_{n+1}, v_{n+1/2})
//! v_{n+1}   = v_{n+1/2} + h_n/2 a_{n+1}
//! ```
//!
//! The positions are exactly those of the seed's scheme started with
//! `v_{1/2} = v_0 + h_0/2 a_0`; the variable step of figure 5.1 follows by taking any `h`
//! at each call. One force per step (the end-of-step force is reused, FSAL); second order;
//! stable for `h omega < 2`.
//!
//! Velocity passed to `a` for damping: at start-up (or after [`Integrator::invalidate`])
//! `v_n`; for the force at `x_{n+1}`, `v_{n+1/2} + h/2 a_n`, which differs from `v_{n+1}`
//! by `O(h^2)` and keeps the scheme second order with damping (the half-step velocity
//! alone, as in the seed's form, makes it first order: test `damping.rs`). Systems
//! without velocity-dependent forces skip that pass
//! ([`SecondOrderSystem::velocity_dependent`]).
//!
//! Memory traffic per DOF-step: one fused kick-drift pass (reads `v, x, a`, writes `v, x`)
//! and one kick pass (reads `v, a`, writes `v`): 8 arrays of 8 bytes = 64 B.

use crate::integrator::Core;
use crate::{Counters, Integrator, SchemeKind, SecondOrderSystem, State, kernels};

/// The central difference scheme (kick-drift-kick form, variable step allowed).
#[derive(Clone, Debug)]
pub struct CentralDifference {
    core: Core,
}

impl CentralDifference {
    /// A scheme for `n` DOFs (allocates its buffers once).
    pub fn new(n: usize) -> Self {
        Self { core: Core::new(n) }
    }
}

impl Integrator for CentralDifference {
    fn kind(&self) -> SchemeKind {
        SchemeKind::CentralDifference
    }

    fn n_dofs(&self) -> usize {
        self.core.a.len()
    }

    fn step(&mut self, system: &mut dyn SecondOrderSystem, state: &mut State, h: f64) {
        let c = &mut self.core;
        c.begin(system, state);
        c.ensure_start_acceleration(system, state);
        let t1 = state.t + h;
        let State { x, v, .. } = state;
        // the system's DOFs, or its part's ranges
        for r in &c.active {
            let (v, x, a) = (&mut v[r.clone()], &mut x[r.clone()], &c.a[r.clone()]);
            kernels::kick_drift(v, x, a, 0.5 * h, h);
        }
        c.constrain(system, t1, x, v);
        system.next_evaluation_ends_step();
        c.eval_lead(system, t1, x, v, 0.5 * h);
        for r in &c.active {
            kernels::kick(&mut v[r.clone()], &c.a[r.clone()], 0.5 * h);
        }
        c.constrain(system, t1, x, v);
        c.finish(system, state, t1, true);
    }

    core_bookkeeping!();
}
