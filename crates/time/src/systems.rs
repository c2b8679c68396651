//! Small reference systems with known answers, used by the tests, the benchmarks and the
//! oscillator study: the harmonic oscillator and a linear mass-spring chain.

use rayon::prelude::*;

use crate::SecondOrderSystem;
use crate::kernels::{CHUNK, PAR_MIN_DOFS};

/// `n` independent oscillators `x'' = -omega^2 x - c v` (unit masses), with an exact
/// force-gradient product `G = 2 M^-1 J M^-1 f = -2 omega^2 a` (or the finite-difference
/// default when `exact_gradient` is false). Exact solution for `c = 0`, `x(0) = x0`,
/// `v(0) = v0`: `x = x0 cos(omega t) + v0/omega sin(omega t)`.
#[derive(Clone, Debug)]
pub struct Oscillator {
    /// Angular frequency `omega` (rad/s).
    pub omega: f64,
    /// Viscous damping rate `c` (1/s): `a = -omega^2 x - c v`.
    pub damping: f64,
    /// Use the exact gradient product (true) or the finite-difference default (false).
    pub exact_gradient: bool,
    /// Prescribed DOFs (held fixed: this system prescribes no motion).
    pub fixed: Vec<usize>,
    inv_mass: Vec<f64>,
}

impl Oscillator {
    /// `n` undamped unit-mass oscillators of angular frequency `omega`, exact gradient.
    pub fn new(n: usize, omega: f64) -> Self {
        Self {
            omega,
            damping: 0.0,
            exact_gradient: true,
            fixed: Vec::new(),
            inv_mass: vec![1.0; n],
        }
    }

    /// Total energy `sum 1/2 v^2 + 1/2 omega^2 x^2` (J, unit masses).
    pub fn energy(&self, x: &[f64], v: &[f64]) -> f64 {
        let w2 = self.omega * self.omega;
        x.iter()
            .zip(v)
            .map(|(x, v)| 0.5 * (v * v + w2 * x * x))
            .sum()
    }
}

impl SecondOrderSystem for Oscillator {
    fn n_dofs(&self) -> usize {
        self.inv_mass.len()
    }

    fn inv_mass(&self) -> &[f64] {
        &self.inv_mass
    }

    fn acceleration(&mut self, _t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        let (w2, c) = (self.omega * self.omega, self.damping);
        if c == 0.0 {
            // One streaming pass (read x, write a): the cheapest possible force.
            crate::kernels::zip_mr(a, x, |a, x| {
                for (a, x) in a.iter_mut().zip(x) {
                    *a = -w2 * x;
                }
            });
        } else {
            for ((a, x), v) in a.iter_mut().zip(x).zip(v) {
                *a = -w2 * x - c * v;
            }
        }
    }

    fn velocity_dependent(&self) -> bool {
        self.damping != 0.0
    }

    fn has_exact_gradient(&self) -> bool {
        self.exact_gradient
    }

    fn force_gradient(
        &mut self,
        t: f64,
        x: &[f64],
        v: &[f64],
        a: &[f64],
        g: &mut [f64],
        work: &mut crate::GradientWork,
    ) {
        if self.exact_gradient {
            let w2 = self.omega * self.omega;
            crate::kernels::zip_mr(g, a, |g, a| {
                for (g, a) in g.iter_mut().zip(a) {
                    *g = -2.0 * w2 * a;
                }
            });
        } else {
            crate::finite_difference_gradient(self, t, x, v, a, g, work);
        }
    }

    fn prescribed_dofs(&self) -> &[usize] {
        &self.fixed
    }
}

/// A chain of `n` equal masses `m` joined by springs `k` (DOF `i` to `i + 1`), free ends:
/// `a_i = k/m (x_{i-1} - 2 x_i + x_{i+1})` with the missing neighbours left out.
/// Positions are displacements from rest. Optionally DOF 0 is fixed and the last DOF
/// moves at a prescribed speed `end_speed` (`x = end_start + end_speed t`), like a platen.
/// Exact gradient product `G = 2 L a` with `L` the same stencil.
#[derive(Clone, Debug)]
pub struct LinearChain {
    /// Spring stiffness over mass, `k/m` (1/s^2).
    pub k_over_m: f64,
    /// Prescribed motion of the last DOF: `(start position, speed)`, with DOF 0 fixed.
    pub ends: Option<(f64, f64)>,
    inv_mass: Vec<f64>,
    prescribed: Vec<usize>,
}

impl LinearChain {
    /// A free chain of `n` unit masses with `k/m = k_over_m`.
    pub fn new(n: usize, k_over_m: f64) -> Self {
        Self {
            k_over_m,
            ends: None,
            inv_mass: vec![1.0; n],
            prescribed: Vec::new(),
        }
    }

    /// DOF 0 fixed, the last DOF moving from `start` at `speed` (m/s).
    pub fn with_ends(mut self, start: f64, speed: f64) -> Self {
        let n = self.inv_mass.len();
        self.ends = Some((start, speed));
        self.prescribed = vec![0, n - 1];
        self
    }

    /// `out = k/m L w` (the chain stencil), in parallel above the threshold.
    fn stencil(&self, w: &[f64], out: &mut [f64]) {
        let n = w.len();
        let c = self.k_over_m;
        let body = |start: usize, out: &mut [f64]| {
            for (j, o) in out.iter_mut().enumerate() {
                let i = start + j;
                let mut s = 0.0;
                if i > 0 {
                    s += w[i - 1] - w[i];
                }
                if i + 1 < n {
                    s += w[i + 1] - w[i];
                }
                *o = c * s;
            }
        };
        if n >= PAR_MIN_DOFS {
            out.par_chunks_mut(CHUNK)
                .enumerate()
                .for_each(|(b, o)| body(b * CHUNK, o));
        } else {
            body(0, out);
        }
    }

    /// Total energy `1/2 sum v^2 + 1/2 k/m sum (x_{i+1} - x_i)^2` (J, unit masses).
    pub fn energy(&self, x: &[f64], v: &[f64]) -> f64 {
        let kin: f64 = v.iter().map(|v| 0.5 * v * v).sum();
        let pot: f64 = x
            .windows(2)
            .map(|w| 0.5 * self.k_over_m * (w[1] - w[0]).powi(2))
            .sum();
        kin + pot
    }
}

impl SecondOrderSystem for LinearChain {
    fn n_dofs(&self) -> usize {
        self.inv_mass.len()
    }

    fn inv_mass(&self) -> &[f64] {
        &self.inv_mass
    }

    fn acceleration(&mut self, _t: f64, x: &[f64], _v: &[f64], a: &mut [f64]) {
        self.stencil(x, a);
    }

    fn velocity_dependent(&self) -> bool {
        false
    }

    fn has_exact_gradient(&self) -> bool {
        true
    }

    fn force_gradient(
        &mut self,
        _t: f64,
        _x: &[f64],
        _v: &[f64],
        a: &[f64],
        g: &mut [f64],
        _work: &mut crate::GradientWork,
    ) {
        self.stencil(a, g);
        for g in g.iter_mut() {
            *g *= 2.0;
        }
    }

    fn prescribed_dofs(&self) -> &[usize] {
        &self.prescribed
    }

    fn prescribe(&mut self, t: f64, x: &mut [f64], v: &mut [f64]) {
        if let Some((start, speed)) = self.ends {
            let n = x.len();
            x[0] = 0.0;
            v[0] = 0.0;
            x[n - 1] = start + speed * t;
            v[n - 1] = speed;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::LinearChain;
    use crate::{GradientWork, SecondOrderSystem, finite_difference_gradient};

    #[test]
    fn finite_difference_gradient_matches_the_exact_product_on_a_chain() {
        // Linear forces: the central difference is exact up to round-off, eps |x| / (e |a|)
        // = sqrt(eps) ~ 1.5e-8 relative to |G| with e = sqrt(eps) |x| / |a|: tolerance 1e-6.
        let n = 50;
        let mut chain = LinearChain::new(n, 3.0);
        let x: Vec<f64> = (0..n)
            .map(|i| (i as f64 * 0.7).sin() + 0.1 * i as f64)
            .collect();
        let v = vec![0.0; n];
        let mut a = vec![0.0; n];
        chain.acceleration(0.0, &x, &v, &mut a);
        let mut work = GradientWork::new(n);
        let mut exact = vec![0.0; n];
        chain.force_gradient(0.0, &x, &v, &a, &mut exact, &mut work);
        let mut fd = vec![0.0; n];
        finite_difference_gradient(&mut chain, 0.0, &x, &v, &a, &mut fd, &mut work);
        let scale = exact.iter().fold(0.0_f64, |m, g| m.max(g.abs()));
        let err = exact
            .iter()
            .zip(&fd)
            .fold(0.0_f64, |m, (e, f)| m.max((e - f).abs()));
        assert!(err <= 1e-6 * scale, "error {err} of {scale}");
    }
}
