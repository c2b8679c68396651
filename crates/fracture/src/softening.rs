//! The scalar laws of the joint: Munjiza's pre-peak penalty curve and the Evans-Marathe
//! post-peak softening curve `z(D)`.
//!
//! Pre-peak, with `x = o/o_p` (or `y = |s|/s_p`) in `[0, 1]`:
//!
//! ```text
//! sigma/ft = 2x - x^2            stored energy / (ft o_p) = x^2 - x^3/3
//! ```
//!
//! The initial slope is `2 ft/o_p = p/h` (with `o_p = 2 h ft/p`), the slope at the peak is 0, and
//! the work to the peak is `(2/3) ft o_p`.
//!
//! Post-peak (Evans & Marathe 1968, as fitted by Munjiza), `D` in `[0, 1]`:
//!
//! ```text
//! z(D) = [1 - (a+b-1)/(a+b) exp(D (a+c b)/((a+b)(1-a-b)))] [a (1-D) + b (1-D)^c]
//! a = 0.63, b = 1.8, c = 6.0
//! ```
//!
//! `z(0) = 1`, `z(1) = 0`, `z'(0) = 0` (a smooth join with the pre-peak curve), z decreases
//! monotonically, and `I_z = integral_0^1 z dD = 0.386307294743945`.

/// Evans-Marathe constant `a`.
pub const A: f64 = 0.63;
/// Evans-Marathe constant `b`.
pub const B: f64 = 1.8;
/// Evans-Marathe constant `c`.
pub const C: f64 = 6.0;

/// `I_z = integral_0^1 z(D) dD` (composite Simpson with 2e5 intervals, checked in the tests
/// against Gauss-Legendre quadrature to 1e-13).
pub const Z_INTEGRAL: f64 = 0.386_307_294_743_945;

/// The softening curve `z(D)`: the tensile (or shear) stress over the strength after the peak.
/// `D` is clamped to `[0, 1]`, so the result is always finite and in `[0, 1]`.
#[inline]
pub fn z(d: f64) -> f64 {
    let d = d.clamp(0.0, 1.0);
    let ab = A + B;
    let e = (d * (A + C * B) / (ab * (1.0 - ab))).exp();
    let one_minus = 1.0 - d;
    // (1-D)^6 by two squarings and a product: exact enough and much cheaper than powf.
    let q2 = one_minus * one_minus;
    let q6 = q2 * q2 * q2;
    (1.0 - (ab - 1.0) / ab * e) * (A * one_minus + B * q6)
}

/// The pre-peak stress ratio `2x - x^2` for `x = o/o_p` in `[0, 1]`.
#[inline]
pub fn pre_peak(x: f64) -> f64 {
    x * (2.0 - x)
}

/// The pre-peak stored energy ratio `x^2 - x^3/3 = integral_0^x (2u - u^2) du`; multiply by
/// `ft o_p` (or `fs s_p`) for the energy per unit joint area.
#[inline]
pub fn pre_peak_energy(x: f64) -> f64 {
    x * x * (1.0 - x / 3.0)
}

/// Work per unit area to break a joint in one pure mode, for strength `f`, peak displacement
/// `d_p` and critical displacement `d_c`: `(2/3) f d_p + I_z f (d_c - d_p)`.
#[inline]
pub fn work_to_break(f: f64, d_p: f64, d_c: f64) -> f64 {
    2.0 / 3.0 * f * d_p + Z_INTEGRAL * f * (d_c - d_p)
}

/// The softening width `d_c - d_p` that makes the work to break equal `g` exactly:
/// `(g - (2/3) f d_p)/(I_z f)`; negative when `g <= (2/3) f d_p` (the caller rejects that).
#[inline]
pub fn softening_width(g: f64, f: f64, d_p: f64) -> f64 {
    (g - 2.0 / 3.0 * f * d_p) / (Z_INTEGRAL * f)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Gauss-Legendre on `n` equal panels with 5 points each.
    fn gauss5(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let x = [
            0.0,
            -0.538_469_310_105_683_1,
            0.538_469_310_105_683_1,
            -0.906_179_845_938_664,
            0.906_179_845_938_664,
        ];
        let w = [
            0.568_888_888_888_888_9,
            0.478_628_670_499_366_5,
            0.478_628_670_499_366_5,
            0.236_926_885_056_189_1,
            0.236_926_885_056_189_1,
        ];
        let h = (b - a) / n as f64;
        let mut s = 0.0;
        for i in 0..n {
            let c = a + (i as f64 + 0.5) * h;
            for k in 0..5 {
                s += w[k] * f(c + 0.5 * h * x[k]);
            }
        }
        s * 0.5 * h
    }

    #[test]
    fn z_is_one_at_zero_and_zero_at_one() {
        assert!((z(0.0) - 1.0).abs() < 1e-15, "z(0) = {}", z(0.0));
        assert_eq!(z(1.0), 0.0);
    }

    #[test]
    fn z_has_zero_slope_at_the_peak_and_decreases() {
        // central difference slope at 0+ (one-sided): O(h) = 1e-6 * z'' ~ 1e-5 tolerance
        let h = 1e-6;
        let slope = (z(h) - z(0.0)) / h;
        assert!(slope.abs() < 1e-4, "z'(0) = {slope}");
        let mut prev = z(0.0);
        for i in 1..=10_000 {
            let v = z(i as f64 / 10_000.0);
            assert!(v <= prev, "z not monotone at D = {}", i as f64 / 1e4);
            prev = v;
        }
    }

    #[test]
    fn z_integral_is_0_386307() {
        let i = gauss5(z, 0.0, 1.0, 200);
        // Gauss-Legendre 5 points on 200 panels is exact to round-off for this smooth z.
        assert!((i - Z_INTEGRAL).abs() < 1e-13, "I_z = {i}");
        assert!((i - 0.386307).abs() < 5e-7);
    }

    #[test]
    fn pre_peak_energy_is_the_integral_of_the_curve() {
        for &x in &[0.1, 0.5, 0.9, 1.0] {
            let i = gauss5(pre_peak, 0.0, x, 4);
            assert!((i - pre_peak_energy(x)).abs() < 1e-15, "x = {x}");
        }
        assert!((pre_peak_energy(1.0) - 2.0 / 3.0).abs() < 1e-15);
        assert_eq!(pre_peak(1.0), 1.0);
    }

    #[test]
    fn softening_width_gives_the_fracture_energy_exactly() {
        let (g, f, dp) = (100.0, 5e6, 1e-6);
        let dc = dp + softening_width(g, f, dp);
        assert!((work_to_break(f, dp, dc) - g).abs() < 1e-12 * g);
    }
}
