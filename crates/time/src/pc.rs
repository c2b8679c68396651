//! Gear's predictor-corrector schemes PC-3, PC-4 and PC-5 (seed Table 5.1) in Nordsieck
//! form, one force per step.
//!
//! Scaled derivatives `r_k = h^k / k! d^k x / dt^k`, `k = 0..q` (`r_0 = x`, `r_1 = h v`).
//!
//! ```text
//! predict:  r_i^p = sum_{k >= i} C(k, i) r_k                    (Pascal triangle)
//! evaluate: a = a(t + h, r_0^p, r_1^p / h)
//! mismatch: D = h^2/2 a - r_2^p
//! correct:  r_k = r_k^p + alpha_k D
//! ```
//!
//! | alpha_k | PC-3 | PC-4 | PC-5 |
//! |---|---|---|---|
//! | 0 | 1/6 | 19/120 | 3/16 |
//! | 1 | 5/6 | 3/4 | 251/360 |
//! | 2 | 1 | 1 | 1 |
//! | 3 | 1/3 | 1/2 | 11/18 |
//! | 4 | - | 1/12 | 1/6 |
//! | 5 | - | - | 1/60 |
//!
//! Positions and velocities live in the [`State`] (`r_0 = x`, `r_1 = h v`); the higher
//! derivatives `r_2..r_q` are owned by the scheme, interleaved per DOF. When `h` changes
//! between steps they are rescaled by `(h_new / h_old)^k` inside the predictor loop.
//!
//! Start-up: the first step (or the first after [`Integrator::invalidate`], or after the
//! state's time was changed) evaluates `a(t, x, v)` once and sets `r_2 = h^2/2 a`,
//! `r_3 = .. = r_q = 0`, unless exact derivatives were given with
//! [`GearPc::set_higher_derivatives`]. The zero start-up of `r_3..r_q` is itself an error
//! of the scheme's start: see `docs/time-integration.md` for what it does to the order.
//!
//! Prescribed DOFs: `r_0, r_1` come from the system's prescribed motion, `r_2..r_q` are 0.
//! Velocity passed to `a` for damping: the predicted velocity `r_1^p / h`.
//! Memory traffic per DOF-step: predictor reads and writes `x, v, r_2..r_q`, corrector the
//! same plus `a`: `(4 (q + 1) + 1) x 8` B, 136 B (PC-3), 168 B (PC-4), 200 B (PC-5).

use rayon::prelude::*;

use crate::integrator::Core;
use crate::kernels::{CHUNK, PAR_MIN_DOFS};
use crate::{Counters, Integrator, SchemeKind, SecondOrderSystem, State};

/// Gear PC of order `Q` (3, 4 or 5): the Nordsieck vector holds `r_0..r_Q`.
#[derive(Clone, Debug)]
pub struct GearPc<const Q: usize> {
    core: Core,
    /// `r_2..r_Q` per DOF: `r[i (Q - 1) + k - 2]`.
    r: Vec<f64>,
    /// The step the stored `r` are scaled with.
    h_r: f64,
    /// Time at which `r` holds the derivatives of the current state.
    r_time: Option<f64>,
    alpha: [f64; 6],
}

/// Gear PC-3 (4 values, `r_0..r_3`).
pub type Pc3 = GearPc<3>;
/// Gear PC-4 (5 values, `r_0..r_4`).
pub type Pc4 = GearPc<4>;
/// Gear PC-5 (6 values, `r_0..r_5`).
pub type Pc5 = GearPc<5>;

/// The corrector coefficients `alpha_0..alpha_q` of Table 5.1 (zero-padded to 6).
pub fn gear_alpha(q: usize) -> [f64; 6] {
    match q {
        3 => [1.0 / 6.0, 5.0 / 6.0, 1.0, 1.0 / 3.0, 0.0, 0.0],
        4 => [19.0 / 120.0, 3.0 / 4.0, 1.0, 1.0 / 2.0, 1.0 / 12.0, 0.0],
        5 => [
            3.0 / 16.0,
            251.0 / 360.0,
            1.0,
            11.0 / 18.0,
            1.0 / 6.0,
            1.0 / 60.0,
        ],
        _ => panic!("Gear PC is defined here for q = 3, 4, 5, not {q}"),
    }
}

impl<const Q: usize> GearPc<Q> {
    const M: usize = Q - 1;

    /// A scheme for `n` DOFs (allocates its buffers once).
    ///
    /// # Panics
    /// If `Q` is not 3, 4 or 5 (a compile-time choice, not user input).
    pub fn new(n: usize) -> Self {
        Self {
            core: Core::new(n),
            r: vec![0.0; n * Self::M],
            h_r: 1.0,
            r_time: None,
            alpha: gear_alpha(Q),
        }
    }

    /// Gives the scheme exact higher derivatives at time `t` instead of the default
    /// start-up: `d[j][i]` is `d^(j+2) x_i / dt^(j+2)` for `j = 0..Q-1` (so `d` holds the
    /// acceleration, then the jerk, ...). The next step must start at `state.t == t`.
    ///
    /// # Panics
    /// If `d` does not hold `Q - 1` arrays of `n_dofs` entries.
    pub fn set_higher_derivatives(&mut self, t: f64, d: &[&[f64]]) {
        let n = self.core.a.len();
        assert_eq!(
            d.len(),
            Self::M,
            "PC-{Q} needs derivatives of orders 2..={Q}"
        );
        let mut fact = 1.0;
        for (j, dj) in d.iter().enumerate() {
            assert_eq!(dj.len(), n);
            fact *= (j + 2) as f64;
            for i in 0..n {
                self.r[i * Self::M + j] = dj[i] / fact;
            }
        }
        self.h_r = 1.0;
        self.r_time = Some(t);
    }

    /// The stored scaled derivatives `r_2..r_Q` (interleaved per DOF) and the step `h`
    /// they are scaled with.
    pub fn scaled_derivatives(&self) -> (&[f64], f64) {
        (&self.r, self.h_r)
    }

    /// Sets the scaled derivatives directly (used to build the one-step operator).
    pub(crate) fn set_scaled_derivatives(&mut self, t: f64, h_r: f64, r: &[f64]) {
        self.r.copy_from_slice(r);
        self.h_r = h_r;
        self.r_time = Some(t);
    }

    fn start_up(&mut self, system: &mut dyn SecondOrderSystem, state: &mut State) {
        self.core
            .constrain(system, state.t, &mut state.x, &mut state.v);
        self.core.eval(system, state.t, &state.x, &state.v);
        let m = Self::M;
        for (r, a) in self.r.chunks_exact_mut(m).zip(&self.core.a) {
            r.fill(0.0);
            r[0] = 0.5 * a;
        }
        self.h_r = 1.0;
        self.r_time = Some(state.t);
    }
}

/// Predictor for one chunk: Pascal triangle on `(x, h v, r_2..r_q * scale)`.
#[inline(always)]
fn predict_chunk<const Q: usize>(
    x: &mut [f64],
    v: &mut [f64],
    r: &mut [f64],
    h: f64,
    scale: &[f64; 6],
) {
    let m = Q - 1;
    let inv_h = 1.0 / h;
    for ((x, v), r) in x.iter_mut().zip(v.iter_mut()).zip(r.chunks_exact_mut(m)) {
        let mut z = [0.0; 6];
        z[0] = *x;
        z[1] = h * *v;
        for k in 2..=Q {
            z[k] = r[k - 2] * scale[k];
        }
        for j in 0..Q {
            for k in (j..Q).rev() {
                z[k] += z[k + 1];
            }
        }
        *x = z[0];
        *v = z[1] * inv_h;
        r.copy_from_slice(&z[2..=Q]);
    }
}

/// Corrector for one chunk.
#[inline(always)]
fn correct_chunk<const Q: usize>(
    x: &mut [f64],
    v: &mut [f64],
    r: &mut [f64],
    a: &[f64],
    h: f64,
    alpha: &[f64; 6],
) {
    let m = Q - 1;
    let hh2 = 0.5 * h * h;
    let a1 = alpha[1] / h;
    for (((x, v), r), a) in x
        .iter_mut()
        .zip(v.iter_mut())
        .zip(r.chunks_exact_mut(m))
        .zip(a)
    {
        let d = hh2 * a - r[0];
        *x += alpha[0] * d;
        *v += a1 * d;
        for k in 2..=Q {
            r[k - 2] += alpha[k] * d;
        }
    }
}

impl<const Q: usize> Integrator for GearPc<Q> {
    fn kind(&self) -> SchemeKind {
        match Q {
            3 => SchemeKind::Pc3,
            4 => SchemeKind::Pc4,
            _ => SchemeKind::Pc5,
        }
    }

    fn n_dofs(&self) -> usize {
        self.core.a.len()
    }

    fn step(&mut self, system: &mut dyn SecondOrderSystem, state: &mut State, h: f64) {
        self.core.begin(system, state);
        if self.r_time != Some(state.t) {
            self.start_up(system, state);
        }
        let m = Self::M;
        let mut scale = [1.0; 6];
        let s = h / self.h_r;
        for k in 2..=Q {
            scale[k] = s.powi(k as i32);
        }
        let n = state.x.len();
        let t1 = state.t + h;
        {
            let State { x, v, .. } = &mut *state;
            if n >= PAR_MIN_DOFS {
                x.par_chunks_mut(CHUNK)
                    .zip(v.par_chunks_mut(CHUNK))
                    .zip(self.r.par_chunks_mut(CHUNK * m))
                    .for_each(|((x, v), r)| predict_chunk::<Q>(x, v, r, h, &scale));
            } else {
                predict_chunk::<Q>(x, v, &mut self.r, h, &scale);
            }
            self.core.constrain(system, t1, x, v);
            self.core.eval(system, t1, x, v);
            let (a, alpha) = (&self.core.a, &self.alpha);
            if n >= PAR_MIN_DOFS {
                x.par_chunks_mut(CHUNK)
                    .zip(v.par_chunks_mut(CHUNK))
                    .zip(self.r.par_chunks_mut(CHUNK * m))
                    .zip(a.par_chunks(CHUNK))
                    .for_each(|(((x, v), r), a)| correct_chunk::<Q>(x, v, r, a, h, alpha));
            } else {
                correct_chunk::<Q>(x, v, &mut self.r, a, h, alpha);
            }
            self.core.constrain(system, t1, x, v);
            for &i in self.core.prescribed() {
                self.r[i * m..(i + 1) * m].fill(0.0);
            }
        }
        self.h_r = h;
        self.r_time = Some(t1);
        self.core.finish(system, state, t1, false);
    }

    fn counters(&self) -> Counters {
        self.core.counters
    }

    fn reset_counters(&mut self) {
        self.core.counters = Counters::default();
    }

    fn invalidate(&mut self) {
        self.core.a_time = None;
        self.r_time = None;
    }
}
