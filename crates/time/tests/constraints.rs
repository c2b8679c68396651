//! Prescribed DOFs never move under any scheme, prescribed motion is followed exactly and
//! keeps each scheme's order, and history is committed once per accepted step.

use fdem_time::systems::{LinearChain, Oscillator};
use fdem_time::{SchemeKind, SecondOrderSystem, State};

#[test]
fn a_fixed_dof_never_moves_whatever_the_scheme() {
    for kind in SchemeKind::ALL {
        // DOF 1 is fixed with a non-zero velocity in the state: no scheme may move it,
        // bit for bit, while DOF 0 oscillates.
        let mut sys = Oscillator::new(2, 1.0);
        sys.fixed = vec![1];
        sys.exact_gradient = false; // the finite-difference probe must not move it either
        let mut st = State::new(0.0, vec![0.0, 0.3], vec![1.0, 0.7]);
        let mut s = kind.build(2);
        for _ in 0..1000 {
            s.step(&mut sys, &mut st, 0.05);
            assert_eq!(st.x[1].to_bits(), 0.3_f64.to_bits(), "{kind}");
            assert_eq!(st.v[1].to_bits(), 0.7_f64.to_bits(), "{kind}");
        }
        // The free DOF really moved: x = sin(50) to within 1e-2 (CD's error at h = 0.05).
        assert!(
            (st.x[0] - 50.0_f64.sin()).abs() < 1e-2,
            "{kind}: {}",
            st.x[0]
        );
    }
}

/// Largest error of the free middle DOF of a 3-DOF chain whose DOF 0 is fixed and DOF 2
/// moves at speed `u`: `x1 = u t / 2 - u / (2 w) sin(w t)`, `w = sqrt(2 k/m)`.
fn platen_error(kind: SchemeKind, h: f64) -> f64 {
    let (k, u) = (1.0_f64, 0.5);
    let w = (2.0 * k).sqrt();
    let mut sys = LinearChain::new(3, k).with_ends(0.0, u);
    let mut st = State::zeros(3);
    let mut s = kind.build(3);
    let n = (10.0 / h).round() as usize;
    let mut worst: f64 = 0.0;
    for _ in 0..n {
        s.step(&mut sys, &mut st, h);
        let t = st.t;
        // The prescribed DOFs follow their motion exactly (up to the rounding of t).
        assert_eq!(st.x[0], 0.0);
        assert!((st.x[2] - u * t).abs() < 1e-12 && st.v[2] == u, "{kind}");
        worst = worst.max((st.x[1] - (0.5 * u * t - u / (2.0 * w) * (w * t).sin())).abs());
    }
    worst
}

#[test]
fn prescribed_platen_motion_keeps_each_schemes_order() {
    for kind in SchemeKind::ALL {
        let (h, e1, e2) = if kind.measured_order() == 4 {
            (0.1, platen_error(kind, 0.1), platen_error(kind, 0.05))
        } else {
            (0.05, platen_error(kind, 0.05), platen_error(kind, 0.025))
        };
        let p = (e1 / e2).log2();
        // The measured order on the oscillator (2 or 4), to within 0.2, and a small error.
        assert!(
            (p - kind.measured_order() as f64).abs() < 0.2,
            "{kind}: order {p} (errors {e1:e}, {e2:e}, h {h})"
        );
        assert!(e1 < 1e-2, "{kind}: error {e1}");
    }
}

/// Records the calls a scheme makes.
struct Recorder {
    inner: Oscillator,
    forces: usize,
    commits: Vec<(f64, f64, f64)>,
}

impl SecondOrderSystem for Recorder {
    fn n_dofs(&self) -> usize {
        1
    }
    fn inv_mass(&self) -> &[f64] {
        self.inner.inv_mass()
    }
    fn acceleration(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        self.forces += 1;
        self.inner.acceleration(t, x, v, a);
    }
    fn end_of_step(&mut self, t: f64, x: &[f64], v: &[f64]) {
        self.commits.push((t, x[0], v[0]));
    }
}

#[test]
fn end_of_step_is_called_once_per_step_with_the_accepted_state_and_forces_are_counted() {
    for kind in SchemeKind::ALL {
        let mut sys = Recorder {
            inner: Oscillator::new(1, 1.0),
            forces: 0,
            commits: Vec::new(),
        };
        let mut st = State::new(0.0, vec![0.0], vec![1.0]);
        let mut s = kind.build(1);
        for step in 1..=20 {
            s.step(&mut sys, &mut st, 0.1);
            assert_eq!(sys.commits.len(), step, "{kind}");
            let (t, x, v) = *sys.commits.last().unwrap();
            assert_eq!((t, x, v), (st.t, st.x[0], st.v[0]), "{kind}");
        }
        let c = s.counters();
        assert_eq!(c.steps, 20);
        // The scheme's own count agrees with the system's, and with the steady-state cost
        // (finite-difference gradients count two forces; FSAL and Gear start with one more).
        assert_eq!(c.forces as usize, sys.forces, "{kind}");
        let per_step = kind.cost().force_equivalents(false) as u64;
        let start = if kind == SchemeKind::Omf32 { 0 } else { 1 };
        assert_eq!(c.forces, start + 20 * per_step, "{kind}");
        assert_eq!(c.gradients, 20 * kind.cost().gradients as u64, "{kind}");
        // invalidate() costs exactly one more start-up evaluation (none for OMF32).
        s.invalidate();
        s.step(&mut sys, &mut st, 0.1);
        assert_eq!(s.counters().forces, c.forces + start + per_step, "{kind}");
    }
}
