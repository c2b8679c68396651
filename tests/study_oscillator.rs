//! `fdem study oscillator` end to end: a small grid writes every file without NaN, and bad
//! input gets a clear error and a non-zero exit, never a panic.

use crate::common;

use std::process::Command;

fn fdem(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_fdem"))
        .args(args)
        .output()
        .expect("fdem runs")
}

#[test]
fn small_study_writes_csv_json_and_plots() {
    let dir = common::temp_dir("study-oscillator");
    let out = dir.to_str().unwrap();
    let o = fdem(&[
        "study",
        "oscillator",
        "--out",
        out,
        "--h-min",
        "0.5",
        "--h-max",
        "2.5",
        "--h-step",
        "0.5",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("forest-ruth") && stdout.contains("omf32"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(dir.join("oscillator.csv")).unwrap();
    // Header + 8 schemes x 5 steps; never a NaN written.
    assert_eq!(csv.lines().count(), 1 + 8 * 5);
    assert!(!csv.to_lowercase().contains("nan"));
    // Central difference at h = 2.0 is past its limit (rho > 1): unbounded, no errors.
    assert!(
        csv.lines()
            .any(|l| l.starts_with("central-difference,2,false,")),
        "{csv}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("oscillator.json")).unwrap())
            .unwrap();
    assert_eq!(json["schemes"].as_array().unwrap().len(), 8);
    for stem in [
        "error_vs_h",
        "error_vs_evaluations",
        "error_vs_seconds",
        "spectral_radius",
    ] {
        for ext in ["png", "svg"] {
            let p = dir.join(format!("{stem}.{ext}"));
            assert!(
                std::fs::metadata(&p)
                    .map(|m| m.len() > 1000)
                    .unwrap_or(false),
                "{}",
                p.display()
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_gets_a_clear_error_and_a_non_zero_exit() {
    let cases: [(&[&str], &str); 5] = [
        (
            &["--schemes", "verlet"],
            "valid names are central-difference",
        ),
        (&["--h-min", "0"], "--h-min must be a positive"),
        (&["--h-step", "-0.1"], "--h-step must be a positive"),
        (
            &["--h-max", "NaN"],
            "--h-max must be a positive, finite number, got NaN",
        ),
        (&["--h-min", "2", "--h-max", "1"], "must not exceed"),
    ];
    for (args, expected) in cases {
        let mut all = vec!["study", "oscillator", "--out", "/nonexistent/never-written"];
        all.extend_from_slice(args);
        let o = fdem(&all);
        let err = String::from_utf8_lossy(&o.stderr);
        // exit code 2: bad input (README, "Exit codes")
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(expected) && !err.contains("panicked"),
            "{args:?}: {err}"
        );
    }
}
