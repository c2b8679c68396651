//! Stress-field regressions of the static CST solve against exact elasticity solutions
//! (examples/kirsch-plate.json on a structured 100 a wide plate, brazilian-disc-elastic.json
//! and lame-cylinder.json on the Gmsh meshes in meshes/).
//!
//! A constant-strain triangle's stress is piecewise constant and noisy from element to element
//! on unstructured meshes (up to 7 % of p at the inner wall of the Lame mesh), so the field is
//! compared at sample points after a least-squares quadratic recovery over the 30 nearest
//! triangle centroids ([`common::recovered_stress`]), as one reads a FE stress field.

use crate::common;

use common::{centroids, recovered_stress};

/// Kirsch solution for a hole of radius a in a plate under uniaxial tension S along x:
/// Cartesian (sxx, syy, sxy) at (x, y).
fn kirsch(s: f64, a: f64, x: f64, y: f64) -> [f64; 3] {
    let r = (x * x + y * y).sqrt();
    let th = y.atan2(x);
    let (q2, q4) = ((a / r).powi(2), (a / r).powi(4));
    let (c2, s2) = ((2.0 * th).cos(), (2.0 * th).sin());
    let srr = 0.5 * s * (1.0 - q2) + 0.5 * s * (1.0 - 4.0 * q2 + 3.0 * q4) * c2;
    let stt = 0.5 * s * (1.0 + q2) - 0.5 * s * (1.0 + 3.0 * q4) * c2;
    let srt = -0.5 * s * (1.0 + 2.0 * q2 - 3.0 * q4) * s2;
    let (c, sn) = (th.cos(), th.sin());
    [
        srr * c * c + stt * sn * sn - 2.0 * srt * sn * c,
        srr * sn * sn + stt * c * c + 2.0 * srt * sn * c,
        (srr - stt) * sn * c + srt * (c * c - sn * sn),
    ]
}

#[test]
fn kirsch_hoop_stress_is_three_times_far_stress_and_field_matches() {
    let scene = common::edited_example("kirsch-plate.json", "kirsch", |_| {});
    let (o, _) = common::run(&scene);
    let f = &o.last_frame;
    let (s, a) = (1e6, 0.01);
    let cen = centroids(f);
    let hoop = recovered_stress(f, &cen, [0.0, a], 30)[0];
    let ratio = hoop / s;
    eprintln!("Kirsch: hoop stress at the hole top / S = {ratio:.4} (exact 3)");
    // Within 5 % of 3 S.
    assert!((ratio - 3.0).abs() < 0.15, "hoop/S = {ratio}");
    fdem_figures::record(1, format!("{ratio:.3} S"));
    // Field between 1.5 a and 3 a on a polar grid: every component within 3 % of S.
    let mut worst: f64 = 0.0;
    for i in 0..=6 {
        let r = a * (1.5 + 0.25 * i as f64);
        for j in 0..=18 {
            let th = (5.0 * j as f64).to_radians();
            let q = [r * th.cos(), r * th.sin()];
            let fe = recovered_stress(f, &cen, q, 30);
            let k = kirsch(s, a, q[0], q[1]);
            for c in 0..3 {
                worst = worst.max((fe[c] - k[c]).abs() / s);
            }
        }
    }
    eprintln!("Kirsch: largest error between 1.5 a and 3 a = {worst:.4} S");
    assert!(worst < 0.03, "largest field error {worst} S");
    fdem_figures::record(2, format!("{:.2} % of S", 100.0 * worst));
}

/// Hondros's field (radial pressure p on two arcs of half-angle alpha at the poles of the y
/// axis of a disc of radius R) at point q, by integrating over the arc the exact solution for a
/// diametral pair of point loads (two Flamant fields plus the uniform tension 2P/(pi D)):
/// returns (sxx, syy, sxy). Midpoint rule with 4000 points (converged to 1e-9 away from the
/// arcs).
fn hondros(p: f64, alpha: f64, rr: f64, q: [f64; 2]) -> [f64; 3] {
    let n = 4000;
    let mut s = [0.0; 3];
    let pi = std::f64::consts::PI;
    for k in 0..n {
        let phi = pi / 2.0 - alpha + 2.0 * alpha * (k as f64 + 0.5) / n as f64;
        let dp = p * rr * 2.0 * alpha / n as f64; // force per unit thickness of this slice
        let d = [phi.cos(), phi.sin()];
        for (pt, dir) in [
            ([rr * d[0], rr * d[1]], [-d[0], -d[1]]),
            ([-rr * d[0], -rr * d[1]], d),
        ] {
            let r = [q[0] - pt[0], q[1] - pt[1]];
            let rho = (r[0] * r[0] + r[1] * r[1]).sqrt();
            let e = [r[0] / rho, r[1] / rho];
            let cos = e[0] * dir[0] + e[1] * dir[1];
            let srr = -2.0 * dp / pi * cos / rho;
            s[0] += srr * e[0] * e[0];
            s[1] += srr * e[1] * e[1];
            s[2] += srr * e[0] * e[1];
        }
        let iso = 2.0 * dp / (pi * 2.0 * rr);
        s[0] += iso;
        s[1] += iso;
    }
    s
}

#[test]
fn brazilian_disc_matches_hondros_on_both_diameters() {
    let scene = common::edited_example("brazilian-disc-elastic.json", "hondros", |_| {});
    let (o, _) = common::run(&scene);
    let f = &o.last_frame;
    let cen = centroids(f);
    let (r, t, p, alpha) = (0.025, 0.01, 100e6, 6f64.to_radians());
    let load = 2.0 * p * r * t * alpha.sin();
    let centre = recovered_stress(f, &cen, [0.0, 0.0], 30);
    let brazil = 2.0 * load / (std::f64::consts::PI * 2.0 * r * t);
    let exact_c = hondros(p, alpha, r, [0.0, 0.0]);
    eprintln!(
        "Brazilian disc: P = {load:.1} N, centre sxx = {:.4e} Pa, 2P/(pi D t) = {brazil:.4e} Pa (ratio {:.4}), Hondros {:.4e} (ratio {:.4})",
        centre[0],
        centre[0] / brazil,
        exact_c[0],
        centre[0] / exact_c[0]
    );
    // Centre tensile stress: within 3 % of 2P/(pi D t) (the 12-degree arcs lower it by 1.3 %).
    assert!((centre[0] / brazil - 1.0).abs() < 0.03);
    fdem_figures::record(
        5,
        format!(
            "{:.4} of Hondros, {:.4} of `2P/(pi D t)`",
            centre[0] / exact_c[0],
            centre[0] / brazil
        ),
    );
    let mut worsts = [0.0; 2];
    let scale = exact_c[1].abs(); // |syy| at the centre, 3x the tensile stress
    for vertical in [false, true] {
        let mut worst: f64 = 0.0;
        for i in -16..=16 {
            let rho = i as f64 * 0.05; // up to 0.8 R: away from the loaded arcs
            let q = if vertical {
                [0.0, rho * r]
            } else {
                [rho * r, 0.0]
            };
            let st = recovered_stress(f, &cen, q, 30);
            let ex = hondros(p, alpha, r, q);
            for k in 0..3 {
                worst = worst.max((st[k] - ex[k]).abs() / scale);
            }
        }
        eprintln!(
            "Brazilian disc: {} diameter, largest error {worst:.4} of |syy(0)| within 0.8 R of the centre",
            if vertical {
                "vertical (loaded)"
            } else {
                "horizontal"
            }
        );
        // Within 3 % of the centre compressive stress along both diameters.
        assert!(worst < 0.03, "largest error {worst}");
        worsts[usize::from(vertical)] = worst;
    }
    fdem_figures::record(
        6,
        format!(
            "{:.2} % (horizontal), {:.2} % (vertical)",
            100.0 * worsts[0],
            100.0 * worsts[1]
        ),
    );
}

#[test]
fn lame_cylinder_radial_and_hoop_stresses_within_two_percent() {
    let scene = common::edited_example("lame-cylinder.json", "lame", |_| {});
    let (o, _) = common::run(&scene);
    let f = &o.last_frame;
    let cen = centroids(f);
    let (a, b, p) = (1.0, 2.0, 10e6);
    let aa = p * a * a / (b * b - a * a);
    let bb = p * a * a * b * b / (b * b - a * a);
    let (mut worst, mut wall): (f64, f64) = (0.0, 0.0);
    for i in 0..=20 {
        let r = a + (b - a) * i as f64 / 20.0;
        for j in 0..=9 {
            let th = (10.0 * j as f64).to_radians();
            let (cs, sn) = (th.cos(), th.sin());
            let st = recovered_stress(f, &cen, [r * cs, r * sn], 30);
            let srr = st[0] * cs * cs + st[1] * sn * sn + 2.0 * st[2] * sn * cs;
            let stt = st[0] * sn * sn + st[1] * cs * cs - 2.0 * st[2] * sn * cs;
            let e =
                ((srr - (aa - bb / (r * r))).abs() / p).max((stt - (aa + bb / (r * r))).abs() / p);
            if i == 0 {
                wall = wall.max(e);
            } else {
                worst = worst.max(e);
            }
        }
    }
    eprintln!(
        "Lame: largest radial/hoop error {worst:.4} of p for 1.05 a <= r <= b; {wall:.4} of p at the loaded wall r = a"
    );
    // Within 2 % of the internal pressure from 1.05 a (1.5 element sizes off the loaded wall)
    // to the outer wall. At r = a itself the recovery extrapolates one-sided into the CST
    // boundary noise (measured 5.6 %): checked loosely, within 8 %.
    assert!(worst < 0.02, "largest error {worst} p");
    assert!(wall < 0.08, "wall error {wall} p");
    fdem_figures::record(3, format!("{:.2} % of p", 100.0 * worst));
    fdem_figures::record(4, format!("{:.1} % of p", 100.0 * wall));
}
