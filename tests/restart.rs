//! Checkpoints and resume, through the `fdem` program as a user runs it: a run stopped
//! (`--stop-after`, SIGINT, SIGKILL) and resumed (`--resume`) writes the very same files as
//! the run that never stopped, byte for byte: every frame, `histories.csv`, `fractures.csv`,
//! `walls.csv`, `results.pvd`, `joints.pvd`, and `summary.json` but for its wall-clock
//! timers. Bad checkpoints are refused with a clear message and exit code 2, and nothing in
//! the folder changes.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use crate::common;

fn fdem() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fdem"))
}

/// Runs `fdem` with `args`: exit code and standard error.
fn fdem_run(args: &[&str]) -> (i32, String) {
    let Output { status, stderr, .. } = fdem().args(args).output().expect("fdem runs");
    (
        status.code().unwrap_or(-1),
        String::from_utf8_lossy(&stderr).into_owned(),
    )
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The files of a run folder that hold results, by name, with their bytes (the checkpoint,
/// the run's id and the summary apart).
fn result_files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| {
            !matches!(
                n.as_str(),
                "checkpoint.fdem" | "run_id.txt" | "summary.json"
            )
        })
        .map(|n| (n.clone(), std::fs::read(dir.join(&n)).unwrap()))
        .collect()
}

/// `summary.json` without what depends on the wall clock (times, throughput), and without
/// the notice of a resume (`resumed`: only the resumed run has it).
fn summary_without_timers(dir: &Path) -> serde_json::Value {
    fn strip(v: &mut serde_json::Value) {
        if let Some(o) = v.as_object_mut() {
            o.retain(|k, _| {
                !matches!(
                    k.as_str(),
                    "wall_time" | "triangle_steps_per_second" | "timers" | "resumed"
                ) && !k.ends_with("_s")
            });
            o.values_mut().for_each(strip);
        }
    }
    let mut v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("summary.json")).unwrap()).unwrap();
    strip(&mut v);
    v
}

/// Asserts that run folders `a` and `b` hold the same results, byte for byte; returns how
/// many files were compared.
fn assert_same_results(a: &Path, b: &Path) -> usize {
    let (fa, fb) = (result_files(a), result_files(b));
    assert_eq!(
        fa.keys().collect::<Vec<_>>(),
        fb.keys().collect::<Vec<_>>(),
        "the two runs wrote different files"
    );
    for (name, bytes) in &fa {
        assert!(bytes == &fb[name], "{name} differs between {a:?} and {b:?}");
    }
    assert_eq!(summary_without_timers(a), summary_without_timers(b));
    fa.len() + 1
}

/// Runs `scene` straight into `dir/straight`, then stopped after each step of `stops` and
/// resumed, into `dir/resumed`; asserts both wrote the same results. Returns the folders.
pub(crate) fn straight_and_resumed(scene: &Path, stops: &[u64]) -> (PathBuf, PathBuf) {
    let dir = scene.parent().unwrap();
    // the same folder name (a plot's legend shows it)
    let (a, b) = (dir.join("straight/run"), dir.join("resumed/run"));
    let (code, err) = fdem_run(&["run", s(scene), "--out", s(&a)]);
    assert_eq!(code, 0, "{err}");
    for (i, stop) in stops.iter().enumerate() {
        let stop = stop.to_string();
        let (code, err) = if i == 0 {
            fdem_run(&["run", s(scene), "--out", s(&b), "--stop-after", &stop])
        } else {
            fdem_run(&["run", "--resume", s(&b), "--stop-after", &stop])
        };
        assert_eq!(code, 4, "stopped after {stop} steps: exit code 4\n{err}");
        assert!(err.contains("fdem run --resume"), "{err}");
        let summary = std::fs::read_to_string(b.join("summary.json")).unwrap();
        assert!(summary.contains("\"interrupted\""), "{summary}");
        assert!(summary.contains(&format!("\"steps\": {stop}")), "{summary}");
    }
    let o = fdem()
        .args(["run", "--resume", s(&b)])
        .output()
        .expect("fdem runs");
    let (out, err) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert_eq!(o.status.code(), Some(0), "{err}");
    // the resumed run says where it took up, in its summary and on the console
    let last = stops.last().copied().unwrap_or(0);
    let resumed = &summary_of(&b)["resumed"];
    assert_eq!(resumed["step"].as_u64(), Some(last), "{resumed}");
    assert!(summary_of(&a).get("resumed").is_none());
    assert!(
        out.contains(&format!("resumed from the checkpoint at step {last}")),
        "{out}"
    );
    let n = assert_same_results(&a, &b);
    eprintln!(
        "{}: {n} files identical after {} stops",
        scene.display(),
        stops.len()
    );
    (a, b)
}

/// The number of files [`assert_same_results`] compares in a run folder.
fn files_of(dir: &Path) -> usize {
    result_files(dir).len() + 1
}

fn summary_of(dir: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(dir.join("summary.json")).unwrap()).unwrap()
}

fn steps_of(dir: &Path) -> u64 {
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("summary.json")).unwrap()).unwrap();
    v["steps"].as_u64().unwrap()
}

/// The fracturing Brazilian disc, loaded four times faster than the example so that it
/// fractures within 0.5 ms (15 454 steps; the first joint breaks at t = 0.467 ms): stopped
/// before any damage (a third of the steps) and again after the first breaks (step 14 600),
/// resumed to the end; and a run killed with SIGKILL after a checkpoint, resumed from it.
#[test]
fn the_fracturing_disc_resumes_bit_for_bit_after_a_stop_and_after_sigkill() {
    let scene = common::edited_example("brazilian-disc-fracture.json", "restart-disc", |v| {
        for w in v["contact"]["walls"].as_array_mut().unwrap() {
            let vy = w["velocity"][1].as_f64().unwrap();
            w["velocity"] = serde_json::json!([0.0, 4.0 * vy]);
        }
        v["duration"] = serde_json::json!(0.5e-3);
        v["output"]["frames"] = serde_json::json!(10);
    });
    let (a, _) = straight_and_resumed(&scene, &[15454 / 3, 14600]);
    assert_eq!(steps_of(&a), 15454);
    let events = std::fs::read_to_string(a.join("fractures.csv")).unwrap();
    let before_stop = events
        .lines()
        .skip(1)
        .filter(|l| l.split(',').next().unwrap().parse::<f64>().unwrap() < 4.72e-4)
        .count();
    assert!(
        before_stop >= 1 && events.lines().count() > before_stop + 2,
        "joints break before and after the second stop:\n{events}"
    );

    // SIGKILL after a checkpoint: the run resumes from it (the rows and frames written
    // after it are dropped and written again)
    let c = scene.parent().unwrap().join("killed/run");
    let mut child = fdem()
        .args([
            "run",
            s(&scene),
            "--out",
            s(&c),
            "--checkpoint-every",
            "3000",
        ])
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let ck = c.join("checkpoint.fdem");
    let at_step = |p: &Path| {
        fdem_solver::checkpoint::read(p)
            .map(|c| c.header.step)
            .unwrap_or(0)
    };
    while at_step(&ck) < 12000 {
        assert!(start.elapsed() < Duration::from_secs(120), "no checkpoint");
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        !c.join("summary.json").exists(),
        "the run was killed before its end"
    );
    let (code, err) = fdem_run(&["run", "--resume", s(&c)]);
    assert_eq!(code, 0, "{err}");
    assert_same_results(&a, &c);
    fdem_figures::record(85, format!("{} files identical", files_of(&a)));
    fdem_figures::record(86, "identical");
}

/// The two discs of the collision example, off-centre (10 mm) and at 4 m/s, with Coulomb
/// friction: they touch at about 0.5 ms (step 5600) and rub past each other; stopped during
/// the contact and resumed; with central difference and with OMF32 (whose velocity
/// extrapolation reads the last step's force).
fn oblique_collision(v: &mut serde_json::Value) {
    v["bodies"][0]["initial_velocity"] = serde_json::json!([4.0, 0.0]);
    v["bodies"][1]["offset"] = serde_json::json!([0.0255, 0.01]);
    v["contact"] = serde_json::json!({ "default": { "friction": 0.5 } });
}

#[test]
fn a_frictional_collision_resumes_bit_for_bit() {
    let mut files = Vec::new();
    for scheme in ["central-difference", "omf32"] {
        let scene = common::edited_example("disc-collision.json", "restart-collision", |v| {
            oblique_collision(v);
            v["integrator"]["scheme"] = serde_json::json!(scheme);
        });
        // during the contact: steps 6000 and 9000 of central difference's 13 385, and the
        // same times of OMF32's 8574 larger steps
        let n = if scheme == "omf32" {
            6000 * 8574 / 13385
        } else {
            6000
        };
        let (a, _) = straight_and_resumed(&scene, &[n, n * 3 / 2]);
        let h = std::fs::read_to_string(a.join("histories.csv")).unwrap();
        let head: Vec<&str> = h.lines().next().unwrap().split(',').collect();
        let k = head.iter().position(|c| *c == "friction").unwrap();
        let last: f64 = h
            .lines()
            .last()
            .unwrap()
            .split(',')
            .nth(k)
            .unwrap()
            .parse()
            .unwrap();
        assert!(last > 1e-6, "{scheme}: friction dissipated {last} J");
        files.push(files_of(&a).to_string());
    }
    fdem_figures::record_part(
        87,
        1,
        format!("identical: collision {} files", files.join(", ")),
    );
}

/// The frictional collision of the signal test stopped at step 6 692, a frame step during
/// the contact: the frame writer's force pass there (after the step's commit of the friction
/// springs) differs from the forces the nodal work books were at, which the checkpoint saves
/// rather than rebuilds from that pass: the energy probe's `contact_residual` continues bit
/// for bit.
#[test]
fn a_stop_where_the_last_contact_pass_is_not_the_booked_one_resumes_bit_for_bit() {
    let scene = common::edited_example("disc-collision.json", "restart-6692", |v| {
        oblique_collision(v);
        v["duration"] = serde_json::json!(4.8e-3);
        v["output"]["frames"] = serde_json::json!(40);
    });
    let (a, _) = straight_and_resumed(&scene, &[6692]);
    fdem_figures::record_part(87, 4, format!("stop at 6 692: {} files", files_of(&a)));
}

/// Gear PC-5 (its scaled derivatives are history) on the vibrating cantilever, stopped
/// three times.
#[test]
fn a_pc5_run_resumes_bit_for_bit() {
    let scene = common::edited_example("cantilever-vibration.json", "restart-pc5", |v| {
        v["integrator"]["scheme"] = serde_json::json!("pc5");
        v["duration"] = serde_json::json!(1.0);
    });
    let (a, _) = straight_and_resumed(&scene, &[1000, 1001, 3000]);
    fdem_figures::record_part(87, 2, format!("PC-5 {} files", files_of(&a)));
}

/// Relaxations: the cantilever (converges before its end: the resumed run converges at the
/// same step) and the elastic Brazilian disc under pressure with mass damping.
#[test]
fn relaxations_resume_bit_for_bit() {
    let scene = common::edited_example("cantilever-relaxation.json", "restart-relax", |_| {});
    let (a, _) = straight_and_resumed(&scene, &[3000]);
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(a.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["converged"], serde_json::json!(true));
    let first = files_of(&a);
    let scene = common::edited_example("brazilian-disc-relaxation.json", "restart-relax", |_| {});
    let (a, _) = straight_and_resumed(&scene, &[1800]);
    fdem_figures::record_part(
        87,
        3,
        format!("relaxations {first}, {} files", files_of(&a)),
    );
}

/// Kinetic and adaptive relaxations of the cantilever (no `damping.mass_proportional`):
/// stopped at steps with and without a kinetic reset in between, they resume bit for bit and
/// converge at the same step.
#[test]
fn kinetic_and_adaptive_relaxations_resume_bit_for_bit() {
    for method in ["kinetic", "adaptive"] {
        let tag = format!("restart-{method}");
        let scene = common::edited_example("cantilever-relaxation.json", &tag, |v| {
            v["damping"] = serde_json::json!({});
            v["integrator"]["relaxation"] = method.into();
        });
        let (a, _) = straight_and_resumed(&scene, &[777, 2500]);
        let v: serde_json::Value =
            serde_json::from_slice(&std::fs::read(a.join("summary.json")).unwrap()).unwrap();
        assert_eq!(v["converged"], serde_json::json!(true), "{method}");
        assert_eq!(v["relaxation"], serde_json::json!(method));
    }
    fdem_figures::record_part(111, 1, "identical, converged");
}

/// SIGINT in the middle of a run (as Ctrl-C sends it), and SIGTERM (as a batch system sends
/// it): the run ends its step, writes a checkpoint and a summary marked interrupted with the
/// signal's name, and exits with code 4; `--resume` completes it identically to a run that
/// was never interrupted.
#[test]
fn sigint_stops_with_a_checkpoint_and_the_run_resumes_bit_for_bit() {
    let scene = common::edited_example("disc-collision.json", "restart-sigint", |v| {
        oblique_collision(v);
        v["duration"] = serde_json::json!(4.8e-3);
        v["output"]["frames"] = serde_json::json!(40);
    });
    let dir = scene.parent().unwrap();
    let a = dir.join("straight/run");
    let (code, err) = fdem_run(&["run", s(&scene), "--out", s(&a)]);
    assert_eq!(code, 0, "{err}");
    for signal in ["INT", "TERM"] {
        let b = dir.join(format!("{signal}/run"));
        let child = fdem()
            .args(["run", s(&scene), "--out", s(&b)])
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let start = Instant::now();
        while !b.join("frame_0004.vtu").exists() {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "the run did not start"
            );
            std::thread::sleep(Duration::from_millis(2));
        }
        let pid = child.id().to_string();
        let sent = Command::new("kill")
            .args([&format!("-{signal}"), &pid])
            .status()
            .unwrap();
        assert!(sent.success());
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(4), "{err}");
        let name = format!("SIG{signal}");
        assert!(err.contains(&format!("interrupted ({name})")), "{err}");
        let summary: serde_json::Value =
            serde_json::from_slice(&std::fs::read(b.join("summary.json")).unwrap()).unwrap();
        assert_eq!(summary["interrupted"]["reason"], serde_json::json!(name));
        let stopped_at = summary["steps"].as_u64().unwrap();
        assert!(stopped_at < steps_of(&a), "stopped at step {stopped_at}");
        let header = fdem_solver::checkpoint::read(&b.join("checkpoint.fdem"))
            .unwrap()
            .header;
        assert_eq!(header.step, stopped_at);
        let (code, err) = fdem_run(&["run", "--resume", s(&b)]);
        assert_eq!(code, 0, "{err}");
        assert_same_results(&a, &b);
    }
    fdem_figures::record(88, "as stated");
}

use crate::common::snapshot;

/// Resuming `dir` (with `scene`, if given) fails with exit code 2, a message that contains
/// `what`, and leaves every file of the folder as it was.
fn refused(dir: &Path, scene: Option<&Path>, what: &str) {
    let before = snapshot(dir);
    let mut args = vec!["run"];
    if let Some(sc) = scene {
        args.push(s(sc));
    }
    args.extend(["--resume", s(dir)]);
    let (code, err) = fdem_run(&args);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(what), "expected `{what}` in: {err}");
    assert!(err.contains("fix:"), "{err}");
    assert!(
        before == snapshot(dir),
        "the refused resume changed {dir:?}"
    );
}

/// A checkpoint cut short, of a newer format, damaged, of another scene or another mesh, or
/// missing: refused with its reason, nothing written. A scene that changes only its end and
/// its output is accepted: the longer run equals a straight run of the longer scene.
#[test]
fn bad_checkpoints_are_refused_and_a_longer_duration_is_accepted() {
    let scene = common::edited_example("disc-collision.json", "restart-bad", |v| {
        v["duration"] = serde_json::json!(0.3e-3);
    });
    let dir = scene.parent().unwrap();
    let b = dir.join("run");
    let (code, err) = fdem_run(&["run", s(&scene), "--out", s(&b), "--stop-after", "1000"]);
    assert_eq!(code, 4, "{err}");
    let ck = b.join("checkpoint.fdem");
    let good = std::fs::read(&ck).unwrap();

    std::fs::write(&ck, &good[..good.len() / 2]).unwrap();
    refused(&b, None, "the checkpoint is damaged");
    let mut newer = good.clone();
    newer[8..12].copy_from_slice(&(fdem_solver::checkpoint::FORMAT + 1).to_le_bytes());
    std::fs::write(&ck, &newer).unwrap();
    refused(&b, None, "newer than this fdem reads");
    let mut older = good.clone();
    older[8..12].copy_from_slice(&(fdem_solver::checkpoint::FORMAT - 1).to_le_bytes());
    std::fs::write(&ck, &older).unwrap();
    refused(&b, None, "written by an older fdem");
    let mut flipped = good.clone();
    let k = good.len() - 100;
    flipped[k] ^= 0x10;
    std::fs::write(&ck, &flipped).unwrap();
    refused(&b, None, "checksum");
    std::fs::write(&ck, &good).unwrap();

    let other = common::edited_example("disc-collision.json", "restart-bad-other", |v| {
        v["duration"] = serde_json::json!(0.3e-3);
        v["bodies"][0]["materials"]["*"]["young"] = serde_json::json!(11e9);
    });
    refused(&b, Some(&other), "belongs to another scene");
    let moved = common::edited_example("disc-collision.json", "restart-bad-mesh", |v| {
        v["duration"] = serde_json::json!(0.3e-3);
        v["bodies"][1]["mesh"] = serde_json::json!(
            common::root()
                .join("meshes/brazilian-disc.msh")
                .display()
                .to_string()
        );
    });
    refused(&b, Some(&moved), "belongs to another mesh");
    let stat = common::root().join("examples/cantilever-static.json");
    refused(&b, Some(&stat), "a static analysis has no checkpoint");
    std::fs::remove_file(&ck).unwrap();
    refused(&b, None, "cannot read the checkpoint");
    std::fs::write(&ck, &good).unwrap();

    // a run extended: run to its end (with a checkpoint there), then resumed with twice the
    // duration and twice the frames, it equals the straight run of the longer scene (a given
    // step, so that both durations have the same one: 7500 and 15 000 steps of 8e-8 s)
    let half = common::edited_example("disc-collision.json", "restart-half", |v| {
        v["integrator"]["time_step"] = serde_json::json!(8e-8);
        v["duration"] = serde_json::json!(0.6e-3);
        v["output"]["frames"] = serde_json::json!(12);
        v["histories"]["every"] = serde_json::json!(20);
    });
    let whole = common::edited_example("disc-collision.json", "restart-whole", |v| {
        v["integrator"]["time_step"] = serde_json::json!(8e-8);
        v["duration"] = serde_json::json!(1.2e-3);
        v["output"]["frames"] = serde_json::json!(24);
        v["histories"]["every"] = serde_json::json!(20);
    });
    let (a, e) = (dir.join("whole/run"), dir.join("extended/run"));
    let (code, err) = fdem_run(&["run", s(&whole), "--out", s(&a)]);
    assert_eq!(code, 0, "{err}");
    let (code, err) = fdem_run(&[
        "run",
        s(&half),
        "--out",
        s(&e),
        "--checkpoint-every",
        "5000",
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, err) = fdem_run(&["run", s(&whole), "--resume", s(&e)]);
    assert_eq!(code, 0, "{err}");
    assert_same_results(&a, &e);
    assert_eq!(steps_of(&e), 15000);

    // with the step fitted to the duration ("auto"), the extended run keeps its step and
    // ends at the first step at or after the new end
    let auto_half = common::edited_example("disc-collision.json", "restart-auto", |v| {
        v["duration"] = serde_json::json!(0.6e-3);
    });
    let auto_whole = common::edited_example("disc-collision.json", "restart-auto", |_| {});
    let f = dir.join("auto/run");
    let (code, err) = fdem_run(&[
        "run",
        s(&auto_half),
        "--out",
        s(&f),
        "--checkpoint-every",
        "off",
        "--stop-after",
        "100",
    ]);
    assert_eq!(code, 4, "{err}");
    let (code, err) = fdem_run(&["run", s(&auto_whole), "--resume", s(&f)]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(f.join("summary.json")).unwrap()).unwrap();
    let (t, h) = (
        v["simulated_time"].as_f64().unwrap(),
        v["time_step"].as_f64().unwrap(),
    );
    assert!(
        t >= 1.2e-3 * (1.0 - 1e-12) && t < 1.2e-3 + h,
        "ends at {t} s, step {h} s"
    );
    fdem_figures::record(89, format!("identical, {} steps; as stated", steps_of(&e)));
    fdem_figures::record(90, "as stated");
}

/// `output.checkpoint_every` in a scene: steps or a wall-clock time; anything else refused at
/// its JSON path with the forms it takes. A fresh run in a folder removes an old checkpoint.
#[test]
fn the_checkpoint_interval_of_a_scene_is_checked() {
    for (value, ok) in [
        (serde_json::json!(5000), true),
        (serde_json::json!("30min"), true),
        (serde_json::json!("off"), true),
        (serde_json::json!(0), false),
        (serde_json::json!(-5), false),
        (serde_json::json!("3 days"), false),
        (serde_json::json!([1]), false),
    ] {
        let scene = common::edited_example("disc-collision.json", "restart-every", |v| {
            v["output"]["checkpoint_every"] = value.clone();
        });
        match fdem_solver::load(&scene) {
            Ok(_) => assert!(ok, "{value} accepted"),
            Err(e) => {
                let m = e.to_string();
                assert!(!ok, "{value}: {m}");
                assert!(m.contains("output.checkpoint_every"), "{m}");
                assert!(m.contains("30min") || m.contains("positive"), "{m}");
            }
        }
    }
    let dir = common::temp_dir("restart-claim");
    std::fs::write(dir.join("checkpoint.fdem"), b"old").unwrap();
    let scene = common::edited_example("cantilever-vibration.json", "restart-claim", |v| {
        v["duration"] = serde_json::json!(0.01);
    });
    let (code, err) = fdem_run(&["run", s(&scene), "--out", s(&dir)]);
    assert_eq!(code, 0, "{err}");
    assert!(!dir.join("checkpoint.fdem").exists());
}
