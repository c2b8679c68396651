//! The accuracy indicators (docs/accuracy.md): `fdem check` predicts what the run reports;
//! the shipped examples raise no warning; deliberately inaccurate variants of the validation
//! specimens are each warned, with their measured error against the accurate reference.

use crate::common;
use crate::cracks::{GRIFFITH_FT, griffith_run, griffith_scene, griffith_stress_of};

use fdem_solver::driver;
use fdem_solver::problem::indicator::Indicator;
use fdem_solver::run::accuracy::before_run;
use serde_json::json;

/// The indicator `name` (of `subject` when given) in `list`.
fn find<'a>(list: &'a [Indicator], name: &str) -> &'a Indicator {
    list.iter()
        .find(|i| i.name == name)
        .unwrap_or_else(|| panic!("no indicator {name} in {list:?}"))
}

/// The names of the indicators that warn.
fn warned(list: &[Indicator]) -> Vec<String> {
    list.iter()
        .filter(|i| !i.passes())
        .map(|i| i.name.clone())
        .collect()
}

/// Every shipped example (static, dynamic, fracturing) predicts no warning but the two
/// compression specimens' loading speed (shipped at 0.1 m/s per platen: their peak loads are
/// 6 % above a run 4 times slower, docs/speed-vs-accuracy.md), and its indicators are finite.
#[test]
fn every_shipped_example_predicts_no_warning() {
    let mut n = 0;
    for entry in std::fs::read_dir(common::root().join("examples")).unwrap() {
        let p = entry.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if !name.ends_with(".json") || name.ends_with(".study.json") {
            continue;
        }
        let l = driver::load(&p).unwrap();
        let list = before_run(&l);
        assert!(list.iter().all(|i| i.value.is_finite()), "{name}: {list:?}");
        let expected: &[&str] = match name.as_str() {
            "block-compression-fracture.json" | "wing-crack.json" => &["loading_speed"],
            _ => &[],
        };
        assert_eq!(warned(&list), expected, "{name}");
        n += 1;
    }
    assert!(n >= 15, "{n} examples");
}

/// `fdem check`'s indicators (process zone, joint compliance, mesh, units, time step) are the
/// ones the run reports, value for value, on the fracturing disc (a short run).
#[test]
fn check_predicts_the_indicators_the_run_reports() {
    let scene = common::edited_example("brazilian-disc-fracture.json", "acc-predict", |v| {
        v["duration"] = json!(2e-5);
        v["output"]["frames"] = json!(0);
    });
    let l = driver::load(&scene).unwrap();
    let predicted = before_run(&l);
    let (o, _) = common::run(&scene);
    let reported = &o.summary.accuracy.indicators;
    for name in [
        "process_zone_i",
        "process_zone_ii",
        "joint_compliance",
        "mesh_quality",
        "units",
        "time_step",
    ] {
        let (p, r) = (find(&predicted, name), find(reported, name));
        assert_eq!(p.value.to_bits(), r.value.to_bits(), "{name}");
        assert_eq!(
            (p.threshold, &p.warning),
            (r.threshold, &r.warning),
            "{name}"
        );
    }
    // the run adds what it measured
    for name in ["energy_error", "quasi_static", "contact_penetration"] {
        find(reported, name);
    }
    let pz = find(&predicted, "process_zone_i");
    // l_ch = E G_I / ft^2 = 30e9 * 50 / 3e6^2 = 0.1667 m over the median joint
    let l_ch = pz.details["l_ch_median"].as_f64().unwrap();
    assert!((l_ch / (30e9 * 50.0 / 9e12) - 1.0).abs() < 1e-12, "{l_ch}");
    let h = pz.details["h_min"].as_f64().unwrap();
    assert_eq!(pz.value, l_ch / h);
    assert_eq!(find(&predicted, "joint_compliance").value, 0.1);
    fdem_figures::record(
        142,
        format!(
            "equal bit for bit (6 indicators); l_ch / h = {:.1}",
            pz.value
        ),
    );
}

/// The Griffith plate (docs/validation.md, row 70) with a fracture energy lowered so that
/// l_ch is half the median joint: warned (process zone), and its failure stress far above
/// Griffith's, against +4.7 % for the accurate plate (l_ch / h = 7.7, no warning).
#[test]
fn a_griffith_plate_with_joints_twice_l_ch_is_warned_and_fails_far_above_fracture_mechanics() {
    let accurate = driver::load(&griffith_scene(
        "griffith-plate-coarse.msh",
        1e-2,
        8.0,
        20.0,
    ))
    .unwrap();
    let pz = find(&accurate.accuracy, "process_zone_i");
    assert!(pz.passes(), "{pz:?}");
    let h = pz.details["h_min"].as_f64().unwrap();
    // l_ch = E G / ft^2 = h / 2, with a penalty of 100 E (20 E in the accurate plate) so that
    // the longest joints keep G_I above their pre-peak work
    let g = 0.5 * h * GRIFFITH_FT * GRIFFITH_FT / 10e9;
    let (s, _, o) = griffith_run("griffith-plate-coarse.msh", 1e-2, g, 100.0);
    let (_, finite) = griffith_stress_of(g);
    let list = &o.summary.accuracy.indicators;
    let ind = find(list, "process_zone_i");
    assert!((ind.value - 0.5).abs() < 1e-9, "{}", ind.value);
    let w = ind.warning.as_deref().expect("warned");
    assert!(
        w.contains("refine") && w.contains("fracture_energy_i"),
        "{w}"
    );
    let err = s / finite - 1.0;
    eprintln!(
        "Griffith at l_ch = h/2 (G_I = {g:.3} J/m^2): {s:.4e} Pa against {finite:.4e} Pa: {:+.1} %",
        100.0 * err
    );
    assert!(err > 0.2, "{err}");
    fdem_figures::record_part(
        143,
        1,
        format!("Griffith l_ch / h = 0.5: {:+.0} %", 100.0 * err),
    );
}

/// The notched beam with joint penalties `penalty_factor` E: its pre-peak secant stiffness
/// and peak [N] (`fracture_specimens::notched_curve`), and its accuracy indicators.
fn notched_beam(tag: &str, penalty_factor: f64) -> (f64, f64, Vec<Indicator>) {
    let scene = common::edited_example("notched-beam-fracture.json", tag, |v| {
        let m = &mut v["fracture"]["material"];
        m["penalty_normal"] = json!(penalty_factor * 30e9);
        m["penalty_tangential"] = json!(penalty_factor * 30e9);
        v["output"]["frames"] = json!(0);
    });
    let (o, out) = common::run(&scene);
    let c = crate::fracture_specimens::notched_curve(&out);
    (c.k, c.p[c.ip], o.summary.accuracy.indicators)
}

/// The notched beam with a joint penalty of 1 E (the example's 10 E is the accurate
/// reference): warned (joint compliance), and softer and lower than the reference.
#[test]
fn a_notched_beam_with_a_joint_penalty_of_one_e_is_warned_and_too_soft() {
    let (k10, p10, ok) = notched_beam("acc-nb-10", 10.0);
    let (k1, p1, bad) = notched_beam("acc-nb-1", 1.0);
    assert!(find(&ok, "joint_compliance").passes());
    let ind = find(&bad, "joint_compliance");
    assert_eq!(ind.value, 1.0);
    assert!(ind.warning.as_deref().unwrap().contains("penalty_normal"));
    let (dk, dp) = (k1 / k10 - 1.0, p1 / p10 - 1.0);
    eprintln!(
        "notched beam p = 1 E against 10 E: stiffness {:+.1} %, peak {:+.1} %",
        100.0 * dk,
        100.0 * dp
    );
    assert!(dk < -0.05, "{dk}");
    fdem_figures::record_part(
        143,
        2,
        format!(
            "notched beam p = 1 E: stiffness {:+.0} %, peak {:+.0} %",
            100.0 * dk,
            100.0 * dp
        ),
    );
}

/// The largest force of the top platen on the fracturing disc [N].
fn disc_peak(out: &std::path::Path) -> f64 {
    let text = std::fs::read_to_string(out.join("walls.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = head.iter().position(|c| *c == "force_y[top]").unwrap();
    lines
        .map(|l| -l.split(',').nth(col).unwrap().parse::<f64>().unwrap())
        .fold(0.0, f64::max)
}

/// The Brazilian disc with its platens 20 times faster: warned (loading speed; the kinetic
/// ratio stays below its limit, docs/speed-vs-accuracy.md), and its peak load above
/// `pi D t ft / 2` by more than the example's.
#[test]
fn a_brazilian_disc_loaded_20_times_faster_is_warned_for_its_loading_speed() {
    let scene = common::edited_example("brazilian-disc-fracture.json", "acc-fast", |v| {
        for w in v["contact"]["walls"].as_array_mut().unwrap() {
            let vy = w["velocity"][1].as_f64().unwrap();
            w["velocity"][1] = json!(20.0 * vy);
            w["ramp"] = json!(w["ramp"].as_f64().unwrap() / 20.0);
        }
        v["duration"] = json!(v["duration"].as_f64().unwrap() / 20.0);
        v["output"]["frames"] = json!(0);
    });
    let (o, out) = common::run(&scene);
    let p_th = std::f64::consts::PI * 0.05 * 0.01 * 3e6 / 2.0;
    let err = disc_peak(&out) / p_th - 1.0;
    let list = &o.summary.accuracy.indicators;
    let (q, ind) = (find(list, "quasi_static"), find(list, "loading_speed"));
    eprintln!(
        "disc loaded 20x faster: speed {:.2e} of the wave speed, kinetic ratio {:.3}, peak {:+.1} % against pi D t ft / 2",
        ind.value,
        q.value,
        100.0 * err
    );
    assert!(!ind.passes(), "{ind:?}");
    assert!(ind.warning.as_deref().unwrap().contains("times slower"));
    assert!(err > 0.05, "{err}");
    fdem_figures::record_part(
        143,
        3,
        format!("disc 20x faster: peak {:+.0} %", 100.0 * err),
    );
}

/// The disc collision with a contact penalty 1000 times softer than the default (10 E):
/// warned (contact penetration), with overlaps far deeper than the accurate run's.
#[test]
fn a_collision_with_a_contact_penalty_1000_times_too_soft_is_warned() {
    let run = |tag: &str, factor: f64| {
        let scene = common::edited_example("disc-collision.json", tag, |v| {
            v["contact"] = json!({"default": {"penalty_factor": factor}});
            v["output"]["frames"] = json!(0);
        });
        common::run(&scene).0.summary.accuracy.indicators
    };
    let (ok, bad) = (run("acc-hard", 10.0), run("acc-soft", 0.01));
    let (a, b) = (
        find(&ok, "contact_penetration"),
        find(&bad, "contact_penetration"),
    );
    eprintln!(
        "collision: deepest overlap {:.2e} (penalty 10 E), {:.2e} (0.01 E) of the element",
        a.value, b.value
    );
    assert!(a.passes() && !b.passes(), "{a:?} {b:?}");
    assert!(b.warning.as_deref().unwrap().contains("penalty"));
    // the mean over the loaded contacts of every pass: below the deepest, and deeper with
    // the soft penalty too
    let mean = |i: &fdem_solver::problem::indicator::Indicator| {
        i.details["mean_depth_over_altitude"].as_f64().unwrap()
    };
    eprintln!(
        "collision: mean overlap {:.2e} (penalty 10 E), {:.2e} (0.01 E)",
        mean(a),
        mean(b)
    );
    for i in [a, b] {
        assert!(mean(i) > 0.0 && mean(i) < i.value, "{i:?}");
    }
    assert!(mean(b) > 5.0 * mean(a), "{} {}", mean(a), mean(b));
    fdem_figures::record_part(
        143,
        4,
        format!(
            "collision p = 0.01 E: overlap {:.0} times the accurate run's",
            b.value / a.value
        ),
    );
}

/// The elastic disc with Young's modulus typed in GPa as Pa (30 for 30e9): a static solve
/// that runs, flagged as a unit slip (wave speed) and as leaving the small-strain range.
#[test]
fn a_modulus_typed_in_gpa_is_flagged_as_a_unit_slip_and_a_large_strain() {
    let scene = common::edited_example("brazilian-disc-elastic.json", "acc-gpa", |v| {
        for m in v["bodies"][0]["materials"]
            .as_object_mut()
            .unwrap()
            .values_mut()
        {
            let e = m["young"].as_f64().unwrap();
            m["young"] = json!(e / 1e9);
        }
    });
    let (o, _) = common::run(&scene);
    let list = &o.summary.accuracy.indicators;
    assert_eq!(warned(list), ["units", "static_strain"]);
    assert!(
        find(list, "units")
            .warning
            .as_deref()
            .unwrap()
            .contains("young in GPa?")
    );
    let good = common::run(&common::edited_example(
        "brazilian-disc-elastic.json",
        "acc-pa",
        |_| {},
    ))
    .0;
    let strain = find(&good.summary.accuracy.indicators, "static_strain").value;
    // linear: the strain scales as 1 / E
    let bad = find(list, "static_strain").value;
    assert!((bad / strain / 1e9 - 1.0).abs() < 1e-6, "{bad} {strain}");
    fdem_figures::record(
        144,
        format!(
            "flagged; largest strain {} (Pa: {})",
            fdem_figures::sci(bad, 1),
            fdem_figures::sci(strain, 1)
        ),
    );
}
