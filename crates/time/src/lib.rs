//! Explicit time integration for fdem: every scheme of Munjiza's chapter 5, behind one trait.
//!
//! A [`SecondOrderSystem`] is `M x'' = f(t, x, v)` with a lumped (diagonal) mass `M`, seen
//! through flat DOF slices: it evaluates `a = M^-1 f(t, x, v)`, optionally the exact
//! force-gradient product `G(x) = 2 M^-1 J M^-1 f` (`J = df/dx`; a central finite
//! difference otherwise), sets prescribed DOFs at each stage time, and commits history
//! once per accepted step in [`SecondOrderSystem::end_of_step`].
//!
//! An [`Integrator`] advances a [`State`] (`t`, `x`, `v`, velocities synchronised with
//! positions) by one step `h`. Velocity-dependent forces get the velocity extrapolated to
//! each stage's time (`v + (tau_x - tau_v) h a_last`), which keeps every scheme second
//! order with viscous damping (the lagged velocity would make the splittings first order). The schemes (one file each, coefficients in each file's docs):
//!
//! | scheme | type | forces + gradients / step | order of x (measured) | limit `h omega` (computed) |
//! |---|---|---|---|---|
//! | central difference (eqs 5.12-5.13, variable step) | [`CentralDifference`] | 1 | 2 | 2.0000 |
//! | Gear PC-3 (Table 5.1) | [`Pc3`] | 1 | 2 (4 with an exact start) | 1.4142 |
//! | Gear PC-4 | [`Pc4`] | 1 | 2 (5 with an exact start) | 0.1222 (weakly unstable at every `h`) |
//! | Gear PC-5 | [`Pc5`] | 1 | 2 (5 with an exact start) | 0.3185 |
//! | CHIN (eq 5.111) | [`Chin`] | 2 + 1 | 4 | 3.4644 |
//! | OMF30 (eq 5.112) | [`Omf30`] | 2 | 2 | 2.5531 |
//! | OMF32 (eq 5.113) | [`Omf32`] | 5 + 2 | 4 | 3.1223 |
//! | Forest & Ruth (eqs 5.114-5.115) | [`ForestRuth`] | 3 | 4 | 1.5734 |
//! | rigid rotation (eqs 5.79-5.82) | [`RigidRotation`] | 1 torque | 2 (energy, axes) | - |
//!
//! The limits are computed by [`stability::stability_limit`] from the spectral radius of
//! each scheme's one-step operator on `x'' = -x`, built by running the scheme's own code
//! (stable: amplitude growth at most 1e-6 per unit of `omega t`). Orders are those the
//! tests in `tests/convergence.rs` and `tests/rigid_rotation.rs` assert.
//! [`SchemeKind`] names the schemes for scene files (`"central-difference"`, `"pc3"`,
//! `"pc4"`, `"pc5"`, `"chin"`, `"omf30"`, `"omf32"`, `"forest-ruth"`) and builds them.
//!
//! [`RigidRotation`] is Munjiza's scheme for the 3D orientation of a rigid discrete element
//! (eqs 5.79-5.82).
//!
//! Performance: each scheme owns its scratch memory (allocated at construction, none per
//! step); its update loops are fused element-wise passes, run on rayon in fixed chunks
//! above [`kernels::PAR_MIN_DOFS`] DOFs, and bit-identical for any thread count.
//!
//! ```
//! use fdem_time::{SchemeKind, State, systems::Oscillator};
//! let mut system = Oscillator::new(1, 1.0);
//! let mut state = State::new(0.0, vec![0.0], vec![1.0]);
//! let mut scheme = "forest-ruth".parse::<SchemeKind>().unwrap().build(1);
//! for _ in 0..100 {
//!     scheme.step(&mut system, &mut state, 0.01);
//! }
//! assert!((state.x[0] - 1.0_f64.sin()).abs() < 1e-8); // 4th order: about 3e-9 here
//! assert_eq!(scheme.counters().forces, 1 + 3 * 100);
//! ```

/// The bookkeeping every scheme delegates to its `Core` (inside `impl Integrator`): the
/// evaluation counters; dropping the cached force of the last step, unless the scheme keeps
/// more history of its own (`keep_invalidate`: it writes its own `invalidate`); and its saved
/// state, the core's, unless it has history of its own (`keep_invalidate, keep_state`: it
/// writes its own `save_state` and `restore_state`).
macro_rules! core_bookkeeping {
    () => {
        core_bookkeeping!(keep_invalidate);

        fn invalidate(&mut self) {
            self.core.a_time = None;
        }
    };
    (keep_invalidate) => {
        core_bookkeeping!(keep_invalidate, keep_state);

        fn save_state(&self) -> $crate::SchemeState {
            self.core.save()
        }

        fn restore_state(
            &mut self,
            s: &$crate::SchemeState,
        ) -> Result<(), $crate::SchemeStateError> {
            self.core.check(s, 0, 0)?;
            self.core.restore(s);
            Ok(())
        }
    };
    (keep_invalidate, keep_state) => {
        fn counters(&self) -> Counters {
            self.core.counters
        }

        fn reset_counters(&mut self) {
            self.core.counters = Counters::default();
        }
    };
}

mod by_kind;
mod central_difference;
mod chin;
mod forest_ruth;
mod integrator;
pub mod kernels;
mod kind;
mod omf30;
mod omf32;
mod pc;
mod rigid_rotation;
pub mod stability;
mod state;
mod system;
pub mod systems;

pub use central_difference::CentralDifference;
pub use chin::Chin;
pub use forest_ruth::{ForestRuth, forest_ruth_coefficients};
pub use integrator::{Counters, Integrator, SchemeState, SchemeStateError};
pub use kind::{ParseSchemeError, SchemeKind, StepCost};
pub use omf30::{Omf30, omf30_lambda};
pub use omf32::{OMF32_LAMBDA, OMF32_RHO, OMF32_THETA, OMF32_VTH, OMF32_XI, Omf32};
pub use pc::{GearPc, Pc3, Pc4, Pc5, gear_alpha};
pub use rigid_rotation::{RigidBody, RigidRotation, reorthonormalise, rotate};
pub use state::State;
pub use system::{GradientWork, SecondOrderSystem, finite_difference_gradient};
