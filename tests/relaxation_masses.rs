//! A relaxation's equal-step masses (`integrator.relaxation_masses`, the default of the
//! kinetic and adaptive methods): every triangle's mass `c E t`, so every triangle's stable
//! step is the same however graded the mesh; the weight keeps the true masses.
//!
//! Checked on Hertz's 2D contact relaxed through the solver: the disc of
//! meshes/hertz-disc.msh (R = 25 mm, graded to a/12 at the contact) under its own weight
//! `P` on a rigid wall (plane strain, frictionless, default wall penalty 10 E), its top
//! pole held in x (the free sliding and rotation of a disc on a frictionless plane), against
//!
//! ```text
//! a = sqrt(4 P R / (pi E*)),   p0 = 2 P / (pi a),   E* = E / (1 - nu^2)
//! ```
//!
//! measured from the wall's nodal forces (the frames' `contact_force`): the half-width
//! `2 sqrt(sum x^2 F / sum F)` (Hertz: `int x^2 p dx = P a^2 / 4`), the peak pressure the
//! bottom pole's force over its tributary length on the rim.

use std::path::PathBuf;

use crate::common;
use fdem_solver::driver;

const R: f64 = 0.025;
const E: f64 = 1e9;
const NU: f64 = 0.3;
const RHO: f64 = 1000.0;

/// The Hertz disc scene in a temporary folder: gravity `g` (about `a = R / 20` at 27 470
/// m/s^2), `edit` applied last.
pub(crate) fn hertz_scene(tag: &str, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let mesh = common::root().join("meshes/hertz-disc.msh");
    let estar = E / (1.0 - NU * NU);
    let a = R / 20.0;
    let p = std::f64::consts::PI * estar * a * a / (4.0 * R);
    let g = p / (RHO * std::f64::consts::PI * R * R);
    let mut v = serde_json::json!({
        "title": "Hertz disc on a rigid wall, relaxed",
        "analysis": "relaxation",
        "bodies": [{
            "name": "disc", "mesh": mesh.display().to_string(),
            "materials": { "*": { "young": E, "poisson": NU, "density": RHO, "plane": "strain" } }
        }],
        "gravity": [0.0, -g],
        "boundary_conditions": [ { "fixed": { "group": "top", "x": true } } ],
        "contact": {
            "pairs": [ { "bodies": ["disc", "disc"], "enabled": false } ],
            "walls": [ { "name": "floor", "point": [0.0, -R], "normal": [0.0, 1.0] } ]
        },
        "integrator": { "safety": 0.9, "relaxation_tolerance": 1e-5 },
        "duration": 1.0,
        "output": { "frames": 1, "arrays": ["contact_force"] }
    });
    edit(&mut v);
    let dir = common::temp_dir(tag);
    let p = dir.join("hertz.json");
    std::fs::write(&p, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    p
}

/// What a Hertz relaxation measured.
#[derive(Debug)]
pub(crate) struct Measured {
    pub(crate) steps: u64,
    pub(crate) converged: Option<bool>,
    /// Half-width over Hertz's.
    pub(crate) a_ratio: f64,
    /// Peak pressure (pole node) over Hertz's.
    pub(crate) p0_ratio: f64,
    /// The wall's resultant over the weight, minus 1.
    pub(crate) equilibrium: f64,
    /// The stable step limit [s].
    pub(crate) dt_limit: f64,
    /// The masses the summary names.
    pub(crate) masses: Option<String>,
}

pub(crate) fn relax_hertz(tag: &str, edit: impl FnOnce(&mut serde_json::Value)) -> Measured {
    let scene = hertz_scene(tag, edit);
    let l = driver::load(&scene).unwrap_or_else(|e| panic!("{e}"));
    let g = l.scene.gravity.unwrap()[1];
    // the load: the true weight, whatever the masses of the relaxation
    let p_load = -g * l.model.weight_mass().iter().sum::<f64>();
    let rim = l.model.group_nodes(0, "rim").unwrap().to_vec();
    let pole = l.model.group_nodes(0, "bottom").unwrap()[0] as usize;
    let dt_limit = l.dt_limit;
    let (o, _out) = common::run(&scene);
    let f = &o.last_frame;
    let cf = &f
        .extra_point_vectors
        .iter()
        .find(|e| e.0 == "contact_force")
        .unwrap()
        .1;
    let x = &f.points;
    let (mut sf, mut sx2) = (0.0, 0.0);
    for (c, p) in cf.iter().zip(x) {
        sf += c[1];
        sx2 += p[0] * p[0] * c[1];
    }
    let mut lower: Vec<usize> = (rim.iter().map(|&i| i as usize))
        .filter(|&i| x[i][1] < 0.0)
        .collect();
    lower.sort_by(|&i, &j| x[i][0].total_cmp(&x[j][0]));
    let k = lower.iter().position(|&i| i == pole).unwrap();
    let trib = 0.5 * (x[lower[k + 1]][0] - x[lower[k - 1]][0]);
    let estar = E / (1.0 - NU * NU);
    let a_h = (4.0 * p_load * R / (std::f64::consts::PI * estar)).sqrt();
    let p0_h = 2.0 * p_load / (std::f64::consts::PI * a_h);
    Measured {
        steps: o.summary.steps,
        converged: o.summary.converged,
        a_ratio: 2.0 * (sx2 / sf).sqrt() / a_h,
        p0_ratio: cf[pole][1] / trib / p0_h,
        equilibrium: sf / p_load - 1.0,
        dt_limit,
        masses: o.summary.relaxation_masses.clone(),
    }
}

#[test]
fn hertz_disc_relaxed_through_the_solver_with_equal_step_masses() {
    // kinetic damping named: frictionless contact is conservative, so the default would be
    // conjugate gradient (tests/relaxation_cg.rs relaxes the same disc that way)
    let m = relax_hertz("hertz-relax", |v| {
        v["integrator"]["relaxation"] = "kinetic".into();
    });
    eprintln!(
        "hertz disc, equal-step masses: {} steps (h_limit {:.3e} s), a/a_H - 1 = {:+.3} %, p0/p0_H - 1 = {:+.3} %, sum F/P - 1 = {:+.1e}",
        m.steps,
        m.dt_limit,
        100.0 * (m.a_ratio - 1.0),
        100.0 * (m.p0_ratio - 1.0),
        m.equilibrium
    );
    // measured: 10 000 steps to 1e-5 of the load (the true masses: 49 500 to
    // 1e-4, not at 1e-5 after 780 000); a +0.077 %, p0 +0.185 % (the penalty layer's
    // compliance, as in the contact crate's test); the wall carries the weight to -3.7e-6
    assert_eq!(m.converged, Some(true), "{m:?}");
    assert!(m.steps <= 20_000, "{m:?}");
    assert!((m.a_ratio - 1.0).abs() < 0.01, "half-width: {m:?}");
    assert!((m.p0_ratio - 1.0).abs() < 0.01, "peak pressure: {m:?}");
    assert!(m.equilibrium.abs() < 1e-5, "{m:?}");
    assert_eq!(m.masses.as_deref(), Some("equal-step"));
    fdem_figures::record(
        113,
        format!(
            "a {:+.3} %, p0 {:+.3} %; {} steps; {:+.1e}",
            100.0 * (m.a_ratio - 1.0),
            100.0 * (m.p0_ratio - 1.0),
            m.steps,
            m.equilibrium
        ),
    );
}

#[test]
fn equal_step_masses_keep_the_total_and_the_weight_and_lengthen_the_step() {
    let load = |tag: &str, masses: &str| {
        let scene = hertz_scene(tag, |v| {
            v["integrator"]["relaxation_masses"] = masses.into();
        });
        driver::load(&scene).unwrap_or_else(|e| panic!("{e}"))
    };
    let (eq, tr) = (load("hertz-eq", "equal-step"), load("hertz-true", "true"));
    // the true lumped masses, summed here from the triangles: rho A t / 3 to each corner
    let m = &eq.model;
    let mut true_mass = vec![0.0; m.x0.len()];
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| m.x0[i as usize]);
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
        for &i in t {
            true_mass[i as usize] += RHO * area / 3.0;
        }
    }
    let total: f64 = true_mass.iter().sum();
    let diff = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    let big = true_mass.iter().fold(0.0f64, |a, b| a.max(*b));
    // the weight keeps the true masses; the scene without equal-step masses has them
    assert!(diff(m.weight_mass(), &true_mass) <= 1e-12 * big);
    assert!(diff(&tr.model.mass, &true_mass) <= 1e-12 * big);
    // the relaxation's masses: the same total, another distribution (every triangle the
    // same mass here: one material, one thickness)
    let eq_total: f64 = m.mass.iter().sum();
    assert!(
        (eq_total / total - 1.0).abs() < 1e-12,
        "{eq_total} vs {total}"
    );
    let m_e = total / m.triangles.len() as f64;
    let mut lumped = vec![0.0; m.x0.len()];
    for t in &m.triangles {
        for &i in t {
            lumped[i as usize] += m_e / 3.0;
        }
    }
    assert!(diff(&m.mass, &lumped) <= 1e-12 * big);
    assert!(diff(&m.mass, &true_mass) > 0.1 * big);
    // the stable step: the mesh is graded from a/12 at the contact to R/15, and the equal
    // step of every triangle is 8.4 times the true masses' smallest (measured 5.97e-8 s
    // against 7.09e-9 s)
    let ratio = eq.dt_limit / tr.dt_limit;
    eprintln!(
        "hertz disc: h_limit {:.3e} s (equal-step masses) vs {:.3e} s (true masses): {ratio:.2} times",
        eq.dt_limit, tr.dt_limit
    );
    assert!(ratio > 5.0, "{ratio}");
    let round_off = (eq_total / total - 1.0)
        .abs()
        .max(diff(m.weight_mass(), &true_mass) / big)
        .max(diff(&tr.model.mass, &true_mass) / big)
        .max(diff(&m.mass, &lumped) / big);
    fdem_figures::record_part(
        114,
        1,
        format!(
            "round-off ({}), {ratio:.2} times ({:.2e} s against {:.2e} s)",
            fdem_figures::sci(round_off, 1),
            eq.dt_limit,
            tr.dt_limit
        ),
    );
}

#[test]
fn relaxation_masses_are_checked_against_the_analysis_and_the_method() {
    let err = |tag: &str, edit: &dyn Fn(&mut serde_json::Value)| {
        let scene = hertz_scene(tag, edit);
        match driver::load(&scene) {
            Ok(_) => panic!("{tag}: accepted"),
            Err(e) => e.to_string(),
        }
    };
    let e = err("rm-dynamic", &|v| {
        v["analysis"] = "dynamic".into();
        v["integrator"] = serde_json::json!({ "relaxation_masses": "true" });
    });
    assert!(
        e.contains("integrator.relaxation_masses") && e.contains("does not relax"),
        "{e}"
    );
    let e = err("rm-viscous", &|v| {
        v["damping"] = serde_json::json!({ "mass_proportional": 100.0 });
        v["integrator"]["relaxation_masses"] = "equal-step".into();
    });
    assert!(
        e.contains("integrator.relaxation_masses") && e.contains("viscous"),
        "{e}"
    );
    let e = err("rm-word", &|v| {
        v["integrator"]["relaxation_masses"] = "equal".into()
    });
    assert!(e.contains("equal-step") && e.contains("true"), "{e}");
    // viscous relaxation keeps the true masses by default
    let scene = hertz_scene("rm-viscous-true", |v| {
        v["damping"] = serde_json::json!({ "mass_proportional": 100.0 });
    });
    let l = driver::load(&scene).unwrap();
    assert!(l.model.relaxation_masses.is_none());
    fdem_figures::record_part(114, 2, "refused");
}
