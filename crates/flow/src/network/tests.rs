//! The network against answers known in closed form: the cavities of a strip, the cubic
//! law's steady flow in series, the faces' forces against the virtual work `p dV`, Carter's
//! leak-off integral, and the volume books at every step.

use super::*;

const WATER: Fluid = Fluid {
    viscosity: 1e-3,
    bulk_modulus: 2.2e9,
    density: 1000.0,
    residual_aperture: 1e-6,
    max_aperture: 1e-2,
    leak_off: 0.0,
};

/// A straight crack along x of `n` joints of length `h` and aperture `a` (the residual
/// aperture plus the opening: its upper face at `y = a - r`, nodes `u_k = k`, its lower one at
/// `y = 0`, nodes `d_k = n + 1 + k`): joint k is
/// P = u_k, Q = u_(k+1), R = d_(k+1), S = d_k. Returns the network, all joints wet, and
/// the positions.
fn strip(n: usize, h: f64, a: f64, fluid: Fluid) -> (Network, Vec<[f64; 2]>) {
    let m = n + 1;
    let mut x = Vec::new();
    for k in 0..m {
        x.push([k as f64 * h, a - fluid.residual_aperture]);
    }
    for k in 0..m {
        x.push([k as f64 * h, 0.0]);
    }
    let joints = (0..n as u32)
        .map(|k| [k, k + 1, m as u32 + k + 1, m as u32 + k])
        .collect();
    let mut net = Network::new(joints, 2 * m, 0.5, fluid).unwrap();
    net.wet_joints(0..n, 0.0);
    net.geometry(&x);
    (net, x)
}

#[test]
fn cavities_join_the_copies_of_each_vertex() {
    let (net, _) = strip(4, 0.1, 1e-4, WATER);
    assert_eq!(net.n_vertices, 5);
    for k in 0..5 {
        assert_eq!(net.vertex_of[k], k as u32);
        assert_eq!(net.vertex_of[5 + k], k as u32);
    }
    assert_eq!(net.ends(2), [2, 3]);
    assert_eq!(net.channels, vec![0, 1, 2, 3]);
}

#[test]
fn volumes_are_the_trapezoid_of_the_apertures() {
    let (net, _) = strip(4, 0.1, 1e-4, WATER);
    let total: f64 = net.volume.iter().sum();
    // four channels of length 0.1, aperture 1e-4, thickness 0.5
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12 * b;
    assert!(close(total, 4.0 * 0.1 * 1e-4 * 0.5));
    assert!(close(net.volume[0], 0.5 * 0.1 * 1e-4 * 0.5));
    assert!(close(net.volume[2], 0.1 * 1e-4 * 0.5));
}

/// Steady flow between two prescribed pressures through channels in series: the flow rate
/// is `t a^3 / (12 mu L) (p_in - p_out)` in every channel and the pressure falls linearly.
#[test]
fn steady_flow_in_series_follows_the_cubic_law() {
    let (n, h, a) = (8usize, 0.05, 2e-4);
    let (mut net, x) = strip(n, h, a, WATER);
    let (p_in, p_out) = (2e6, 0.5e6);
    net.fixed[0] = p_in;
    net.fixed[n] = p_out;
    // start filled at p_out
    for v in 1..n {
        net.fill(v, p_out);
    }
    net.geometry(&x);
    // backward Euler at a thousand times the explicit bound reaches the steady state
    let dt = 1000.0 * net.stable_step();
    for s in 0..400 {
        net.advance_implicit(s as f64 * dt, dt);
    }
    let length = n as f64 * h;
    let expect = 0.5 * a.powi(3) / (12.0 * WATER.viscosity * length) * (p_in - p_out);
    let mut worst_q: f64 = 0.0;
    for g in &net.geometry {
        worst_q = worst_q.max((g.flow - expect).abs() / expect);
    }
    assert!(worst_q < 1e-8, "flow off by {worst_q:e}");
    let mut worst_p: f64 = 0.0;
    for v in 0..=n {
        let lin = p_in + (p_out - p_in) * v as f64 / n as f64;
        worst_p = worst_p.max((net.pressure[v] - lin).abs() / p_in);
    }
    assert!(worst_p < 1e-9, "pressure off by {worst_p:e}");
    fdem_figures::record_part(
        150,
        1,
        format!(
            "series flow {} off the cubic law, pressures {} off linear",
            fdem_figures::sci(worst_q.max(1e-17), 1),
            fdem_figures::sci(worst_p.max(1e-17), 1)
        ),
    );
    assert!(net.balance_error() < 1e-10, "{}", net.balance_error());
    // the viscous dissipation's rate is q dp over the whole length
    let before = net.books.viscous;
    net.advance_implicit(0.0, dt);
    let rate = (net.books.viscous - before) / dt;
    assert!((rate - expect * (p_in - p_out)).abs() < 1e-9 * rate);
}

/// The faces' forces do the work `p dV` when the upper face rises by `delta` at a uniform
/// pressure `p`, and add up to zero.
#[test]
fn face_forces_do_the_work_p_dv() {
    let (n, h, a) = (5usize, 0.1, 1e-4);
    let (mut net, x) = strip(n, h, a, WATER);
    let p = 3e6;
    net.fixed.iter_mut().for_each(|f| *f = p);
    net.geometry(&x);
    let mut f = vec![[0.0; 2]; x.len()];
    net.add_face_forces(&x, &mut f);
    let sum = f.iter().fold([0.0; 2], |s, g| [s[0] + g[0], s[1] + g[1]]);
    assert!(sum[0].abs() < 1e-9 && sum[1].abs() < 1e-9);
    // lift the upper face (nodes 0..=n) by delta: dV = L t delta
    let delta = 1e-6;
    let work: f64 = f[..=n].iter().map(|g| g[1] * delta).sum();
    let dv = n as f64 * h * 0.5 * delta;
    let e = (work - p * dv).abs() / (p * dv);
    assert!(e < 1e-12, "{e:e}");
    fdem_figures::record_part(
        150,
        2,
        format!(
            "face forces' work {} off p dV",
            fdem_figures::sci(e.max(1e-17), 1)
        ),
    );
    let upper: f64 = f[..=n].iter().map(|g| g[1]).sum();
    assert!((upper - p * n as f64 * h * 0.5).abs() < 1e-9);
}

/// Carter's leak-off from a channel held open and fed: the volume leaked over `[0, T]` is
/// `4 C_L l t sqrt(T)` per channel (two faces), whatever the sub-steps.
#[test]
fn leak_off_integrates_carter_law() {
    let fluid = Fluid {
        leak_off: 1e-5,
        ..WATER
    };
    let (n, h, a) = (3usize, 0.1, 1e-3);
    let (mut net, _) = strip(n, h, a, fluid);
    net.fixed[0] = 1e5;
    for v in 1..=n {
        net.fill(v, 1e5);
    }
    let (t_end, steps) = (2.0, 400);
    let dt = t_end / steps as f64;
    for s in 0..steps {
        net.advance_implicit(s as f64 * dt, dt);
        assert!(
            net.balance_error() < 1e-10,
            "step {s}: {}",
            net.balance_error()
        );
    }
    // the cavities start filled and the source keeps them so: leak-off is never limited
    let expect = n as f64 * 4.0 * 1e-5 * h * 0.5 * t_end.sqrt();
    let cut = net.books.leaked;
    let e = (cut - expect).abs() / expect;
    assert!(e < 1e-12, "{cut} vs {expect}");
    fdem_figures::record_part(
        150,
        3,
        format!(
            "leak-off {} off Carter's integral",
            fdem_figures::sci(e.max(1e-17), 1)
        ),
    );
}

/// Injection into the middle of a dry crack, drained at one end, with leak-off, stepped
/// explicitly below the stable step or implicitly (`implicit`, steps of `dt`); returns the
/// network after `steps` steps, checking the books at every step.
fn inject(implicit: bool, dt: f64, steps: usize) -> Network {
    let fluid = Fluid {
        leak_off: 1e-8,
        ..WATER
    };
    let (n, h, a) = (10usize, 0.02, 5e-5);
    let (mut net, _) = strip(n, h, a, fluid);
    net.fixed[n] = 0.0;
    net.rate[n / 2] = 5e-5;
    for s in 0..steps {
        let t = s as f64 * dt;
        if implicit {
            net.advance_implicit(t, dt);
        } else {
            net.advance(t, dt, 0.9);
        }
        let e = net.balance_error();
        assert!(e < 1e-10, "step {s}: {e}");
    }
    net
}

/// The books close to round-off at every step either way, and backward Euler converges to
/// the explicit answer at first order in its step.
#[test]
fn books_close_and_implicit_converges_to_explicit() {
    let t_end = 0.02;
    let explicit = inject(false, 1e-5, 2000);
    assert!(explicit.books.injected > 0.0 && explicit.books.leaked > 0.0);
    let err = |steps: usize| {
        let imp = inject(true, t_end / steps as f64, steps);
        let d = (imp.pressure[5] - explicit.pressure[5]).abs() / explicit.pressure[5];
        (d, imp.books.injected_energy)
    };
    let (e1, _) = err(50);
    let (e2, _) = err(100);
    let (e3, _) = err(200);
    // first order: halving the step halves the error (the explicit run's own error, at
    // steps 100 times smaller, is far below these)
    assert!(e1 < 0.05 && e3 < e2 && e2 < e1, "{e1} {e2} {e3}");
    let order = (e1 / e3).log2() / 2.0;
    assert!((order - 1.0).abs() < 0.2, "order {order}: {e1} {e2} {e3}");
    fdem_figures::record_part(
        150,
        4,
        format!(
            "backward Euler {}, {}, {} off the explicit answer at 50, 100, 200 steps (order {order:.2})",
            fdem_figures::sci(e1, 2),
            fdem_figures::sci(e2, 2),
            fdem_figures::sci(e3, 2)
        ),
    );
    // the steady pressure at the source: the rate through half the channels (one side
    // drained) less the leak-off, below rate * 12 mu L_half / (t a^3)
    let (n, h, a) = (10.0, 0.02, 5e-5);
    let bound = 5e-5 * 12.0 * 1e-3 * (n / 2.0 * h) / (0.5 * f64::powi(a, 3));
    let p_max = explicit.pressure.iter().fold(0.0f64, |m, &p| m.max(p));
    assert!(
        p_max.is_finite() && p_max < 1.01 * bound,
        "{p_max} vs {bound}"
    );
}

#[test]
fn bad_properties_are_refused_by_name() {
    let bad = Fluid {
        viscosity: -1.0,
        ..WATER
    };
    let e = Network::new(vec![], 0, 1.0, bad).unwrap_err();
    assert!(e.to_string().contains("viscosity"));
    let bad = Fluid {
        max_aperture: 1e-9,
        ..WATER
    };
    assert!(matches!(
        bad.check(),
        Err(FlowError::Property {
            name: "max_aperture",
            ..
        })
    ));
    let e = Network::new(vec![[0, 1, 2, 7]], 4, 1.0, WATER).unwrap_err();
    assert!(matches!(e, FlowError::Node { node: 7, .. }));
}

/// The faces' forces are the gradient of the stored fluid's energy
/// `sum_v K (m ln(m/V) - (m - V))` (whose `-dE/dV` is the pressure `K (m/V - 1)`), under
/// pressures that differ from cavity to cavity and apertures that differ along the strip: a
/// central difference of the energy in each upper node's height against the force (the
/// lumped forces `p_k l t / 2` of each end differ from it by `l t (p_0 - p_1) / 8` per node).
#[test]
fn face_forces_are_the_gradient_of_the_fluid_energy() {
    let (n, h, a) = (6usize, 0.05, 5e-5);
    let (mut net, mut x) = strip(n, h, a, WATER);
    for k in 0..=n {
        x[k][1] += 2e-5 * (k as f64 * 1.3).sin();
    }
    net.geometry(&x);
    for v in 0..=n {
        // 0.1 % to 0.6 % compression: pressures of 2 to 13 MPa
        net.stored[v] = net.volume[v] * (1.0 + 1e-3 * (1.0 + (v % 6) as f64));
    }
    let energy = |net: &mut Network, x: &[[f64; 2]]| -> f64 {
        net.geometry(x);
        let k = WATER.bulk_modulus;
        (0..net.n_vertices)
            .map(|v| {
                let (m, vol) = (net.stored[v], net.volume[v]);
                k * (m * (m / vol).ln() - (m - vol))
            })
            .sum()
    };
    net.geometry(&x);
    let mut f = vec![[0.0; 2]; x.len()];
    net.add_face_forces(&x, &mut f);
    let scale = f.iter().fold(0.0f64, |m, g| m.max(g[1].abs()));
    let d = 1e-9;
    let mut worst: f64 = 0.0;
    for k in 0..=n {
        let mut xp = x.clone();
        xp[k][1] += d;
        let mut xm = x.clone();
        xm[k][1] -= d;
        let de = (energy(&mut net, &xp) - energy(&mut net, &xm)) / (2.0 * d);
        worst = worst.max((-de - f[k][1]).abs() / scale);
    }
    assert!(
        worst < 1e-6,
        "force against -dE/dy off by {worst:e} of the largest"
    );
    fdem_figures::record_part(
        150,
        6,
        format!(
            "faces' forces {} off the energy's gradient under unequal pressures",
            fdem_figures::sci(worst.max(1e-17), 1)
        ),
    );
}
