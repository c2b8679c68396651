//! Names and derived quantities: every name a scene refers to is resolved in one place
//! (`fdem_solver::input::resolve`), every derived quantity of a run is checked in one place
//! (`fdem_solver::problem::limits`), the step count takes whole quotients, and history columns are
//! unique. Bad input: `fdem check` and `fdem run` exit 2, name the JSON path and the valid
//! names, and write nothing.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use fdem_solver::input::resolve::{RefKind, reference_fields};
use serde_json::{Value, json};

/// Runs the fdem binary with `args`, killed after `limit` (then the code is -9); returns (exit
/// code, stderr).
fn fdem(args: &[&str], limit: Duration) -> (i32, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_fdem"));
    cmd.args(args);
    match common::run_limited(&mut cmd, limit) {
        Some((code, err)) => (code.unwrap_or(-1), err),
        None => (-9, format!("killed after {limit:?}: {args:?}")),
    }
}

/// `fdem check SCENE` and `fdem run SCENE --out DIR`: both must exit 2 and the output folder
/// must not exist afterwards. Returns the two stderr texts.
fn both_refuse(scene: &Path, tag: &str) -> [String; 2] {
    let s = scene.to_str().unwrap();
    let limit = Duration::from_secs(60);
    let (code, check_err) = fdem(&["check", s], limit);
    assert_eq!(code, 2, "{tag}: fdem check exit code {code}:\n{check_err}");
    let out = scene.parent().unwrap().join(format!("out-{tag}"));
    let (code, run_err) = fdem(&["run", s, "--out", out.to_str().unwrap()], limit);
    assert_eq!(code, 2, "{tag}: fdem run exit code {code}:\n{run_err}");
    assert!(
        !out.exists(),
        "{tag}: fdem run created its output folder {}",
        out.display()
    );
    [check_err, run_err]
}

fn assert_says(errs: &[String], tag: &str, needles: &[&str]) {
    for e in errs {
        for n in needles {
            assert!(e.contains(n), "{tag}: stderr lacks {n:?}:\n{e}");
        }
    }
}

// ---------------------------------------------------------------------------------------
// A scene with every kind of name.

/// A structured `nx` x `ny` block of cells of size `c`, as a JSON mesh: surface groups
/// `rock` (left half of the columns) and `weak` (right half), edge groups `top` and `base`,
/// point group `center`; `tip` (the top right corner) and the edge group `flaw` (the middle
/// row's inner edges) when `tip` is set.
fn block_mesh(nx: usize, ny: usize, c: f64, tip: bool) -> Value {
    let (nodes, tris) = common::structured_rectangle(nx, ny, nx as f64 * c, ny as f64 * c);
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let (mut rock, mut weak) = (Vec::new(), Vec::new());
    for j in 0..ny {
        for i in 0..nx {
            let t = 2 * (j * nx + i);
            let g = if i < nx / 2 { &mut rock } else { &mut weak };
            g.extend([t, t + 1]);
        }
    }
    let top: Vec<[usize; 2]> = (0..nx).map(|i| [id(i + 1, ny), id(i, ny)]).collect();
    let base: Vec<[usize; 2]> = (0..nx).map(|i| [id(i, 0), id(i + 1, 0)]).collect();
    let mut groups = vec![
        json!({"name": "rock", "dim": 2, "triangles": rock}),
        json!({"name": "weak", "dim": 2, "triangles": weak}),
        json!({"name": "top", "dim": 1, "edges": top}),
        json!({"name": "base", "dim": 1, "edges": base}),
        json!({"name": "center", "dim": 0, "nodes": [id(nx / 2, ny / 2)]}),
    ];
    if tip {
        groups.push(json!({"name": "tip", "dim": 0, "nodes": [id(nx, ny)]}));
        // a crack along the middle row, its two tips inside the block
        let flaw: Vec<[usize; 2]> = (1..nx - 1)
            .map(|i| [id(i, ny / 2), id(i + 1, ny / 2)])
            .collect();
        groups.push(json!({"name": "flaw", "dim": 1, "edges": flaw}));
    }
    json!({"nodes": nodes, "triangles": tris, "groups": groups})
}

/// The groups of the two meshes: (all, edge, surface).
const LEFT_GROUPS: [&[&str]; 3] = [
    &["base", "center", "rock", "top", "weak"],
    &["base", "top"],
    &["rock", "weak"],
];
const RIGHT_GROUPS: [&[&str]; 3] = [
    &["base", "center", "flaw", "rock", "tip", "top", "weak"],
    &["base", "flaw", "top"],
    &["rock", "weak"],
];

/// Two blocks `left` and `right` (both with groups `rock`, `weak`, `top`, `base`, `center`;
/// `right` also `tip` and `flaw`), with every kind of name: boundary conditions of every kind,
/// with and without `body`, probes, fracture regions with and without groups, a pre-existing
/// crack, contact pairs and named and unnamed walls. Returns the scene file.
fn every_name_scene(tag: &str) -> PathBuf {
    let dir = common::temp_dir(tag);
    let c = 0.0025;
    std::fs::write(
        dir.join("left.json"),
        block_mesh(4, 4, c, false).to_string(),
    )
    .unwrap();
    std::fs::write(
        dir.join("right.json"),
        block_mesh(4, 4, c, true).to_string(),
    )
    .unwrap();
    let mat = |nu: f64| json!({"young": 30e9, "poisson": nu, "density": 2500.0, "plane": "stress"});
    let scene = json!({
        "title": "two blocks with every kind of name",
        "bodies": [
            {"name": "left", "mesh": "left.json", "materials": {"rock": mat(0.2), "weak": mat(0.25)}, "thickness": 0.01},
            {"name": "right", "mesh": "right.json", "materials": {"*": mat(0.2)}, "thickness": 0.01, "offset": [0.012, 0.0]}
        ],
        "boundary_conditions": [
            {"fixed": {"group": "base", "body": "left", "y": true}},
            {"fixed": {"group": "base", "body": "right", "y": true}},
            {"pressure": {"group": "top", "body": "left", "value": 1e5}},
            {"traction": {"group": "top", "body": "right", "value": [0.0, -1e5]}},
            {"velocity": {"group": "center", "body": "left", "x": 0.0}},
            {"point-load": {"group": "tip", "force": [0.0, -1.0]}}
        ],
        "fracture": {
            "regions": [ {"body": "left", "groups": ["weak"]}, {"body": "right", "material": "tough"} ],
            "material": {
                "tensile_strength": 3e6, "cohesion": 10e6, "friction_angle_deg": 30.0,
                "fracture_energy_i": 50.0, "fracture_energy_ii": 250.0,
                "penalty_normal": 300e9, "penalty_tangential": 300e9
            },
            "materials": {"tough": {
                "tensile_strength": 6e6, "cohesion": 10e6, "friction_angle_deg": 30.0,
                "fracture_energy_i": 50.0, "fracture_energy_ii": 250.0,
                "penalty_normal": 300e9, "penalty_tangential": 300e9
            }},
            "interfaces": [ {"body": "left", "groups": ["rock", "weak"], "material": "tough"} ],
            "cracks": [ {"body": "right", "group": "flaw"} ]
        },
        "contact": {
            "pairs": [
                {"bodies": ["left", "right"], "law": {"friction": 0.3}},
                {"bodies": ["right", "right"]}
            ],
            "walls": [
                {"name": "floor", "point": [0.0, 0.0], "normal": [0.0, 1.0]},
                {"name": "platen", "point": [0.0, 0.0101], "normal": [0.0, -1.0], "velocity": [0.0, -0.01]},
                {"point": [-0.0001, 0.0], "normal": [1.0, 0.0]}
            ]
        },
        "integrator": {"scheme": "central-difference", "time_step": "auto", "safety": 0.5},
        "duration": 2e-7,
        "output": {"frames": 1},
        "histories": {"probes": [
            {"velocity": {"group": "center", "body": "left"}},
            {"velocity": {"group": "center", "body": "right"}},
            {"reaction": {"group": "base", "body": "left"}},
            {"displacement": {"group": "tip"}},
            "energy"
        ]}
    });
    let p = dir.join("every-name.json");
    std::fs::write(&p, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    p
}

/// Splits a JSON pointer into its unescaped tokens.
fn tokens(pointer: &str) -> Vec<String> {
    pointer
        .split('/')
        .skip(1)
        .map(|t| t.replace("~1", "/").replace("~0", "~"))
        .collect()
}

/// The parent pointer of `pointer`.
fn parent(pointer: &str) -> &str {
    &pointer[..pointer.rfind('/').unwrap()]
}

/// Every string value and every material key of `v`, as JSON pointers.
fn strings(v: &Value, at: &str, out: &mut Vec<String>) {
    match v {
        Value::String(_) => out.push(at.to_string()),
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                strings(x, &format!("{at}/{i}"), out);
            }
        }
        Value::Object(o) => {
            for (k, x) in o {
                let p = format!("{at}/{}", k.replace('~', "~0").replace('/', "~1"));
                if at.ends_with("/materials") {
                    out.push(p.clone());
                }
                strings(x, &p, out);
            }
        }
        _ => {}
    }
}

#[test]
fn every_name_field_is_resolved_in_one_place_and_a_wrong_name_is_refused() {
    let scene_path = every_name_scene("names-every");
    let dir = scene_path.parent().unwrap().to_path_buf();
    // The scene itself is good: a wrong name below is the only fault.
    let (code, err) = fdem(
        &["check", scene_path.to_str().unwrap()],
        Duration::from_secs(120),
    );
    assert_eq!(code, 0, "the base scene does not pass fdem check:\n{err}");
    let base: Value = serde_json::from_str(&std::fs::read_to_string(&scene_path).unwrap()).unwrap();
    let scene = fdem_solver::Scene::from_file(&scene_path).unwrap();
    let fields = reference_fields(&scene);

    // The resolver's list covers every string of the scene that is a name: each string
    // value (and material key) is either in the list or one of the known non-name fields.
    let listed: Vec<&str> = fields.iter().map(|f| f.pointer.as_str()).collect();
    let mut all = Vec::new();
    strings(&base, "", &mut all);
    for p in &all {
        let t = tokens(p);
        let not_a_name = p == "/title"
            || p == "/integrator/scheme"
            || p == "/integrator/time_step"
            || (t.len() == 3 && t[0] == "bodies" && t[2] == "mesh")
            || (t.len() == 5 && t[2] == "materials" && (t[4] == "plane" || t[4] == "law"))
            || (t.len() == 3 && t[0] == "histories" && t[1] == "probes")
            // the definitions of joint material names (their uses are checked)
            || (t.len() == 3 && t[0] == "fracture" && t[1] == "materials");
        assert!(
            listed.contains(&p.as_str()) || not_a_name,
            "the string at {p} is neither a name the resolver checks nor a known non-name field"
        );
    }
    // Every kind occurs.
    for kind in [
        RefKind::BodyName,
        RefKind::WallName,
        RefKind::Body,
        RefKind::MaterialKey,
        RefKind::Group,
        RefKind::EdgeGroup,
        RefKind::SurfaceGroup,
        RefKind::JointMaterial,
    ] {
        assert!(
            fields.iter().any(|f| f.kind == kind),
            "no {kind:?} in the scene"
        );
    }
    assert!(fields.len() >= 30, "{} fields", fields.len());

    for (n, f) in fields.iter().enumerate() {
        let mut v = base.clone();
        let tag = format!("field{n}");
        let wrong = "zz-no-such-name";
        // (needles in stderr)
        let mut needles: Vec<String> = vec![];
        match f.kind {
            RefKind::BodyName | RefKind::WallName => {
                // a definition: give it the name of another one of its kind
                let t = tokens(&f.pointer);
                let i: usize = t[t.len() - 2].parse().unwrap();
                let other = if i == 0 { 1 } else { 0 };
                let list = parent(parent(&f.pointer)).to_string();
                let other_name = v.pointer(&format!("{list}/{other}/name")).unwrap().clone();
                *v.pointer_mut(&f.pointer).unwrap() = other_name;
                let elem = f.path.rsplit_once('.').unwrap().0.to_string();
                needles.push(elem);
                needles.push("named".into());
            }
            RefKind::MaterialKey => {
                let obj = v
                    .pointer_mut(parent(&f.pointer))
                    .unwrap()
                    .as_object_mut()
                    .unwrap();
                let m = obj.remove(&f.name).unwrap();
                obj.insert(wrong.into(), m);
                let body = if f.pointer.starts_with("/bodies/0/") {
                    0
                } else {
                    1
                };
                let groups = if body == 0 { LEFT_GROUPS } else { RIGHT_GROUPS };
                needles.push(f.path.replace(&f.name, wrong));
                needles.extend(groups[2].iter().map(|s| s.to_string()));
            }
            RefKind::JointMaterial => {
                *v.pointer_mut(&f.pointer).unwrap() = wrong.into();
                needles.extend([
                    f.path.clone(),
                    format!("no joint material is named '{wrong}'"),
                    "tough".into(),
                ]);
            }
            RefKind::Body => {
                *v.pointer_mut(&f.pointer).unwrap() = wrong.into();
                needles.extend([f.path.clone(), format!("no body is named '{wrong}'")]);
                needles.extend(["left".into(), "right".into()]);
            }
            RefKind::Group | RefKind::EdgeGroup | RefKind::SurfaceGroup => {
                *v.pointer_mut(&f.pointer).unwrap() = wrong.into();
                needles.push(f.path.clone());
                needles.push(format!("'{wrong}'"));
                // the body: the `body` beside the group (or of the fracture region)
                let owner = if f.kind == RefKind::SurfaceGroup {
                    parent(parent(&f.pointer)).to_string()
                } else {
                    parent(&f.pointer).to_string()
                };
                let k = match f.kind {
                    RefKind::Group => 0,
                    RefKind::EdgeGroup => 1,
                    _ => 2,
                };
                match base
                    .pointer(&format!("{owner}/body"))
                    .and_then(Value::as_str)
                {
                    Some("left") => needles.extend(LEFT_GROUPS[k].iter().map(|s| s.to_string())),
                    Some(_) => needles.extend(RIGHT_GROUPS[k].iter().map(|s| s.to_string())),
                    None => {
                        // no body: the names of both bodies' meshes
                        needles.extend(RIGHT_GROUPS[k].iter().map(|s| s.to_string()));
                        needles.extend(["body left".into(), "body right".into()]);
                    }
                }
            }
        }
        needles.push("fix:".into());
        let p = dir.join(format!("{tag}.json"));
        std::fs::write(&p, serde_json::to_string_pretty(&v).unwrap()).unwrap();
        let errs = both_refuse(&p, &tag);
        let needles: Vec<&str> = needles.iter().map(String::as_str).collect();
        assert_says(
            &errs,
            &format!("{tag} ({}, {:?})", f.path, f.kind),
            &needles,
        );
    }
}

/// An edit of a scene's JSON.
type Edit = Box<dyn Fn(&mut Value)>;

#[test]
fn resolution_refuses_ambiguous_and_duplicate_names() {
    let scene_path = every_name_scene("names-ambiguous");
    let dir = scene_path.parent().unwrap().to_path_buf();
    let base: Value = serde_json::from_str(&std::fs::read_to_string(&scene_path).unwrap()).unwrap();
    let cases: Vec<(&str, Edit, Vec<&str>)> = vec![
        (
            "group-in-both-bodies",
            Box::new(|v| {
                v["boundary_conditions"][0]["fixed"]
                    .as_object_mut()
                    .unwrap()
                    .remove("body");
            }),
            vec![
                "boundary_conditions[0].fixed.group",
                "several bodies",
                "'base'",
                "left, right",
            ],
        ),
        (
            "edge-group-of-another-dimension",
            Box::new(|v| v["boundary_conditions"][2]["pressure"]["group"] = "center".into()),
            vec![
                "boundary_conditions[2].pressure.group",
                "no edge group",
                "base, top",
            ],
        ),
        (
            "two-regions-of-one-body-overlap-with-two-materials",
            Box::new(|v| v["fracture"]["regions"][1]["body"] = "left".into()),
            vec![
                "fracture.regions[1]",
                "overlaps fracture.regions[0]",
                "'tough'",
            ],
        ),
        (
            "interface-without-body-among-several",
            Box::new(|v| {
                v["fracture"]["interfaces"][0]
                    .as_object_mut()
                    .unwrap()
                    .remove("body");
                v["fracture"]["interfaces"][0]["groups"] = json!(["rock", "tip"]);
            }),
            vec!["fracture.interfaces[0].groups[0]", "several bodies"],
        ),
        (
            "region-without-body-among-several",
            Box::new(|v| {
                v["fracture"]["regions"][1]
                    .as_object_mut()
                    .unwrap()
                    .remove("body");
            }),
            vec!["fracture.regions[1]", "several bodies", "left, right"],
        ),
        (
            "same-pair-twice",
            Box::new(|v| v["contact"]["pairs"][1]["bodies"] = json!(["right", "left"])),
            vec!["contact.pairs[1].bodies", "contact.pairs[0]"],
        ),
        (
            "wall-named-like-an-unnamed-one",
            Box::new(|v| v["contact"]["walls"][0]["name"] = "wall2".into()),
            vec!["contact.walls[0]", "contact.walls[2]", "'wall2'"],
        ),
        (
            "same-probe-twice",
            Box::new(|v| {
                v["histories"]["probes"][1]["velocity"]["body"] = "left".into();
            }),
            vec!["histories.probes[1]", "histories.probes[0]"],
        ),
        (
            "surface-without-material",
            Box::new(|v| {
                v["bodies"][0]["materials"]
                    .as_object_mut()
                    .unwrap()
                    .remove("weak");
            }),
            vec!["bodies[0].materials", "'weak'", "no material"],
        ),
        (
            "body-name-with-a-slash",
            Box::new(|v| {
                v["bodies"][1]["name"] = "right/2".into();
            }),
            vec!["bodies[1].name", "right/2"],
        ),
    ];
    for (tag, edit, needles) in cases {
        let mut v = base.clone();
        edit(&mut v);
        let p = dir.join(format!("{tag}.json"));
        std::fs::write(&p, serde_json::to_string_pretty(&v).unwrap()).unwrap();
        let errs = both_refuse(&p, tag);
        assert_says(&errs, tag, &needles);
    }
}

#[test]
fn case01_fracture_region_naming_a_missing_body_is_rejected() {
    let p = common::edited_example("brazilian-disc-fracture.json", "names-case01", |v| {
        v["fracture"]["regions"][0]["body"] = "disk".into();
    });
    let errs = both_refuse(&p, "case01");
    assert_says(
        &errs,
        "case01",
        &[
            "brazilian-disc-fracture.json",
            "fracture.regions[0].body",
            "no body is named 'disk'",
            "use one of: disc",
        ],
    );
}

// ---------------------------------------------------------------------------------------
// Derived quantities.

/// The fracturing Brazilian disc with one edit; `fdem check` and `fdem run` must refuse it at
/// `path` (well within 60 s: no spinning) with `needles`.
fn case04(tag: &str, edit: impl FnOnce(&mut Value), path: &str, needles: &[&str]) {
    let p = common::edited_example("brazilian-disc-fracture.json", tag, edit);
    let start = Instant::now();
    let errs = both_refuse(&p, tag);
    let mut all = vec![path, "fix:"];
    all.extend_from_slice(needles);
    assert_says(&errs, tag, &all);
    assert!(
        start.elapsed() < Duration::from_secs(30),
        "{tag}: took {:?}",
        start.elapsed()
    );
}

#[test]
fn case04_contact_penalty_factor_of_1e308_is_named_as_what_makes_the_step_zero() {
    case04(
        "names-case04-penalty",
        |v| v["contact"]["default"] = json!({"penalty_factor": 1e308}),
        "contact.default.penalty_factor",
        &["stable time step", "contact penalty"],
    );
}

#[test]
fn case04_density_of_1e_300_is_named_as_what_makes_the_step_zero() {
    case04(
        "names-case04-density",
        |v| v["bodies"][0]["materials"]["*"]["density"] = json!(1e-300),
        "bodies[0].materials.*.density",
        &["stable time step", "wave speed"],
    );
}

#[test]
fn case04_time_step_of_1e_300_is_refused() {
    case04(
        "names-case04-step",
        |v| v["integrator"]["time_step"] = json!(1e-300),
        "integrator.time_step",
        &["1.000e-300 s", "smallest step"],
    );
}

#[test]
fn case04_duration_of_1e300_is_refused_by_the_step_cap() {
    case04(
        "names-case04-duration",
        |v| v["duration"] = json!(1e300),
        "duration",
        &["1.0000e300 s", "steps", "1e10"],
    );
}

#[test]
fn more_frames_than_steps_and_huge_history_rows_are_refused() {
    let p = common::edited_example("brazilian-disc-fracture.json", "names-frames", |v| {
        v["duration"] = json!(1e-7);
    });
    let errs = both_refuse(&p, "frames");
    assert_says(&errs, "frames", &["output.frames", "33 frames", "fix:"]);
    let p = common::edited_example("brazilian-disc-fracture.json", "names-rows", |v| {
        v["duration"] = json!(1.0);
        v["histories"]["every"] = json!(1);
    });
    let errs = both_refuse(&p, "rows");
    assert_says(&errs, "rows", &["histories.every", "GiB", "fix:"]);
}

// ---------------------------------------------------------------------------------------
// Step count.

/// Two triangles of a soft, heavy material (stable step about 18 s): any step below it is
/// accepted as given.
fn soft_pair(tag: &str, h: f64, duration: f64) -> PathBuf {
    let dir = common::temp_dir(tag);
    let mesh = json!({
        "nodes": [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        "triangles": [[0, 1, 2], [0, 2, 3]],
        "groups": [{"name": "corner", "dim": 0, "nodes": [0]}]
    });
    std::fs::write(dir.join("pair.json"), mesh.to_string()).unwrap();
    let scene = json!({
        "bodies": [{"mesh": "pair.json", "materials": {"*": {"young": 1.0, "poisson": 0.25, "density": 1000.0}},
                    "initial_velocity": [1e-3, 0.0]}],
        "boundary_conditions": [{"fixed": {"group": "corner", "y": true}}],
        "integrator": {"time_step": h},
        "duration": duration,
        "output": {"frames": 1},
        "histories": {"probes": ["energy"]}
    });
    let p = dir.join("pair.scene.json");
    std::fs::write(&p, scene.to_string()).unwrap();
    p
}

#[test]
fn case07_step_count_from_duration_and_time_step_not_exact_in_binary() {
    for (h, duration, steps) in [
        (1e-8, 2e-5, 2000u64),
        (0.1, 0.3, 3),
        (1e-7, 7e-6, 70),
        (0.1, 0.7, 7),
        (1e-3, 0.0561, 57),
        (3e-9, 9e-7, 300),
        (1e-6, 1.1e-3, 1100),
    ] {
        let p = soft_pair("names-case07", h, duration);
        let l = fdem_solver::load(&p).unwrap();
        assert!(l.dt_limit > 1.0, "stable step {}", l.dt_limit);
        // 0.0561 / 1e-3 = 56.1: not whole, rounded up
        let whole = ((duration / h) - (duration / h).round()).abs() < 1e-9;
        assert_eq!(l.n_steps, steps, "time_step {h}, duration {duration}");
        if whole {
            assert!(
                (l.dt - h).abs() <= 1e-12 * h,
                "time_step {h}, duration {duration}: h used {}",
                l.dt
            );
        }
        assert!((l.dt * l.n_steps as f64 - duration).abs() <= 1e-12 * duration);
    }
    // The run takes exactly those steps and ends at the duration.
    let p = soft_pair("names-case07-run", 1e-8, 2e-5);
    let (o, _) = common::run(&p);
    assert_eq!(o.summary.steps, 2000);
    assert!((o.summary.time_step - 1e-8).abs() <= 1e-12 * 1e-8);
    assert!((o.summary.simulated_time - 2e-5).abs() <= 1e-12 * 2e-5);
}

// ---------------------------------------------------------------------------------------
// History columns.

#[test]
fn case08_history_columns_are_unique_when_two_bodies_share_a_group_name() {
    let scene_path = every_name_scene("names-case08");
    let mut v: Value =
        serde_json::from_str(&std::fs::read_to_string(&scene_path).unwrap()).unwrap();
    v["histories"]["probes"]
        .as_array_mut()
        .unwrap()
        .push(json!({"reaction": {"group": "base", "body": "right"}}));
    std::fs::write(&scene_path, v.to_string()).unwrap();
    let (_, out) = common::run(&scene_path);
    let (head, rows) = common::histories(&out);
    for (i, h) in head.iter().enumerate() {
        assert!(
            !head[..i].contains(h),
            "column {h} repeats: {}",
            head.join(",")
        );
    }
    for c in [
        "v_x[left/center]",
        "v_y[right/center]",
        "reaction_y[left/base]",
        "reaction_y[right/base]",
        // a group only one body has keeps its plain name
        "u_x[tip]",
    ] {
        assert!(
            head.iter().any(|h| h == c),
            "no column {c}: {}",
            head.join(",")
        );
    }
    assert!(!rows.is_empty());
}

#[test]
fn case08_plot_refuses_a_column_name_that_a_file_repeats() {
    // an older run folder: two bodies' `center` under one name
    let d = common::temp_dir("names-case08-plot");
    std::fs::write(
        d.join("histories.csv"),
        "time,reaction_x[center],reaction_y[center],u_x[center],u_y[center],reaction_x[center],reaction_y[center],u_x[center],u_y[center]\n\
         0,0,0,0,0,0,0,0,0\n\
         1,1,-700,1e-7,-1e-5,2,-300,2e-7,-3e-5\n",
    )
    .unwrap();
    let dir = d.to_str().unwrap();
    let limit = Duration::from_secs(60);
    for args in [
        vec![
            "plot",
            "load-displacement",
            dir,
            "--load",
            "reaction_y[center]",
            "--displacement",
            "u_y[center]",
        ],
        vec!["plot", "load-displacement", dir],
    ] {
        let (code, err) = fdem(&args, limit);
        assert_ne!(code, 0, "{args:?}: exit 0\n{err}");
        for n in [
            "reaction_y[center]",
            "more than once",
            "columns: time,reaction_x[center]",
        ] {
            assert!(err.contains(n), "{args:?}: stderr lacks {n:?}:\n{err}");
        }
        assert!(!d.join("load_displacement.png").exists());
    }
}
