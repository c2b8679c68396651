//! Verification of the triangle-triangle potential contact force against known answers:
//! conservation laws, an independent area integral, the energy gradient, the flat-overlap
//! stiffness, and robustness at deep penetration and degenerate input.

use crate::common;
use common::{Rng, area, cross, random_triangle};
use fdem_contact::potential_tri_tri::{
    TriPotential, overlap_area, pair_energy, pair_force_area, pair_normal_force,
};

/// Random overlapping pairs of random sizes and orientations.
type Tri = [[f64; 2]; 3];

fn random_pairs(seed: u64, n: usize) -> Vec<(Tri, Tri)> {
    let mut rng = Rng(seed);
    let mut out = Vec::new();
    while out.len() < n {
        let s1 = rng.range(0.3, 2.0);
        let s2 = rng.range(0.3, 2.0);
        let c = random_triangle(&mut rng, [0.0, 0.0], s1);
        let d = rng.range(0.0, 1.2) * (s1 + s2);
        let a = rng.range(0.0, std::f64::consts::TAU);
        let t = random_triangle(&mut rng, [d * a.cos(), d * a.sin()], s2);
        if overlap_area(&c, &t) > 1e-6 * (s1 * s2) {
            out.push((c, t));
        }
    }
    out
}

#[test]
fn momentum_and_angular_momentum_sum_to_round_off_on_random_pairs() {
    // Tolerance: 1e-14 of the largest nodal force (theory: exact up to round-off).
    let (mut worst_f, mut worst_m): (f64, f64) = (0.0, 0.0);
    for (c, t) in random_pairs(1, 500) {
        let f = pair_normal_force(&c, &t, 1.0);
        let x = [c[0], c[1], c[2], t[0], t[1], t[2]];
        let fmax = f.iter().map(|g| g[0].hypot(g[1])).fold(0.0, f64::max);
        let xmax = x.iter().map(|g| g[0].hypot(g[1])).fold(0.0, f64::max);
        assert!(fmax > 0.0);
        let sx: f64 = f.iter().map(|g| g[0]).sum();
        let sy: f64 = f.iter().map(|g| g[1]).sum();
        let m: f64 = (0..6).map(|k| cross(x[k], f[k])).sum();
        assert!(
            sx.abs() < 1e-14 * fmax && sy.abs() < 1e-14 * fmax,
            "{sx} {sy} {fmax}"
        );
        assert!(
            m.abs() < 1e-14 * fmax * xmax,
            "torque {m} vs {}",
            fmax * xmax
        );
        worst_f = worst_f.max(sx.abs().max(sy.abs()) / fmax);
        worst_m = worst_m.max(m.abs() / (fmax * xmax));
    }
    fdem_figures::record(27, format!("{worst_f:.1e}, {worst_m:.1e}"));
}

#[test]
fn edge_integral_equals_independent_area_integral() {
    // The force on c from the closed-form edge integral equals the area integral of
    // p (grad phi_c - grad phi_t) over the clipped 3x3 sub-triangle pieces, to 1e-10 relative.
    for (c, t) in random_pairs(2, 500) {
        let f = pair_normal_force(&c, &t, 7.0);
        let fc = [f[0][0] + f[1][0] + f[2][0], f[0][1] + f[1][1] + f[2][1]];
        let fa = pair_force_area(&c, &t, 7.0);
        let scale = fa[0]
            .hypot(fa[1])
            .max(f.iter().map(|g| g[0].hypot(g[1])).fold(0.0, f64::max));
        let err = (fc[0] - fa[0]).hypot(fc[1] - fa[1]);
        assert!(err <= 1e-10 * scale, "edge {fc:?} area {fa:?}");
    }
}

#[test]
fn pair_energy_matches_fine_grid_quadrature() {
    // Midpoint quadrature of p (phi_c + phi_t) on a 1000 x 1000 grid over the overlap's box:
    // the integrand is continuous and piecewise linear, the cut cells give an O(h) error
    // (~1e-3 relative); the exact decomposition must agree within 3e-3.
    for (c, t) in random_pairs(3, 5) {
        let (pc, pt) = (TriPotential::new(c).unwrap(), TriPotential::new(t).unwrap());
        let xs: Vec<f64> = c.iter().chain(t.iter()).map(|p| p[0]).collect();
        let ys: Vec<f64> = c.iter().chain(t.iter()).map(|p| p[1]).collect();
        let (x0, x1) = (
            xs.iter().cloned().fold(f64::MAX, f64::min),
            xs.iter().cloned().fold(f64::MIN, f64::max),
        );
        let (y0, y1) = (
            ys.iter().cloned().fold(f64::MAX, f64::min),
            ys.iter().cloned().fold(f64::MIN, f64::max),
        );
        let n = 1000;
        let (hx, hy) = ((x1 - x0) / n as f64, (y1 - y0) / n as f64);
        let mut w = 0.0;
        for i in 0..n {
            for j in 0..n {
                let p = [x0 + (i as f64 + 0.5) * hx, y0 + (j as f64 + 0.5) * hy];
                let (a, b) = (pc.phi(p), pt.phi(p));
                if a > 0.0 && b > 0.0 {
                    w += (a + b) * hx * hy;
                }
            }
        }
        let e = pair_energy(&c, &t, 1.0);
        assert!((w - e).abs() < 3e-3 * e, "quadrature {w} exact {e}");
    }
}

fn moved(x: &[[f64; 2]; 3], d: [f64; 2], th: f64) -> [[f64; 2]; 3] {
    let c = [
        (x[0][0] + x[1][0] + x[2][0]) / 3.0,
        (x[0][1] + x[1][1] + x[2][1]) / 3.0,
    ];
    x.map(|p| {
        let r = [p[0] - c[0], p[1] - c[1]];
        [
            c[0] + d[0] + th.cos() * r[0] - th.sin() * r[1],
            c[1] + d[1] + th.sin() * r[0] + th.cos() * r[1],
        ]
    })
}

#[test]
fn force_and_torque_equal_minus_energy_gradient_for_rigid_motion() {
    // Central differences of W under rigid translation / rotation of c (step 1e-6 of the
    // size): agreement to 1e-6 of the force scale (truncation ~h^2, round-off ~eps W/h).
    let mut worst: f64 = 0.0;
    for (c, t) in random_pairs(4, 200) {
        let p = 3.0;
        let f = pair_normal_force(&c, &t, p);
        let fc = [f[0][0] + f[1][0] + f[2][0], f[0][1] + f[1][1] + f[2][1]];
        let cen = [
            (c[0][0] + c[1][0] + c[2][0]) / 3.0,
            (c[0][1] + c[1][1] + c[2][1]) / 3.0,
        ];
        let torque: f64 = (0..3)
            .map(|k| cross([c[k][0] - cen[0], c[k][1] - cen[1]], f[k]))
            .sum();
        let h = 1e-6;
        let w = |d: [f64; 2], th: f64| pair_energy(&moved(&c, d, th), &t, p);
        let gx = -(w([h, 0.0], 0.0) - w([-h, 0.0], 0.0)) / (2.0 * h);
        let gy = -(w([0.0, h], 0.0) - w([0.0, -h], 0.0)) / (2.0 * h);
        let gt = -(w([0.0, 0.0], h) - w([0.0, 0.0], -h)) / (2.0 * h);
        let scale = f.iter().map(|g| g[0].hypot(g[1])).fold(0.0, f64::max);
        let size = c
            .iter()
            .map(|q| (q[0] - cen[0]).hypot(q[1] - cen[1]))
            .fold(0.0, f64::max);
        assert!(
            (gx - fc[0]).abs() < 1e-6 * scale.max(1e-3),
            "fx {} vs {gx}",
            fc[0]
        );
        assert!(
            (gy - fc[1]).abs() < 1e-6 * scale.max(1e-3),
            "fy {} vs {gy}",
            fc[1]
        );
        assert!(
            (gt - torque).abs() < 1e-6 * scale.max(1e-3) * size,
            "m {torque} vs {gt}"
        );
        let s = scale.max(1e-3);
        worst = worst
            .max((gx - fc[0]).abs() / s)
            .max((gy - fc[1]).abs() / s)
            .max((gt - torque).abs() / (s * size));
    }
    fdem_figures::record(28, format!("{worst:.1e}"));
}

#[test]
fn flat_overlap_traction_is_3pd_over_altitudes() {
    // t: top edge y = 0 from x = 1 to -1, altitude H_t = 1.5; c: bottom edge at y = -d from
    // x = -0.5 to 0.5, altitude H_c = 1 + d. Overlap strip of length 1 (minus O(d) at the
    // sloped ends). Expected F_y = 3 p d (1/H_c + 1/H_t) L to O(d/H): 1e-3 relative at d = 1e-5.
    let p = 2.0e9;
    let mut worst: f64 = 0.0;
    for d in [1e-5, 1e-4] {
        let t = [[-1.0, 0.0], [0.0, -1.5], [1.0, 0.0]];
        let c = [[-0.5, -d], [0.5, -d], [0.0, 1.0]];
        let f = pair_normal_force(&c, &t, p);
        let fc = [f[0][0] + f[1][0] + f[2][0], f[0][1] + f[1][1] + f[2][1]];
        let hc = 1.0 + d;
        let expect = 3.0 * p * d * (1.0 / hc + 1.0 / 1.5);
        assert!(
            ((fc[1] - expect) / expect).abs() < 30.0 * d,
            "d={d}: {} vs {expect}",
            fc[1]
        );
        assert!(fc[0].abs() < 1e-12 * expect);
        // Energy (3/2) p L d^2 (1/H_c + 1/H_t), same order of accuracy.
        let w = pair_energy(&c, &t, p);
        let we = 1.5 * p * d * d * (1.0 / hc + 1.0 / 1.5);
        assert!(((w - we) / we).abs() < 30.0 * d, "W {w} vs {we}");
        let e = (fc[1] - expect) / expect / d;
        if e.abs() > worst.abs() {
            worst = e;
        }
    }
    fdem_figures::record(29, format!("{worst:.2} d/H"));
}

#[test]
fn deep_penetration_and_identical_triangles_stay_finite_and_conservative() {
    // Beyond H/3 the force is no longer monotone (documented), but it must stay finite and
    // conserve momentum: identical triangles (zero net force by symmetry), a triangle inside
    // another, and a centroid-to-centroid overlap.
    let t = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let inner = [[0.2, 0.2], [0.4, 0.2], [0.2, 0.4]];
    let shifted = [[0.1, 0.1], [1.1, 0.1], [0.1, 1.1]];
    for c in [t, inner, shifted] {
        let f = pair_normal_force(&c, &t, 1.0);
        assert!(f.iter().all(|g| g[0].is_finite() && g[1].is_finite()));
        let sx: f64 = f.iter().map(|g| g[0]).sum();
        let sy: f64 = f.iter().map(|g| g[1]).sum();
        assert!(sx.abs() < 1e-14 && sy.abs() < 1e-14);
        assert!(pair_energy(&c, &t, 1.0).is_finite());
    }
    // Identical triangles: each gets zero net force.
    let f = pair_normal_force(&t, &t, 1.0);
    let fc = [f[0][0] + f[1][0] + f[2][0], f[0][1] + f[1][1] + f[2][1]];
    assert!(fc[0].abs() < 1e-14 && fc[1].abs() < 1e-14, "{fc:?}");
}

#[test]
fn degenerate_inverted_and_non_finite_triangles_give_zero_force() {
    let t = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let line = [[0.1, 0.1], [0.5, 0.1], [0.9, 0.1]];
    let inverted = [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]];
    let nan = [[f64::NAN, 0.1], [0.5, 0.1], [0.1, 0.5]];
    let inf = [[f64::INFINITY, 0.1], [0.5, 0.1], [0.1, 0.5]];
    let point = [[0.2, 0.2]; 3];
    for c in [line, inverted, nan, inf, point] {
        for f in [
            pair_normal_force(&c, &t, 1.0),
            pair_normal_force(&t, &c, 1.0),
        ] {
            assert!(f.iter().all(|g| *g == [0.0, 0.0]), "{c:?}: {f:?}");
        }
        assert_eq!(pair_energy(&c, &t, 1.0), 0.0);
    }
    assert!(area(&t) > 0.0);
}
