//! General rules of trust: the energy-growth check never stops a stable run for round-off
//! (class 6: a body at rest, platens started away from the specimen); every tolerance,
//! factor and rate of a scene has a valid range checked at load (class 9); a check on a
//! derived quantity names the input that drives it (class 10).

use crate::common;

use std::path::Path;

use serde_json::{Value, json};

use crate::common::fdem;
use crate::common::fdem_run as run;

/// A run that must end with exit code 0; returns its output folder.
fn succeeds(scene: &Path, tag: &str) -> std::path::PathBuf {
    let out = scene.parent().unwrap().join(format!("out-{tag}"));
    let (code, _, err) = run(scene, &out);
    assert_eq!(code, 0, "{tag}: exit code {code}, stderr:\n{err}");
    out
}

/// The largest `|force_y|` of any wall over the rows of `walls.csv` in `out`.
fn largest_wall_force(out: &Path) -> f64 {
    let text = std::fs::read_to_string(out.join("walls.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let cols: Vec<usize> = (0..head.len())
        .filter(|&k| head[k].starts_with("force_y"))
        .collect();
    assert!(!cols.is_empty(), "{head:?}");
    lines
        .flat_map(|l| {
            let row: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            cols.iter().map(move |&k| row[k].abs()).collect::<Vec<_>>()
        })
        .fold(0.0, f64::max)
}

/// Moves every wall of the scene `v` 1 mm away from the specimen (against its normal, which
/// points into the free side).
fn walls_one_mm_away(v: &mut Value) {
    for w in v["contact"]["walls"].as_array_mut().unwrap() {
        let n = [
            w["normal"][0].as_f64().unwrap(),
            w["normal"][1].as_f64().unwrap(),
        ];
        let len = n[0].hypot(n[1]);
        for k in 0..2 {
            let p = w["point"][k].as_f64().unwrap();
            w["point"][k] = json!(p - 1e-3 * n[k] / len);
        }
    }
}

/// The shipped scenes (not studies) that have rigid walls.
fn examples_with_walls() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(common::root().join("examples"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".json") && !n.ends_with(".study.json"))
        .filter(|n| {
            let text = std::fs::read_to_string(common::root().join("examples").join(n)).unwrap();
            let v: Value = serde_json::from_str(&text).unwrap();
            v["contact"]["walls"]
                .as_array()
                .is_some_and(|w| !w.is_empty())
        })
        .collect();
    names.sort();
    names
}

/// Two discs at rest, no load, no support (the shipped collision with the left disc's
/// velocity removed), 3000 steps: nothing happens but round-off. Before the round-off
/// floor, the energy-growth check stopped it at step 100 (exit 3: `3.6e-23 J` of strain
/// round-off, 45 times the initial `8e-25 J`), with the fix "lower `integrator.safety`",
/// which does not help. The fracturing block without its platens, at rest, likewise.
#[test]
fn class6_bodies_at_rest_without_loads_run_to_the_end() {
    let discs = common::edited_example("disc-collision.json", "class6-rest-discs", |v| {
        v["bodies"][0]["initial_velocity"] = json!([0.0, 0.0]);
        v["duration"] = json!(3000.0 * 8.9658e-8);
        v["output"]["frames"] = json!(1);
    });
    succeeds(&discs, "rest-discs");
    let block = common::edited_example(
        "block-compression-fracture.json",
        "class6-rest-block",
        |v| {
            v["contact"]["walls"] = json!([]);
            v["duration"] = json!(3000.0 * 3.6964e-8);
            v["output"]["frames"] = json!(1);
        },
    );
    succeeds(&block, "rest-block");
    fdem_figures::record_part(132, 1, "at rest: exit 0");
}

/// The fracturing block with its platens started 1 mm away from it, loaded ten times faster
/// (`loading.rate` 10: the platens at 1 m/s) for long enough that they close the gap and
/// press on the block (the walls' force is nonzero by the end). Before the round-off floor,
/// it stopped at step 100 (exit 3: `5.2e-24 J` of round-off, 106 times the initial
/// `4.9e-26 J`).
#[test]
fn class6_platens_started_away_from_the_specimen_reach_it_without_a_false_alarm() {
    let s = common::edited_example("block-compression-fracture.json", "class6-gap", |v| {
        walls_one_mm_away(v);
        v["loading"] = json!({ "rate": 10.0 });
        // 1.1e-3 s at rate 10: the gap closes at 1.005e-3 s
        v["duration"] = json!(1.1e-2);
        v["output"]["frames"] = json!(0);
    });
    let out = succeeds(&s, "gap");
    let f = largest_wall_force(&out);
    assert!(
        f > 1e3,
        "the platens did not reach the block: largest force {f} N"
    );
    fdem_figures::record_part(132, 2, format!("platens: exit 0, largest force {f:.0} N"));
}

/// Every shipped scene with walls, its walls started 1 mm away from the specimen, runs to the
/// end (exit 0) over the first 5 % of its duration (1300 to 4800 steps: the round-off that
/// stopped them, at step 100, is there from the start).
#[test]
fn class6_every_example_with_walls_started_1_mm_away_runs_to_the_end() {
    let names = examples_with_walls();
    assert!(names.len() >= 3, "{names:?}");
    for name in &names {
        let s = common::edited_example(name, "class6-walls", |v| {
            walls_one_mm_away(v);
            v["duration"] = json!(0.05 * v["duration"].as_f64().unwrap());
            v["output"]["frames"] = json!(1);
        });
        succeeds(&s, name);
    }
    fdem_figures::record_part(
        132,
        3,
        format!("{} examples with walls: exit 0", names.len()),
    );
}

/// Refused as bad input by `fdem check` and by `fdem run` alike: exit code 2 from both, the
/// same error (from `error:` to the end of its `fix:` line), no output folder; returns the
/// error.
fn refused_by_check_and_run(scene: &Path, tag: &str) -> String {
    let (code_c, _, err_c) = fdem(&["check".as_ref(), scene.as_os_str()]);
    assert_eq!(
        code_c, 2,
        "{tag}: fdem check exit code {code_c}, stderr:\n{err_c}"
    );
    let out = scene.parent().unwrap().join(format!("out-{tag}"));
    let (code_r, _, err_r) = run(scene, &out);
    assert_eq!(
        code_r, 2,
        "{tag}: fdem run exit code {code_r}, stderr:\n{err_r}"
    );
    assert!(!out.exists(), "{tag}: {} was created", out.display());
    let error = |e: &str| -> String {
        let start = e
            .find("error:")
            .unwrap_or_else(|| panic!("{tag}: no error in\n{e}"));
        let rest = &e[start..];
        let fix = rest.find("\n  fix:").map_or(rest.len(), |f| {
            f + rest[f + 1..].find('\n').map_or(rest.len() - f, |n| n + 1)
        });
        rest[..fix].to_string()
    };
    assert_eq!(error(&err_c), error(&err_r), "{tag}: check and run differ");
    for internal in ["panicked", "index:", "NonPositivePivot"] {
        assert!(
            !err_c.contains(internal),
            "{tag}: internal wording:\n{err_c}"
        );
    }
    error(&err_r)
}

/// Sets the value at the JSON pointer `ptr` of `v`, creating the objects on the way.
fn set(v: &mut Value, ptr: &str, value: Value) {
    let mut cur = v;
    for key in ptr.trim_start_matches('/').split('/') {
        cur = match cur {
            Value::Array(a) => &mut a[key.parse::<usize>().unwrap()],
            other => {
                if !other.is_object() {
                    *other = json!({});
                }
                other
                    .as_object_mut()
                    .unwrap()
                    .entry(key)
                    .or_insert(Value::Null)
            }
        };
    }
    *cur = value;
}

/// A relaxation tolerance of 1 or more passes the unloaded state itself (its residual, the
/// load, is 1 times the load): the cantilever relaxation was reported converged at once
/// (exit 0). Refused at load, with the path, the value and the range (0, 1).
#[test]
fn class9_relaxation_tolerance_of_one_or_more_is_refused() {
    for tol in [1.0, 1.5, 1e3] {
        let s = common::edited_example("cantilever-relaxation.json", "class9-tol", |v| {
            v["integrator"]["relaxation_tolerance"] = json!(tol);
        });
        let err = refused_by_check_and_run(&s, &format!("tol-{tol}"));
        assert!(
            err.contains("at `integrator.relaxation_tolerance`")
                && err.contains(&format!("relaxation tolerance {tol} "))
                && err.contains("(0, 1)")
                && err.contains("fix:"),
            "{err}"
        );
    }
    // a tolerance in range is accepted
    let s = common::edited_example("cantilever-relaxation.json", "class9-tol-ok", |v| {
        v["integrator"]["relaxation_tolerance"] = json!(0.5);
    });
    let (code, _, err) = fdem(&["check".as_ref(), s.as_os_str()]);
    assert_eq!(code, 0, "{err}");
}

/// Every tolerance, factor, ratio and rate out of its range: refused at load by `fdem check`
/// and `fdem run` with exit code 2, the same message, naming the JSON path (not a parent
/// section), the value and the range. Rows: (example, JSON pointer, value, path, range).
#[test]
fn class9_every_range_is_checked_at_load_with_its_path() {
    let rows: &[(&str, &str, Value, &str, &str)] = &[
        (
            "cantilever-relaxation.json",
            "/integrator/relaxation_tolerance",
            json!(0.0),
            "integrator.relaxation_tolerance",
            "(0, 1)",
        ),
        (
            "cantilever-relaxation.json",
            "/integrator/relaxation_tolerance",
            json!(-1e-8),
            "integrator.relaxation_tolerance",
            "(0, 1)",
        ),
        (
            "cantilever-vibration.json",
            "/integrator/safety",
            json!(1.5),
            "integrator.safety",
            "(0, 1]",
        ),
        (
            "cantilever-vibration.json",
            "/integrator/safety",
            json!(0.0),
            "integrator.safety",
            "(0, 1]",
        ),
        (
            "cantilever-vibration.json",
            "/damping/viscosity_ratio",
            json!(-0.1),
            "damping.viscosity_ratio",
            "[0, inf)",
        ),
        (
            "cantilever-vibration.json",
            "/damping/mass_proportional",
            json!(-1.0),
            "damping.mass_proportional",
            "[0, inf)",
        ),
        (
            "cantilever-vibration.json",
            "/boundary_conditions/1/traction/ramp",
            json!(-1.0),
            "boundary_conditions[1].traction.ramp",
            "[0, inf)",
        ),
        (
            "disc-collision.json",
            "/contact/buffer",
            json!(-1e-3),
            "contact.buffer",
            "[0, inf)",
        ),
        (
            "disc-collision.json",
            "/contact/max_phi",
            json!(1.5),
            "contact.max_phi",
            "(0, 1]",
        ),
        (
            "disc-collision.json",
            "/contact/default/friction",
            json!(-0.5),
            "contact.default.friction",
            "[0, inf)",
        ),
        (
            "disc-collision.json",
            "/contact/default/penalty_factor",
            json!(0.0),
            "contact.default.penalty_factor",
            "(0, inf)",
        ),
        (
            "disc-collision.json",
            "/contact/default/penalty",
            json!(-1e9),
            "contact.default.penalty",
            "(0, inf)",
        ),
        (
            "disc-collision.json",
            "/contact/default/damping",
            json!(-1.0),
            "contact.default.damping",
            "[0, inf)",
        ),
        (
            "block-compression-fracture.json",
            "/contact/walls/0/ramp",
            json!(-1e-4),
            "contact.walls[0].ramp",
            "[0, inf)",
        ),
        (
            "block-compression-fracture.json",
            "/contact/walls/1/law/tangential_penalty",
            json!(0.0),
            "contact.walls[1].law.tangential_penalty",
            "(0, inf)",
        ),
    ];
    for (i, (example, ptr, value, path, range)) in rows.iter().enumerate() {
        let s = common::edited_example(example, "class9-range", |v| {
            set(v, ptr, value.clone());
            v["output"]["frames"] = json!(0);
        });
        let err = refused_by_check_and_run(&s, &format!("row{i}"));
        eprintln!("{err}");
        assert!(
            err.contains(&format!("at `{path}`:"))
                && err.contains(&format!(
                    " {} is outside its valid range {range}",
                    value.as_f64().unwrap()
                ))
                && err.contains("fix:"),
            "row {i} ({path}): {err}"
        );
    }
    // the ranges checked before, with their own words: path and value named
    let rows: &[(&str, &str, Value, &str)] = &[
        (
            "cantilever-vibration.json",
            "/mass_scaling",
            json!({ "factor": 0.5 }),
            "mass_scaling.factor",
        ),
        (
            "cantilever-vibration.json",
            "/loading",
            json!({ "rate": 0.0 }),
            "loading.rate",
        ),
        (
            "cantilever-vibration.json",
            "/loading",
            json!({ "kinetic_ratio_limit": -0.1 }),
            "loading.kinetic_ratio_limit",
        ),
        (
            "cantilever-vibration.json",
            "/bodies/0/materials/beam/poisson",
            json!(0.5),
            "bodies[0].materials.beam.poisson",
        ),
    ];
    for (i, (example, ptr, value, path)) in rows.iter().enumerate() {
        let s = common::edited_example(example, "class9-range-old", |v| {
            set(v, ptr, value.clone());
            v["output"]["frames"] = json!(0);
        });
        let err = refused_by_check_and_run(&s, &format!("old{i}"));
        assert!(
            err.contains(&format!("at `{path}`:")) && err.contains("fix:"),
            "{err}"
        );
    }
    fdem_figures::record(133, "refused");
}

/// A `mass_scaling.target_step` so large that its factor overflows was reported as a density
/// of infinity at `bodies` ("check the materials and the mesh"). Now at the target step.
#[test]
fn class10_huge_mass_scaling_target_step_is_named_not_a_density() {
    for (target, tag) in [(1e160, "overflow"), (1e150, "one-step")] {
        let s = common::edited_example("cantilever-vibration.json", "class10-target", |v| {
            v["mass_scaling"] = json!({ "target_step": target });
        });
        let err = refused_by_check_and_run(&s, tag);
        assert!(
            err.contains("at `mass_scaling.target_step`:") && err.contains("fix:"),
            "{err}"
        );
    }
}

/// A huge `mass_scaling.factor`: with frames, "N frames over a run of 1 step" was laid at
/// `output.frames`; without, the one-step run stopped as unstable, with the fix "lower
/// `integrator.safety`" (exit 3). A factor that cuts the steps below the frames is named too.
#[test]
fn class10_huge_mass_scaling_factor_is_named_not_the_frames_or_the_step() {
    for (factor, frames, tag) in [
        (1e300, 20, "frames"),
        (1e300, 0, "no-frames"),
        (1e7, 20, "few-steps"),
    ] {
        let s = common::edited_example("cantilever-vibration.json", "class10-factor", |v| {
            v["mass_scaling"] = json!({ "factor": factor });
            v["output"]["frames"] = json!(frames);
        });
        let err = refused_by_check_and_run(&s, tag);
        assert!(
            err.contains("at `mass_scaling.factor`:") && err.contains("fix:"),
            "{tag}: {err}"
        );
    }
}

/// A huge `loading.rate` shortened the duration below any step and multiplied the velocity
/// of a boundary condition: the run was stopped as unstable (exit 3) with the cause laid at
/// `boundary_conditions[2]`, a velocity of 1e300 m/s that the scene does not write (it
/// writes 1 m/s). Now refused at `loading.rate`; and a rate that makes the velocity too
/// large for the material, in a run, is named as the cause.
#[test]
fn class10_huge_loading_rate_is_named_not_a_velocity() {
    let scene = |rate: f64, tag: &str| {
        common::edited_example("cantilever-vibration.json", tag, |v| {
            v["boundary_conditions"]
                .as_array_mut()
                .unwrap()
                .push(json!({ "velocity": { "group": "right", "y": -1.0 } }));
            v["loading"] = json!({ "rate": rate });
            v["output"]["frames"] = json!(0);
        })
    };
    let err = refused_by_check_and_run(&scene(1e300, "class10-rate"), "rate");
    assert!(
        err.contains("at `loading.rate`:") && !err.contains("boundary_conditions"),
        "{err}"
    );
    let s = scene(1e3, "class10-rate-run");
    let (code, _, err) = run(&s, &s.parent().unwrap().join("out"));
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains("cause: `loading.rate` is far too large")
            && err.contains("fix: lower `loading.rate`"),
        "{err}"
    );
}

/// An initial stress of 1e300 Pa: a static solve reported "the stiffness is nearly singular",
/// a dynamic run "the stable time step is 0" at `bodies[0].mesh` ("remesh"). Now at the
/// initial stress entry, for either analysis.
#[test]
fn class10_huge_initial_stress_is_named_not_the_stiffness_or_the_mesh() {
    for example in ["cantilever-static.json", "cantilever-vibration.json"] {
        let s = common::edited_example(example, "class10-stress", |v| {
            v["initial_stress"] = json!([{ "uniform": [1e300, 0.0, 0.0] }]);
            v["output"]["frames"] = json!(0);
        });
        let err = refused_by_check_and_run(&s, example);
        assert!(
            err.contains("at `initial_stress[0].uniform`:")
                && err.contains("times its Young's modulus")
                && !err.contains("singular"),
            "{example}: {err}"
        );
    }
}

/// A Young's modulus drawn per triangle from a distribution so wide that a draw is NaN, 0 or
/// infinite was reported at `bodies` ("material 0: youngs_modulus = NaN", "check the
/// materials and the mesh"). Now at the distribution.
#[test]
fn class10_drawn_young_modulus_out_of_range_names_its_distribution() {
    for (dist, law) in [
        (
            json!({ "lognormal": { "mean": 200e3, "cov": 1e200 } }),
            "lognormal",
        ),
        (
            json!({ "weibull": { "modulus": 1e-300, "scale": 200e3 } }),
            "weibull",
        ),
        (
            json!({ "normal": { "mean": 1e300, "cov": 1e300 } }),
            "normal",
        ),
    ] {
        let s = common::edited_example("cantilever-vibration.json", "class10-young", |v| {
            let m = &mut v["bodies"][0]["materials"]["beam"];
            m.as_object_mut().unwrap().remove("young");
            m["heterogeneity"] = json!({ "seed": 1, "young": dist });
        });
        let err = refused_by_check_and_run(&s, law);
        assert!(
            err.contains(&format!(
                "at `bodies[0].materials.beam.heterogeneity.young.{law}`:"
            )) && err.contains("drew Young's modulus"),
            "{law}: {err}"
        );
    }
    fdem_figures::record(134, "refused at the input");
}
