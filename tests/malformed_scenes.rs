//! Malformed scenes: each gives a clear error naming the file, the field and the fix, exit
//! code 2, and writes no output at all (the output folder is never created).

use crate::common;

use std::path::Path;
use std::process::Command;

/// Runs `fdem run SCENE --out DIR`; returns (exit code, stderr) and checks DIR was not created.
fn run_bad(scene: &Path, tag: &str) -> (i32, String) {
    let out = scene.parent().unwrap().join(format!("out-{tag}"));
    let o = Command::new(env!("CARGO_BIN_EXE_fdem"))
        .arg("run")
        .arg(scene)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        !out.exists(),
        "{tag}: output folder {} was created",
        out.display()
    );
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn write(tag: &str, text: &str) -> std::path::PathBuf {
    let d = common::temp_dir(&format!("bad-{tag}"));
    let p = d.join("scene.json");
    std::fs::write(&p, text).unwrap();
    p
}

/// The cantilever relaxation example with an edit, as text.
fn edited(tag: &str, edit: impl FnOnce(&mut serde_json::Value)) -> std::path::PathBuf {
    common::edited_example("cantilever-relaxation.json", &format!("bad-{tag}"), edit)
}

fn expect(scene: &Path, tag: &str, needles: &[&str]) {
    let (code, err) = run_bad(scene, tag);
    assert_eq!(code, 2, "{tag}: exit code {code}, stderr:\n{err}");
    for n in needles {
        assert!(err.contains(n), "{tag}: stderr lacks {n:?}:\n{err}");
    }
    assert!(
        err.contains("scene.json") || err.contains("cantilever-relaxation.json"),
        "{tag}: no file named:\n{err}"
    );
}

#[test]
fn bad_json_syntax_names_line_and_column() {
    let p = write(
        "syntax",
        "{\n  \"bodies\": [\n    {\"mesh\": \"m.json\",,}\n  ]\n}\n",
    );
    expect(&p, "syntax", &["scene.json:3:", "fix:"]);
}

#[test]
fn wrong_type_names_the_field_path() {
    let p = edited("type", |v| v["duration"] = "long".into());
    expect(&p, "type", &["duration", "invalid type", "fix:"]);
}

#[test]
fn unknown_field_names_its_path() {
    let p = edited("unknown", |v| v["integrator"]["saftey"] = 0.5.into());
    expect(
        &p,
        "unknown",
        &["integrator.saftey", "unknown field", "safety"],
    );
}

#[test]
fn missing_mesh_file_is_reported_with_the_body() {
    let p = edited("mesh", |v| {
        v["bodies"][0]["mesh"] = "/nonexistent/beam.msh".into()
    });
    expect(&p, "mesh", &["bodies[0].mesh", "/nonexistent/beam.msh"]);
}

#[test]
fn unknown_group_lists_the_groups_that_exist() {
    let p = edited("group", |v| {
        v["boundary_conditions"][0]["fixed"]["group"] = "clamp".into()
    });
    expect(
        &p,
        "group",
        &["boundary_conditions[0].fixed.group", "'clamp'", "left"],
    );
}

#[test]
fn unknown_material_group_is_rejected() {
    let p = edited("matgroup", |v| {
        let m = v["bodies"][0]["materials"]["beam"].clone();
        v["bodies"][0]["materials"] = serde_json::json!({ "steel": m });
    });
    expect(&p, "matgroup", &["materials", "steel"]);
}

#[test]
fn zero_or_negative_material_constants_are_rejected() {
    let p = edited("young", |v| {
        v["bodies"][0]["materials"]["beam"]["young"] = 0.0.into()
    });
    expect(
        &p,
        "young",
        &["bodies[0].materials.beam.young", "not positive"],
    );
    let p = edited("density", |v| {
        v["bodies"][0]["materials"]["beam"]["density"] = (-1.0).into()
    });
    expect(&p, "density", &["density", "not positive"]);
    let p = edited("poisson", |v| {
        v["bodies"][0]["materials"]["beam"]["poisson"] = 0.5.into()
    });
    expect(&p, "poisson", &["poisson", "[0, 0.5)"]);
}

#[test]
fn time_step_above_the_stability_limit_is_rejected() {
    let p = edited("dt", |v| v["integrator"]["time_step"] = 1.0.into());
    expect(
        &p,
        "dt",
        &["integrator.time_step", "above the stability limit", "fix:"],
    );
}

#[test]
fn unknown_scheme_lists_the_schemes() {
    let p = edited("scheme", |v| v["integrator"]["scheme"] = "verlet".into());
    expect(
        &p,
        "scheme",
        &["integrator.scheme", "central-difference", "omf32"],
    );
}

#[test]
fn dynamic_scene_without_duration_is_rejected() {
    let p = edited("duration", |v| {
        v.as_object_mut().unwrap().remove("duration");
    });
    expect(&p, "duration", &["duration", "needs a duration"]);
}

#[test]
fn missing_scene_file_is_an_input_error() {
    let d = common::temp_dir("bad-nofile");
    let (code, err) = run_bad(&d.join("absent.json"), "nofile");
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("absent.json") && err.contains("cannot read"),
        "{err}"
    );
}

#[test]
fn check_reports_each_scheme_and_writes_nothing() {
    let p = edited("check", |_| {});
    let o = Command::new(env!("CARGO_BIN_EXE_fdem"))
        .arg("check")
        .arg(&p)
        .output()
        .unwrap();
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    for k in fdem_time::SchemeKind::ALL {
        assert!(
            text.contains(k.name()),
            "check output lacks {}:\n{text}",
            k.name()
        );
    }
    let entries = std::fs::read_dir(p.parent().unwrap()).unwrap().count();
    assert_eq!(entries, 1, "check wrote files");
}
