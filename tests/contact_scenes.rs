//! Contact in whole scenes (examples/disc-collision.json): two identical elastic discs
//! (R = 25 mm, ring mesh h = R/8, 384 triangles each, meshes/disc_rings.py) collide head-on,
//! the left at 2 m/s, the right at rest, frictionless, default penalty p = 10 E,
//! central difference at 0.9 of the stable step including the contact term.

mod common;

use fdem_solver::driver;

#[test]
fn head_on_disc_collision_conserves_momentum_and_energy_with_small_overlap() {
    let scene = common::edited_example("disc-collision.json", "disc-collision", |_| {});
    let l = driver::load(&scene).unwrap();
    let mass = l.model.mass.clone();
    let body_nodes = l.model.body_nodes.clone();
    let (o, _out) = common::run(&scene);
    let v = &o.last_frame.velocity;
    let (m_total, v0) = (mass.iter().sum::<f64>(), 2.0);
    let p0 = 0.5 * m_total * v0; // the left disc's momentum
    let k0 = 0.5 * (0.5 * m_total) * v0 * v0;
    let px: f64 = mass.iter().zip(v).map(|(m, v)| m * v[0]).sum();
    let py: f64 = mass.iter().zip(v).map(|(m, v)| m * v[1]).sum();
    let mean_vx = |b: usize| {
        let r = body_nodes[b].clone();
        let (mut mv, mut mm) = (0.0, 0.0);
        for i in r {
            mv += mass[i as usize] * v[i as usize][0];
            mm += mass[i as usize];
        }
        mv / mm
    };
    let (vl, vr) = (mean_vx(0), mean_vx(1));
    let k1 = o.summary.energy.kinetic;
    let c = &o.summary.stages["contact"];
    let depth = c["max_depth_over_altitude"].as_f64().unwrap();
    eprintln!(
        "discs: momentum error {:.3e} (x), {:.3e} (y) of p0; v_left {vl:.5} v_right {vr:.5} m/s; K1/K0 - 1 = {:.4e}; max overlap d/H = {depth:.3e}; contact stored {:.3e} J; detections {}",
        (px - p0) / p0,
        py / p0,
        k1 / k0 - 1.0,
        c["contact_potential"].as_f64().unwrap(),
        c["detections"]
    );
    // Momentum: contact forces are equal and opposite through the same point: round-off.
    assert!(((px - p0) / p0).abs() < 1e-12, "px {px} vs {p0}");
    assert!((py / p0).abs() < 1e-12, "py {py}");
    // The discs have separated and exchanged their velocities (the right one now moves).
    assert!(
        c["contact_potential"].as_f64().unwrap() == 0.0,
        "still in contact"
    );
    assert!(vr > 1.8 && vl < 0.2, "velocities {vl} {vr}");
    // Overlap below 1 % of the element size (d/H <= d/h... H < h, so d/H bounds d/h).
    assert!(depth < 0.01, "overlap d/H = {depth}");
    // Kinetic energy after separation within 2 % of before (no damping; the rest is
    // vibration left in the discs).
    assert!((k1 / k0 - 1.0).abs() < 0.02, "K1/K0 = {}", k1 / k0);
}

/// Regression: running the same loaded scene twice attached the contact stage a second time
/// (the stages went back into the loaded scene with its own contributions), doubling the
/// contact force. The second run must equal the first bit for bit.
#[test]
fn running_a_loaded_scene_twice_attaches_its_stages_once() {
    let scene = common::edited_example("disc-collision.json", "disc-collision-twice", |_| {});
    let mut l = driver::load(&scene).unwrap();
    let out = scene.parent().unwrap().join("out");
    let options = fdem_solver::driver::RunOptions {
        out_dir: out,
        raw: false,
    };
    let first = driver::run_outcome(&mut l, &options, &mut |_| {}).unwrap();
    let second = driver::run_outcome(&mut l, &options, &mut |_| {}).unwrap();
    assert_eq!(first.last_frame.velocity, second.last_frame.velocity);
    assert_eq!(first.summary.energy.kinetic, second.summary.energy.kinetic);
}
