//! Long-run energy behaviour: bounded for the symplectic schemes over 10^6 steps; a steady
//! amplitude drift for Gear PC, measured and checked against its one-step operator.

use fdem_time::stability::spectral_radius;
use fdem_time::systems::Oscillator;
use fdem_time::{SchemeKind, State};

#[test]
fn symplectic_schemes_keep_the_energy_error_bounded_over_a_million_steps() {
    // h = 0.5 (a quarter of CD's limit, about a third of Forest & Ruth's): the energy
    // error oscillates at O(h^p) and must not grow: its largest value over the last
    // 100 000 steps may not exceed that over the first 100 000 by more than 1 % (+1e-13
    // for round-off, which random-walks to about 1e-14 over 10^6 steps).
    let h = 0.5;
    let mut figures = Vec::new();
    for kind in SchemeKind::ALL.into_iter().filter(|k| k.is_symplectic()) {
        let mut sys = Oscillator::new(1, 1.0);
        let mut st = State::new(0.0, vec![0.0], vec![1.0]);
        let mut s = kind.build(1);
        let e0 = sys.energy(&st.x, &st.v);
        let (mut first, mut last, mut all) = (0.0_f64, 0.0_f64, 0.0_f64);
        let n = 1_000_000;
        for i in 0..n {
            s.step(&mut sys, &mut st, h);
            let de = (sys.energy(&st.x, &st.v) - e0).abs() / e0;
            all = all.max(de);
            if i < 100_000 {
                first = first.max(de);
            }
            if i >= n - 100_000 {
                last = last.max(de);
            }
        }
        println!(
            "{kind}: relative energy error, max over first 1e5 steps {first:.3e}, last 1e5 {last:.3e}, all {all:.3e}"
        );
        assert!(
            last <= 1.01 * first + 1e-13,
            "{kind}: energy error grew from {first:e} to {last:e}"
        );
        assert!(all <= 1.01 * first + 1e-13, "{kind}");
        figures.push(format!("{kind} {all:.1e}"));
    }
    fdem_figures::record(19, figures.join(", "));
}

#[test]
fn gear_amplitude_drift_per_period_matches_the_one_step_operator() {
    // Gear PC is not symplectic: the amplitude changes by rho^(2 pi / h) per period. Over
    // 2000 periods from x = 0, v = 1 the measured amplitude drift per period (from the mean
    // of x^2 + v^2 over the first and the last 10 periods) must agree with the principal
    // eigenvalue's prediction to 0.5 % of the drift (the start-up transient of the spurious
    // roots and the window sampling are smaller than that: 0.03 % measured).
    for kind in [SchemeKind::Pc3, SchemeKind::Pc4, SchemeKind::Pc5] {
        for h in [0.2, 0.5] {
            let period = std::f64::consts::TAU;
            let periods = 2000.0;
            let mut sys = Oscillator::new(1, 1.0);
            let mut st = State::new(0.0, vec![0.0], vec![1.0]);
            let mut s = kind.build(1);
            let (mut s1, mut n1, mut s2, mut n2) = (0.0, 0.0, 0.0, 0.0);
            while st.t < periods * period {
                s.step(&mut sys, &mut st, h);
                let r2 = st.x[0] * st.x[0] + st.v[0] * st.v[0];
                if st.t <= 10.0 * period {
                    s1 += r2;
                    n1 += 1.0;
                } else if st.t > (periods - 10.0) * period {
                    s2 += r2;
                    n2 += 1.0;
                }
            }
            let measured = 0.5 * ((s2 / n2) / (s1 / n1)).ln() / (periods - 10.0);
            let predicted = spectral_radius(kind, h).ln() * period / h;
            println!(
                "{kind} h = {h}: amplitude drift per period {measured:.4e} (operator: {predicted:.4e})"
            );
            assert!(
                (measured - predicted).abs() <= 0.005 * predicted.abs(),
                "{kind} h {h}: {measured:e} vs {predicted:e}"
            );
            // PC-4 amplifies at every h; PC-5 damps below its limit 0.318 and amplifies above.
            let grows = kind == SchemeKind::Pc4 || (kind == SchemeKind::Pc5 && h > 0.32);
            let expected_sign = if grows { 1.0 } else { -1.0 };
            assert_eq!(measured.signum(), expected_sign, "{kind} h {h}");
        }
    }
}
