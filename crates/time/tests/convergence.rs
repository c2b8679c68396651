//! Measured order of convergence of every scheme on the oscillator `x'' = -x`,
//! `x(0) = 0`, `v(0) = 1` (exact `x = sin t`), against the orders the reference claims.
//!
//! The error measure is the largest position error over a run of `T_END = 20` (about three
//! periods): unlike the error at one instant it cannot pass near zero by chance, and its
//! slope against `h` is clean over the step ranges used (checked down to round-off).

use fdem_time::systems::Oscillator;
use fdem_time::{CentralDifference, GearPc, Integrator, SchemeKind, State};

const T_END: f64 = 20.0;

/// Largest error of `x` over `[0, T_END]` with a constant step `h` (T_END / h an integer).
fn error_at_end(scheme: &mut dyn Integrator, sys: &mut Oscillator, h: f64) -> f64 {
    let mut st = State::new(0.0, vec![0.0], vec![1.0]);
    let n = (T_END / h).round() as usize;
    let mut worst: f64 = 0.0;
    for _ in 0..n {
        scheme.step(sys, &mut st, h);
        worst = worst.max((st.x[0] - st.t.sin()).abs());
    }
    worst
}

/// Least-squares slope of log(error) against log(h).
fn slope(hs: &[f64], es: &[f64]) -> f64 {
    let n = hs.len() as f64;
    let lx: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
    let ly: Vec<f64> = es.iter().map(|e| e.ln()).collect();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

fn measured_order(kind: SchemeKind, hs: &[f64], exact_gradient: bool) -> f64 {
    let es: Vec<f64> = hs
        .iter()
        .map(|&h| {
            let mut sys = Oscillator::new(1, 1.0);
            sys.exact_gradient = exact_gradient;
            error_at_end(kind.build(1).as_mut(), &mut sys, h)
        })
        .collect();
    let p = slope(hs, &es);
    println!("{kind}: errors {es:?} order {p:.3}");
    p
}

// Step ranges: small enough to be in the asymptotic range, large enough that the errors
// stay far above round-off (1e-13 after a few hundred steps).
const H2: [f64; 4] = [0.2, 0.1, 0.05, 0.025];
const H4: [f64; 4] = [0.4, 0.2, 0.1, 0.05];

#[test]
fn central_difference_is_second_order() {
    // Tolerance 0.05 on the slope: the asymptotic constant is reached at h = 0.2 already.
    let p = measured_order(SchemeKind::CentralDifference, &H2, true);
    assert!((p - 2.0).abs() < 0.05, "order {p}");
    fdem_figures::record_part(17, 1, format!("CD {p:.2}"));
}

#[test]
fn omf30_is_second_order() {
    let p = measured_order(SchemeKind::Omf30, &H2, true);
    assert!((p - 2.0).abs() < 0.05, "order {p}");
    fdem_figures::record_part(17, 2, format!("OMF30 {p:.2}"));
}

#[test]
fn forest_ruth_is_fourth_order() {
    let p = measured_order(SchemeKind::ForestRuth, &H4, true);
    assert!((p - 4.0).abs() < 0.1, "order {p}");
    fdem_figures::record_part(17, 6, format!("F&R {p:.2}"));
}

#[test]
fn chin_is_fourth_order_with_the_reference_gradient_sign() {
    // G = +2 M^-1 J M^-1 f (the reference's sign): fourth order, as the reference claims.
    let p = measured_order(SchemeKind::Chin, &H4, true);
    assert!((p - 4.0).abs() < 0.1, "order {p}");
    fdem_figures::record_part(17, 4, format!("CHIN {p:.2}"));
}

#[test]
fn chin_with_the_finite_difference_gradient_is_fourth_order() {
    let p = measured_order(SchemeKind::Chin, &H4, false);
    assert!((p - 4.0).abs() < 0.1, "order {p}");
}

#[test]
fn omf32_is_fourth_order_with_the_reference_gradient_sign() {
    // Its error constant is tiny (4e-8 at h = 0.4): round-off is reached below h = 0.05.
    let hs = [0.4, 0.2, 0.1, 0.05];
    let p = measured_order(SchemeKind::Omf32, &hs, true);
    assert!((p - 4.0).abs() < 0.15, "order {p}");
    fdem_figures::record_part(17, 5, format!("OMF32 {p:.2}"));
    let p = measured_order(SchemeKind::Omf32, &hs, false);
    assert!(
        (p - 4.0).abs() < 0.15,
        "finite-difference gradient: order {p}"
    );
}

#[test]
fn gear_schemes_with_the_default_start_up_are_second_order() {
    // r_3..r_q start at zero: an O(h^3) error in r_3 = h^3/6 x''' that propagates to an
    // O(h^2) global error, whatever q. Measured, not nominal.
    let mut orders = Vec::new();
    for kind in [SchemeKind::Pc3, SchemeKind::Pc4, SchemeKind::Pc5] {
        let p = measured_order(kind, &[0.1, 0.05, 0.025, 0.0125], true);
        assert!((p - 2.0).abs() < 0.1, "{kind}: order {p}");
        orders.push(format!("{kind} {p:.2}"));
    }
    fdem_figures::record_part(17, 3, orders.join(", "));
}

fn gear_exact_start_order<const Q: usize>(hs: &[f64]) -> f64 {
    // Exact derivatives of sin t at 0: x'' = 0, x''' = -1, x'''' = 0, x^(5) = 1.
    let d: [[f64; 1]; 4] = [[0.0], [-1.0], [0.0], [1.0]];
    let d: Vec<&[f64]> = d[..Q - 1].iter().map(|x| &x[..]).collect();
    let es: Vec<f64> = hs
        .iter()
        .map(|&h| {
            let mut s = GearPc::<Q>::new(1);
            s.set_higher_derivatives(0.0, &d);
            error_at_end(&mut s, &mut Oscillator::new(1, 1.0), h)
        })
        .collect();
    let p = slope(hs, &es);
    println!("PC-{Q} exact start: errors {es:?} order {p:.3}");
    p
}

#[test]
fn gear_schemes_with_an_exact_start_reach_their_own_orders() {
    // Started from the exact derivatives, the position error of PC-3 falls like h^4,
    // that of PC-4 and PC-5 like h^5 (PC-4 approaches 5 from below: 4.9 at these steps).
    // The velocity error of PC-3 is one order lower (3); see docs/time-integration.md.
    let p3 = gear_exact_start_order::<3>(&[0.1, 0.05, 0.025, 0.0125]);
    assert!((p3 - 4.0).abs() < 0.1, "PC-3: order {p3}");
    let p4 = gear_exact_start_order::<4>(&[0.1, 0.05, 0.025, 0.0125]);
    assert!((p4 - 5.0).abs() < 0.2, "PC-4: order {p4}");
    let p5 = gear_exact_start_order::<5>(&[0.1, 0.05, 0.025, 0.0125]);
    assert!((p5 - 5.0).abs() < 0.15, "PC-5: order {p5}");
}

#[test]
fn variable_step_central_difference_matches_the_seed_form_and_is_second_order() {
    // Seed figure 5.1: v_{n+1/2} = v_{n-1/2} + (h_{n-1} + h_n)/2 a_n, x_{n+1} = x_n + h_n v_{n+1/2},
    // started with v_{1/2} = v_0 + h_0/2 a_0. Steps h_n = h (1 + 0.5 sin(n)) are far from
    // constant; the positions of fdem's kick-drift-kick form must agree to round-off, and
    // the error at a fixed end time must fall like h^2 as the base step halves.
    let mut errs = Vec::new();
    let mut hs = Vec::new();
    for base in [0.1, 0.05, 0.025, 0.0125] {
        let steps: Vec<f64> = (0..)
            .map(|n: i32| base * (1.0 + 0.5 * (n as f64).sin()))
            .take_while({
                let mut t = 0.0;
                move |h| {
                    t += h;
                    t < 8.0
                }
            })
            .collect();
        let mut sys = Oscillator::new(1, 1.0);
        let mut cd = CentralDifference::new(1);
        let mut st = State::new(0.0, vec![0.0], vec![1.0]);
        // Seed form.
        let (mut x, mut vh) = (0.0_f64, 1.0_f64);
        let mut h_prev = 0.0;
        for (n, &h) in steps.iter().enumerate() {
            cd.step(&mut sys, &mut st, h);
            let a = -x;
            vh += if n == 0 {
                0.5 * h * a
            } else {
                0.5 * (h_prev + h) * a
            };
            x += h * vh;
            h_prev = h;
            assert!((st.x[0] - x).abs() < 1e-13, "step {n}: {} vs {x}", st.x[0]);
        }
        errs.push((st.x[0] - st.t.sin()).abs());
        hs.push(base);
    }
    let p = slope(&hs, &errs);
    assert!(
        (p - 2.0).abs() < 0.1,
        "variable-step order {p}, errors {errs:?}"
    );
}

/// The oscillator with the gradient term's sign flipped (`G = -2 M^-1 J M^-1 f`).
struct FlippedGradient(Oscillator);

impl fdem_time::SecondOrderSystem for FlippedGradient {
    fn n_dofs(&self) -> usize {
        1
    }
    fn inv_mass(&self) -> &[f64] {
        self.0.inv_mass()
    }
    fn acceleration(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        self.0.acceleration(t, x, v, a);
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
        _w: &mut fdem_time::GradientWork,
    ) {
        g[0] = 2.0 * a[0];
    }
}

#[test]
fn the_gradient_sign_matters_flipped_it_drops_chin_and_omf32_to_second_order() {
    // Confirms that the fourth order above comes from the gradient term with the
    // reference's sign, not from the force stages alone.
    for kind in [SchemeKind::Chin, SchemeKind::Omf32] {
        let hs = [0.1, 0.05, 0.025, 0.0125];
        let es: Vec<f64> = hs
            .iter()
            .map(|&h| {
                let mut sys = FlippedGradient(Oscillator::new(1, 1.0));
                let mut st = State::new(0.0, vec![0.0], vec![1.0]);
                let mut s = kind.build(1);
                let mut worst: f64 = 0.0;
                for _ in 0..(T_END / h).round() as usize {
                    s.step(&mut sys, &mut st, h);
                    worst = worst.max((st.x[0] - st.t.sin()).abs());
                }
                worst
            })
            .collect();
        let p = slope(&hs, &es);
        assert!((p - 2.0).abs() < 0.1, "{kind} with -G: order {p}");
    }
}
