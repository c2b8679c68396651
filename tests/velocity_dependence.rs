//! Which scenes make the time crate extrapolate velocities before each force evaluation
//! (`SecondOrderSystem::velocity_dependent`): only those with a force that reads them. The
//! fracturing Brazilian disc between frictionless platens has none (joints never read
//! velocities, frictionless undamped contact neither), so central difference skips that pass;
//! the compressed block has friction 0.5 at its platens, so it keeps it.

use crate::common;

use std::path::Path;

use fdem_solver::load;
use fdem_solver::stages::system::SceneSystem;
use fdem_time::SecondOrderSystem;

/// The scene system of an example with its contact and fracture stages attached.
fn system(example: &str) -> SceneSystem {
    let l = load(Path::new(example)).expect("example loads");
    let mut sys = SceneSystem::new(l.model.clone(), l.elements.clone(), 0.0);
    let out = common::temp_dir("velocity-dependence");
    std::fs::create_dir_all(&out).unwrap();
    fdem_solver::stages::attach(&l, &mut sys, l.dt, &out, 1).expect("stages");
    let _ = std::fs::remove_dir_all(&out);
    assert_eq!(
        sys.contributions.len(),
        2,
        "{example}: fracture and contact stages"
    );
    sys
}

#[test]
fn only_scenes_with_friction_or_damping_depend_on_velocities() {
    // joints and frictionless, undamped contact: no force reads v
    assert!(!system("examples/brazilian-disc-fracture.json").velocity_dependent());
    // Coulomb friction at the platens reads the relative sliding velocity
    assert!(system("examples/block-compression-fracture.json").velocity_dependent());
}
