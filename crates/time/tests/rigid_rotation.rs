//! Munjiza's rigid-rotation scheme: conservation of angular momentum, the order of its
//! energy error, and the precession of a torque-free symmetric top.

use fdem_time::{RigidBody, RigidRotation, rotate};
use nalgebra::{Matrix3, Vector3};

fn body(inertia: Vector3<f64>, omega_body: Vector3<f64>) -> RigidBody {
    // A generic initial orientation.
    let axes = rotate(&Matrix3::identity(), &Vector3::new(0.3, -0.7, 0.5));
    RigidBody {
        axes,
        omega: axes * omega_body,
        inertia,
    }
}

fn slope(hs: &[f64], es: &[f64]) -> f64 {
    let n = hs.len() as f64;
    let lx: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
    let ly: Vec<f64> = es.iter().map(|e| e.ln()).collect();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

#[test]
fn torque_free_body_keeps_angular_momentum_to_round_off_and_stays_orthonormal() {
    let mut b = body(Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.3, 1.0, 0.2));
    let l0 = b.angular_momentum();
    let zero = Vector3::zeros();
    let mut worst: f64 = 0.0;
    for _ in 0..100_000 {
        RigidRotation.step(&mut b, &zero, 0.01);
        worst = worst.max((b.angular_momentum() - l0).norm() / l0.norm());
    }
    let ortho = (b.axes.transpose() * b.axes - Matrix3::identity()).norm();
    println!("angular momentum drift {worst:e}, orthonormality {ortho:e}");
    // Round-off: a few ulps per step, no O(h^p) term (which would be ~1e-4 here):
    // under 1e-15 per step over the 1e5 steps (measured 1.3e-11 in all).
    assert!(worst < 1e-15 * 1e5, "{worst}");
    assert!(ortho < 1e-12, "{ortho}");
}

fn energy_error(h: f64) -> f64 {
    // The intermediate-axis body (the hardest case): largest relative energy error over t in [0, 10].
    let mut b = body(Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.3, 1.0, 0.2));
    let e0 = b.kinetic_energy();
    let n = (10.0 / h).round() as usize;
    let mut worst: f64 = 0.0;
    for _ in 0..n {
        RigidRotation.step(&mut b, &Vector3::zeros(), h);
        worst = worst.max((b.kinetic_energy() - e0).abs() / e0);
    }
    worst
}

#[test]
fn torque_free_energy_error_falls_at_the_measured_rate() {
    let hs = [0.1, 0.05, 0.025, 0.0125];
    let es: Vec<f64> = hs.iter().map(|&h| energy_error(h)).collect();
    let p = slope(&hs, &es);
    println!("energy errors {es:?} order {p:.3}");
    // Measured: second order (slope 2.00), not the fourth of the Runge-Kutta weights:
    // averaging angular velocities taken in different frames and applying the average as
    // one rotation leaves an O(h^3) local error (the rotations do not commute).
    assert!((p - 2.0).abs() < 0.05, "order {p}");
    // And the constant: about 0.028 h^2 for this body over t = 10 (tolerance 10 %).
    assert!(es[3] < 0.03 * 0.0125 * 0.0125, "{}", es[3]);
}

/// Error of the symmetry axis of a torque-free symmetric top after time 10 (it must
/// precess uniformly about L at Omega = |L| / I1), and the relative error of the
/// precession rate measured by accumulating the angle swept about L step by step.
fn top_axis_error(h: f64) -> (f64, f64, f64) {
    let (i1, i3) = (1.0, 2.5);
    let mut b = body(Vector3::new(i1, i1, i3), Vector3::new(0.4, 0.0, 1.2));
    let l = b.angular_momentum();
    let n_hat = l.normalize();
    let rate = l.norm() / i1;
    let k0: Vector3<f64> = b.axes.column(2).into();
    let cone = k0.dot(&n_hat);
    let steps = (10.0 / h).round() as usize;
    let mut swept = 0.0;
    let mut prev = k0 - cone * n_hat;
    let mut nutation: f64 = 0.0;
    for _ in 0..steps {
        RigidRotation.step(&mut b, &Vector3::zeros(), h);
        let k: Vector3<f64> = b.axes.column(2).into();
        // The nutation angle is constant for a torque-free symmetric top.
        nutation = nutation.max((k.dot(&n_hat) - cone).abs());
        let p = k - k.dot(&n_hat) * n_hat;
        swept += prev.cross(&p).dot(&n_hat).atan2(prev.dot(&p));
        prev = p;
    }
    let t = steps as f64 * h;
    let exact = rotate(&Matrix3::from_columns(&[k0, k0, k0]), &(n_hat * (rate * t)));
    let k: Vector3<f64> = b.axes.column(2).into();
    let e = (k - Vector3::from(exact.column(0))).norm();
    (e, (swept / t - rate).abs() / rate, nutation)
}

#[test]
fn torque_free_symmetric_top_precesses_at_the_analytical_rate() {
    let hs = [0.1, 0.05, 0.025, 0.0125];
    let r: Vec<(f64, f64, f64)> = hs.iter().map(|&h| top_axis_error(h)).collect();
    let es: Vec<f64> = r.iter().map(|e| e.0).collect();
    let rate_errs: Vec<f64> = r.iter().map(|e| e.1).collect();
    let p = slope(&hs, &es);
    let q = slope(&hs, &rate_errs);
    let nut: Vec<f64> = r.iter().map(|e| e.2).collect();
    println!(
        "top axis errors {es:?} order {p:.3}; precession rate errors {rate_errs:?} order {q:.3}; nutation {nut:?}"
    );
    // The precession rate converges to |L| / I1 at second order, like the axis itself.
    assert!(
        (p - 2.0).abs() < 0.05 && (q - 2.0).abs() < 0.05,
        "orders {p}, {q}"
    );
    // Constants (measured 0.180 h^2 and 0.720 h^2, tolerance 5 %): at h = 0.0125 the rate
    // is right to 2.8e-5 relative and the axis to 1.1e-4 after t = 10.
    let h2 = hs[3] * hs[3];
    assert!(
        rate_errs[3] < 0.19 * h2 && es[3] < 0.76 * h2,
        "{rate_errs:?} {es:?}"
    );
    // The nutation angle (constant in the exact motion) wanders at third order.
    let pn = slope(&hs, &nut);
    assert!((pn - 3.0).abs() < 0.1, "nutation order {pn}");
}

#[test]
fn constant_torque_changes_angular_momentum_by_exactly_torque_times_time() {
    // dL/dt = M: after n steps L = L0 + n h M, to round-off (1e-12 relative over 1000 steps).
    let mut b = body(Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.3, 1.0, 0.2));
    let l0 = b.angular_momentum();
    let m = Vector3::new(0.1, -0.2, 0.05);
    for _ in 0..1000 {
        RigidRotation.step(&mut b, &m, 0.01);
    }
    let expected = l0 + m * 10.0;
    let err = (b.angular_momentum() - expected).norm() / expected.norm();
    assert!(err < 1e-12, "{err}");
}
