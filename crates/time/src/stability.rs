//! Stability limits computed from the spectral radius of each scheme's one-step operator.
//!
//! On the undamped oscillator `x'' = -x` (`omega = 1`) every scheme here is linear: one step
//! maps the scheme's state (`(x, v)` for the splittings, `(x, v, r_2..r_q)` for Gear PC) by
//! a matrix `T(h)`. This module builds `T(h)` column by column by running the scheme's own
//! code on basis states, so the limits are those of the code, not of a formula.
//!
//! A step is stable when the amplitude it leaves grows no faster than `GROWTH_TOL` = 1e-6
//! per unit of `omega t`: `rho(T(h)) <= 1 + GROWTH_TOL h`. Over a long run of `omega t` =
//! 1e6 (10^6 steps near the limit) that is at most a factor `e`. Why a growth tolerance
//! and not `rho <= 1`:
//! - Gear PC-4 has `rho - 1 ~ 3.7e-8 (h/0.1)^6 > 0` at *every* `h` (weakly unstable) and
//!   PC-5 becomes weakly unstable above `h ~ 0.32`: "rho <= 1" would give PC-4 no stable
//!   step at all, and a limit set by round-off for the other.
//! - For the symplectic splittings `rho = 1` exactly inside the stable interval; past it
//!   `rho` rises like `sqrt(h - h*)` (central difference, OMF30, OMF32, Forest & Ruth),
//!   so the tolerance moves the limit by about 1e-12; for CHIN the trace touches -2
//!   almost tangentially at `h* = 2 sqrt(3)` and `rho` rises slowly, so its limit lies a
//!   little above `2 sqrt(3)` (see the tests).
//!
//! The limit is the smallest `h` where stability fails, found by a scan in steps of 1e-3
//! and bisection to 1e-12. Some schemes are stable again in windows above it (OMF32 just
//! above its limit, PC-4 near `h = 1.1`): the limit is the first failure.

use std::sync::OnceLock;

use nalgebra::DMatrix;

use crate::systems::Oscillator;
use crate::{GearPc, Integrator, SchemeKind, State};

/// Growth tolerance per unit of `omega t`: a step `h` is stable while
/// `rho(T(h)) <= 1 + GROWTH_TOL h`.
pub const GROWTH_TOL: f64 = 1e-6;

fn gear_operator<const Q: usize>(h: f64) -> DMatrix<f64> {
    let dim = Q + 1;
    let mut t = DMatrix::zeros(dim, dim);
    let mut sys = Oscillator::new(1, 1.0);
    for j in 0..dim {
        let mut e = vec![0.0; dim];
        e[j] = 1.0;
        let mut scheme = GearPc::<Q>::new(1);
        scheme.set_scaled_derivatives(0.0, h, &e[2..]);
        let mut state = State::new(0.0, vec![e[0]], vec![e[1]]);
        scheme.step(&mut sys, &mut state, h);
        t[(0, j)] = state.x[0];
        t[(1, j)] = state.v[0];
        for k in 2..dim {
            t[(k, j)] = scheme.scaled_derivative(0, k);
        }
    }
    t
}

/// The one-step operator `T(h)` of `kind` on `x'' = -x`: a 2 x 2 matrix on `(x, v)`, or
/// `(q + 1) x (q + 1)` on `(x, v, r_2..r_q)` for Gear PC-q.
pub fn one_step_operator(kind: SchemeKind, h: f64) -> DMatrix<f64> {
    match kind {
        SchemeKind::Pc3 => gear_operator::<3>(h),
        SchemeKind::Pc4 => gear_operator::<4>(h),
        SchemeKind::Pc5 => gear_operator::<5>(h),
        _ => {
            let mut t = DMatrix::zeros(2, 2);
            let mut sys = Oscillator::new(1, 1.0);
            for j in 0..2 {
                let mut scheme = kind.build(1);
                let mut state = State::new(
                    0.0,
                    vec![if j == 0 { 1.0 } else { 0.0 }],
                    vec![if j == 1 { 1.0 } else { 0.0 }],
                );
                scheme.step(&mut sys, &mut state, h);
                t[(0, j)] = state.x[0];
                t[(1, j)] = state.v[0];
            }
            t
        }
    }
}

/// The spectral radius `rho(T(h))` (largest eigenvalue modulus) of `kind` on `x'' = -x`.
pub fn spectral_radius(kind: SchemeKind, h: f64) -> f64 {
    let t = one_step_operator(kind, h);
    if t.nrows() == 2 {
        // Closed form, accurate near the double root at the limit.
        let tr = t[(0, 0)] + t[(1, 1)];
        let det = t[(0, 0)] * t[(1, 1)] - t[(0, 1)] * t[(1, 0)];
        let disc = 0.25 * tr * tr - det;
        if disc < 0.0 {
            det.abs().sqrt()
        } else {
            0.5 * tr.abs() + disc.sqrt()
        }
    } else {
        t.complex_eigenvalues()
            .iter()
            .map(|z| z.norm())
            .fold(0.0, f64::max)
    }
}

impl SchemeKind {
    /// The largest stable `h omega` on the undamped oscillator, computed from the spectral
    /// radius of the one-step operator ([`stability_limit`]); computed once per process and
    /// cached.
    pub fn stability_limit(self) -> f64 {
        static LIMITS: OnceLock<[f64; 8]> = OnceLock::new();
        let limits = LIMITS.get_or_init(|| Self::ALL.map(stability_limit));
        limits[Self::ALL.iter().position(|k| *k == self).expect("in ALL")]
    }
}

/// Whether step `h` is unstable on `x'' = -x`: `rho(T(h)) > 1 + GROWTH_TOL h`.
pub fn is_unstable(kind: SchemeKind, h: f64) -> bool {
    spectral_radius(kind, h) > 1.0 + GROWTH_TOL * h
}

/// The largest stable `h omega`: the smallest `h` where [`is_unstable`] holds (scan by 1e-3
/// from 1e-3, then bisection), or `f64::INFINITY` if none below 20.
pub fn stability_limit(kind: SchemeKind) -> f64 {
    let unstable = |h: f64| is_unstable(kind, h);
    let dh = 1e-3;
    let mut lo = 0.0;
    let mut hi = dh;
    while !unstable(hi) {
        lo = hi;
        hi += dh;
        if hi > 20.0 {
            return f64::INFINITY;
        }
    }
    while hi - lo > 1e-12 {
        let mid = 0.5 * (lo + hi);
        if unstable(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo
}

/// The windows of `h omega` above [`stability_limit`] and below `h_max` where `kind` is stable
/// again, each as `[first stable, first unstable after it]` (scan by 1e-3, edges by bisection
/// to 1e-9; a window narrower than the scan step can be missed). Empty for a scheme whose
/// stable set is the interval `(0, limit]`: for such a scheme a step that keeps the highest
/// mode of a system stable keeps every mode stable. For one with windows (OMF32: unstable in
/// `[3.122, 3.160]`, stable again up to 5.69) a step past the limit can leave the highest
/// modes in a window and lower modes in the unstable band below it: a stability check of
/// such a step must excite the middle of the spectrum, not only its top.
pub fn stable_windows(kind: SchemeKind, h_max: f64) -> Vec<[f64; 2]> {
    let unstable = |h: f64| is_unstable(kind, h);
    let edge = |mut lo: f64, mut hi: f64, lo_unstable: bool| {
        // the point where the verdict changes between lo (verdict lo_unstable) and hi
        while hi - lo > 1e-9 {
            let mid = 0.5 * (lo + hi);
            if unstable(mid) == lo_unstable {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    };
    let dh = 1e-3;
    let mut windows = Vec::new();
    let mut h = stability_limit(kind);
    if !h.is_finite() {
        return windows;
    }
    let mut start: Option<f64> = None;
    let mut was_unstable = true;
    while h < h_max {
        let next = h + dh;
        let u = unstable(next);
        if u != was_unstable {
            let e = edge(h, next, was_unstable);
            match start.take() {
                None => start = Some(e),
                Some(s) => windows.push([s, e]),
            }
            was_unstable = u;
        }
        h = next;
    }
    if let Some(s) = start {
        windows.push([s, h_max]);
    }
    windows
}
