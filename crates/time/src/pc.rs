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
//! derivatives `r_2..r_q` are owned by the scheme, in blocks of [`CHUNK`] DOFs holding one
//! contiguous array per derivative (so that the loops vectorise across DOFs and rayon
//! splits them with the positions). When `h` changes between steps they are rescaled by
//! `(h_new / h_old)^k` inside the predictor loop.
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
    /// `r_2..r_Q` in blocks of `CHUNK` DOFs: block `b` holds `r_2` of its DOFs, then `r_3`...
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

    /// Index of `r_k` of DOF `i` in the blocked layout.
    fn index(&self, i: usize, k: usize) -> usize {
        let n = self.core.a.len();
        let (b, o) = (i / CHUNK, i % CHUNK);
        let len = CHUNK.min(n - b * CHUNK);
        b * CHUNK * Self::M + (k - 2) * len + o
    }

    /// The scaled derivative `r_k = h^k / k! d^k x_i / dt^k` (`k = 2..=Q`) of DOF `i`, with
    /// `h` the step of [`scaled_derivatives_step`](Self::scaled_derivatives_step).
    pub fn scaled_derivative(&self, i: usize, k: usize) -> f64 {
        self.r[self.index(i, k)]
    }

    /// The step the stored scaled derivatives are scaled with.
    pub fn scaled_derivatives_step(&self) -> f64 {
        self.h_r
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
                let idx = self.index(i, j + 2);
                self.r[idx] = dj[i] / fact;
            }
        }
        self.h_r = 1.0;
        self.r_time = Some(t);
    }

    /// Sets the scaled derivatives of a one-DOF scheme directly, `r[k - 2] = r_k`
    /// (used to build the one-step operator).
    pub(crate) fn set_scaled_derivatives(&mut self, t: f64, h_r: f64, r: &[f64]) {
        debug_assert_eq!(self.core.a.len(), 1);
        self.r.copy_from_slice(r);
        self.h_r = h_r;
        self.r_time = Some(t);
    }

    fn start_up(&mut self, system: &mut dyn SecondOrderSystem, state: &mut State) {
        self.core
            .constrain(system, state.t, &mut state.x, &mut state.v);
        self.core.eval(system, state.t, &state.x, &state.v);
        let m = Self::M;
        for (r, a) in self.r.chunks_mut(CHUNK * m).zip(self.core.a.chunks(CHUNK)) {
            r.fill(0.0);
            for (r2, a) in r[..a.len()].iter_mut().zip(a) {
                *r2 = 0.5 * a;
            }
        }
        self.h_r = 1.0;
        self.r_time = Some(state.t);
    }
}

/// Splits a block of `r_2..r_Q` for `len` DOFs into one slice per derivative (unused
/// entries empty).
#[inline(always)]
fn split_block<const Q: usize>(r: &mut [f64], len: usize) -> [&mut [f64]; 4] {
    let (r2, rest) = r.split_at_mut(len);
    let (r3, rest) = rest.split_at_mut(len);
    let (r4, rest) = rest.split_at_mut(if Q >= 4 { len } else { 0 });
    let (r5, _) = rest.split_at_mut(if Q >= 5 { len } else { 0 });
    [r2, r3, r4, r5]
}

/// Predictor for one block: Pascal triangle on `(x, h v, r_2..r_q * scale)`.
#[inline(always)]
fn predict_chunk<const Q: usize>(
    x: &mut [f64],
    v: &mut [f64],
    r: &mut [f64],
    h: f64,
    scale: &[f64; 6],
) {
    let len = x.len();
    let v = &mut v[..len];
    let [r2, r3, r4, r5] = split_block::<Q>(r, len);
    let inv_h = 1.0 / h;
    for i in 0..len {
        let mut z = [0.0; 6];
        z[0] = x[i];
        z[1] = h * v[i];
        z[2] = r2[i] * scale[2];
        z[3] = r3[i] * scale[3];
        if Q >= 4 {
            z[4] = r4[i] * scale[4];
        }
        if Q >= 5 {
            z[5] = r5[i] * scale[5];
        }
        for j in 0..Q {
            for k in (j..Q).rev() {
                z[k] += z[k + 1];
            }
        }
        x[i] = z[0];
        v[i] = z[1] * inv_h;
        r2[i] = z[2];
        r3[i] = z[3];
        if Q >= 4 {
            r4[i] = z[4];
        }
        if Q >= 5 {
            r5[i] = z[5];
        }
    }
}

/// Corrector for one block.
#[inline(always)]
fn correct_chunk<const Q: usize>(
    x: &mut [f64],
    v: &mut [f64],
    r: &mut [f64],
    a: &[f64],
    h: f64,
    alpha: &[f64; 6],
) {
    let len = x.len();
    let (v, a) = (&mut v[..len], &a[..len]);
    let [r2, r3, r4, r5] = split_block::<Q>(r, len);
    let hh2 = 0.5 * h * h;
    let a1 = alpha[1] / h;
    for i in 0..len {
        let d = hh2 * a[i] - r2[i];
        x[i] += alpha[0] * d;
        v[i] += a1 * d;
        r2[i] += alpha[2] * d;
        r3[i] += alpha[3] * d;
        if Q >= 4 {
            r4[i] += alpha[4] * d;
        }
        if Q >= 5 {
            r5[i] += alpha[5] * d;
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
                x.chunks_mut(CHUNK)
                    .zip(v.chunks_mut(CHUNK))
                    .zip(self.r.chunks_mut(CHUNK * m))
                    .for_each(|((x, v), r)| predict_chunk::<Q>(x, v, r, h, &scale));
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
                x.chunks_mut(CHUNK)
                    .zip(v.chunks_mut(CHUNK))
                    .zip(self.r.chunks_mut(CHUNK * m))
                    .zip(a.chunks(CHUNK))
                    .for_each(|(((x, v), r), a)| correct_chunk::<Q>(x, v, r, a, h, alpha));
            }
            self.core.constrain(system, t1, x, v);
            for k in 0..self.core.prescribed().len() {
                let i = self.core.prescribed()[k];
                for d in 2..=Q {
                    let idx = self.index(i, d);
                    self.r[idx] = 0.0;
                }
            }
        }
        self.h_r = h;
        self.r_time = Some(t1);
        self.core.finish(system, state, t1, false);
    }

    core_bookkeeping!(keep_invalidate, keep_state);

    fn save_state(&self) -> crate::SchemeState {
        crate::SchemeState {
            history: self.r.clone(),
            scalars: vec![self.h_r, self.r_time.unwrap_or(f64::NAN)],
            ..self.core.save()
        }
    }

    fn restore_state(&mut self, s: &crate::SchemeState) -> Result<(), crate::SchemeStateError> {
        self.core.check(s, self.r.len(), 2)?;
        self.core.restore(s);
        self.r.copy_from_slice(&s.history);
        self.h_r = s.scalars[0];
        self.r_time = (!s.scalars[1].is_nan()).then_some(s.scalars[1]);
        Ok(())
    }

    fn invalidate(&mut self) {
        self.core.a_time = None;
        self.r_time = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::Oscillator;

    #[test]
    fn blocked_layout_gives_every_dof_the_same_result_as_a_lone_dof() {
        // n = 2 blocks + 7 DOFs of independent oscillators with different starts and exact
        // derivatives: each DOF must evolve bit for bit as the same oscillator run alone.
        let n = 2 * CHUNK + 7;
        let x0 = |i: usize| (i as f64 * 0.37).sin();
        let v0 = |i: usize| (i as f64 * 0.11).cos();
        // Derivatives of x = x0 cos t + v0 sin t: x'' = -x, x''' = -v, x'''' = x, x^(5) = v.
        let d: Vec<Vec<f64>> = vec![
            (0..n).map(|i| -x0(i)).collect(),
            (0..n).map(|i| -v0(i)).collect(),
            (0..n).map(x0).collect(),
        ];
        let dd: Vec<&[f64]> = d.iter().map(|v| &v[..]).collect();
        let mut all = Pc4::new(n);
        all.set_higher_derivatives(0.0, &dd);
        let mut sys = Oscillator::new(n, 1.0);
        let mut st = State::new(0.0, (0..n).map(x0).collect(), (0..n).map(v0).collect());
        for _ in 0..10 {
            all.step(&mut sys, &mut st, 0.1);
        }
        for i in [0, 1, CHUNK - 1, CHUNK, 2 * CHUNK, n - 1] {
            let mut one = Pc4::new(1);
            one.set_higher_derivatives(0.0, &[&[-x0(i)], &[-v0(i)], &[x0(i)]]);
            let mut s1 = State::new(0.0, vec![x0(i)], vec![v0(i)]);
            let mut sys1 = Oscillator::new(1, 1.0);
            for _ in 0..10 {
                one.step(&mut sys1, &mut s1, 0.1);
            }
            assert_eq!(st.x[i].to_bits(), s1.x[0].to_bits(), "DOF {i}");
            assert_eq!(st.v[i].to_bits(), s1.v[0].to_bits(), "DOF {i}");
            for k in 2..=4 {
                assert_eq!(
                    all.scaled_derivative(i, k).to_bits(),
                    one.scaled_derivative(0, k).to_bits()
                );
            }
        }
    }
}
