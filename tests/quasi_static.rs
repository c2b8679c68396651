//! The levers of slow runs (docs/speed-vs-accuracy.md, "Mass scaling and loading rate"):
//!
//! - mass scaling keeps the Brazilian disc's peak load within 2 % at factor 4 and lengthens
//!   the stable step by exactly sqrt(4); it is the same run as the loading rate sqrt(4) faster
//!   (the equations of motion of a rate-independent, undamped specimen depend on the mass and
//!   the time only through `m / T^2`);
//! - the loading rate scales velocities and stretches times: rate 0.5 with its doubled
//!   duration ends with the same wall displacements, and is bit for bit the scene edited by
//!   hand;
//! - the quasi-static indicator `K / (U + S)` against the exact ratio of a bar stretched
//!   slowly, its growth with the mass factor, and its warning above the limit;
//! - the weight keeps the true mass; the sections' bad values are rejected with their path.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::json;

/// The largest |force_y| of the top wall in `walls.csv`, and the wall's last `u_y`.
fn wall_peak_and_end(out: &Path) -> (f64, f64) {
    let text = std::fs::read_to_string(out.join("walls.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let f = head.iter().position(|h| *h == "force_y[top]").unwrap();
    let u = head.iter().position(|h| *h == "u_y[top]").unwrap();
    let (mut peak, mut end) = (0.0f64, 0.0);
    for l in lines {
        let r: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        peak = peak.max(r[f].abs());
        end = r[u];
    }
    (peak, end)
}

/// The Brazilian disc on the small mesh at the shipped platen speed, no frames, with the
/// given mass-scaling factor and loading rate.
fn disc(tag: &str, factor: f64, rate: f64) -> PathBuf {
    common::edited_example("brazilian-disc-fracture.json", tag, |v| {
        v["bodies"][0]["mesh"] = json!(common::root().join("meshes/disc-small.msh"));
        v["output"] = json!({ "frames": 0 });
        // walls.csv at every step: its last row is the end
        v["histories"] = json!({ "every": 1, "probes": [] });
        if factor != 1.0 {
            v["mass_scaling"] = json!({ "factor": factor });
        }
        if rate != 1.0 {
            v["loading"] = json!({ "rate": rate });
        }
    })
}

/// Disc at half the shipped rate: factor 4 against the unscaled run; the same factor against
/// the shipped rate unscaled; the end displacement of the walls at both rates.
#[test]
fn mass_scaling_keeps_the_disc_peak_and_equals_a_faster_rate() {
    let (a, out_a) = common::run(&disc("qs_disc_f1", 1.0, 0.5));
    let (b, out_b) = common::run(&disc("qs_disc_f4", 4.0, 0.5));
    let (c, out_c) = common::run(&disc("qs_disc_r1", 1.0, 1.0));
    let (pa, ua) = wall_peak_and_end(&out_a);
    let (pb, _) = wall_peak_and_end(&out_b);
    let (pc, uc) = wall_peak_and_end(&out_c);
    // the stable step grows by sqrt(4) = 2 (measured: 2.0 exactly)
    let ratio = b.summary.time_step_limit / a.summary.time_step_limit;
    eprintln!(
        "disc: step limit ratio {ratio:.17} (f = 4); peak {pa:.2} N unscaled, {pb:.2} N f = 4 ({:+.3} %), {pc:.2} N rate 1 (f = 4 vs rate 1: {:.2e}); wall end {ua:.6e} / {uc:.6e}",
        100.0 * (pb / pa - 1.0),
        (pb / pc - 1.0).abs()
    );
    assert!((ratio - 2.0).abs() < 1e-12, "step limit ratio {ratio}");
    assert_eq!(b.summary.mass_scaling_factor, Some(4.0));
    assert!(b.summary.steps * 2 <= a.summary.steps + 2, "steps");
    // peak within 2 % of the unscaled run (measured: 2434.4 N against 2418.1 N, +0.68 %)
    let d = pb / pa - 1.0;
    assert!(d.abs() < 0.02, "peak {pb} N vs unscaled {pa} N: {d:+.4}");
    // mass scaling 4 at rate 0.5 is the unscaled run at rate 1 (measured: the same peak to
    // the last bit)
    let e = (pb / pc - 1.0).abs();
    assert!(
        e < 1e-8,
        "factor 4, rate 0.5: {pb} N; rate 1: {pc} N ({e:.2e})"
    );
    assert_eq!(
        b.summary.stages["fracture"]["broken"],
        c.summary.stages["fracture"]["broken"]
    );
    // rate 0.5 doubles the duration and ends at the same wall displacement (measured: both
    // -3.200000e-5 m)
    let t = a.summary.simulated_time / c.summary.simulated_time;
    assert!((t - 2.0).abs() < 1e-12, "duration ratio {t}");
    assert!((ua / uc - 1.0).abs() < 1e-12, "wall end {ua} vs {uc}");
    assert!(uc < -2e-5, "the walls moved: {uc}");
    fdem_figures::record(
        101,
        if ratio == 2.0 {
            "2 exactly".to_string()
        } else {
            format!("{ratio:.15}")
        },
    );
    fdem_figures::record(102, format!("{pb:.1} N, {:+.2} %", 100.0 * d));
    fdem_figures::record(
        103,
        if e == 0.0 {
            "identical peaks".to_string()
        } else {
            format!("peaks within {e:.1e}")
        },
    );
    let dev = (t - 2.0).abs().max((ua / uc - 1.0).abs());
    fdem_figures::record_part(
        104,
        1,
        if dev == 0.0 {
            "exact".to_string()
        } else {
            format!("within {dev:.1e}")
        },
    );
}

/// A bar `[0, 1] x [0, 0.1]` (20 x 2 cells, E = 200 MPa, nu = 0, rho = 2000: c = 316 m/s,
/// first period 4 L / c = 12.6 ms) fixed at the left end, its right end pulled at `v` over a
/// ramp of 15 periods, for 40 periods; histories every 100 steps (the indicator's checks).
fn bar(tag: &str, extra: serde_json::Value) -> PathBuf {
    let dir = common::temp_dir(tag);
    common::rectangle_with_sides(&dir, 20, 2, 1.0, 0.1);
    let t1 = 4.0 / (2e8f64 / 2000.0).sqrt();
    let mut s = json!({
        "bodies": [{ "mesh": "rect.json", "materials": { "*": { "young": 2e8, "poisson": 0.0, "density": 2000.0, "plane": "stress" } } }],
        "boundary_conditions": [
            { "fixed": { "group": "left", "x": true, "y": true } },
            { "velocity": { "group": "right", "x": 1e-3, "ramp": 15.0 * t1 } }
        ],
        "integrator": { "scheme": "central-difference", "time_step": "auto", "safety": 0.9 },
        "duration": 40.0 * t1,
        "output": { "frames": 0 },
        "histories": { "every": 100, "probes": [ { "displacement": { "group": "right" } }, "energy" ] }
    });
    for (k, v) in extra.as_object().unwrap() {
        s[k] = v.clone();
    }
    let p = dir.join("bar.json");
    std::fs::write(&p, s.to_string()).unwrap();
    p
}

/// The exact quasi-static ratio of the bar at end displacement `u` and end velocity 1e-3:
/// kinetic energy of the free columns `1/2 sum_{i=1}^{19} (rho t ly h) (v i / 20)^2` over the
/// strain energy `E (u / L)^2 L ly t / 2` (times the mass factor `f`).
fn bar_ratio(u: f64, f: f64) -> f64 {
    let (rho, e, ly, h, v) = (2000.0, 2e8, 0.1, 0.05, 1e-3);
    let k: f64 = (1..20)
        .map(|i| 0.5 * f * rho * ly * h * (v * i as f64 / 20.0).powi(2))
        .sum();
    k / (0.5 * e * u * u * ly)
}

/// The indicator of a bar run: (summary's indicator, its time, the exact ratio then, the
/// histories' ratio at the same row).
fn bar_indicator(out: &Path, o: &fdem_solver::driver::Outcome, f: f64) -> (f64, f64, f64, f64) {
    let q = o.summary.quasi_static.clone().expect("the indicator");
    let (head, rows) = common::histories(out);
    let t = common::column(&head, &rows, "time");
    let u = common::column(&head, &rows, "u_x[right]");
    let r = common::column(&head, &rows, "kinetic_ratio");
    let i = t.iter().position(|x| *x == q.transient_end).unwrap();
    (q.kinetic_ratio_max, t[i], bar_ratio(u[i], f), r[i])
}

/// The indicator against the exact ratio of a slowly stretched bar, and the histories'
/// column against the summary (the same checks).
#[test]
fn indicator_matches_a_slowly_stretched_bar() {
    let (o1, out1) = common::run(&bar("qs_bar_f1", json!({ "loading": { "rate": 1.0 } })));
    let (ind, t, exact, col) = bar_indicator(&out1, &o1, 1.0);
    // the largest ratio while loading is at the window's start (the ratio falls as 1/t^2)
    // measured: 1.6879e-4 against the exact 1.6903e-4 (-0.14 %)
    let e = ind / exact - 1.0;
    eprintln!("bar: indicator {ind:.5e} at t = {t:.4e} s, exact {exact:.5e} ({e:+.4})");
    assert!(
        e.abs() < 0.03,
        "indicator {ind:.5e} at t = {t:.4e} s, exact {exact:.5e} ({e:+.4})"
    );
    assert!(
        (col / ind - 1.0).abs() < 1e-12,
        "histories {col} vs summary {ind}"
    );
    // mass scaling 4: four times the ratio (measured: -0.05 % off the exact ratio, 4.006
    // times the unscaled indicator)
    let (o4, out4) = common::run(&bar(
        "qs_bar_f4",
        json!({ "mass_scaling": { "factor": 4.0 } }),
    ));
    let (ind4, t4, exact4, _) = bar_indicator(&out4, &o4, 4.0);
    let e4 = ind4 / exact4 - 1.0;
    assert!(
        e4.abs() < 0.03,
        "f = 4: indicator {ind4:.5e} at t = {t4:.4e} s, exact {exact4:.5e} ({e4:+.4})"
    );
    let g = ind4 / ind;
    eprintln!("bar f = 4: indicator {ind4:.5e}, exact {exact4:.5e} ({e4:+.4}); growth {g:.4}");
    assert!((g / 4.0 - 1.0).abs() < 0.05, "growth with the factor: {g}");
    assert!(o1.summary.quasi_static.as_ref().unwrap().warning.is_none());
    fdem_figures::record(
        105,
        format!("{:+.2} %, {:+.2} %; {g:.3}", 100.0 * e, 100.0 * e4),
    );
}

/// The warning: in summary.json and on stderr above the limit, absent below it.
#[test]
fn indicator_warns_above_its_limit() {
    let probe = bar("qs_bar_probe", json!({ "loading": { "rate": 1.0 } }));
    let (o, _) = common::run(&probe);
    let r = o.summary.quasi_static.unwrap().kinetic_ratio_max;
    for (limit, warned) in [(0.5 * r, true), (2.0 * r, false)] {
        let p = bar(
            &format!("qs_bar_warn_{warned}"),
            json!({ "loading": { "rate": 1.0, "kinetic_ratio_limit": limit } }),
        );
        let out = p.parent().unwrap().join("out");
        let o = Command::new(env!("CARGO_BIN_EXE_fdem"))
            .args(["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(o.status.success());
        let console = format!(
            "{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        let w = &s["quasi_static"]["warning"];
        assert_eq!(w.is_string(), warned, "limit {limit}: {w}");
        // the warning once, in the accuracy block of the console
        let once = usize::from(warned);
        assert_eq!(
            console.matches("the run is not quasi-static").count(),
            once,
            "{console}"
        );
        assert_eq!(
            console.matches("WARN quasi_static").count(),
            once,
            "{console}"
        );
        assert_eq!(s["quasi_static"]["limit"].as_f64(), Some(limit));
    }
    fdem_figures::record(106, "as expected");
}

/// Rate 0.5 is the scene with halved velocities and doubled ramp and duration, bit for bit.
#[test]
fn loading_rate_is_the_scene_edited_by_hand() {
    let t1 = 4.0 / (2e8f64 / 2000.0).sqrt();
    let (_, out_r) = common::run(&bar("qs_bar_rate", json!({ "loading": { "rate": 0.5 } })));
    let by_hand = bar(
        "qs_bar_hand",
        json!({
            "boundary_conditions": [
                { "fixed": { "group": "left", "x": true, "y": true } },
                { "velocity": { "group": "right", "x": 0.5e-3, "ramp": 30.0 * t1 } }
            ],
            "duration": 80.0 * t1,
        }),
    );
    let (_, out_h) = common::run(&by_hand);
    let (hr, rr) = common::histories(&out_r);
    let (hh, rh) = common::histories(&out_h);
    // the same columns but the indicator (a scene with a loading section has it)
    for name in ["time", "u_x[right]", "kinetic", "strain"] {
        assert_eq!(
            common::column(&hr, &rr, name),
            common::column(&hh, &rh, name),
            "{name}"
        );
    }
    fdem_figures::record_part(104, 2, "identical columns");
}

/// The weight `m g` keeps the true mass under mass scaling.
#[test]
fn weight_keeps_the_true_mass() {
    let dir = common::temp_dir("qs_weight");
    common::rectangle_with_sides(&dir, 4, 2, 1.0, 0.5);
    let scene = |f: f64| {
        json!({
            "bodies": [{ "mesh": "rect.json", "materials": { "*": { "young": 1e9, "poisson": 0.25, "density": 2000.0 } } }],
            "boundary_conditions": [{ "fixed": { "group": "bottom", "x": true, "y": true } }],
            "gravity": [0.0, -9.81],
            "mass_scaling": { "factor": f },
            "duration": 1e-3,
            "output": { "frames": 0 }
        })
    };
    let mut forces = Vec::new();
    for f in [1.0, 100.0] {
        let p = dir.join(format!("w{f}.json"));
        std::fs::write(&p, scene(f).to_string()).unwrap();
        let l = fdem_solver::driver::load(&p).unwrap();
        let mut ext = vec![0.0; 2 * l.model.n_nodes()];
        l.model.add_external(0.0, &mut ext);
        forces.push(ext);
        assert!((l.model.mass_factor() - f).abs() < 1e-15);
    }
    assert_eq!(
        forces[0], forces[1],
        "the weight changed with the mass factor"
    );
    assert!(forces[0].iter().any(|f| *f < 0.0));
    fdem_figures::record(107, "identical");
}

/// Bad values of the sections, each named by its path.
#[test]
fn bad_sections_are_rejected_with_their_path() {
    let dir = common::temp_dir("qs_bad");
    common::rectangle_with_sides(&dir, 4, 2, 1.0, 0.5);
    let base = json!({
        "bodies": [{ "mesh": "rect.json", "materials": { "*": { "young": 1e9, "poisson": 0.25, "density": 2000.0 } } }],
        "boundary_conditions": [{ "fixed": { "group": "bottom", "x": true, "y": true } }],
        "duration": 1e-3,
        "output": { "frames": 0 }
    });
    let cases = [
        (
            json!({ "mass_scaling": { "factor": 0.5 } }),
            "mass_scaling.factor",
            ">= 1",
        ),
        (
            json!({ "mass_scaling": { "factor": 4.0, "target_step": 1e-6 } }),
            "mass_scaling",
            "both",
        ),
        (json!({ "mass_scaling": {} }), "mass_scaling", "neither"),
        (
            json!({ "mass_scaling": { "target_step": -1.0 } }),
            "mass_scaling.target_step",
            "positive",
        ),
        (
            json!({ "mass_scaling": { "target_step": 1e-12 } }),
            "mass_scaling.target_step",
            "below the unscaled step",
        ),
        (
            json!({ "mass_scaling": { "fator": 4.0 } }),
            "mass_scaling.fator",
            "unknown field",
        ),
        (
            json!({ "loading": { "rate": 0.0 } }),
            "loading.rate",
            "positive",
        ),
        (
            json!({ "loading": { "rate": 1e-320 } }),
            "loading.rate",
            "finite",
        ),
        (
            json!({ "loading": { "kinetic_ratio_limit": -1.0 } }),
            "loading.kinetic_ratio_limit",
            "positive",
        ),
        (
            json!({ "analysis": "static", "mass_scaling": { "factor": 4.0 } }),
            "mass_scaling",
            "static",
        ),
        (
            json!({ "integrator": { "time_step": 1e-6 }, "mass_scaling": { "target_step": 1e-5 } }),
            "mass_scaling.target_step",
            "fixed",
        ),
    ];
    for (i, (extra, path, what)) in cases.iter().enumerate() {
        let mut s = base.clone();
        for (k, v) in extra.as_object().unwrap() {
            s[k] = v.clone();
        }
        let p = dir.join(format!("bad{i}.json"));
        std::fs::write(&p, s.to_string()).unwrap();
        let e = match fdem_solver::driver::load(&p) {
            Ok(_) => panic!("case {i} ({extra}) was accepted"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(path) && e.contains(what), "case {i}: {e}");
    }
    // a target step above the unscaled one gives that step (the factor (target / h)^2)
    let mut s = base.clone();
    s["mass_scaling"] = json!({ "target_step": 1e-3 });
    s["duration"] = json!(0.1);
    let p = dir.join("target.json");
    std::fs::write(&p, s.to_string()).unwrap();
    let l = fdem_solver::driver::load(&p).unwrap();
    let h = l.scene.integrator.safety * l.dt_limit;
    assert!((h / 1e-3 - 1.0).abs() < 1e-12, "target step: {h}");
    assert!(l.dt <= 1e-3 && l.dt > 0.99e-3, "step {}", l.dt);
    assert!(
        l.model.mass_factor() > 50.0,
        "factor {}",
        l.model.mass_factor()
    );
}
