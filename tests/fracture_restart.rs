//! A run restarted from a saved state with joints: positions, velocities and the joints'
//! history (`Outcome::joint_state`, adopted through `Problem::initial_joint_state`) carry
//! the run on as if it had not stopped.
//!
//! A free 8 x 2-cell bar (40 x 10 mm, the whole bar fracturing, no loads) whose two halves
//! start at -20 and +20 m/s: the middle joints break within microseconds (stress `rho c v` ~ 170
//! MPa against `f_t` = 3 MPa; the two middle joints break at 1.1 us) and the halves fly
//! apart. Central difference, 45 steps (10 us) in one run against 18 steps, a restart from
//! the saved state, then 27 steps: measured displacements equal to 8e-21 of the
//! largest, damage and times of failure identical.

use crate::common;

use fdem_solver::driver::{self, Outcome, Problem, RunOptions};

fn scene(dir: &std::path::Path) -> std::path::PathBuf {
    let (nodes, tris) = common::structured_rectangle(8, 2, 0.04, 0.01);
    let mesh = serde_json::json!({
        "nodes": nodes, "triangles": tris,
        "groups": [{"name": "b", "dim": 2, "triangles": (0..tris.len()).collect::<Vec<_>>()}]
    });
    std::fs::write(dir.join("bar.json"), mesh.to_string()).unwrap();
    let v = serde_json::json!({
        "analysis": "dynamic",
        "bodies": [{
            "name": "bar", "mesh": "bar.json",
            "materials": { "b": { "young": 30e9, "poisson": 0.2, "density": 2500.0, "plane": "stress" } },
            "thickness": 0.01
        }],
        "fracture": {
            "regions": [ { "body": "bar" } ],
            "material": {
                "tensile_strength": 3e6, "cohesion": 10e6, "friction_angle_deg": 30.0,
                "fracture_energy_i": 50.0, "fracture_energy_ii": 250.0,
                "penalty_normal": 300e9, "penalty_tangential": 300e9
            }
        },
        "integrator": { "scheme": "central-difference", "safety": 0.9 },
        "duration": 1e-5,
        "output": { "frames": 0 }
    });
    let p = dir.join("pull.json");
    std::fs::write(&p, v.to_string()).unwrap();
    p
}

/// The scene loaded with its halves at -20 and +20 m/s, run for `steps` of the full run's step.
fn load(p: &std::path::Path, dt: f64, steps: u64) -> Problem {
    let mut l = driver::load(p).unwrap();
    // per triangle (each has its own nodes in the exploded mesh): by its centroid's side
    for t in &l.model.triangles {
        let cx: f64 = t.iter().map(|&i| l.model.x0[i as usize][0]).sum::<f64>() / 3.0;
        for &i in t {
            l.model.v0[i as usize] = [if cx < 0.02 { -20.0 } else { 20.0 }, 0.0];
        }
    }
    l.dt = dt;
    l.n_steps = steps;
    l.scene.duration = Some(dt * steps as f64);
    l
}

fn run(l: &mut Problem, out: &std::path::Path) -> Outcome {
    driver::run_outcome(
        l,
        &RunOptions {
            out_dir: out.to_path_buf(),
            raw: false,
            ..Default::default()
        },
        &mut |_| {},
    )
    .unwrap()
}

fn broken(o: &Outcome) -> u64 {
    o.summary.stages["fracture"]["broken"].as_u64().unwrap()
}

#[test]
fn restart_from_a_saved_fracture_state_continues_the_run() {
    let dir = common::temp_dir("fracture-restart");
    let p = scene(&dir);
    let l0 = driver::load(&p).unwrap();
    let (dt, n) = (l0.dt, l0.n_steps);
    let n1 = (4 * n) / 10;
    let full = run(&mut load(&p, dt, n), &dir.join("full"));
    let first = run(&mut load(&p, dt, n1), &dir.join("first"));
    let js = first.joint_state.clone().expect("the joints' state");
    assert!(broken(&first) > 0, "no joint broke by the restart");
    // the restart: positions and velocities of the first part, with or without its joints
    let restart = |saved: bool, tag: &str| {
        let mut l = load(&p, dt, n - n1);
        for (x, u) in l.model.x0.iter_mut().zip(&first.last_frame.displacement) {
            *x = [x[0] + u[0], x[1] + u[1]];
        }
        l.model.v0.clone_from(&first.last_frame.velocity);
        if saved {
            l.initial_joint_state = Some(js.clone());
        }
        let o = run(&mut l, &dir.join(tag));
        let u: Vec<[f64; 2]> = o
            .last_frame
            .displacement
            .iter()
            .zip(&first.last_frame.displacement)
            .map(|(a, b)| [a[0] + b[0], a[1] + b[1]])
            .collect();
        (o, u)
    };
    let (second, u) = restart(true, "second");
    let (fresh, _) = restart(false, "fresh");
    let scale = full
        .last_frame
        .displacement
        .iter()
        .map(|a| a[0].abs().max(a[1].abs()))
        .fold(0.0, f64::max);
    let d = u
        .iter()
        .zip(&full.last_frame.displacement)
        .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
        .fold(0.0, f64::max)
        / scale;
    let (jf, js2, jfresh) = (
        full.joint_state.as_ref().unwrap(),
        second.joint_state.as_ref().unwrap(),
        fresh.joint_state.as_ref().unwrap(),
    );
    let damage_diff = jf
        .history
        .damage
        .iter()
        .zip(&js2.history.damage)
        .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
        .fold(0.0, f64::max);
    eprintln!(
        "{} steps ({} + {}), broken joints: full {}, at the restart {}, restarted {}; displacement difference to the full run / max |u| {d:.2e}, damage difference {damage_diff:.2e}; times of the breaks: full {:?}, restarted {:?}, restarted from fresh joints {:?}",
        n,
        n1,
        n - n1,
        broken(&full),
        broken(&first),
        broken(&second),
        jf.broken_at.iter().flatten().collect::<Vec<_>>(),
        js2.broken_at.iter().flatten().collect::<Vec<_>>(),
        jfresh.broken_at.iter().flatten().collect::<Vec<_>>(),
    );
    // the same run up to the rounding of `x0 + u` at the restart (measured 8e-21 of the
    // largest displacement): 1e-12
    assert!(d < 1e-12, "restart differs from the full run by {d:.3e}");
    assert!(damage_diff < 1e-12, "damage differs by {damage_diff:.3e}");
    assert_eq!(broken(&second), broken(&full));
    // the joints broken before the restart keep their time of failure (every break here
    // happens before it); from fresh joints they would break again at the restart's first
    // steps, at other times
    assert_eq!(js2.broken_at, jf.broken_at);
    assert_ne!(jfresh.broken_at, jf.broken_at);

    // The adopted state's broken joints leave the bonded list before the first force
    // evaluation (the contact stage's exclusions at set-up): their triangle pairs are in the
    // fresh stage's list and not in the adopted one's, which is shorter by at least them.
    let l = driver::load(&p).unwrap();
    let pairs = |saved: Option<fdem_fracture::JointState>| {
        let set = l.fracturing.set.clone().unwrap();
        let tris = set.triangles.clone();
        let (_, initial) =
            fdem_solver::stages::fracture::FractureStage::new(set, &l.model, None, saved, false);
        (tris, initial)
    };
    let (tris, fresh_pairs) = pairs(None);
    let (_, saved_pairs) = pairs(Some(js.clone()));
    let broken_pairs: Vec<[u32; 2]> = js
        .intact
        .iter()
        .zip(&tris)
        .filter(|(i, _)| !**i)
        .map(|(_, t)| [t[0].min(t[1]), t[0].max(t[1])])
        .collect();
    eprintln!(
        "bonded pairs at set-up: {} fresh, {} from the saved state ({} broken joints)",
        fresh_pairs.len(),
        saved_pairs.len(),
        broken_pairs.len()
    );
    let has = |list: &[[u32; 2]], p: &[u32; 2]| {
        list.iter().any(|q| [q[0].min(q[1]), q[0].max(q[1])] == *p)
    };
    for p in &broken_pairs {
        assert!(has(&fresh_pairs, p), "{p:?} not bonded in the fresh stage");
        assert!(
            !has(&saved_pairs, p),
            "{p:?} still bonded from the saved state"
        );
    }
    assert!(saved_pairs.len() + broken_pairs.len() <= fresh_pairs.len());
}

/// The fracture stage's set-up (star bonds built while the joints' state and scratch are)
/// gives, on 1- and 2-thread pools, the bonded list of `StarBonds::with_pairs` and the state
/// of `JointState::new` called on their own, bit for bit.
#[test]
fn fracture_stage_set_up_is_the_serial_one_on_1_and_2_threads() {
    use fdem_solver::stages::system::StageCheckpoint;
    let dir = common::temp_dir("stage-setup");
    std::fs::create_dir_all(&dir).unwrap();
    let l = driver::load(&scene(&dir)).unwrap();
    let set = || l.fracturing.set.clone().unwrap();
    let s = set();
    let mut want_pairs = Vec::new();
    fdem_solver::stages::star_bonds::StarBonds::with_pairs(
        &s.nodes,
        &s.triangles,
        l.model.n_nodes(),
        &mut want_pairs,
    );
    let want_state = fdem_fracture::JointState::new(&s, &l.model.x0);
    assert!(want_pairs.len() > s.len(), "vertex pairs listed too");
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let (stage, bonded) = pool.install(|| {
            fdem_solver::stages::fracture::FractureStage::new(set(), &l.model, None, None, false)
        });
        assert_eq!(bonded, want_pairs, "{threads} threads");
        let st = stage.joint_state().unwrap();
        assert_eq!(st.history, want_state.history, "{threads} threads");
        assert_eq!(st.intact, want_state.intact);
        assert_eq!(
            st.stored_initial.to_bits(),
            want_state.stored_initial.to_bits()
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A saved fracture state of another scene (another number of joints) is refused before the
/// run folder is claimed: the earlier run's files there stay.
#[test]
fn a_saved_state_of_another_scene_is_refused_before_the_folder_is_touched() {
    let dir = common::temp_dir("fracture-restart-mismatch");
    let p = scene(&dir);
    let l0 = driver::load(&p).unwrap();
    let (dt, n) = (l0.dt, l0.n_steps);
    let out = dir.join("out");
    let first = run(&mut load(&p, dt, n / 10), &out);
    let mut js = first.joint_state.clone().expect("the joints' state");
    js.intact.pop();
    let before = std::fs::read(out.join("summary.json")).unwrap();
    let mut l = load(&p, dt, n / 10);
    l.initial_joint_state = Some(js);
    let e = driver::run_outcome(
        &mut l,
        &RunOptions {
            out_dir: out.clone(),
            raw: false,
            ..Default::default()
        },
        &mut |_| {},
    )
    .err()
    .expect("a state with a joint less is refused");
    let msg = e.to_string();
    assert!(
        msg.contains("saved fracture state") && msg.contains("fracture"),
        "{msg}"
    );
    assert_eq!(std::fs::read(out.join("summary.json")).unwrap(), before);
    assert!(out.join("fractures.csv").exists());
}
