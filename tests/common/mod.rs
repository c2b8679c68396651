//! Helpers shared by the whole-solver tests: run an example scene (possibly modified) into a
//! fresh temporary folder and read its histories.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use fdem_solver::driver::{self, Outcome, RunOptions};

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A fresh, empty temporary folder named after `tag`.
pub fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fdem-test-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Loads an example scene as JSON, applies `edit`, makes mesh paths absolute, and writes it
/// into a temporary folder; returns the new scene path.
pub fn edited_example(name: &str, tag: &str, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let src = root().join("examples").join(name);
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&src).unwrap()).unwrap();
    for b in v["bodies"].as_array_mut().unwrap() {
        let m = b["mesh"].as_str().unwrap().to_string();
        b["mesh"] =
            serde_json::Value::String(root().join("examples").join(m).display().to_string());
    }
    edit(&mut v);
    let dir = temp_dir(tag);
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    p
}

/// Runs a scene into `<scene folder>/out` and returns the outcome.
pub fn run(scene: &Path) -> (Outcome, PathBuf) {
    let mut l = driver::load(scene).unwrap_or_else(|e| panic!("{e}"));
    let out = scene.parent().unwrap().join("out");
    let o = driver::run_outcome(
        &mut l,
        &RunOptions {
            out_dir: out.clone(),
            raw: false,
        },
        &mut |_| {},
    )
    .unwrap_or_else(|e| panic!("{e}"));
    (o, out)
}

/// Reads `histories.csv`: column names and rows.
pub fn histories(out: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(out.join("histories.csv")).unwrap();
    let mut lines = text.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (head, rows)
}

/// Column `name` of the histories.
pub fn column(head: &[String], rows: &[Vec<f64>], name: &str) -> Vec<f64> {
    let i = head
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    rows.iter().map(|r| r[i]).collect()
}
