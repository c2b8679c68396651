//! An oracle fuzzer: valid scenes and their meshes, edited the way users get them wrong, each
//! variant run by `fdem run` for a short while; every variant that ends with exit code 0 must
//! keep the invariants of a correct run.
//!
//! Seeds ([`seeds`]): a static cantilever (with the reaction of its support probed), the
//! pressure pulse along a bar, two discs colliding (contact between a pair of bodies) and the
//! fracturing Brazilian disc between platens (a fracture region, walls), each shortened to a
//! few hundred steps, with its mesh written as a JSON mesh beside it so that the mesh can be
//! edited too. Edits ([`Edit`]), one to three stacked per variant: drop, duplicate or
//! reorder an entry of any array or object of the scene; push a number to an extreme or to
//! zero; swap a name for another name of the scene or its mesh; repeat an entity of a mesh
//! group (an edge reversed, a triangle, a node); move a pressure or traction onto internal
//! edges. Durations are only shortened and frame counts kept small, so that every variant
//! stays short.
//!
//! Outcomes: exit code 2 (refused: no output folder may exist, and `fdem check` must refuse it
//! with exit code 2 and the same message) and 3 (stopped: `summary.json` must exist) are
//! answers. Exit code 0 is checked against the invariants ([`violations`]):
//! - the energy ledger closes: `|error| <= ENERGY_TOL in_play + 1e4 (E t)_max (eps L)^2`
//!   (the seeds book the contact and elastic residuals with the `energy` probe; the second
//!   term is the round-off of a scene where nothing moves, [`round_off_energy`]);
//! - a static solve's reactions balance the applied loads (when every support is probed);
//! - every section the scene names has an effect: a fracture section has joints, an enabled
//!   contact section a contact stage;
//! - the step count equals the duration over the step, and the run reached its duration;
//! - no `NaN` or infinite value in `summary.json` or `histories.csv`.
//!
//! Any other exit code, a run past [`VARIANT_SECONDS`] or an exit 0 that breaks an invariant
//! is a failure; its scene and mesh are kept in `target/oracle-failures/`.
//!
//! `FDEM_ORACLE_SECONDS` (default 45) bounds the whole run; `FDEM_ORACLE_SEED` (default 1)
//! seeds the generator; `FDEM_ORACLE_BIN` runs another `fdem` binary (a copy, for a long run
//! beside a rebuild). A long run: `FDEM_ORACLE_SECONDS=3600 cargo test --release --test all
//! -- oracle:: --nocapture` (docs/testing.md).

use crate::common::{self, Rng};

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use serde_json::{Value, json};

/// The energy ledger's error allowed, as a fraction of the energy in play.
const ENERGY_TOL: f64 = 0.02;

/// A static solve's reactions balance the loads to this fraction of the largest force.
const BALANCE_TOL: f64 = 1e-6;

/// A variant running longer than this is killed and counted a failure [s].
const VARIANT_SECONDS: u64 = 60;

/// One seed: a scene whose bodies' meshes are JSON meshes (file names relative to the scene).
#[derive(Clone)]
struct Seed {
    name: &'static str,
    scene: Value,
    meshes: BTreeMap<String, Value>,
}

/// The JSON form of a repository mesh.
fn json_mesh(rel: &str) -> Value {
    let m = fdem_mesh::read_mesh(common::root().join(rel)).unwrap();
    serde_json::to_value(fdem_mesh::JsonMesh::from_mesh(&m)).unwrap()
}

/// An example scene with its meshes as JSON meshes (`m0.json`, ...) and `edit` applied.
fn seed(name: &'static str, example: &str, edit: impl FnOnce(&mut Value)) -> Seed {
    let src = common::root().join("examples").join(example);
    let mut scene: Value = serde_json::from_str(&std::fs::read_to_string(&src).unwrap()).unwrap();
    let mut meshes = BTreeMap::new();
    for (i, b) in scene["bodies"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .enumerate()
    {
        let rel = b["mesh"].as_str().unwrap().to_string();
        let path = src.parent().unwrap().join(&rel);
        let file = format!("m{i}.json");
        let m = fdem_mesh::read_mesh(&path).unwrap();
        meshes.insert(
            file.clone(),
            serde_json::to_value(fdem_mesh::JsonMesh::from_mesh(&m)).unwrap(),
        );
        b["mesh"] = json!(file);
    }
    edit(&mut scene);
    Seed {
        name,
        scene,
        meshes,
    }
}

/// The seeds (module docs).
fn seeds() -> Vec<Seed> {
    let energy = |v: &mut Value| {
        let probes = v["histories"]["probes"].as_array_mut().unwrap();
        probes.push(json!("energy"));
        v["histories"]["every"] = json!(20);
    };
    vec![
        seed("cantilever-static", "cantilever-static.json", |v| {
            v["bodies"][0]["mesh"] = json!("m0.json");
        }),
        seed("bar-pulse", "bar-pulse.json", |v| {
            v["duration"] = json!(6e-5);
            v["output"]["frames"] = json!(2);
            energy(v);
        }),
        seed("disc-collision", "disc-collision.json", |v| {
            v["duration"] = json!(3e-5);
            v["output"]["frames"] = json!(2);
            energy(v);
        }),
        seed("disc-fracture", "brazilian-disc-fracture.json", |v| {
            v["duration"] = json!(4e-5);
            v["output"]["frames"] = json!(2);
            energy(v);
        }),
    ]
}

/// The cantilever seed's mesh is the coarse one (a mesh per seed is written as JSON).
fn fix_static_mesh(seeds: &mut [Seed]) {
    for s in seeds.iter_mut().filter(|s| s.name == "cantilever-static") {
        s.meshes.insert(
            "m0.json".into(),
            json_mesh("examples/meshes/cantilever-coarse.json"),
        );
    }
}

/// One edit of a variant.
#[derive(Debug, Clone, Copy)]
enum Edit {
    Drop,
    Duplicate,
    Reorder,
    Extreme,
    SwapName,
    RepeatMeshEntity,
    LoadInterior,
}

const EDITS: [Edit; 7] = [
    Edit::Drop,
    Edit::Duplicate,
    Edit::Reorder,
    Edit::Extreme,
    Edit::SwapName,
    Edit::RepeatMeshEntity,
    Edit::LoadInterior,
];

/// Every JSON pointer of `v` with its value's kind, depth first.
fn pointers(v: &Value, at: String, out: &mut Vec<(String, &'static str)>) {
    match v {
        Value::Object(m) => {
            out.push((at.clone(), "object"));
            for (k, x) in m {
                pointers(
                    x,
                    format!("{at}/{}", k.replace('~', "~0").replace('/', "~1")),
                    out,
                );
            }
        }
        Value::Array(a) => {
            out.push((at.clone(), "array"));
            for (i, x) in a.iter().enumerate() {
                pointers(x, format!("{at}/{i}"), out);
            }
        }
        Value::Number(_) => out.push((at, "number")),
        Value::String(_) => out.push((at, "string")),
        _ => {}
    }
}

/// The last token of a pointer.
fn last(p: &str) -> &str {
    p.rsplit('/').next().unwrap_or("")
}

/// Applies one edit to the seed; returns a description (`None`: the edit found nothing).
fn apply(edit: Edit, s: &mut Seed, rng: &mut Rng) -> Option<String> {
    let mut ps = Vec::new();
    pointers(&s.scene, String::new(), &mut ps);
    let of_kind = |k: &str| -> Vec<String> {
        ps.iter()
            .filter(|(p, kind)| *kind == k && !p.is_empty())
            .map(|(p, _)| p.clone())
            .collect()
    };
    match edit {
        Edit::Drop | Edit::Duplicate | Edit::Reorder => {
            let mut places: Vec<String> = of_kind("array");
            if matches!(edit, Edit::Drop) {
                places.extend(of_kind("object"));
            }
            let p = places.get(rng.below(places.len()))?.clone();
            let x = s.scene.pointer_mut(&p)?;
            match (edit, x) {
                (Edit::Drop, Value::Array(a)) if !a.is_empty() => {
                    let i = rng.below(a.len());
                    a.remove(i);
                    Some(format!("drop {p}/{i}"))
                }
                (Edit::Drop, Value::Object(m)) if !m.is_empty() => {
                    let k = m.keys().nth(rng.below(m.len()))?.clone();
                    if k == "duration" {
                        return None;
                    }
                    m.remove(&k);
                    Some(format!("drop {p}/{k}"))
                }
                (Edit::Duplicate, Value::Array(a)) if !a.is_empty() => {
                    let i = rng.below(a.len());
                    let e = a[i].clone();
                    a.insert(i, e);
                    Some(format!("duplicate {p}/{i}"))
                }
                (Edit::Reorder, Value::Array(a)) if a.len() > 1 => {
                    a.reverse();
                    Some(format!("reverse {p}"))
                }
                _ => None,
            }
        }
        Edit::Extreme => {
            let nums = of_kind("number");
            let p = nums.get(rng.below(nums.len()))?.clone();
            let key = p
                .rsplit('/')
                .find(|t| t.parse::<usize>().is_err())
                .unwrap_or("");
            let x = s.scene.pointer_mut(&p)?;
            let v = x.as_f64()?;
            let choices = [
                0.0,
                -v,
                v * 1e6,
                v * 1e-6,
                1e300,
                1e-300,
                -1.0,
                0.5,
                1.0,
                2.0,
            ];
            let mut new = choices[rng.below(choices.len())];
            // the run stays short: durations only shrink, counts stay small
            if key == "duration" {
                new = v * [0.5, 1e-3, 0.0, -1.0][rng.below(4)];
            }
            if matches!(key, "frames" | "every" | "active_bound_every") {
                new = [0.0, 1.0, 3.0, -1.0][rng.below(4)];
            }
            *x = serde_json::Number::from_f64(new)
                .map(Value::Number)
                .unwrap_or(Value::Null);
            Some(format!("{p} = {new:e}"))
        }
        Edit::SwapName => {
            let strings = of_kind("string");
            let p = strings.get(rng.below(strings.len()))?.clone();
            if matches!(last(&p), "mesh" | "title" | "scheme") {
                return None;
            }
            let mut names: Vec<String> = strings
                .iter()
                .filter_map(|q| s.scene.pointer(q)?.as_str().map(String::from))
                .collect();
            for m in s.meshes.values() {
                for g in m["groups"].as_array().into_iter().flatten() {
                    names.extend(g["name"].as_str().map(String::from));
                }
            }
            names.sort();
            names.dedup();
            let n = names.get(rng.below(names.len()))?.clone();
            *s.scene.pointer_mut(&p)? = json!(n);
            Some(format!("{p} = {n:?}"))
        }
        Edit::RepeatMeshEntity => {
            let files: Vec<String> = s.meshes.keys().cloned().collect();
            let f = files.get(rng.below(files.len()))?.clone();
            let groups = s.meshes.get_mut(&f)?["groups"].as_array_mut()?;
            let gi = rng.below(groups.len());
            let g = groups.get_mut(gi)?;
            let name = g["name"].as_str().unwrap_or("").to_string();
            for field in ["edges", "triangles", "nodes"] {
                if let Some(a) = g[field].as_array_mut().filter(|a| !a.is_empty()) {
                    let i = rng.below(a.len());
                    let mut e = a[i].clone();
                    if let Some(pair) = e.as_array_mut() {
                        pair.reverse();
                    }
                    a.push(e);
                    return Some(format!("{f}: group {name:?} repeats its {field} entry {i}"));
                }
            }
            None
        }
        Edit::LoadInterior => {
            // an edge group of internal edges, and a pressure or traction on it
            let (file, body) = s.meshes.keys().next().cloned().map(|f| (f, 0))?;
            let mesh =
                fdem_mesh::read_mesh_bytes(s.meshes[&file].to_string().as_bytes(), "m").ok()?;
            let interior: Vec<[u32; 2]> = mesh
                .edges
                .iter()
                .filter(|e| e.right.is_some())
                .map(|e| [e.nodes[0].0, e.nodes[1].0])
                .collect();
            if interior.is_empty() {
                return None;
            }
            let k = 1 + rng.below(interior.len().min(8));
            let start = rng.below(interior.len() - k + 1);
            let edges = &interior[start..start + k];
            s.meshes.get_mut(&file)?["groups"]
                .as_array_mut()?
                .push(json!({"name": "inner", "dim": 1, "edges": edges}));
            let bname = s.scene["bodies"][body]["name"].clone();
            let load = if rng.below(2) == 0 {
                json!({ "pressure": { "group": "inner", "body": bname, "value": 1e5 } })
            } else {
                json!({ "traction": { "group": "inner", "body": bname, "value": [1e5, 0.0] } })
            };
            let bcs = s
                .scene
                .as_object_mut()?
                .entry("boundary_conditions")
                .or_insert(json!([]));
            bcs.as_array_mut()?.push(load);
            Some(format!("{file}: load on {k} internal edge(s)"))
        }
    }
}

/// Writes a variant into `dir`; returns the scene file.
fn write(s: &Seed, dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    for (f, m) in &s.meshes {
        std::fs::write(dir.join(f), m.to_string()).unwrap();
    }
    let file = dir.join("scene.json");
    std::fs::write(&file, serde_json::to_string_pretty(&s.scene).unwrap()).unwrap();
    file
}

/// `fdem run SCENE --out OUT`, killed after [`VARIANT_SECONDS`]; the exit code (`None`: killed
/// or ended by a signal) and stderr.
fn run(scene: &Path, out: &Path) -> (Option<i32>, String) {
    let mut cmd = Command::new(fdem_bin());
    cmd.args([
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ])
    .env("RAYON_NUM_THREADS", "1");
    common::run_limited(&mut cmd, Duration::from_secs(VARIANT_SECONDS))
        .unwrap_or_else(|| (None, format!("killed after {VARIANT_SECONDS} s")))
}

/// The `fdem` binary the variants run: this build's, or `FDEM_ORACLE_BIN` (a copy, so that a
/// long run is not disturbed by a rebuild).
fn fdem_bin() -> PathBuf {
    std::env::var_os("FDEM_ORACLE_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_fdem")))
}

/// A number of a JSON value as f64 (0 when absent).
fn num(v: &Value, key: &str) -> f64 {
    v.get(key).and_then(Value::as_f64).unwrap_or(0.0)
}

/// The invariants an exit-0 run of `scene` (written in `out`) breaks (module docs).
fn violations(scene_file: &Path, scene: &Value, out: &Path) -> Vec<String> {
    let mut bad = Vec::new();
    let Ok(text) = std::fs::read_to_string(out.join("summary.json")) else {
        return vec!["exit 0 without summary.json".into()];
    };
    let Ok(sum) = serde_json::from_str::<Value>(&text) else {
        return vec!["summary.json is not JSON".into()];
    };
    // JSON has no NaN: a non-finite term of the ledger would be written as null
    if let Some(k) = sum["energy"]
        .as_object()
        .and_then(|m| m.iter().find(|(_, x)| x.is_null()).map(|(k, _)| k.clone()))
    {
        bad.push(format!("summary.json: energy.{k} is not a finite number"));
    }
    if let Ok(h) = std::fs::read_to_string(out.join("histories.csv"))
        && h.lines()
            .skip(1)
            .flat_map(|l| l.split(','))
            .any(|x| x.trim().parse::<f64>().is_ok_and(|v| !v.is_finite()))
    {
        bad.push("histories.csv holds a non-finite value".into());
    }
    let e = &sum["energy"];
    let (error, in_play) = (num(e, "error"), num(e, "in_play"));
    let floor = round_off_energy(scene_file);
    // NaN counts as open
    let closes = error.abs() <= ENERGY_TOL * in_play.abs() + floor;
    if !closes {
        bad.push(format!(
            "the energy ledger does not close: error {error:e} of {in_play:e} in play (round-off floor {floor:e})"
        ));
    }
    let analysis = sum["analysis"].as_str().unwrap_or("").to_lowercase();
    if analysis != "static" && sum.get("interrupted").is_none_or(Value::is_null) {
        let (h, steps, t) = (
            num(&sum, "time_step"),
            num(&sum, "steps"),
            num(&sum, "simulated_time"),
        );
        let duration = scene["duration"].as_f64().unwrap_or(f64::NAN);
        let adaptive = sum.get("time_step_range").is_some_and(|r| !r.is_null());
        if !adaptive && ((steps * h - duration).abs() > 1e-9 * duration) {
            bad.push(format!(
                "{steps} steps of {h:e} s do not span the duration {duration:e} s"
            ));
        }
        if (t - duration).abs() > 1e-9 * duration && sum["converged"] != json!(true) {
            bad.push(format!(
                "the run ended at t = {t:e} s, not at the duration {duration:e} s"
            ));
        }
    }
    let stages = &sum["stages"];
    if scene.get("fracture").is_some_and(|f| f.is_object())
        && stages["fracture"]["joints"].as_u64().unwrap_or(0) == 0
    {
        bad.push("a fracture section without joints".into());
    }
    if scene
        .get("contact")
        .is_some_and(|c| c.is_object() && c["enabled"] != json!(false))
        && stages.get("contact").is_none_or(Value::is_null)
    {
        bad.push("an enabled contact section without a contact stage".into());
    }
    if analysis == "static" {
        bad.extend(static_balance(scene_file, scene, out));
    }
    bad
}

/// The round-off floor of the ledger's error [J]: `1e4 (E t)_max (eps L)^2`, the elastic
/// energy of the positions rounded to `eps L` (`L` the scene's size), at which a scene where
/// nothing moves (no load, bodies at rest) closes its books.
fn round_off_energy(scene_file: &Path) -> f64 {
    let Ok(l) = fdem_solver::load(scene_file) else {
        return 0.0;
    };
    let m = &l.model;
    let et = (m.tri_material.iter().zip(&m.tri_thickness))
        .map(|(&k, t)| m.materials[k as usize].0.young * t)
        .fold(0.0, f64::max);
    let (lo, hi) = m.x0.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    );
    let size = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    1e4 * et * (f64::EPSILON * size).powi(2)
}

/// A static solve's reactions against its loads, when its one support group is probed.
fn static_balance(scene_file: &Path, scene: &Value, out: &Path) -> Option<String> {
    let bcs = scene["boundary_conditions"].as_array()?;
    let supports: Vec<&str> = bcs
        .iter()
        .filter_map(|b| {
            let (k, v) = b.as_object()?.iter().next()?;
            matches!(k.as_str(), "fixed" | "velocity" | "displacement")
                .then(|| v["group"].as_str())?
        })
        .collect();
    let [group] = supports[..] else {
        return None;
    };
    let l = fdem_solver::load(scene_file).ok()?;
    if l.model.gravity.is_some() || !l.model.prescribed.is_empty() {
        return None;
    }
    let mut applied = [0.0f64; 2];
    for (dof, f) in l.model.loads.iter().flat_map(|r| r.forces.iter()) {
        applied[(*dof % 2) as usize] += f;
    }
    if !out.join("histories.csv").exists() {
        return None;
    }
    let (head, rows) = common::histories(out);
    let row = rows.last()?;
    let col = |name: &str| head.iter().position(|h| h == name).map(|i| row[i]);
    let r = [
        col(&format!("reaction_x[{group}]"))?,
        col(&format!("reaction_y[{group}]"))?,
    ];
    let scale = applied[0]
        .abs()
        .max(applied[1].abs())
        .max(r[0].abs())
        .max(r[1].abs());
    let off = (applied[0] + r[0]).abs().max((applied[1] + r[1]).abs());
    (off > BALANCE_TOL * scale + 1e-12).then(|| {
        format!("the reactions {r:?} do not balance the loads {applied:?} (off by {off:e})")
    })
}

/// Runs variants for `seconds`; returns (variants, exit-code counts, failures).
fn fuzz(seconds: f64, seed: u64) -> (usize, BTreeMap<String, usize>, Vec<String>) {
    let mut seeds = seeds();
    fix_static_mesh(&mut seeds);
    let mut rng = Rng(seed);
    let root = common::temp_dir("oracle");
    let keep = common::root().join("target/oracle-failures");
    let start = Instant::now();
    let (mut n, mut codes, mut failures) = (0usize, BTreeMap::new(), Vec::new());
    // each seed unedited first: the invariants hold on the valid scenes
    let mut plain = seeds.clone().into_iter();
    while start.elapsed().as_secs_f64() < seconds || n < seeds.len() {
        let (mut s, mut what) = match plain.next() {
            Some(s) => (s, vec!["(unedited)".to_string()]),
            None => (seeds[rng.below(seeds.len())].clone(), Vec::new()),
        };
        if what.is_empty() {
            for _ in 0..1 + rng.below(3) {
                let e = EDITS[rng.below(EDITS.len())];
                what.extend(apply(e, &mut s, &mut rng));
            }
            if what.is_empty() {
                continue;
            }
        }
        n += 1;
        let dir = root.join(format!("v{n}"));
        let file = write(&s, &dir);
        let out = dir.join("out");
        let (code, err) = run(&file, &out);
        *codes.entry(format!("{code:?}")).or_insert(0) += 1;
        let broken: Vec<String> = match code {
            Some(0) => violations(&file, &s.scene, &out),
            Some(2) if out.exists() => vec!["refused, but the output folder was made".into()],
            Some(2) => check_agrees(&file, &err),
            Some(3) if !out.join("summary.json").exists() => {
                vec!["stopped without summary.json".into()]
            }
            Some(3) => Vec::new(),
            _ => vec![format!("exit {code:?}: {}", common_tail(&err))],
        };
        if !broken.is_empty() {
            let kept = keep.join(format!("{}-{seed}-{n}", s.name));
            let _ = std::fs::remove_dir_all(&kept);
            write(&s, &kept);
            failures.push(format!(
                "{} [{}]: {} (kept in {})",
                s.name,
                what.join("; "),
                broken.join("; "),
                kept.display()
            ));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    (n, codes, failures)
}

/// The error of a message: from its `error:` line on.
fn error_part(s: &str) -> &str {
    s.find("error:").map_or(s, |i| &s[i..])
}

/// `fdem check` refuses what `fdem run` refused (`run_err`), with exit code 2 and the same
/// message.
fn check_agrees(scene: &Path, run_err: &str) -> Vec<String> {
    let o = Command::new(fdem_bin())
        .args(["check".as_ref(), scene.as_os_str()])
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    if o.status.code() != Some(2) || error_part(&err) != error_part(run_err) {
        vec![format!(
            "run refused with {:?}, check answered {:?} with {:?}",
            error_part(run_err),
            o.status.code(),
            error_part(&err)
        )]
    } else {
        Vec::new()
    }
}

/// The last lines of a message.
fn common_tail(s: &str) -> String {
    let lines: Vec<&str> = s.lines().collect();
    lines[lines.len().saturating_sub(4)..].join(" | ")
}

#[test]
fn oracle_fuzzer_finds_no_exit_0_that_breaks_an_invariant() {
    let seconds: f64 = std::env::var("FDEM_ORACLE_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(45.0);
    let seed: u64 = std::env::var("FDEM_ORACLE_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let (n, codes, failures) = fuzz(seconds, seed);
    eprintln!("oracle fuzzer: {n} variants in {seconds} s (seed {seed}), exit codes {codes:?}");
    assert!(n >= 4, "only {n} variants ran");
    assert!(
        failures.is_empty(),
        "{} failure(s):\n{}",
        failures.len(),
        failures.join("\n")
    );
    // the number of variants depends on the machine's speed (a time budget): not a figure
    fdem_figures::record(141, "none");
}

#[test]
fn the_invariants_catch_a_run_that_breaks_them() {
    // a summary as a broken run would write it: the ledger open, a fracture section without
    // joints, 99 steps where the duration takes 100, and a non-finite term
    let dir = common::temp_dir("oracle-broken");
    let scene = json!({ "duration": 1e-3, "fracture": { "regions": [] }, "contact": {} });
    let summary = json!({
        "analysis": "Dynamic", "time_step": 1e-5, "steps": 99, "simulated_time": 1e-3,
        "energy": { "error": 0.5, "in_play": 1.0, "kinetic": null },
        "stages": { "fracture": { "joints": 0 } }
    });
    std::fs::write(dir.join("summary.json"), summary.to_string()).unwrap();
    let found = violations(&dir.join("scene.json"), &scene, &dir);
    for needle in [
        "energy.kinetic is not a finite number",
        "the energy ledger does not close",
        "do not span the duration",
        "a fracture section without joints",
        "an enabled contact section without a contact stage",
    ] {
        assert!(
            found.iter().any(|f| f.contains(needle)),
            "{needle}: {found:?}"
        );
    }
    // the same summary, mended, breaks none
    let good = json!({
        "analysis": "Dynamic", "time_step": 1e-5, "steps": 100, "simulated_time": 1e-3,
        "energy": { "error": 1e-4, "in_play": 1.0, "kinetic": 0.2 },
        "stages": { "fracture": { "joints": 12 }, "contact": { "couples": 3 } }
    });
    std::fs::write(dir.join("summary.json"), good.to_string()).unwrap();
    assert_eq!(
        violations(&dir.join("scene.json"), &scene, &dir),
        Vec::<String>::new()
    );
}
