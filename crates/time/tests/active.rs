//! A system that gives the central-difference scheme only some of its DOFs to move (one
//! process's part of a distributed system): those DOFs follow the whole system's run bit for
//! bit, the others are never touched.

use std::ops::Range;

use fdem_time::systems::Oscillator;
use fdem_time::{CentralDifference, Integrator, SecondOrderSystem, State};

/// Damped oscillators of which only `active` are moved, with `fixed` held (inside `active`);
/// the acceleration is written only on the active DOFs, the rest of `a` poisoned with NaN.
struct Part {
    whole: Oscillator,
    active: Vec<Range<usize>>,
}

impl SecondOrderSystem for Part {
    fn n_dofs(&self) -> usize {
        self.whole.n_dofs()
    }

    fn inv_mass(&self) -> &[f64] {
        self.whole.inv_mass()
    }

    fn acceleration(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        let mut full = vec![0.0; a.len()];
        self.whole.acceleration(t, x, v, &mut full);
        a.fill(f64::NAN);
        for r in &self.active {
            a[r.clone()].copy_from_slice(&full[r.clone()]);
        }
    }

    fn velocity_dependent(&self) -> bool {
        true
    }

    fn active_dofs(&self) -> Option<&[Range<usize>]> {
        Some(&self.active)
    }

    fn prescribed_dofs(&self) -> &[usize] {
        &self.whole.fixed
    }
}

#[test]
fn the_active_dofs_follow_the_whole_run_and_the_others_never_move() {
    let n = 10;
    let mut whole = Oscillator::new(n, 3.0);
    whole.damping = 0.4;
    whole.fixed = vec![3];
    let x0: Vec<f64> = (0..n).map(|i| 0.1 * i as f64 - 0.3).collect();
    let v0: Vec<f64> = (0..n).map(|i| 0.05 * (i * i) as f64).collect();
    let (mut a, mut b) = (
        State::new(0.0, x0.clone(), v0.clone()),
        State::new(0.0, x0.clone(), v0.clone()),
    );
    let mut part = Part {
        whole: whole.clone(),
        active: vec![1..4, 6..9],
    };
    let (mut sa, mut sb) = (CentralDifference::new(n), CentralDifference::new(n));
    for _ in 0..500 {
        sa.step(&mut whole, &mut a, 0.01);
        sb.step(&mut part, &mut b, 0.01);
    }
    for i in 0..n {
        let moved = part.active.iter().any(|r| r.contains(&i)) && i != 3;
        let (x, v) = if moved {
            (a.x[i], a.v[i])
        } else {
            (x0[i], v0[i])
        };
        assert_eq!(b.x[i].to_bits(), x.to_bits(), "x of DOF {i}");
        assert_eq!(b.v[i].to_bits(), v.to_bits(), "v of DOF {i}");
        if moved {
            assert!((b.x[i] - x0[i]).abs() > 1e-3, "DOF {i} moved");
        }
    }
    fdem_figures::record(131, "identical");
}
