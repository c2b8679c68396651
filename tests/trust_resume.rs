//! Runs that end with a wrong or lost output, through the `fdem` program as a user runs it:
//! a run stopped as unstable writes every file it would write, up to the stop (class 7); a
//! resume goes on only in the folder of the run that wrote the checkpoint, from a folder
//! that holds the files it goes on from, to an end after the checkpoint, and says what it
//! does (class 8). Every refusal is exit code 2 with a message and its fix, and leaves the
//! folder as it was.

use std::path::Path;
use std::process::Command;

use serde_json::json;

use crate::common;

/// Runs `fdem ARGS`: exit code, standard output and standard error.
fn fdem(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_fdem"))
        .args(args)
        .output()
        .expect("fdem runs");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(dir.join("summary.json")).unwrap()).unwrap()
}

/// `histories.csv` of `dir`: its columns and its rows, every value parsed (a value that does
/// not parse fails the test).
fn histories(dir: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join("histories.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or_else(|_| panic!("`{v}` in `{l}`")))
                .collect()
        })
        .collect();
    for r in &rows {
        assert_eq!(r.len(), head.len());
    }
    (head, rows)
}

// ---- class 7: a run stopped as unstable writes its files up to the stop ----

/// The vibrating cantilever under a 1e20 Pa traction (an absurd load), a history row at every
/// step and no frame before the end: it is stopped as unstable (exit 3) at a stability check,
/// and `histories.csv` holds the rows sampled up to the stop, every value finite.
#[test]
fn class7_a_run_stopped_as_unstable_writes_its_histories_up_to_the_stop() {
    let scene = common::edited_example("cantilever-vibration.json", "class7-histories", |v| {
        v["boundary_conditions"][1]["traction"]["value"] = json!([0.0, -1e20]);
        v["duration"] = json!(0.05);
        v["output"]["frames"] = json!(1);
    });
    let out = scene.parent().unwrap().join("out");
    let (code, _, err) = fdem(&["run", s(&scene), "--out", s(&out)]);
    assert_eq!(code, 3, "{err}");
    let sum = summary(&out);
    let (stop_step, h) = (
        sum["steps"].as_u64().unwrap(),
        sum["time_step"].as_f64().unwrap(),
    );
    let (head, rows) = histories(&out);
    assert!(head.contains(&"u_y[tip]".to_string()) && head.contains(&"kinetic".to_string()));
    assert!(!rows.is_empty(), "no history row written before the stop");
    eprintln!(
        "stopped at step {stop_step}: {} rows, the last at t = {:e} s",
        rows.len(),
        rows.last().unwrap()[0]
    );
    // one row per step from the first, each of finite values, up to the stop
    for (k, r) in rows.iter().enumerate() {
        assert!(r.iter().all(|v| v.is_finite()), "row {k}: {r:?}");
        let t = (k + 1) as f64 * h;
        assert!(
            (r[0] - t).abs() <= 1e-9 * t,
            "row {k} at t = {}, not {t}",
            r[0]
        );
    }
    assert!(rows.len() as u64 <= stop_step);
    // the rows reach the last stability check before the stop (every 100 steps), unless the
    // values stopped being finite before it
    let u = head.iter().position(|c| c == "u_y[tip]").unwrap();
    assert!(
        rows.len() as u64 + 100 >= stop_step || rows.last().unwrap()[u].abs() > 1e3,
        "{} rows for a stop at step {stop_step}",
        rows.len()
    );
}

/// The notched beam with a 1e20 Pa traction on its loading pad (an absurd load): it is stopped as
/// unstable (exit 3), with every file the run writes up to the stop: the frames and their
/// collections, `histories.csv`, `fractures.csv` and the load-displacement curve drawn from
/// them.
#[test]
fn class7_an_unstable_fracturing_run_writes_its_csv_files_and_its_curve() {
    let scene = common::edited_example("notched-beam-fracture.json", "class7-beam", |v| {
        v["boundary_conditions"][2] =
            json!({ "traction": { "group": "load", "value": [0.0, -1e20] } });
        v["duration"] = json!(2e-4);
        v["output"]["frames"] = json!(4);
        v["histories"]["every"] = json!(1);
    });
    let out = scene.parent().unwrap().join("out");
    let (code, stdout, err) = fdem(&["run", s(&scene), "--out", s(&out)]);
    assert_eq!(code, 3, "{stdout}\n{err}");
    for f in [
        "summary.json",
        "results.pvd",
        "frame_0000.vtu",
        "joints.pvd",
        "histories.csv",
        "fractures.csv",
        "load_displacement.png",
        "load_displacement.svg",
    ] {
        assert!(out.join(f).is_file(), "{f} missing after exit 3\n{stdout}");
    }
    let (_, rows) = histories(&out);
    assert!(!rows.is_empty());
    assert!(rows.iter().flatten().all(|v| v.is_finite()));
    let events = std::fs::read_to_string(out.join("fractures.csv")).unwrap();
    assert!(events.starts_with("time,"), "{events}");
    assert!(stdout.contains("load-displacement curve"), "{stdout}");
    fdem_figures::record_part(140, 1, "written");
}

// ---- class 8: a resume that mixes runs ----

use crate::common::snapshot;

/// Resuming `dir` (with `scene`, if given) fails with exit code 2 and a message with a fix
/// that contains each of `what`, and leaves every file of the folder as it was; returns the
/// message.
fn refused(dir: &Path, scene: Option<&Path>, what: &[&str]) -> String {
    let before = snapshot(dir);
    let mut args = vec!["run"];
    if let Some(sc) = scene {
        args.push(s(sc));
    }
    args.extend(["--resume", s(dir)]);
    let (code, _, err) = fdem(&args);
    assert_eq!(code, 2, "{err}");
    for w in what {
        assert!(err.contains(w), "expected `{w}` in: {err}");
    }
    assert!(err.contains("fix:"), "{err}");
    assert!(
        before == snapshot(dir),
        "the refused resume changed {dir:?}"
    );
    err
}

/// The collision of the two discs, 0.3 ms (3347 steps), with `frames` frames.
fn collision(tag: &str, frames: usize) -> std::path::PathBuf {
    common::edited_example("disc-collision.json", tag, |v| {
        v["duration"] = json!(0.3e-3);
        v["output"]["frames"] = json!(frames);
    })
}

/// The run id that the folder `dir` holds.
fn run_id(dir: &Path) -> String {
    std::fs::read_to_string(dir.join("run_id.txt"))
        .unwrap()
        .trim()
        .to_string()
}

/// A checkpoint copied into the folder of another run of the same scene (one stopped at
/// another step, and one that wrote no checkpoint) is refused, naming both runs; a copy of
/// the whole folder resumes.
#[test]
fn class8_a_checkpoint_copied_from_another_run_is_refused() {
    let scene = collision("class8-copied", 6);
    let dir = scene.parent().unwrap();
    let (a, b, c) = (dir.join("a"), dir.join("b"), dir.join("c"));
    let (code, _, err) = fdem(&["run", s(&scene), "--out", s(&a), "--stop-after", "1500"]);
    assert_eq!(code, 4, "{err}");
    let (code, _, err) = fdem(&["run", s(&scene), "--out", s(&b), "--stop-after", "700"]);
    assert_eq!(code, 4, "{err}");
    let (code, _, err) = fdem(&["run", s(&scene), "--out", s(&c)]);
    assert_eq!(code, 0, "{err}");
    std::fs::copy(a.join("checkpoint.fdem"), b.join("checkpoint.fdem")).unwrap();
    std::fs::copy(a.join("checkpoint.fdem"), c.join("checkpoint.fdem")).unwrap();
    let err_b = refused(&b, None, &["another run"]);
    let err_c = refused(&c, None, &["run_id.txt"]);
    // each message names the runs
    let (id_a, id_b) = (run_id(&a), run_id(&b));
    assert_ne!(id_a, id_b);
    assert!(err_b.contains(&id_a) && err_b.contains(&id_b), "{err_b}");
    assert!(err_c.contains(&id_a), "{err_c}");
    // the whole folder copied: its files are the run's
    let copy = dir.join("a-copy");
    std::fs::create_dir_all(&copy).unwrap();
    for (name, bytes) in snapshot(&a) {
        std::fs::write(copy.join(name), bytes).unwrap();
    }
    let (code, _, err) = fdem(&["run", "--resume", s(&copy)]);
    assert_eq!(code, 0, "{err}");
    // the run that never stopped, in `c`: the same results
    assert_eq!(summary(&copy)["steps"], summary(&c)["steps"]);
    let results = |d: &Path| {
        let mut files = snapshot(d);
        files.retain(|n, _| {
            !matches!(
                n.as_str(),
                "checkpoint.fdem" | "run_id.txt" | "summary.json"
            )
        });
        files
    };
    assert!(results(&copy) == results(&c));
}

/// A frame written before the checkpoint and removed from the folder is refused by name (a
/// resumed run writes only the frames after its checkpoint); put back, the run resumes and
/// every frame its collection lists is there.
#[test]
fn class8_a_frame_missing_before_the_resume_is_refused() {
    let scene = collision("class8-missing", 12);
    let out = scene.parent().unwrap().join("out");
    let (code, _, err) = fdem(&["run", s(&scene), "--out", s(&out), "--stop-after", "2000"]);
    assert_eq!(code, 4, "{err}");
    let frame = out.join("frame_0002.vtu");
    let kept = std::fs::read(&frame).unwrap();
    std::fs::remove_file(&frame).unwrap();
    refused(&out, None, &["frame_0002.vtu", "missing"]);
    std::fs::write(&frame, kept).unwrap();
    let (code, _, err) = fdem(&["run", "--resume", s(&out)]);
    assert_eq!(code, 0, "{err}");
    let pvd = std::fs::read_to_string(out.join("results.pvd")).unwrap();
    let listed: Vec<&str> = pvd
        .split("file=\"")
        .skip(1)
        .map(|r| r.split('"').next().unwrap())
        .collect();
    assert_eq!(listed.len(), 13, "{pvd}");
    for f in listed {
        assert!(out.join(f).is_file(), "{f} listed but missing");
    }
}

/// A resume whose `duration` ends before the checkpoint's time, or at it (a run that ended
/// with a checkpoint, resumed with its own scene), is refused, naming `duration` and the
/// checkpoint's time.
#[test]
fn class8_a_resume_that_ends_at_or_before_the_checkpoint_is_refused() {
    let scene = collision("class8-end", 4);
    let dir = scene.parent().unwrap();
    let out = dir.join("out");
    let (code, _, err) = fdem(&["run", s(&scene), "--out", s(&out), "--stop-after", "2000"]);
    assert_eq!(code, 4, "{err}");
    let header = fdem_solver::checkpoint::read(&out.join("checkpoint.fdem"))
        .unwrap()
        .header;
    let shorter = common::edited_example("disc-collision.json", "class8-end-short", |v| {
        v["duration"] = json!(0.1e-3);
        v["output"]["frames"] = json!(4);
    });
    let t = format!("{:e}", header.time);
    refused(&out, Some(&shorter), &["`duration`", &t, "step 2000"]);
    // a run that ended, with a checkpoint at its end
    let ended = dir.join("ended");
    let (code, _, err) = fdem(&[
        "run",
        s(&scene),
        "--out",
        s(&ended),
        "--checkpoint-every",
        "1000",
    ]);
    assert_eq!(code, 0, "{err}");
    let header = fdem_solver::checkpoint::read(&ended.join("checkpoint.fdem"))
        .unwrap()
        .header;
    assert_eq!(json!(header.step), summary(&ended)["steps"]);
    refused(&ended, None, &["`duration`", &format!("{:e}", header.time)]);
    fdem_figures::record_part(140, 2, "refused");
}

/// The value after `key` in `text`, up to `end`.
fn after<'t>(text: &'t str, key: &str, end: &str) -> &'t str {
    let rest = &text[text
        .find(key)
        .unwrap_or_else(|| panic!("no `{key}` in {text}"))
        + key.len()..];
    &rest[..rest.find(end).unwrap()]
}

/// With `"time_step": "auto"` the step is fitted to the duration, and a resume with another
/// duration keeps the checkpoint's step: the step and the step count `fdem` prints are those
/// the run takes, and the steps it says are left are those it runs.
#[test]
fn class8_what_a_resume_prints_is_the_step_it_takes() {
    // the step of the auto fit over a long run: about the target step
    let long = collision("class8-print", 4);
    let h0 = fdem_solver::load(&long).unwrap().dt;
    // 3 steps over 2.5 target steps, then 101 target steps resumed: the kept step differs
    // from the one the longer scene alone is fitted to
    let first = common::edited_example("disc-collision.json", "class8-print-a", |v| {
        v["duration"] = json!(2.5 * h0);
        v["output"]["frames"] = json!(1);
    });
    let second = common::edited_example("disc-collision.json", "class8-print-b", |v| {
        v["duration"] = json!(100.5 * h0);
        v["output"]["frames"] = json!(1);
    });
    let (h1, h2) = (
        fdem_solver::load(&first).unwrap().dt,
        fdem_solver::load(&second).unwrap().dt,
    );
    assert_ne!(format!("{h1:.4e}"), format!("{h2:.4e}"));
    let out = first.parent().unwrap().join("out");
    let (code, _, err) = fdem(&["run", s(&first), "--out", s(&out), "--stop-after", "2"]);
    assert_eq!(code, 4, "{err}");
    let (code, _, err) = fdem(&["run", s(&second), "--resume", s(&out)]);
    assert_eq!(code, 0, "{err}");
    eprintln!("{err}");
    let sum = summary(&out);
    let (h, steps) = (
        sum["time_step"].as_f64().unwrap(),
        sum["steps"].as_u64().unwrap(),
    );
    assert_eq!(h, h1, "the resumed run keeps the checkpoint's step");
    // the scene's description: `with h = H s (limit L s), N steps`
    let described = after(&err, "with h = ", "\n");
    assert_eq!(after(described, "", " s"), format!("{h:.4e}"), "{err}");
    assert_eq!(
        after(described, "), ", " steps"),
        steps.to_string(),
        "{err}"
    );
    // the resume's line: `resuming from step 2 (...): K steps left of h = H s`
    let left: u64 = after(&err, "resuming from step 2 (", " steps left")
        .rsplit(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(left, steps - 2, "{err}");
    assert_eq!(after(&err, "steps left of h = ", " s"), format!("{h:.4e}"));
    fdem_figures::record_part(140, 3, "equal");
}
