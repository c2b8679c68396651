//! The relaxation analysis's methods (`integrator.relaxation`): kinetic damping (the default
//! without `damping.mass_proportional`), adaptive damping and viscous damping.
//!
//! The cantilever of examples/cantilever-*.json (10 m x 1 m, plane stress, E = 200e3,
//! nu = 0.3, rho = 1, clamped left end, shear traction on the right end) on a structured
//! 120 x 12-cell mesh (2 880 triangles) built here:
//! - at a tip load of 1 N, kinetic damping reaches a relative residual of 1e-7 in 17 300
//!   steps (asserted <= 20 000), adaptive damping in 36 200, mass-proportional damping
//!   tuned to the first mode (alpha = 9 1/s) in 30 800;
//! - at 1 mN (1000 times less: the finite-strain relaxation and the small-strain static
//!   solve then differ by ~1e-6 of the deflection at most) the relaxation stops at its
//!   round-off floor and its tip deflection equals the static solve's to 1e-6;
//! - the run is bit-identical on 1 and 2 threads; the energy books balance;
//! - on the 360 x 36-cell mesh (25 920 triangles) kinetic damping takes 53 200 steps (the
//!   20 000 asked for are out of reach: see its test).

use std::path::{Path, PathBuf};

use crate::common;

/// Writes the `nx` x `ny`-cell cantilever mesh (groups beam, left, right, tip) into `dir`.
fn cantilever_mesh(dir: &Path, nx: usize, ny: usize) -> PathBuf {
    let (nodes, tris) = common::structured_rectangle(nx, ny, 10.0, 1.0);
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let left: Vec<[u32; 2]> = (0..ny).map(|j| [id(0, j), id(0, j + 1)]).collect();
    let right: Vec<[u32; 2]> = (0..ny).map(|j| [id(nx, j), id(nx, j + 1)]).collect();
    let mesh = serde_json::json!({
        "nodes": nodes, "triangles": tris,
        "groups": [
            {"name": "beam", "dim": 2, "triangles": (0..tris.len()).collect::<Vec<_>>()},
            {"name": "left", "dim": 1, "edges": left},
            {"name": "right", "dim": 1, "edges": right},
            {"name": "tip", "dim": 0, "nodes": [id(nx, ny / 2)]}
        ]
    });
    let p = dir.join(format!("cantilever-{nx}x{ny}.json"));
    std::fs::write(&p, mesh.to_string()).unwrap();
    p
}

/// The cantilever scene (analysis `analysis`, tip load `load` N, `edit` applied) in a fresh
/// folder `tag`.
pub(crate) fn cantilever(
    tag: &str,
    n: (usize, usize),
    analysis: &str,
    load: f64,
    edit: impl FnOnce(&mut serde_json::Value),
) -> PathBuf {
    let dir = common::temp_dir(tag);
    let mesh = cantilever_mesh(&dir, n.0, n.1);
    let mut v = serde_json::json!({
        "analysis": analysis,
        "bodies": [{
            "name": "beam", "mesh": mesh.display().to_string(),
            "materials": { "beam": { "young": 200e3, "poisson": 0.3, "density": 1.0, "plane": "stress" } }
        }],
        "boundary_conditions": [
            { "fixed": { "group": "left", "x": true, "y": true } },
            { "traction": { "group": "right", "value": [0.0, -load] } }
        ],
        "output": { "frames": 0 },
        "histories": { "every": 1000000, "probes": [ { "displacement": { "group": "tip" } } ] }
    });
    if analysis == "relaxation" {
        v["duration"] = 20.0.into();
        v["integrator"] = serde_json::json!({ "safety": 0.9, "relaxation_tolerance": 1e-7 });
    }
    edit(&mut v);
    let p = dir.join("scene.json");
    std::fs::write(&p, v.to_string()).unwrap();
    p
}

pub(crate) fn tip(out: &Path) -> f64 {
    let (h, rows) = common::histories(out);
    *common::column(&h, &rows, "u_y[tip]").last().unwrap()
}

/// Runs `scene` on a pool of `threads` threads.
pub(crate) fn run_on(threads: usize, scene: &Path) -> (fdem_solver::driver::Outcome, PathBuf) {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| common::run(scene))
}

#[test]
fn kinetic_relaxation_of_the_cantilever_is_fast_and_thread_independent() {
    let scene = cantilever("kdr-cant", (120, 12), "relaxation", 1.0, |v| {
        v["integrator"]["relaxation"] = "kinetic".into();
    });
    let (o1, _) = run_on(1, &scene);
    let s = &o1.summary;
    eprintln!(
        "kinetic relaxation, 120 x 12 cantilever, 1 N: {} steps, {} resets, residual {:.3e} (floor {:.2e}), kinetic/strain {:.1e}, energy error {:.2e} of in_play",
        s.steps,
        s.kinetic_resets.unwrap(),
        s.relative_residual.unwrap(),
        s.residual_floor.unwrap(),
        s.kinetic_to_strain.unwrap(),
        s.energy.relative_error()
    );
    assert_eq!(s.converged, Some(true));
    assert_eq!(s.relaxation.as_deref(), Some("kinetic"));
    // measured 17 300 steps
    assert!(s.steps <= 20_000, "{} steps", s.steps);
    assert!(s.relative_residual.unwrap() <= 1e-7);
    // the ledger with the resets booked as damping: measured 1.1e-6 of in_play; the books
    // must close to 1e-4
    assert!(s.energy.relative_error().abs() < 1e-4, "{:?}", s.energy);
    assert!(s.energy.mass_damping > 0.0);
    // measured 2.7e-15: the relaxation ends at rest
    assert!(s.kinetic_to_strain.unwrap() < 1e-9);
    let (o2, _) = run_on(2, &scene);
    assert_eq!(o2.summary.steps, s.steps);
    assert!(
        common::state_bits(&o1) == common::state_bits(&o2),
        "1 and 2 threads differ"
    );
    fdem_figures::record(
        108,
        format!(
            "{} steps, {} resets, kinetic/strain {:.1e}; identical; closes ({:.1e} of in_play)",
            s.steps,
            s.kinetic_resets.unwrap(),
            s.kinetic_to_strain.unwrap(),
            s.energy.relative_error()
        ),
    );
}

/// The 360 x 36-cell cantilever (25 920 triangles) by kinetic damping to 1e-7 of a 1 N tip
/// load. 20 000 steps are out of reach of any damping of the central difference
/// here: `omega_max / omega_1` = 12 900 (`omega_1` = 4.54 rad/s from beam theory,
/// `omega_max = 2 / h_limit`), and the best viscous damping needs about
/// `(omega_max / omega_1) ln(1/tol) / 2` = 104 000 steps; kinetic damping took 53 200
/// (15 s on 1 core), about half. Reaching 20 000 needs a lower `omega_max /
/// omega_1` (a coarser mesh) or a preconditioned solver.
#[test]
fn kinetic_relaxation_of_the_25k_triangle_cantilever() {
    let scene = cantilever("kdr-cant-360", (360, 36), "relaxation", 1.0, |v| {
        v["integrator"]["relaxation"] = "kinetic".into();
    });
    let (o, out) = common::run(&scene);
    let st = cantilever("kdr-cant-360-static", (360, 36), "static", 1.0, |_| {});
    let (_, out_st) = common::run(&st);
    let (u, u_st) = (tip(&out), tip(&out_st));
    let s = &o.summary;
    let err = (u / u_st - 1.0).abs();
    eprintln!(
        "kinetic relaxation, 360 x 36 cantilever ({} triangles), 1 N: {} steps, residual {:.2e}, tip {u:.9e} vs static {u_st:.9e} ({err:.1e}, the finite-strain terms)",
        s.triangles,
        s.steps,
        s.relative_residual.unwrap()
    );
    assert_eq!(s.converged, Some(true));
    assert!(s.triangles >= 25_000);
    assert!(s.steps <= 56_000, "{} steps", s.steps);
    // at 1 N the finite-strain deflection differs from the small-strain one by ~4e-6 (120 x 12)
    assert!(err < 1e-5, "{err:e}");
    fdem_figures::record(112, format!("{} steps, {err:.1e}", s.steps));
}

#[test]
fn relaxation_equals_the_static_solve_to_the_geometric_nonlinearity() {
    let static_tip = |load: f64| {
        let st = cantilever(
            &format!("kdr-static-{load}"),
            (120, 12),
            "static",
            load,
            |_| {},
        );
        tip(&common::run(&st).1) / load
    };
    let w_st = static_tip(1.0);
    // kinetic damping only: adaptive damping (alpha = 2 omega from the Rayleigh quotient)
    // stops at the floor of the 1 mN run with its lowest mode still creeping (residual 2.9e-5,
    // tip 5.6e-3 from the static solve): a small residual of an overdamped mode is not a
    // small error
    {
        let method = "kinetic";
        let relaxed = |load: f64, tol: f64| {
            let tag = format!("kdr-{method}-{load}");
            let scene = cantilever(&tag, (120, 12), "relaxation", load, |v| {
                v["integrator"]["relaxation"] = method.into();
                v["integrator"]["relaxation_tolerance"] = tol.into();
                v["duration"] = 100.0.into();
            });
            let (o, out) = common::run(&scene);
            let s = &o.summary;
            assert_eq!(s.converged, Some(true));
            eprintln!(
                "{method} relaxation, tip load {load} N: {} steps, residual {:.2e} (floor {:.2e}), tip / load {:.10e}",
                s.steps,
                s.relative_residual.unwrap(),
                s.residual_floor.unwrap(),
                tip(&out) / load
            );
            (tip(&out) / load, s.residual_floor.unwrap())
        };
        // At 1 mN the loads resolve to ~2e-5 of themselves only (the positions are absolute,
        // 10 m, the displacements 2e-5 m): the run stops at its floor, and the tip deflection
        // is as good as that floor (measured 2.5e-5 from the static solve, kinetic).
        let (w_small, floor) = relaxed(1e-3, 1e-7);
        let e_small = (w_small / w_st - 1.0).abs();
        assert!(floor > 1e-7, "floor {floor}");
        assert!(e_small < 1e-4, "{method}: {e_small:e}");
        // The finite-strain deflection per load is w(P) = w_0 + b P + c P^2 + O(P^3) (odd
        // terms too: the mesh's diagonals are not symmetric under y -> -y). The mean of +P
        // and -P removes the odd terms; relaxed to their floors (~3e-8 of the load) at
        // +-1 N and +-0.5 N, (4 m(0.5) - m(1)) / 3 is the small-strain deflection per load to
        // O(P^4) and the convergence error (the residual's ~3e-8 and 6e-8 of the load,
        // amplified up to ~10 times in the tip deflection: ~1e-6 after the extrapolation).
        let mean = |p: f64| 0.5 * (relaxed(p, 1e-10).0 + relaxed(-p, 1e-10).0);
        let (w1, w05) = (mean(1.0), mean(0.5));
        let w0 = (4.0 * w05 - w1) / 3.0;
        let (e_full, e0) = ((w1 / w_st - 1.0).abs(), (w0 / w_st - 1.0).abs());
        eprintln!(
            "{method}: tip/load at +-1 N {e_full:.2e} from the static solve (finite strain), extrapolated to zero load {e0:.2e}; at 1 mN {e_small:.2e}"
        );
        // measured: see the message
        assert!(e0 < 2e-6, "{method}: {e0:e}");
        fdem_figures::record(
            109,
            format!("{e_small:.1e}; {e0:.1e} ({e_full:.1e} at 1 N)"),
        );
    }
}

#[test]
fn relaxation_method_is_checked_against_the_damping() {
    let check = |tag: &str, edit: &dyn Fn(&mut serde_json::Value), needle: &str| {
        let scene = cantilever(tag, (4, 2), "relaxation", 1.0, |v| edit(v));
        let e = fdem_solver::driver::load(&scene)
            .err()
            .expect("rejected")
            .to_string();
        assert!(e.contains("integrator.relaxation"), "{e}");
        assert!(e.contains(needle), "{e}");
    };
    check(
        "kdr-bad-name",
        &|v| v["integrator"]["relaxation"] = "kinetc".into(),
        "kinetic",
    );
    check(
        "kdr-viscous-no-alpha",
        &|v| v["integrator"]["relaxation"] = "viscous".into(),
        "mass_proportional",
    );
    check(
        "kdr-kinetic-alpha",
        &|v| {
            v["integrator"]["relaxation"] = "kinetic".into();
            v["damping"] = serde_json::json!({ "mass_proportional": 9.0 });
        },
        "mass_proportional",
    );
    let dynamic = cantilever("kdr-dynamic", (4, 2), "dynamic", 1.0, |v| {
        v["duration"] = 1.0.into();
        v["integrator"] = serde_json::json!({ "relaxation": "kinetic" });
    });
    let e = fdem_solver::driver::load(&dynamic)
        .err()
        .expect("rejected")
        .to_string();
    assert!(e.contains("integrator.relaxation"), "{e}");
    fdem_figures::record_part(111, 2, "as stated");
}

/// Loads `scene` with the positions moved by `u`, the velocities `v` and the joints' history
/// `js`, and runs it into `<scene folder>/out`.
fn run_from(
    scene: &Path,
    u: &[[f64; 2]],
    v: &[[f64; 2]],
    js: &fdem_fracture::JointState,
) -> fdem_solver::driver::Outcome {
    use fdem_solver::driver::{self, RunOptions};
    let mut l = driver::load(scene).unwrap();
    for (x, u) in l.model.x0.iter_mut().zip(u) {
        *x = [x[0] + u[0], x[1] + u[1]];
    }
    l.model.v0 = v.to_vec();
    l.initial_joint_state = Some(js.clone());
    let out = scene.parent().unwrap().join("out");
    let options = RunOptions {
        out_dir: out,
        ..Default::default()
    };
    driver::run_outcome(&mut l, &options, &mut |_| {}).unwrap()
}

/// The notched beam of examples/notched-beam-fracture.json loaded dynamically (1.2 ms) until
/// 14 of its joints are damaged, unloaded dynamically (the pad drawn back at 20 mm/s for
/// 0.6 ms), then relaxed by kinetic damping from that state (positions, joints' history,
/// velocities zeroed, the pad held): the relaxation converges and no joint's history
/// (damage, shear secant, mode) changes, so it dissipates exactly nothing by fracture; the
/// ledger's trapezoidal book of the joints' work moves by its quadrature error only.
/// Adaptive damping (alpha = 2 omega) fails here: 2 joints' damage grows on its way; the
/// conjugate-gradient relaxation keeps every joint's history too.
#[test]
fn relaxation_of_a_damaged_notched_beam_keeps_its_damage() {
    let dynamic = common::edited_example("notched-beam-fracture.json", "kdr-notch", |v| {
        v["duration"] = 1.2e-3.into();
        v["output"]["frames"] = 0.into();
        v["histories"] = serde_json::json!({});
    });
    let (first, _) = common::run(&dynamic);
    let js = first.joint_state.clone().expect("the joints' state");
    let damaged = |h: &fdem_fracture::Histories| h.damage.iter().filter(|d| d[0] > 0.0).count();
    let unload = common::edited_example("notched-beam-fracture.json", "kdr-notch-unload", |v| {
        v["duration"] = 0.6e-3.into();
        v["output"]["frames"] = 0.into();
        v["histories"] = serde_json::json!({});
        v["boundary_conditions"][2]["velocity"]["y"] = 0.02.into();
    });
    let f0 = &first.last_frame;
    let second = run_from(&unload, &f0.displacement, &f0.velocity, &js);
    let js2 = second.joint_state.clone().unwrap();
    let fracture0 = second.summary.energy.fracture;
    eprintln!(
        "notched beam: {} damaged joints of {} after loading, {} after unloading; fracture energy {:.6e} J, {fracture0:.6e} J",
        damaged(&js.history),
        js.history.len(),
        damaged(&js2.history),
        first.summary.energy.fracture
    );
    assert!(damaged(&js2.history) > 0 && fracture0 > 0.0);
    let u: Vec<[f64; 2]> = f0
        .displacement
        .iter()
        .zip(&second.last_frame.displacement)
        .map(|(a, b)| [a[0] + b[0], a[1] + b[1]])
        .collect();
    let relaxed = |masses: &str, method: &str| {
        let tag = format!("kdr-notch-relax-{masses}-{method}");
        let relax = common::edited_example("notched-beam-fracture.json", &tag, |v| {
            v["analysis"] = "relaxation".into();
            v["duration"] = 1.0.into();
            v["output"]["frames"] = 0.into();
            v["histories"] = serde_json::json!({});
            v["integrator"]["relaxation_tolerance"] = 1e-6.into();
            v["integrator"]["relaxation_masses"] = masses.into();
            v["integrator"]["relaxation"] = method.into();
            v["boundary_conditions"][2] =
                serde_json::json!({ "fixed": { "group": "load", "y": true } });
        });
        let o = run_from(&relax, &u, &vec![[0.0; 2]; u.len()], &js2);
        let s = &o.summary;
        let js3 = o.joint_state.as_ref().unwrap();
        let (h2, h3) = (&js2.history, &js3.history);
        let changed = (0..h2.len())
            .filter(|&j| h2.damage[j] != h3.damage[j])
            .count();
        // The whole history (damage, shear secant, mode indicator) bit for bit. A joint
        // dissipates only in a step that changes its history (with the history frozen the law
        // has a potential, so its exact work is the change of its stored energy), and the
        // history is monotone (damage never falls, the shear secant never rises, the mode
        // indicator moves only with the damage): equal at both ends means unchanged in every
        // step, so the energy the relaxation dissipated by fracture is exactly 0.
        let history_changed = (0..h2.len())
            .filter(|&j| {
                h2.damage[j] != h3.damage[j]
                    || h2.shear_secant[j] != h3.shear_secant[j]
                    || h2.mode_mix[j] != h3.mode_mix[j]
            })
            .count();

        let d_fracture = (s.energy.fracture - fracture0).abs() / fracture0;
        eprintln!(
            "notched beam relaxed, {method}, {masses} masses: {} steps, {} force evaluations, residual {:.2e}, {changed} joints' damage and {history_changed} joints' history changed, the ledger's fracture energy {:.6e} J ({d_fracture:.1e} relative change: the trapezoid's quadrature)",
            s.steps,
            s.force_evaluations,
            s.relative_residual.unwrap(),
            s.energy.fracture,
        );
        // what the joints whose history changed dissipated meanwhile (their books: the
        // trapezoid's work less the change of their stored energy), relative
        let d_history = (0..h2.len())
            .filter(|&j| {
                h2.shear_secant[j] != h3.shear_secant[j] || h2.mode_mix[j] != h3.mode_mix[j]
            })
            .map(|j| (h3.dissipated[j] - h2.dissipated[j]).abs())
            .sum::<f64>()
            / fracture0;
        eprintln!(
            "  the joints whose history changed dissipated {d_history:.1e} of the fracture energy"
        );
        assert_eq!(s.converged, Some(true));
        assert_eq!(changed, 0);
        (
            s.steps,
            d_fracture,
            history_changed,
            d_history,
            s.force_evaluations,
        )
    };
    // No joint's history changed, bit for bit: the dissipation is exactly the same. The ledger's
    // `fracture` is the joints' trapezoidal work less their stored energy, and the
    // quadrature's error over the relaxation's 11 600 steps of the damaged joints' unloading
    // and reloading moves it: measured 4.7e-8 relative with the true masses at the example's
    // safety 0.9, 5.2e-9 at 0.45 and 2.1e-9 at 0.225 (a quadrature error, shrinking with the
    // step; the joints' work is kept on the trapezoidal rule so that it matches the nodal
    // trapezoid of the ledger).
    let (steps_true, d_true, h_true, _, _) = relaxed("true", "kinetic");
    assert_eq!(h_true, 0);
    assert!(d_true <= 1e-7, "{d_true:e}");
    // The equal-step masses (the default): 3 900 steps, the quadrature's error 1.4e-7 (the
    // steps are longer against the joints' motion).
    let (steps_eq, d_eq, h_eq, _, _) = relaxed("equal-step", "kinetic");
    assert_eq!(h_eq, 0);
    assert!(steps_eq < steps_true, "{steps_eq} vs {steps_true}");
    assert!(d_eq <= 3e-7, "{d_eq:e}");
    // Conjugate gradient (its trial evaluations commit no history): 1 500 iterations (3 000
    // force evaluations), no damage changed, the quadrature's error 1.3e-7. Its longer moves
    // soften one undamaged joint's pre-peak shear secant (by 2.7e-5 of it): that joint
    // dissipated 1.3e-15 J meanwhile, 1.5e-12 of the fracture energy.
    let (steps_cg, d_cg, h_cg, dh_cg, evals_cg) = relaxed("equal-step", "conjugate-gradient");
    assert!(dh_cg <= 1e-9, "{dh_cg:e}");
    assert!(steps_cg < steps_eq, "{steps_cg} vs {steps_eq}");
    assert!(d_cg <= 3e-7, "{d_cg:e}");
    fdem_figures::record(
        110,
        format!(
            "{steps_true} steps, no history changed (dissipation change 0); the ledger's `fracture` {d_true:.1e}"
        ),
    );
    fdem_figures::record(
        115,
        format!(
            "{h_eq}; {steps_eq} steps against {steps_true}; {d_eq:.1e} (true masses {d_true:.1e})"
        ),
    );
    fdem_figures::record_part(
        121,
        1,
        format!(
            "0 joints, {h_cg} joint's history changed by conjugate gradient, dissipating {} of the fracture energy (kinetic damping changes none), {d_cg:.1e}, {steps_cg} iterations ({evals_cg} force evaluations) against {steps_eq} steps",
            fdem_figures::sci(dh_cg, 1)
        ),
    );
}
