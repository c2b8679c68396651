//! The joint pass ahead of the element forces: a fracturing disc stepped with the joints'
//! forces added inside the element pass ([`crate::stages::system::ForceTerm::forces_ahead`])
//! and stepped with them added after it gives the same positions, velocities and joint
//! states bit for bit: through its first breaks with central difference (the pass that
//! writes the new history in place), and over 2 000 steps of a scheme of several force
//! evaluations per step (trial histories).

use fdem_time::{CentralDifference, Integrator, Omf32, SecondOrderSystem, State};

use super::checkpoint_tests::{TempDir, broken, disc, stage, system, temp_dir};
use crate::problem::load::Problem;
use crate::stages::contact::ContactStage;
use crate::stages::system::SceneSystem;

/// The disc's system with its fracture and contact stages, at its initial state.
fn scene(l: &Problem, ahead: bool) -> (SceneSystem, State) {
    let mut sys = system(l);
    sys.ahead = ahead;
    let (a, bonded) = stage(l, &sys, None, false);
    let mut contact = ContactStage::new(&l.scene, &sys.model, l.dt, None, u64::MAX, false)
        .expect("a scene with contact");
    contact.bonded = Some(bonded);
    sys.events.released_taken = true;
    sys.contributions.push(Box::new(a));
    sys.contributions.push(Box::new(contact));
    let mut x0 = sys.model.x0.as_flattened().to_vec();
    let mut v0 = sys.model.v0.as_flattened().to_vec();
    for &d in sys.constrained() {
        v0[d] = 0.0;
    }
    sys.prescribe(0.0, &mut x0, &mut v0);
    (sys, State::new(0.0, x0, v0))
}

/// The bits of the state and of every joint's committed history.
fn bits(sys: &SceneSystem, state: &State) -> Vec<u64> {
    let js = sys.contributions[0].joint_state().unwrap();
    let h = &js.history;
    let mut v: Vec<u64> = state
        .x
        .iter()
        .chain(&state.v)
        .map(|d| d.to_bits())
        .collect();
    let fields = [
        h.damage.as_flattened(),
        h.shear_secant.as_flattened(),
        h.mode_mix.as_flattened(),
        h.local.as_flattened(),
        h.normal.as_flattened(),
        &h.stored,
        &h.dissipated,
    ];
    v.extend(fields.iter().flat_map(|f| f.iter().map(|d| d.to_bits())));
    v.extend(js.intact.iter().map(|&i| u64::from(i)));
    v
}

/// Steps the disc with `integ` until `breaks` joints broke (`cap` steps when `breaks` is 0),
/// the joints' forces ahead of the element pass; then the same number of steps with them
/// after it.
fn compare<I: Integrator>(
    l: &Problem,
    new: impl Fn(usize) -> I,
    breaks: usize,
    cap: u64,
) -> (u64, usize) {
    let (mut a, mut sa) = scene(l, true);
    let mut ia = new(sa.x.len());
    let mut steps = 0;
    while (breaks == 0 || broken(&a) < breaks) && steps < cap {
        ia.step(&mut a, &mut sa, l.dt);
        steps += 1;
    }
    let (mut b, mut sb) = scene(l, false);
    let mut ib = new(sb.x.len());
    for _ in 0..steps {
        ib.step(&mut b, &mut sb, l.dt);
    }
    assert!(
        broken(&a) >= breaks,
        "{} broken in {steps} steps",
        broken(&a)
    );
    assert_eq!(a.ahead_evaluations, a.evaluations, "a pass not ahead");
    assert_eq!(b.ahead_evaluations, 0);
    assert_eq!(broken(&a), broken(&b));
    assert!(
        bits(&a, &sa) == bits(&b, &sb),
        "states differ after {steps} steps"
    );
    (steps, broken(&a))
}

#[test]
fn joint_forces_inside_the_element_pass_change_no_bit() {
    let dir: TempDir = temp_dir("ahead");
    let l = disc(&dir, "disc-small.msh");
    let (steps, breaks) = compare(&l, CentralDifference::new, 3, 40_000);
    compare(&l, Omf32::new, 0, 2_000);
    fdem_figures::record_part(
        147,
        3,
        format!(
            "identical after {steps} steps of central difference ({breaks} breaks) and 2000 of OMF32"
        ),
    );
}
