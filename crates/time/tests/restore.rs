//! A scheme's saved state ([`Integrator::save_state`]) taken up by a new scheme of the same
//! kind continues bit for bit: N steps, save, restore into a fresh scheme, M more steps equal
//! N + M steps of one scheme, for every scheme, with damping (the velocity extrapolation
//! reads the last acceleration) and a step that changes (Gear PC rescales its derivatives).

use fdem_time::systems::Oscillator;
use fdem_time::{SchemeKind, State};

/// A damped oscillator of three DOFs with different frequencies' worth of initial state.
fn system() -> Oscillator {
    let mut s = Oscillator::new(3, 2.0);
    s.damping = 0.3;
    s
}

fn h(step: usize) -> f64 {
    // a step that changes every few steps
    0.05 * (1.0 + 0.1 * ((step / 7) % 3) as f64)
}

fn bits(s: &State) -> Vec<u64> {
    s.x.iter()
        .chain(&s.v)
        .map(|v| v.to_bits())
        .chain([s.t.to_bits()])
        .collect()
}

#[test]
fn every_scheme_resumes_from_its_saved_state_bit_for_bit() {
    let (n, m) = (23, 31);
    for kind in SchemeKind::ALL {
        let mut sys = system();
        let start = State::new(0.0, vec![1.0, -0.5, 0.2], vec![0.0, 0.3, -1.0]);
        let mut straight = kind.build(3);
        let mut s1 = start.clone();
        for k in 0..n + m {
            straight.step(&mut sys, &mut s1, h(k));
        }
        let mut first = kind.build(3);
        let mut s2 = start.clone();
        for k in 0..n {
            first.step(&mut sys, &mut s2, h(k));
        }
        let saved = first.save_state();
        let mut resumed = kind.build(3);
        resumed.restore_state(&saved).unwrap();
        assert_eq!(resumed.save_state(), saved, "{kind}");
        for k in n..n + m {
            resumed.step(&mut sys, &mut s2, h(k));
        }
        assert_eq!(bits(&s1), bits(&s2), "{kind}: resumed run differs");
        assert_eq!(straight.counters(), resumed.counters(), "{kind}");

        // the saved state matters: a fresh scheme from the same positions and velocities
        // starts up afresh (Gear PC's derivatives from the acceleration alone)
        if matches!(kind, SchemeKind::Pc3 | SchemeKind::Pc4 | SchemeKind::Pc5) {
            let mut s3 = State::new(0.0, vec![0.0; 3], vec![0.0; 3]);
            let mut cold = kind.build(3);
            let mut s_n = start.clone();
            for k in 0..n {
                cold.step(&mut sys, &mut s_n, h(k));
            }
            s3.clone_from(&s_n);
            let mut fresh = kind.build(3);
            for k in n..n + m {
                fresh.step(&mut sys, &mut s3, h(k));
            }
            assert_ne!(bits(&s1), bits(&s3), "{kind}: the test cannot tell");
        }
    }
    fdem_figures::record(
        84,
        format!("identical for all {} schemes", SchemeKind::ALL.len()),
    );
}

#[test]
fn a_state_of_another_size_or_scheme_is_refused_and_leaves_the_scheme_as_it_was() {
    let mut sys = system();
    let mut s = State::new(0.0, vec![1.0, 0.0, 0.0], vec![0.0; 3]);
    let mut pc = SchemeKind::Pc5.build(3);
    pc.step(&mut sys, &mut s, 0.05);
    let before = pc.save_state();
    let cd = SchemeKind::CentralDifference.build(3).save_state();
    let e = pc.restore_state(&cd).unwrap_err();
    assert!(e.to_string().contains("history values"), "{e}");
    let small = SchemeKind::Pc5.build(2).save_state();
    assert!(pc.restore_state(&small).is_err());
    assert_eq!(pc.save_state(), before);
    let mut cd = SchemeKind::CentralDifference.build(3);
    assert!(cd.restore_state(&before).is_err());
}
