//! General rules of trust: the energy-growth check never stops a stable run for round-off
//! (class 6: a body at rest, platens started away from the specimen); every tolerance,
//! factor and rate of a scene has a valid range checked at load (class 9); a check on a
//! derived quantity names the input that drives it (class 10).

use crate::common;

use std::path::Path;
use std::process::Command;

use serde_json::{Value, json};

/// Runs `fdem ARGS`; returns (exit code, stdout, stderr).
fn fdem(args: &[&std::ffi::OsStr]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_fdem"))
        .args(args)
        .output()
        .unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// `fdem run SCENE --out OUT`.
fn run(scene: &Path, out: &Path) -> (i32, String, String) {
    fdem(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ])
}

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
}
