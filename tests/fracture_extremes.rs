//! Fracture at the extremes, whole solver: a joint penalty of 1000 E, platens at a sizeable
//! fraction of the wave speed, and a joint breaking with the time step at 0.99 of the predicted
//! stable step (elements + joints + contact). Each run stays finite and keeps its energy
//! balance, or stops with a message naming the step and the fix.

use crate::common;

use fdem_solver::driver::{self, Outcome, RunOptions};

/// Runs a scene; `Err` carries the solver's message.
fn try_run(scene: &std::path::Path) -> Result<(Outcome, std::path::PathBuf), String> {
    let mut l = driver::load(scene).map_err(|e| e.to_string())?;
    let out = scene.parent().unwrap().join("out");
    let o = driver::run_outcome(
        &mut l,
        &RunOptions {
            out_dir: out.clone(),
            raw: false,
            ..Default::default()
        },
        &mut |_| {},
    )
    .map_err(|e| e.to_string())?;
    Ok((o, out))
}

/// Every number in the run's text outputs (summary, histories, walls, fractures, frames)
/// parses as a finite value or is not a number at all: no NaN or inf anywhere.
fn assert_outputs_finite(out: &std::path::Path) {
    for entry in std::fs::read_dir(out).unwrap() {
        let p = entry.unwrap().path();
        let text = std::fs::read_to_string(&p).unwrap_or_default();
        for bad in ["NaN", "nan", "inf"] {
            assert!(!text.contains(bad), "{} contains {bad}", p.display());
        }
    }
}

/// (peak platen stress [Pa], residual/work, events)
fn pair_figures(o: &Outcome, out: &std::path::Path) -> (f64, f64, usize) {
    let text = std::fs::read_to_string(out.join("walls.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = head.iter().position(|c| *c == "force_y[top]").unwrap();
    let peak = lines
        .map(|r| -r.split(',').nth(col).unwrap().parse::<f64>().unwrap())
        .fold(0.0, f64::max);
    let e = &o.summary.energy;
    let work = e.supplied;
    let events = std::fs::read_to_string(out.join("fractures.csv"))
        .map_or(0, |t| t.lines().count().saturating_sub(1));
    (peak / (0.01 * 0.01), e.error / work, events)
}

const EXPECTED: f64 = 4.732_050_807_568_877e6; // 2 c/(1 - tan 30 deg), c = 1 MPa

#[test]
fn joint_penalty_of_1000_e_stays_finite_and_balanced() {
    // p = p_t = 1000 E = 3e13 Pa: the joints set the time step (about 10 times smaller)
    let scene = common::diagonal_pair_scene(
        "fx-penalty",
        &common::PairScene {
            penalty: 3e13,
            speed: 0.02,
            ramp: 1e-4,
            safety: 0.9,
            duration: 1.2e-3,
            frames: 2,
            every: 1,
        },
    );
    let (o, out) = try_run(&scene).unwrap_or_else(|e| panic!("{e}"));
    assert_outputs_finite(&out);
    let (sigma, res, events) = pair_figures(&o, &out);
    eprintln!(
        "p = 1000 E: dt = {:.3e} s, {} steps, peak {sigma:.4e} Pa ({:.4} of 2c/(1 - tan phi)), {events} break(s), residual {res:.3e} of the work",
        o.summary.time_step,
        o.summary.steps,
        sigma / EXPECTED
    );
    assert_eq!(events, 1, "the diagonal breaks");
    // the stiffer joints change nothing in the strength: within 5 %
    assert!((sigma / EXPECTED - 1.0).abs() < 0.05, "peak {sigma}");
    assert!(res.abs() < 1e-3, "residual {res}");
}

#[test]
fn platen_at_a_tenth_of_the_wave_speed_stays_finite_or_stops_with_a_clear_message() {
    // c = sqrt(E/rho) = 3464 m/s; the platen reaches 350 m/s in 0.1 us and crushes the square
    // by a third in 10 us (stresses of 10 GPa, rho c v = 3 GPa). The run either stays finite,
    // or stops with the contact stage's message naming the time and the fix.
    let scene = common::diagonal_pair_scene(
        "fx-fast",
        &common::PairScene {
            penalty: 3e11,
            speed: 350.0,
            ramp: 1e-7,
            safety: 0.9,
            duration: 1e-5,
            frames: 2,
            every: 1,
        },
    );
    match try_run(&scene) {
        Ok((o, out)) => {
            assert_outputs_finite(&out);
            let (sigma, res, events) = pair_figures(&o, &out);
            // the same impact on the square without the joint (no fracture section: one
            // connected body): the energy error of the crushing impact on the rigid walls
            let mut v: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
            v.as_object_mut().unwrap().remove("fracture");
            let solid = scene.parent().unwrap().join("solid");
            std::fs::create_dir_all(&solid).unwrap();
            let solid_scene = solid.join("solid.scene.json");
            std::fs::write(&solid_scene, v.to_string()).unwrap();
            let (os, outs) = try_run(&solid_scene).unwrap_or_else(|e| panic!("{e}"));
            let (_, res_solid, _) = pair_figures(&os, &outs);
            eprintln!(
                "platen at 350 m/s: finished, peak {sigma:.4e} Pa, {events} break(s), residual {res:.3e} of the work; the same impact without the joint: {res_solid:.3e}"
            );
            assert_eq!(events, 1, "the diagonal breaks");
            // measured 8.2 % with the joint, 22 % without: the error is the crushing impact's
            // (wall penalty and elements at 35 % strain), and the joint adds none
            assert!(
                res.abs() <= res_solid.abs() + 0.01,
                "residual {res} vs {res_solid} without the joint"
            );
        }
        Err(msg) => {
            eprintln!("platen at 350 m/s: stopped: {msg}");
            assert!(msg.contains("step"), "the message names the step: {msg}");
            assert!(
                msg.contains("fix"),
                "the message says what to change: {msg}"
            );
            let out = scene.parent().unwrap().join("out");
            assert_outputs_finite(&out);
        }
    }
}

#[test]
fn joint_breaking_at_0_99_of_the_predicted_stable_step_stays_finite_and_balanced() {
    // the auto step is 0.99 times 2/omega_max with omega_max^2 = omega_el^2 + omega_c^2 +
    // omega_j^2 (the joint's Gershgorin bound): the joint softens and breaks at that step
    let scene = common::diagonal_pair_scene(
        "fx-limit",
        &common::PairScene {
            penalty: 3e11,
            speed: 0.02,
            ramp: 1e-4,
            safety: 0.99,
            duration: 1.2e-3,
            frames: 2,
            every: 1,
        },
    );
    let (o, out) = try_run(&scene).unwrap_or_else(|e| panic!("{e}"));
    assert_outputs_finite(&out);
    let (sigma, res, events) = pair_figures(&o, &out);
    eprintln!(
        "safety 0.99: dt = {:.3e} s, {} steps, peak {sigma:.4e} Pa ({:.4}), {events} break(s), residual {res:.3e} of the work",
        o.summary.time_step,
        o.summary.steps,
        sigma / EXPECTED
    );
    assert_eq!(events, 1);
    assert!((sigma / EXPECTED - 1.0).abs() < 0.05, "peak {sigma}");
    assert!(res.abs() < 1e-3, "residual {res}");
}
