//! The conjugate-gradient relaxation (`integrator.relaxation: "conjugate-gradient"`): a
//! nonlinear conjugate-gradient minimisation of the total potential energy (Polak-Ribiere+,
//! a secant line search) preconditioned by the lumped equal-step masses, one iteration (two
//! force evaluations) per step, on the cantilever of `relaxation_methods.rs` and the Hertz
//! disc of `relaxation_masses.rs`:
//! - the 360 x 36-cell cantilever (25 920 triangles) converges at 1e-7 of its 1 N tip load
//!   (the rule max(tolerance, round-off floor): it stops at its floor, 1.4e-7) in 4 800
//!   iterations (kinetic damping: 53 200 steps), the 120 x 12 one in 1 700 (kinetic:
//!   17 300); the finite-strain (corotated) forces change the stiffness between iterations
//!   and cost iterations at small residuals, the more the larger the load;
//! - its tip equals the static solve's to the geometric nonlinearity, and the books close
//!   with the energy taken out equal to the strain energy (Clapeyron);
//! - bit-identical on 1 and 2 threads; a stopped run resumes byte for byte;
//! - the Hertz disc converges with Hertz's half-width and peak pressure;
//! - the method is refused with mass damping, outside a relaxation, and with friction.

use crate::common;
use crate::relaxation_masses::{hertz_scene, relax_hertz};
use crate::relaxation_methods::{cantilever, run_on, tip};

fn cg(v: &mut serde_json::Value) {
    v["integrator"]["relaxation"] = "conjugate-gradient".into();
}

/// The 25 920-triangle cantilever to 1e-7 of a 1 N tip load in at most 20 000 steps, by
/// default: the scene names no method, and an elastic body under a dead load is
/// conservative, so it relaxes by conjugate gradient.
#[test]
fn cg_relaxation_of_the_25k_triangle_cantilever() {
    let scene = cantilever("cg-cant-360", (360, 36), "relaxation", 1.0, |_| {});
    let t = std::time::Instant::now();
    let (o, out) = common::run(&scene);
    let wall = t.elapsed().as_secs_f64();
    let st = cantilever("cg-cant-360-static", (360, 36), "static", 1.0, |_| {});
    let (_, out_st) = common::run(&st);
    let (u, u_st) = (tip(&out), tip(&out_st));
    let s = &o.summary;
    let err = (u / u_st - 1.0).abs();
    let e = &s.energy;
    let clapeyron = e.mass_damping / e.strain - 1.0;
    let rise = s.cg_largest_rise.unwrap() / e.strain;
    eprintln!(
        "conjugate-gradient relaxation, 360 x 36 cantilever ({} triangles), 1 N: {} iterations, {} force evaluations, {} restarts, {wall:.2} s; residual {:.2e} (floor {:.2e}); tip {u:.9e} vs static {u_st:.9e} ({err:.1e}); energy taken out / strain energy - 1 = {clapeyron:.1e}, largest rise of one iteration {rise:.1e} of the strain energy",
        s.triangles,
        s.steps,
        s.force_evaluations,
        s.cg_restarts.unwrap(),
        s.relative_residual.unwrap(),
        s.residual_floor.unwrap(),
    );
    assert_eq!(s.converged, Some(true));
    assert_eq!(s.relaxation.as_deref(), Some("conjugate-gradient"));
    let why = s.relaxation_reason.as_deref().unwrap();
    assert!(
        why.contains("the default for a conservative scene"),
        "{why}"
    );
    assert!(s.triangles >= 25_000);
    // measured 4 800 iterations (the residual checked every 100), 9 600 force evaluations
    assert!(s.steps <= 20_000, "{} steps", s.steps);
    assert_eq!(s.force_evaluations, 2 * s.steps);
    // converged at its round-off floor (1.4e-7 here) or the tolerance
    assert!(s.relative_residual.unwrap() <= s.residual_floor.unwrap().max(1e-7));
    // measured 4.1e-6: the finite-strain deflection at 1 N (the 120 x 12 beam's +-P
    // extrapolation below puts the small-strain one within 2e-6 of the static solve), as
    // kinetic damping's test bounds it
    assert!(err < 1e-5, "{err:e}");
    // a linear elastic body under a dead load: at equilibrium the load's work is twice the
    // strain energy, so the minimiser took out the strain energy (Clapeyron); measured
    // within 1e-5 (the finite-strain terms and the residual)
    assert!(clapeyron.abs() < 1e-4, "{clapeyron:e}");
    // no iteration raised the total potential beyond the round-off of the strain energy's
    // sum (absolute positions of 10 m, elements of 0.03 m, strains of 1e-4: ~1e-10 of it);
    // measured 1.1e-11
    assert!(rise <= 1e-9, "{rise:e}");
    // the books close: the iterations' energy is booked as damping
    assert!(e.relative_error().abs() < 1e-9, "{e:?}");
    assert_eq!(e.kinetic, 0.0);
    fdem_figures::record(
        117,
        format!(
            "{} iterations ({} force evaluations, stops at its round-off floor {:.1e}); {err:.1e}; {clapeyron:.1e}; {rise:.1e}",
            s.steps,
            s.force_evaluations,
            s.residual_floor.unwrap()
        ),
    );
}

/// The default method where the energy is not a potential: kinetic damping, saying what
/// rules the potential out (friction, contact damping, viscosity, joints); viscous with a
/// mass-proportional damping; the one the scene names otherwise.
#[test]
fn the_default_relaxation_is_conjugate_gradient_only_for_a_conservative_scene() {
    use fdem_solver::input::scene::RelaxationMethod::{ConjugateGradient, Kinetic, Viscous};
    let choice = |tag: &str, edit: &dyn Fn(&mut serde_json::Value)| {
        let scene = crate::common::edited_example("disc-collision.json", tag, |v| {
            v["analysis"] = "relaxation".into();
            edit(v);
        });
        fdem_solver::driver::load(&scene)
            .unwrap()
            .scene
            .relaxation_choice()
    };
    let (m, why) = choice("rc-plain", &|_| {});
    assert_eq!(m, ConjugateGradient, "{why}");
    let (m, why) = choice("rc-friction", &|v| {
        v["contact"] = serde_json::json!({"default": {"friction": 0.3}});
    });
    assert_eq!(m, Kinetic);
    assert!(why.contains("contact.default.friction > 0"), "{why}");
    let (m, why) = choice("rc-damped", &|v| {
        v["contact"] = serde_json::json!({"default": {"damping": 0.1}});
    });
    assert_eq!(m, Kinetic);
    assert!(why.contains("contact.default.damping > 0"), "{why}");
    let (m, why) = choice("rc-viscous", &|v| {
        v["damping"] = serde_json::json!({"viscosity_ratio": 0.05});
    });
    assert_eq!(m, Kinetic);
    assert!(why.contains("viscosity_ratio"), "{why}");
    let (m, _) = choice("rc-alpha", &|v| {
        v["damping"] = serde_json::json!({"mass_proportional": 100.0});
    });
    assert_eq!(m, Viscous);
    let (m, why) = choice("rc-named", &|v| {
        v["integrator"]["relaxation"] = "kinetic".into();
    });
    assert_eq!(m, Kinetic);
    assert!(why.contains("named"), "{why}");
    // joints that soften: the fracturing disc, relaxed
    let scene = crate::common::edited_example("brazilian-disc-fracture.json", "rc-joints", |v| {
        v["analysis"] = "relaxation".into();
    });
    let (m, why) = fdem_solver::driver::load(&scene)
        .unwrap()
        .scene
        .relaxation_choice();
    assert_eq!(m, Kinetic);
    assert!(why.contains("joints"), "{why}");
}

/// 120 x 12 cells: converges, bit-identical on 1 and 2 threads, and the +-P extrapolation
/// to zero load equals the small-strain static solve.
#[test]
fn cg_relaxation_is_thread_independent_and_equals_the_static_solve() {
    let scene = cantilever("cg-cant-120", (120, 12), "relaxation", 1.0, cg);
    let (o1, _) = run_on(1, &scene);
    let s = &o1.summary;
    eprintln!(
        "conjugate-gradient relaxation, 120 x 12 cantilever, 1 N: {} iterations, {} force evaluations, {} restarts, residual {:.2e} (floor {:.2e}), {:.2} s",
        s.steps,
        s.force_evaluations,
        s.cg_restarts.unwrap(),
        s.relative_residual.unwrap(),
        s.residual_floor.unwrap(),
        s.wall_time
    );
    assert_eq!(s.converged, Some(true));
    // measured 1 700 (kinetic damping: 17 300)
    assert!(s.steps <= 3_000, "{} steps", s.steps);
    let (o2, _) = run_on(2, &scene);
    assert_eq!(o2.summary.steps, s.steps);
    assert!(
        common::state_bits(&o1) == common::state_bits(&o2),
        "1 and 2 threads differ"
    );

    let st = cantilever("cg-static-120", (120, 12), "static", 1.0, |_| {});
    let w_st = tip(&common::run(&st).1);
    let relaxed = |p: f64| {
        let tag = format!("cg-cant-120-{p}");
        let scene = cantilever(&tag, (120, 12), "relaxation", p, |v| {
            cg(v);
            v["integrator"]["relaxation_tolerance"] = 1e-10.into();
        });
        let (o, out) = common::run(&scene);
        assert_eq!(o.summary.converged, Some(true));
        tip(&out) / p
    };
    // w(P) / P = w_0 + b P + c P^2 + ...: the mean of +-P removes the odd terms, and
    // (4 m(0.5) - m(1)) / 3 the P^2 term (as for kinetic damping in relaxation_methods.rs)
    let mean = |p: f64| 0.5 * (relaxed(p) + relaxed(-p));
    let (m1, m05) = (mean(1.0), mean(0.5));
    let w0 = (4.0 * m05 - m1) / 3.0;
    let (e1, e0) = ((relaxed(1.0) / w_st - 1.0).abs(), (w0 / w_st - 1.0).abs());
    eprintln!(
        "conjugate-gradient: tip/load at 1 N {e1:.2e} from the static solve, extrapolated to zero load {e0:.2e}"
    );
    // measured: see the message; kinetic damping's bound
    assert!(e0 < 2e-6, "{e0:e}");
    fdem_figures::record(
        118,
        format!(
            "identical, {} iterations; {e0:.1e} ({e1:.1e} at 1 N)",
            s.steps
        ),
    );
}

/// A run stopped after iterations 177 and 350 of its 500 resumes byte for byte.
#[test]
fn cg_relaxation_resumes_bit_for_bit() {
    let scene = common::edited_example("cantilever-relaxation.json", "restart-cg", |v| {
        v["damping"] = serde_json::json!({});
        cg(v);
    });
    let (a, _) = crate::restart::straight_and_resumed(&scene, &[177, 350]);
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(a.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["converged"], serde_json::json!(true));
    assert_eq!(v["relaxation"], serde_json::json!("conjugate-gradient"));
    assert!(v["steps"].as_u64().unwrap() > 350, "{v}");
    fdem_figures::record(119, format!("identical, converged at {}", v["steps"]));
}

/// Hertz's disc on a frictionless wall (relaxation_masses.rs) by conjugate gradient.
#[test]
fn cg_relaxation_of_the_hertz_disc() {
    let m = relax_hertz("cg-hertz", cg);
    eprintln!(
        "hertz disc, conjugate gradient: {} iterations, a/a_H - 1 = {:+.3} %, p0/p0_H - 1 = {:+.3} %, sum F/P - 1 = {:+.1e}",
        m.steps,
        100.0 * (m.a_ratio - 1.0),
        100.0 * (m.p0_ratio - 1.0),
        m.equilibrium
    );
    // measured: 7 500 iterations to 1e-5 (kinetic damping: 10 000 steps); a +0.077 %,
    // p0 +0.184 % (the penalty layer's compliance, as with kinetic damping); the wall carries
    // the weight to 1.4e-6
    assert_eq!(m.converged, Some(true), "{m:?}");
    assert!(m.steps <= 10_000, "{m:?}");
    assert!((m.a_ratio - 1.0).abs() < 0.01, "half-width: {m:?}");
    assert!((m.p0_ratio - 1.0).abs() < 0.01, "peak pressure: {m:?}");
    assert!(m.equilibrium.abs() < 1e-5, "{m:?}");
    assert_eq!(m.masses.as_deref(), Some("equal-step"));
    fdem_figures::record(
        120,
        format!(
            "a {:+.3} %, p0 {:+.3} %; {:.1e}; {} iterations",
            100.0 * (m.a_ratio - 1.0),
            100.0 * (m.p0_ratio - 1.0),
            m.equilibrium,
            m.steps
        ),
    );
}

#[test]
fn cg_relaxation_is_refused_with_mass_damping_friction_or_outside_a_relaxation() {
    let refused = |scene: &std::path::Path, path: &str, needle: &str| {
        let e = fdem_solver::driver::load(scene)
            .err()
            .expect("rejected")
            .to_string();
        assert!(e.contains(path), "{e}");
        assert!(e.contains(needle), "{e}");
    };
    let damped = cantilever("cg-alpha", (4, 2), "relaxation", 1.0, |v| {
        cg(v);
        v["damping"] = serde_json::json!({ "mass_proportional": 9.0 });
    });
    refused(&damped, "integrator.relaxation", "mass_proportional");
    let dynamic = cantilever("cg-dynamic", (4, 2), "dynamic", 1.0, |v| {
        v["duration"] = 1.0.into();
        v["integrator"] = serde_json::json!({ "relaxation": "conjugate-gradient" });
    });
    refused(&dynamic, "integrator.relaxation", "does not relax");
    let friction = hertz_scene("cg-friction", |v| {
        cg(v);
        v["contact"]["walls"][0]["law"] = serde_json::json!({ "friction": 0.3 });
    });
    refused(&friction, "contact.walls[0].law.friction", "kinetic");
    // frictionless contact is accepted
    let frictionless = hertz_scene("cg-frictionless", cg);
    assert!(fdem_solver::driver::load(&frictionless).is_ok());
    fdem_figures::record_part(121, 2, "refused");
}
