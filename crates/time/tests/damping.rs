//! Viscous damping: the velocity each scheme passes to `a(t, x, v)` decides its order on a
//! damped oscillator `x'' + c x' + x = 0`, `c = 0.2` (exact `x = e^(-c t/2) sin(w_d t) / w_d`).

use fdem_time::systems::Oscillator;
use fdem_time::{GradientWork, SchemeKind, SecondOrderSystem, State};

/// The damped oscillator, optionally hiding that its forces depend on `v` (so that the
/// schemes pass their velocity variable as it is, the seed's lagged velocity).
struct Damped {
    inner: Oscillator,
    declare_velocity: bool,
}

impl SecondOrderSystem for Damped {
    fn n_dofs(&self) -> usize {
        1
    }
    fn inv_mass(&self) -> &[f64] {
        self.inner.inv_mass()
    }
    fn acceleration(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        self.inner.acceleration(t, x, v, a);
    }
    fn velocity_dependent(&self) -> bool {
        self.declare_velocity
    }
    fn has_exact_gradient(&self) -> bool {
        true
    }
    fn force_gradient(
        &mut self,
        _: f64,
        _: &[f64],
        _: &[f64],
        a: &[f64],
        g: &mut [f64],
        _: &mut GradientWork,
    ) {
        // J = -1 at fixed v: G = 2 J a.
        g[0] = -2.0 * a[0];
    }
}

fn damped_error(kind: SchemeKind, h: f64, declare_velocity: bool) -> f64 {
    let c = 0.2_f64;
    let wd = (1.0 - c * c / 4.0).sqrt();
    let mut inner = Oscillator::new(1, 1.0);
    inner.damping = c;
    let mut sys = Damped {
        inner,
        declare_velocity,
    };
    let mut st = State::new(0.0, vec![0.0], vec![1.0]);
    let mut s = kind.build(1);
    let mut worst: f64 = 0.0;
    for _ in 0..(20.0 / h).round() as usize {
        s.step(&mut sys, &mut st, h);
        let exact = (-0.5 * c * st.t).exp() * (wd * st.t).sin() / wd;
        worst = worst.max((st.x[0] - exact).abs());
    }
    worst
}

fn order(kind: SchemeKind, declare_velocity: bool) -> f64 {
    let (e1, e2) = (
        damped_error(kind, 0.05, declare_velocity),
        damped_error(kind, 0.025, declare_velocity),
    );
    (e1 / e2).log2()
}

#[test]
fn every_scheme_is_second_order_with_viscous_damping() {
    // With the velocity extrapolated to each stage time (O(h^2)), every scheme is second
    // order on the damped oscillator: the fourth-order splittings lose their order (the
    // damping force is not part of a symplectic splitting), Gear keeps its start-up order 2.
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for kind in SchemeKind::ALL {
        let p = order(kind, true);
        assert!((p - 2.0).abs() < 0.05, "{kind}: order {p} with damping");
        (lo, hi) = (lo.min(p), hi.max(p));
    }
    fdem_figures::record(20, format!("orders {lo:.3} to {hi:.3}"));
}

#[test]
fn the_lagged_velocity_of_the_seed_form_makes_the_splittings_first_order() {
    // Passing the velocity variable as it is (the half-step velocity for central
    // difference, as in the seed's eqs 5.12-5.13) is first order in the damping term.
    for kind in SchemeKind::ALL.into_iter().filter(|k| k.is_symplectic()) {
        let p = order(kind, false);
        assert!(
            (p - 1.0).abs() < 0.05,
            "{kind}: order {p} with the lagged velocity"
        );
    }
    // Gear's predicted velocity needs no extrapolation: second order either way.
    assert!((order(SchemeKind::Pc4, false) - 2.0).abs() < 0.05);
}
