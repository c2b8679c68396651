//! Distributed runs against the single-process run. The ranks here are threads of the test
//! process talking through channels (`ThreadComm`): the same decomposition, exchanges and
//! output as under MPI (`tests/mpi/mpi_runs.sh` runs them through `mpirun`). Known answer:
//! the single-process run's files, byte for byte.

use std::path::{Path, PathBuf};

use fdem_solver::distributed::ThreadComm;
use fdem_solver::driver::{self, Outcome, RunOptions};

use crate::common::{edited_example, root, temp_dir};

/// Runs `scene` on `size` ranks (threads) into `out`; the outcome of each rank.
fn run_ranks(scene: &Path, size: usize, out: &Path) -> Vec<Result<Outcome, String>> {
    let options = RunOptions {
        out_dir: out.to_path_buf(),
        ..Default::default()
    };
    run_with(scene, size, options)
}

/// Runs `scene` in one process into `out`.
fn run_serial(scene: &Path, out: &Path) -> Outcome {
    let mut l = driver::load(scene).unwrap();
    let options = RunOptions {
        out_dir: out.to_path_buf(),
        ..Default::default()
    };
    driver::run_outcome(&mut l, &options, &mut |_| {}).unwrap()
}

/// The files of a run folder but `summary.json` (its timings differ from run to run), sorted.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap() != "summary.json")
        .collect();
    v.sort();
    v
}

/// Asserts that the folders hold the same files with the same bytes; returns their number.
fn assert_same_files(serial: &Path, other: &Path) -> usize {
    assert_same_files_but(serial, other, &[])
}

/// The single-process run and the runs on 2, 3 and 4 ranks of `scene`: the same files, the
/// same end state and the same summary but for its timings.
/// Returns, per rank count, how often the whole state was shared.
fn compare(scene: &Path, tag: &str) -> Vec<u64> {
    compare_on(scene, tag, &[2, 3, 4])
}

/// [`compare`] on the rank counts `sizes`.
fn compare_on(scene: &Path, tag: &str, sizes: &[usize]) -> Vec<u64> {
    let mut shares = Vec::new();
    let dir = temp_dir(tag);
    let serial = run_serial(scene, &dir.join("np1"));
    for &size in sizes {
        let out = dir.join(format!("np{size}"));
        let outcomes = run_ranks(scene, size, &out);
        let n = assert_same_files(&dir.join("np1"), &out);
        assert!(n >= 3, "frames, pvd and histories compared ({n} files)");
        for o in outcomes {
            let o = o.unwrap_or_else(|e| panic!("{size} ranks: {e}"));
            assert_eq!(
                crate::common::state_bits(&o),
                crate::common::state_bits(&serial)
            );
            assert_eq!(o.summary.steps, serial.summary.steps);
            assert_eq!(
                o.summary.energy.error.to_bits(),
                serial.summary.energy.error.to_bits()
            );
            // every rank's stage books (the contact's slip and damping dissipation, wall
            // work, work on the nodes, switch jump, active bound; the joints'), but for the
            // timers and the rank's own counts
            assert_eq!(
                books(&o.summary.stages),
                books(&serial.summary.stages),
                "{size} ranks"
            );
        }
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(summary["steps"], serde_json::json!(serial.summary.steps));
        let d = &summary["distributed"];
        assert_eq!(d["ranks"], serde_json::json!(size));
        shares.push(d["whole_state_shares"].as_u64().unwrap());
    }
    shares
}

/// The stages' reports without their timers (`*_s`) and the rank's own counts (`rank_*`).
fn books(stages: &serde_json::Value) -> serde_json::Value {
    let mut v = stages.clone();
    if let Some(m) = v.as_object_mut() {
        for stage in m.values_mut() {
            if let Some(d) = stage.as_object_mut() {
                d.retain(|k, _| !k.ends_with("_s") && !k.starts_with("rank_"));
            }
        }
    }
    v
}

#[test]
fn the_bar_pulse_on_2_3_and_4_ranks_writes_the_single_process_files_byte_for_byte() {
    // a pressure on the left end (loaded DOFs, shared with every rank after each step),
    // histories every step (the whole state shared after each step)
    let shares = compare(&root().join("examples/bar-pulse.json"), "dist-bar");
    assert!(
        shares.iter().all(|&s| s > 1000),
        "shared after every step: {shares:?}"
    );
    fdem_figures::record_part(122, 1, "bar pulse identical");
}

#[test]
fn the_cantilever_with_sparse_histories_on_2_3_and_4_ranks_is_the_single_process_run() {
    // a clamped end and a tip load; histories every 37 steps and 7 frames, so that most steps
    // share only the ghosts and the loaded nodes
    let scene = edited_example("cantilever-vibration.json", "dist-cantilever", |v| {
        // without the energy probe, whose work of the element forces sums over every node
        // in every step (and so shares the whole state after each)
        v["histories"] = serde_json::json!({
            "every": 37, "probes": [ { "displacement": { "group": "tip" } } ]
        });
        v["output"]["frames"] = serde_json::json!(7);
    });
    let shares = compare(&scene, "dist-cantilever-runs");
    // the whole state after 1 step in 27 (checks every 100, rows every 37, frames, the last)
    assert!(
        shares.iter().all(|&s| s < 1000),
        "shared when observed only: {shares:?}"
    );
    fdem_figures::record_part(122, 2, "cantilever identical");
}

#[test]
fn the_disc_collision_on_2_and_4_ranks_writes_the_single_process_files_byte_for_byte() {
    // frictionless contact between two bodies, walls.csv-free; each rank evaluates the
    // couples that touch its nodes
    compare_on(
        &root().join("examples/disc-collision.json"),
        "dist-collision",
        &[2, 4],
    );
    fdem_figures::record_part(123, 1, "disc collision identical");
}

#[test]
fn the_disc_collision_with_friction_damping_and_a_floor_on_2_and_3_ranks_is_the_single_process_run()
{
    // friction and damping between the discs and with a floor they slide on: the couples'
    // friction histories, the damping power and the walls' reactions folded across ranks
    let scene = edited_example("disc-collision.json", "dist-collision-damped", |v| {
        let law = serde_json::json!({ "friction": 0.3, "damping": 7.7e6 });
        v["contact"] = serde_json::json!({
            "default": law,
            "walls": [ { "name": "floor", "point": [0.0, -0.025], "normal": [0.0, 1.0],
                         "law": law } ]
        });
        v["gravity"] = serde_json::json!([0.0, -9.81]);
    });
    compare_on(&scene, "dist-collision-damped-runs", &[2, 3]);
    fdem_figures::record(129, "identical");
}

#[test]
fn the_fracturing_disc_on_2_and_4_ranks_writes_the_single_process_files_byte_for_byte() {
    // joints that soften and break, contact taking over, platens (walls.csv), fractures.csv
    // and the joint frames
    compare_on(
        &root().join("examples/brazilian-disc-fracture.json"),
        "dist-disc",
        &[2, 4],
    );
    // each rank evaluated its own joints and couples and those that cross to another rank
    // only
    let dir = temp_dir("dist-disc-share");
    let out = dir.join("np2");
    let o = run_ranks(
        &root().join("examples/brazilian-disc-fracture.json"),
        2,
        &out,
    );
    let rank0 = o[0].as_ref().unwrap().summary.stages["fracture"].clone();
    let (all, mine) = (
        rank0["joints"].as_u64().unwrap(),
        rank0["rank_joints"].as_u64().unwrap(),
    );
    assert!(
        mine < all * 3 / 5,
        "rank 0 of 2 evaluates {mine} of {all} joints"
    );
    let joints = format!("{mine} of {all} joints");
    let contact = o[0].as_ref().unwrap().summary.stages["contact"].clone();
    let (all, mine) = (
        contact["couples"].as_u64().unwrap(),
        contact["rank_couples"].as_u64().unwrap(),
    );
    assert!(
        all > 100 && mine < all * 3 / 5,
        "rank 0 of 2 evaluates {mine} of {all} couples"
    );
    fdem_figures::record_part(
        123,
        2,
        format!("fracturing disc identical, rank 0 of 2: {joints}, {mine} of {all} couples"),
    );
}

#[test]
fn the_block_compressed_to_failure_on_2_and_4_ranks_is_the_single_process_run() {
    // fragments and a crack across the partition's cuts
    compare_on(
        &root().join("examples/block-compression-fracture.json"),
        "dist-block",
        &[2, 4],
    );
    fdem_figures::record_part(123, 3, "block identical");
}

#[test]
fn the_block_repartitioned_as_it_breaks_is_the_single_process_run() {
    // a threshold of 1: the parts are cut again, weighted by the triangles', joints' and
    // couples' costs, at every check where that is better balanced; the new owners take the
    // nodes, joints and couples with their histories
    let scene = root().join("examples/block-compression-fracture.json");
    let dir = temp_dir("dist-rebalance");
    run_serial(&scene, &dir.join("np1"));
    // on 3 ranks with the threshold `rebalance`: rank 0's `distributed` summary
    let on_3 = |tag: &str, rebalance: f64| {
        let out = dir.join(tag);
        let options = RunOptions {
            out_dir: out.clone(),
            rebalance: Some(rebalance),
            ..Default::default()
        };
        let outcomes = run_with(&scene, 3, options);
        assert_same_files(&dir.join("np1"), &out);
        outcomes[0]
            .as_ref()
            .unwrap()
            .summary
            .distributed
            .clone()
            .unwrap()
    };
    let d = on_3("np3", 1.0);
    let n = d["repartitions"].as_u64().unwrap();
    let imbalance = d["imbalance_after_repartition"].as_f64().unwrap();
    assert!(n >= 2, "{n} repartitions");
    let (now, after) = (
        d["imbalance_last_check"].as_f64().unwrap(),
        d["imbalance_after_repartition"].as_f64().unwrap(),
    );
    assert!(
        after < 1.1 && now < 1.25,
        "imbalance {now} at the last check, {after} after the last repartition"
    );
    // off: never
    let d = on_3("np3-off", f64::INFINITY);
    assert_eq!(d["repartitions"].as_u64(), Some(0));
    assert!(d["imbalance_last_check"].as_f64().unwrap() > 1.0);
    fdem_figures::record(
        130,
        format!(
            "identical; {n} repartitions (3 ranks as threads) and none, imbalance {imbalance:.3} after the last"
        ),
    );
}

#[test]
fn what_a_distributed_run_does_not_do_is_refused_with_its_field_before_anything_is_written() {
    let dir = temp_dir("dist-refused");
    let cases = [
        ("cantilever-relaxation.json", 2, "at `analysis`"),
        ("cantilever-static.json", 2, "at `analysis`"),
    ];
    for (name, size, path) in cases {
        let out = dir.join(name);
        let errors = run_ranks(&root().join("examples").join(name), size, &out);
        for e in errors {
            let e = e.err().expect(name);
            assert!(
                e.contains(path) && e.contains("fix: run it as one process"),
                "{name}: {e}"
            );
        }
        assert!(!out.exists(), "{name}: nothing written");
    }
    // more ranks than triangles: a bar of 2 triangles on 3 ranks
    let scene = crate::common::edited_example("bar-pulse.json", "dist-tiny", |_| {});
    let mesh = scene.parent().unwrap().join("two.json");
    std::fs::write(
        &mesh,
        serde_json::json!({
            "nodes": [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            "triangles": [[0, 1, 2], [0, 2, 3]],
            "groups": [
                { "name": "bar", "dim": 2, "triangles": [0, 1] },
                { "name": "left", "dim": 1, "edges": [[3, 0]] }
            ]
        })
        .to_string(),
    )
    .unwrap();
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    v["bodies"][0]["mesh"] = serde_json::json!(mesh.display().to_string());
    v["histories"] = serde_json::json!({ "every": 1, "probes": [] });
    v["output"] = serde_json::json!({ "frames": 1 });
    std::fs::write(&scene, v.to_string()).unwrap();
    let out = dir.join("tiny");
    for e in run_ranks(&scene, 3, &out) {
        let e = e.err().expect("3 ranks for 2 triangles");
        assert!(
            e.contains("3 processes for 2 triangles") && e.contains("at most 2"),
            "{e}"
        );
    }
    assert!(!out.exists());
    fdem_figures::record(125, "refused");
}

/// Runs `scene` on `size` ranks (threads, or one process for 1) into `out` with `options`.
fn run_with(scene: &Path, size: usize, options: RunOptions) -> Vec<Result<Outcome, String>> {
    if size == 1 {
        let mut l = driver::load(scene).unwrap();
        return vec![driver::run_outcome(&mut l, &options, &mut |_| {}).map_err(|e| e.to_string())];
    }
    let comms = ThreadComm::ranks(size);
    std::thread::scope(|s| {
        let handles: Vec<_> = comms
            .into_iter()
            .map(|c| {
                let options = options.clone();
                s.spawn(move || {
                    let mut l = driver::load(scene).map_err(|e| e.to_string())?;
                    driver::run_distributed(&mut l, &options, Box::new(c), &mut |_| {})
                        .map_err(|e| e.to_string())
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    })
}

/// Resumes the run in `out` of `scene` on `size` ranks (1: one process) and asserts that its
/// files are those of the run that never stopped, in `straight` (the checkpoint and the run's
/// id left aside).
fn resume_and_compare(scene: &Path, size: usize, out: &Path, straight: &Path) -> usize {
    let resumed = run_with(
        scene,
        size,
        RunOptions {
            out_dir: out.to_path_buf(),
            resume: true,
            ..Default::default()
        },
    );
    for r in resumed {
        r.unwrap_or_else(|e| panic!("resumed on {size} ranks: {e}"));
    }
    assert_same_files_but(straight, out, &["checkpoint.fdem", "run_id.txt"])
}

#[test]
fn a_distributed_checkpoint_is_the_single_process_one_and_resumes_on_any_number_of_ranks() {
    // the fracturing disc (joints, contact, platens) stopped at step 20 000: on 2 ranks and
    // resumed on 2, on 1 and on 4; on 1 process and resumed on 3 ranks: every file of each
    // equals the run that never stopped
    let scene = root().join("examples/brazilian-disc-fracture.json");
    let dir = temp_dir("dist-restart");
    let straight = dir.join("straight");
    run_serial(&scene, &straight);
    let cases: [(usize, usize); 4] = [(2, 2), (2, 1), (2, 4), (1, 3)];
    for (first, then) in cases {
        let out = dir.join(format!("np{first}-then-np{then}"));
        let stopped = run_with(
            &scene,
            first,
            RunOptions {
                out_dir: out.clone(),
                stop_after: Some(20_000),
                ..Default::default()
            },
        );
        for r in stopped {
            let e = r.err().expect("stopped");
            assert!(e.contains("stop_after"), "{e}");
        }
        // the checkpoint is left in the folder of a resumed run
        let n = resume_and_compare(&scene, then, &out, &straight);
        assert!(n > 60, "{n} files");
    }
    fdem_figures::record(126, "identical");
}

/// [`assert_same_files`], leaving out the files named in `except` too.
fn assert_same_files_but(serial: &Path, other: &Path, except: &[&str]) -> usize {
    let keep = |v: Vec<PathBuf>| -> Vec<PathBuf> {
        v.into_iter()
            .filter(|p| !except.iter().any(|e| p.file_name().unwrap() == *e))
            .collect()
    };
    let (a, b) = (keep(files(serial)), keep(files(other)));
    let names = |v: &[PathBuf]| -> Vec<String> {
        v.iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect()
    };
    assert_eq!(names(&a), names(&b), "the same files");
    for (p, q) in a.iter().zip(&b) {
        let (x, y) = (std::fs::read(p).unwrap(), std::fs::read(q).unwrap());
        assert!(x == y, "{} differs from {}", q.display(), p.display());
    }
    a.len()
}

#[test]
fn a_stop_signal_is_taken_up_by_every_rank_at_the_next_agreed_step() {
    // rank 0's stop flag (a signal) already set: every rank stops after step 16 (the first
    // step at which the ranks take up rank 0's decision) with the checkpoint, and the run
    // resumes on 3 ranks to the files of the run that never stopped
    let scene = root().join("examples/disc-collision.json");
    let dir = temp_dir("dist-signal");
    let straight = dir.join("straight");
    run_serial(&scene, &straight);
    let out = dir.join("stopped");
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(2));
    let stopped = run_with(
        &scene,
        2,
        RunOptions {
            out_dir: out.clone(),
            stop: Some(stop),
            ..Default::default()
        },
    );
    for r in stopped {
        let e = r.err().expect("stopped");
        assert!(e.contains("SIGINT") && e.contains("at step 16 "), "{e}");
    }
    resume_and_compare(&scene, 3, &out, &straight);
    fdem_figures::record(127, "step 16; identical");
}
