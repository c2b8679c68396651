//! No input gives a wrong answer without a word: static analyses the supports do not hold
//! (case 2) or that carry sections the solve cannot honour (case 3), output folders shared by
//! two runs (case 5), a relaxation that does not converge (case 9), huge tokens in input files
//! (case 10), the instability message of an absurd load, a run started as several processes
//! of a parallel launcher, and the exit codes of every
//! subcommand (0 success, 2 bad input with nothing written, 3 a run that did not reach its
//! goal, 1 anything else).

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::json;

use crate::common::fdem;
use crate::common::fdem_run as run;

/// The static cantilever on the coarse mesh (205 nodes), edited.
fn static_cantilever(tag: &str, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    common::edited_example("cantilever-static.json", tag, |v| {
        v["bodies"][0]["mesh"] = json!(
            common::root()
                .join("examples/meshes/cantilever-coarse.json")
                .display()
                .to_string()
        );
        edit(v);
    })
}

/// A run that must be rejected as bad input: exit code 2, the output folder never created,
/// no internal wording; returns stderr.
fn rejected(scene: &Path, tag: &str) -> String {
    let out = scene.parent().unwrap().join(format!("out-{tag}"));
    let (code, _, err) = run(scene, &out);
    assert_eq!(code, 2, "{tag}: exit code {code}, stderr:\n{err}");
    assert!(!out.exists(), "{tag}: {} was created", out.display());
    for internal in ["Numeric", "NonPositivePivot", "index:", "panicked"] {
        assert!(!err.contains(internal), "{tag}: internal wording:\n{err}");
    }
    err
}

#[test]
fn case02_static_mechanism_single_node_hold_is_rejected() {
    // Held at the one node of the `tip` group, loaded on its top edge: free to rotate about
    // that node (main: exit 0, displacements of 1e9 m).
    let s = static_cantilever("case02-pin", |v| {
        v["boundary_conditions"] = json!([
            { "fixed": { "group": "tip", "x": true, "y": true } },
            { "traction": { "group": "top", "value": [0.0, -1.0] } }
        ]);
    });
    let err = rejected(&s, "pin");
    eprintln!("{err}");
    assert!(
        err.contains("body 'beam'") && err.contains("rotation about (1.0000e1, "),
        "{err}"
    );
    assert!(!err.contains("translation in"), "{err}");
    assert!(
        err.contains("boundary_conditions") && err.contains("fix:"),
        "{err}"
    );
    assert!(err.contains("hold a second point"), "{err}");
    // `fdem check` says the same, also with exit code 2
    let (code, _, err_check) = fdem(&["check".as_ref(), s.as_os_str()]);
    assert_eq!(code, 2, "{err_check}");
    assert!(err_check.contains("rotation about"), "{err_check}");
}

#[test]
fn case02_static_without_supports_and_self_equilibrated_loads_is_rejected() {
    // No support at all; equal and opposite tractions on the top and bottom edges (main:
    // accepted, with whatever rigid motion the factorisation gave).
    let s = static_cantilever("case02-free", |v| {
        v["boundary_conditions"] = json!([
            { "traction": { "group": "top", "value": [0.0, 1.0] } },
            { "traction": { "group": "bottom", "value": [0.0, -1.0] } }
        ]);
        v["histories"] = json!({});
    });
    let err = rejected(&s, "free");
    eprintln!("{err}");
    for needle in [
        "body 'beam' is free: translation in x, translation in y, rotation",
        "no node of it is supported",
        "add supports to body 'beam'",
        "'left'",
    ] {
        assert!(err.contains(needle), "lacks {needle:?}:\n{err}");
    }
}

#[test]
fn case02_static_rollers_leave_the_motions_they_do_not_hold() {
    // Only x fixed along the (vertical) left edge: translation in y free; rotation held.
    let s = static_cantilever("case02-roller-x", |v| {
        v["boundary_conditions"][0] = json!({ "fixed": { "group": "left", "x": true } });
    });
    let err = rejected(&s, "roller-x");
    assert!(
        err.contains("body 'beam' is free: translation in y\n")
            && err.contains("fix y at a node of body 'beam'"),
        "{err}"
    );
    assert!(!err.contains("rotation"), "{err}");
    // Only y fixed along it: translation in x, and (to first order) rotation about a point
    // of that edge, where it moves only in x
    let s = static_cantilever("case02-roller-y", |v| {
        v["boundary_conditions"][0] = json!({ "fixed": { "group": "left", "y": true } });
    });
    let err = rejected(&s, "roller-y");
    assert!(
        err.contains("body 'beam' is free: translation in x, rotation about (0.0000e0, "),
        "{err}"
    );
}

/// A JSON mesh of two triangles that share one node (and no edge): `a` = nodes 0, 1, 2 and
/// `b` = nodes 2, 3, 4, with point groups for each node `n0`..`n4`.
fn two_triangles_joined_at_a_node(dir: &Path, b_nodes: [[f64; 2]; 2]) -> PathBuf {
    let mesh = json!({
        "nodes": [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], b_nodes[0], b_nodes[1]],
        "triangles": [[0, 1, 2], [2, 3, 4]],
        "groups": [
            { "name": "part", "dim": 2, "triangles": [0, 1] },
            { "name": "n0", "dim": 0, "nodes": [0] },
            { "name": "n1", "dim": 0, "nodes": [1] },
            { "name": "n2", "dim": 0, "nodes": [2] },
            { "name": "n3", "dim": 0, "nodes": [3] },
            { "name": "n4", "dim": 0, "nodes": [4] }
        ]
    });
    let p = dir.join("hinge.json");
    std::fs::write(&p, mesh.to_string()).unwrap();
    p
}

fn hinge_scene(dir: &Path, mesh: &Path, fixed: &[&str]) -> PathBuf {
    let mut bcs: Vec<serde_json::Value> = fixed
        .iter()
        .map(|g| json!({ "fixed": { "group": g, "x": true, "y": true } }))
        .collect();
    bcs.push(json!({ "point-load": { "group": "n4", "force": [0.3, -1.0] } }));
    let scene = json!({
        "analysis": "static",
        "bodies": [{ "name": "frame", "mesh": mesh,
            "materials": { "*": { "young": 1e9, "poisson": 0.25, "density": 1000.0 } } }],
        "boundary_conditions": bcs,
        "output": { "frames": 1 }
    });
    let p = dir.join(format!("hinge-{}.json", fixed.join("-")));
    std::fs::write(&p, scene.to_string()).unwrap();
    p
}

#[test]
fn case02_static_parts_joined_at_one_node_form_a_mechanism_unless_held() {
    let dir = common::temp_dir("case02-hinge");
    // b = (1,1), (2,0), (2,1): a fully held triangle `a` (nodes 0 and 1 pinned) with `b`
    // hanging from node 2: b rotates about (1, 1).
    let mesh = two_triangles_joined_at_a_node(&dir, [[2.0, 0.0], [2.0, 1.0]]);
    let s = hinge_scene(&dir, &mesh, &["n0", "n1"]);
    let err = rejected(&s, "hinge");
    eprintln!("{err}");
    assert!(
        err.contains("rotation about (1.0000e0, 1.0000e0) m")
            && err.contains("joined to the rest at single nodes"),
        "{err}"
    );
    // A three-hinged arch: `a` pinned at node 0, `b` pinned at node 3, joined at node 2 (not
    // in line with the pins): held, solved (exit 0), nodes 0 and 3 do not move.
    let s = hinge_scene(&dir, &mesh, &["n0", "n3"]);
    let out = dir.join("out-arch");
    let (code, _, err) = run(&s, &out);
    assert_eq!(code, 0, "{err}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let umax = summary["max_displacement"].as_f64().unwrap();
    // a 1 N load on 1e9 Pa triangles of 1 m: displacements of order 1e-9 m, not a mechanism
    assert!(umax > 0.0 && umax < 1e-7, "max displacement {umax}");
}

#[test]
fn case02_nearly_singular_stiffness_is_rejected_by_the_residual_check() {
    // Two triangles joined along an edge, one 1e-15 times as stiff as the other, the stiff
    // one loaded, the soft one held: K is positive definite in exact arithmetic, but its
    // condition (~1e15) leaves a solution that does not balance the loads.
    let dir = common::temp_dir("case02-soft");
    let mesh = json!({
        "nodes": [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]],
        "triangles": [[0, 1, 2], [1, 3, 2]],
        "groups": [
            { "name": "soft", "dim": 2, "triangles": [0] },
            { "name": "stiff", "dim": 2, "triangles": [1] },
            { "name": "base", "dim": 1, "edges": [[0, 1]] },
            { "name": "corner", "dim": 0, "nodes": [3] }
        ]
    });
    std::fs::write(dir.join("m.json"), mesh.to_string()).unwrap();
    let scene = json!({
        "analysis": "static",
        "bodies": [{ "mesh": "m.json", "materials": {
            "soft": { "young": 1.0, "poisson": 0.25, "density": 1.0 },
            "stiff": { "young": 1e15, "poisson": 0.25, "density": 1.0 } } }],
        "boundary_conditions": [
            { "fixed": { "group": "base", "x": true, "y": true } },
            { "point-load": { "group": "corner", "force": [1.0, 0.0] } }
        ]
    });
    let s = dir.join("scene.json");
    std::fs::write(&s, scene.to_string()).unwrap();
    let out = dir.join("out");
    let (code, _, err) = run(&s, &out);
    eprintln!("{err}");
    // main: exit 0 with an answer whose out-of-balance force is 11 % of the load
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("nearly singular") && err.contains("of the load") && !out.exists(),
        "{err}"
    );
}

#[test]
fn case03_static_with_contact_or_fracture_is_rejected() {
    let s = static_cantilever("case03-contact", |v| {
        v["contact"] = json!({});
    });
    let err = rejected(&s, "contact");
    assert!(
        err.contains("at `contact`")
            && err.contains("cannot honour contact")
            && err.contains("\"analysis\": \"relaxation\""),
        "{err}"
    );
    let s = static_cantilever("case03-fracture", |v| {
        v["fracture"] = json!({
            "regions": [{ "body": "beam" }],
            "material": { "tensile_strength": 3e6, "cohesion": 1e7, "friction_angle_deg": 30.0,
                "fracture_energy_i": 20.0, "fracture_energy_ii": 100.0,
                "penalty_normal": 3e11, "penalty_tangential": 3e11 }
        });
    });
    let err = rejected(&s, "fracture");
    assert!(
        err.contains("at `fracture`") && err.contains("\"analysis\": \"relaxation\""),
        "{err}"
    );
}

#[test]
fn case05_a_second_run_leaves_no_file_of_the_first_in_the_folder() {
    let dir = common::temp_dir("case05");
    let out = dir.join("out");
    // 1. a fracturing run: joints.pvd, joints_*.vtu, fractures.csv
    let fracture = common::edited_example("notched-beam-fracture.json", "case05-a", |v| {
        v["duration"] = json!(2e-6);
        v["output"] = json!({ "frames": 2 });
    });
    let (code, _, err) = run(&fracture, &out);
    assert_eq!(code, 0, "{err}");
    let names = |d: &Path| -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    let first = names(&out);
    eprintln!("first run: {first:?}");
    assert!(
        first.contains(&"joints.pvd".to_string()) && first.contains(&"fractures.csv".to_string()),
        "{first:?}"
    );
    // files another run (contact, plot) would have left, temporaries, and a user's own file
    for f in [
        "walls.csv",
        "load_displacement.png",
        "load_displacement.svg",
        "stress_strain.png",
        ".frame_0007.vtu.tmp123",
        "frame_0042.vtu",
        "notes.txt",
    ] {
        std::fs::write(out.join(f), "x").unwrap();
    }
    std::fs::create_dir_all(out.join("mine")).unwrap();
    // 2. an elastic run into the same folder
    let elastic = common::edited_example("cantilever-vibration.json", "case05-b", |v| {
        v["duration"] = json!(0.01);
        v["output"] = json!({ "frames": 1 });
    });
    let (code, _, err) = run(&elastic, &out);
    assert_eq!(code, 0, "{err}");
    let second = names(&out);
    eprintln!("second run: {second:?}");
    for gone in [
        "joints.pvd",
        "fractures.csv",
        "walls.csv",
        "load_displacement.png",
        "load_displacement.svg",
        "stress_strain.png",
        ".frame_0007.vtu.tmp123",
        "frame_0042.vtu",
        "frame_0002.vtu",
    ] {
        assert!(
            !second.contains(&gone.to_string()),
            "{gone} left: {second:?}"
        );
    }
    assert!(
        !second.iter().any(|n| n.starts_with("joints_")),
        "{second:?}"
    );
    // the second run's own files, and the user's, are there
    for kept in [
        "results.pvd",
        "frame_0000.vtu",
        "frame_0001.vtu",
        "summary.json",
        "histories.csv",
        "notes.txt",
        "mine",
    ] {
        assert!(
            second.contains(&kept.to_string()),
            "{kept} missing: {second:?}"
        );
    }
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("cantilever-vibration.json"), "{summary}");
}

#[test]
fn case09_relaxation_not_converged_writes_its_output_and_exits_3() {
    // The cantilever relaxation stopped after 0.5 s of its 20 s: far from its 1e-7 tolerance.
    let s = common::edited_example("cantilever-relaxation.json", "case09", |v| {
        v["duration"] = json!(0.5);
    });
    let out = s.parent().unwrap().join("out");
    let (code, stdout, err) = run(&s, &out);
    eprintln!("{err}");
    assert_eq!(code, 3, "stdout:\n{stdout}\nstderr:\n{err}");
    for needle in [
        "did not converge",
        "relative residual",
        "tolerance 1e-7",
        "fix:",
        "duration",
        "damping.mass_proportional",
        "relaxation_tolerance",
    ] {
        assert!(err.contains(needle), "lacks {needle:?}:\n{err}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["converged"], json!(false));
    let r = summary["relative_residual"].as_f64().unwrap();
    assert!(r > 1e-7, "{r}");
    // the message gives the residual the summary has
    assert!(err.contains(&format!("{r:.3e}")), "{r:.3e} not in:\n{err}");
    assert!(out.join("results.pvd").exists() && out.join("histories.csv").exists());
    // the full run converges: exit 0 (tests/cantilever.rs checks its numbers)
}

/// stderr of `fdem ARGS` must stay under 1 kB (and the exit code be 2).
fn short_error(args: &[&std::ffi::OsStr], what: &str) -> String {
    let (code, _, err) = fdem(args);
    // (main: the whole 20 MB token, 20000078 bytes for msh 0)
    assert!(err.len() < 1024, "{what}: {} bytes of stderr", err.len());
    eprintln!("{what}: {} bytes: {err}", err.len());
    assert_eq!(code, 2, "{what}: exit code {code}");
    err
}

#[test]
fn case10_a_huge_token_gives_a_short_message() {
    let dir = common::temp_dir("case10");
    let big = "Z".repeat(20_000_000);
    // .msh: a 20 MB token where the file type, a count and a section name are expected
    let msh = [
        format!("$MeshFormat\n4.1 {big} 8\n$EndMeshFormat\n"),
        format!("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n{big}\n"),
        format!("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n{big}\n"),
        format!("$MeshFormat\n{big} 0 8\n$EndMeshFormat\n"),
        format!(
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n{big}\n$EndPhysicalNames\n"
        ),
    ];
    for (i, text) in msh.iter().enumerate() {
        let p = dir.join(format!("big{i}.msh"));
        std::fs::write(&p, text).unwrap();
        let err = short_error(&["info".as_ref(), p.as_os_str()], &format!("msh {i}"));
        assert!(err.contains("ZZZZ") && err.contains("bytes)"), "{err}");
        // through a scene
        let scene = dir.join(format!("scene{i}.json"));
        std::fs::write(
            &scene,
            json!({ "bodies": [{ "mesh": p, "materials": { "*": {
                "young": 1e9, "poisson": 0.25, "density": 1000.0 } } }], "duration": 1e-3 })
            .to_string(),
        )
        .unwrap();
        short_error(
            &["check".as_ref(), scene.as_os_str()],
            &format!("scene msh {i}"),
        );
    }
    // JSON mesh: a string where the nodes should be, and a group name
    for (i, text) in [
        format!("{{\"nodes\": \"{big}\", \"triangles\": []}}"),
        format!(
            "{{\"nodes\": [[0,0],[1,0],[0,1]], \"triangles\": [[0,1,2]], \"groups\": [{{\"name\": \"{big}\", \"dim\": 9}}]}}"
        ),
        format!("{{\"{big}\": 1}}"),
    ]
    .iter()
    .enumerate()
    {
        let p = dir.join(format!("big{i}.json"));
        std::fs::write(&p, text).unwrap();
        short_error(&["info".as_ref(), p.as_os_str()], &format!("json mesh {i}"));
    }
    // scene values: an enum variant, a scheme name, a material key, a group name
    let mesh = common::root().join("examples/meshes/cantilever-coarse.json");
    let base = json!({
        "bodies": [{ "mesh": mesh, "materials": { "*": {
            "young": 1e9, "poisson": 0.25, "density": 1000.0 } } }],
        "duration": 1e-3
    });
    let mut cases = Vec::new();
    let mut v = base.clone();
    v["analysis"] = json!(big);
    cases.push(("analysis", v));
    let mut v = base.clone();
    v["integrator"] = json!({ "scheme": big });
    cases.push(("scheme", v));
    let mut v = base.clone();
    v["bodies"][0]["materials"] =
        json!({ big.clone(): { "young": -1.0, "poisson": 0.25, "density": 1.0 } });
    cases.push(("material key", v));
    let mut v = base.clone();
    v["boundary_conditions"] = json!([{ "fixed": { "group": big, "x": true } }]);
    cases.push(("group", v));
    let mut v = base.clone();
    v[big.as_str()] = json!(1);
    cases.push(("unknown field", v));
    for (what, v) in cases {
        let p = dir.join("scene.json");
        std::fs::write(&p, v.to_string()).unwrap();
        let err = short_error(&["check".as_ref(), p.as_os_str()], what);
        assert!(err.contains("scene.json"), "{what}: {err}");
        let out = dir.join("out");
        short_error(
            &[
                "run".as_ref(),
                p.as_os_str(),
                "--out".as_ref(),
                out.as_os_str(),
            ],
            what,
        );
        assert!(!out.exists());
    }
}

#[test]
fn an_absurd_load_is_named_as_the_cause_of_the_instability() {
    // The vibrating cantilever with a 1e20 Pa traction in place of 1 Pa.
    let s = common::edited_example("cantilever-vibration.json", "absurd-load", |v| {
        v["boundary_conditions"][1]["traction"]["value"] = json!([0.0, -1e20]);
        v["duration"] = json!(0.05);
    });
    let out = s.parent().unwrap().join("out");
    let (code, _, err) = run(&s, &out);
    eprintln!("{err}");
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains("`boundary_conditions[1]` is far too large")
            && err.contains("traction on 'right'")
            && err.contains("fix: check the magnitude and units of `boundary_conditions[1]`"),
        "{err}"
    );
    assert!(!err.contains("lower the time step"), "{err}");
    // the partial summary is written
    assert!(out.join("summary.json").exists());
}

// ---- exit codes of every subcommand ----

#[test]
fn exit_codes_run() {
    let dir = common::temp_dir("exit-run");
    // 0: a short elastic run
    let ok = common::edited_example("cantilever-vibration.json", "exit-run-ok", |v| {
        v["duration"] = json!(0.01);
    });
    assert_eq!(run(&ok, &dir.join("ok")).0, 0);
    // 2: a missing scene, a scene error, a bad mesh; nothing written
    let out = dir.join("bad");
    assert_eq!(run(&dir.join("missing.json"), &out).0, 2);
    let bad = common::edited_example("cantilever-vibration.json", "exit-run-bad", |v| {
        v["duration"] = json!(-1.0);
    });
    assert_eq!(run(&bad, &out).0, 2);
    let bad_mesh = common::edited_example("cantilever-vibration.json", "exit-run-mesh", |v| {
        v["bodies"][0]["mesh"] = json!("/nonexistent/mesh.msh");
    });
    assert_eq!(run(&bad_mesh, &out).0, 2);
    assert!(!out.exists());
    // 2: bad arguments (clap)
    assert_eq!(fdem(&["run".as_ref()]).0, 2);
    assert_eq!(
        fdem(&["run".as_ref(), ok.as_os_str(), "--nope".as_ref()]).0,
        2
    );
    // 1: an output folder that cannot be created (a file is in the way)
    std::fs::write(dir.join("file"), "x").unwrap();
    let (code, _, err) = run(&ok, &dir.join("file").join("sub"));
    assert_eq!(code, 1, "{err}");
    // 0: a relaxation that converges (the shipped cantilever)
    let relax = common::root().join("examples/cantilever-relaxation.json");
    let (code, _, err) = run(&relax, &dir.join("relax"));
    assert_eq!(code, 0, "{err}");
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("relax").join("summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(summary["converged"], json!(true));
    // 3: see case09 (not converged) and the absurd load (unstable)
}

#[test]
fn exit_codes_check() {
    let ok = common::root().join("examples/cantilever-vibration.json");
    assert_eq!(fdem(&["check".as_ref(), ok.as_os_str()]).0, 0);
    let bad = common::edited_example("cantilever-vibration.json", "exit-check", |v| {
        v["integrator"]["scheme"] = json!("rk99");
    });
    let (code, _, err) = fdem(&["check".as_ref(), bad.as_os_str()]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(
        fdem(&["check".as_ref(), "/nonexistent/scene.json".as_ref()]).0,
        2
    );
}

#[test]
fn exit_codes_info() {
    let dir = common::temp_dir("exit-info");
    let ok = common::root().join("examples/meshes/bar.json");
    assert_eq!(fdem(&["info".as_ref(), ok.as_os_str()]).0, 0);
    // a bad mesh (main: 1) and a missing one: 2
    let bad = dir.join("bad.msh");
    std::fs::write(&bad, "$MeshFormat\n9.9 0 8\n$EndMeshFormat\n").unwrap();
    let (code, _, err) = fdem(&["info".as_ref(), bad.as_os_str()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("9.9"), "{err}");
    assert_eq!(
        fdem(&["info".as_ref(), dir.join("none.msh").as_os_str()]).0,
        2
    );
}

#[test]
fn exit_codes_plot() {
    let dir = common::temp_dir("exit-plot");
    let run_dir = dir.join("run");
    std::fs::create_dir_all(&run_dir).unwrap();
    std::fs::write(
        run_dir.join("histories.csv"),
        "time,reaction_y[load],u_y[load]\n0,0,0\n1,-5,-1e-3\n",
    )
    .unwrap();
    let ld = "load-displacement";
    assert_eq!(
        fdem(&["plot".as_ref(), ld.as_ref(), run_dir.as_os_str()]).0,
        0
    );
    assert!(run_dir.join("load_displacement.png").exists());
    // a missing folder, an unknown column, a folder without curves: 2
    let (code, _, err) = fdem(&["plot".as_ref(), ld.as_ref(), dir.join("none").as_os_str()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no such folder"), "{err}");
    let (code, _, err) = fdem(&[
        "plot".as_ref(),
        ld.as_ref(),
        run_dir.as_os_str(),
        "--load".as_ref(),
        "nope".as_ref(),
        "--displacement".as_ref(),
        "u_y[load]".as_ref(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("reaction_y[load]"), "{err}");
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    assert_eq!(
        fdem(&["plot".as_ref(), ld.as_ref(), empty.as_os_str()]).0,
        2
    );
    // 1: the plot cannot be written (its folder is a file)
    std::fs::write(dir.join("file"), "x").unwrap();
    let (code, _, err) = fdem(&[
        "plot".as_ref(),
        ld.as_ref(),
        run_dir.as_os_str(),
        "--out".as_ref(),
        dir.join("file").join("plot").as_os_str(),
    ]);
    assert_eq!(code, 1, "{err}");
}

#[test]
fn exit_codes_study() {
    let dir = common::temp_dir("exit-study");
    let out = dir.join("osc");
    // 0: a small oscillator study
    let (code, _, err) = fdem(&[
        "study".as_ref(),
        "oscillator".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        "--h-min".as_ref(),
        "0.1".as_ref(),
        "--h-max".as_ref(),
        "0.2".as_ref(),
        "--h-step".as_ref(),
        "0.1".as_ref(),
        "--periods".as_ref(),
        "2".as_ref(),
    ]);
    assert_eq!(code, 0, "{err}");
    // 2: bad arguments
    let (code, _, err) = fdem(&[
        "study".as_ref(),
        "oscillator".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        "--h-min".as_ref(),
        "-1".as_ref(),
    ]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = fdem(&[
        "study".as_ref(),
        "oscillator".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        "--schemes".as_ref(),
        "rk99".as_ref(),
    ]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = fdem(&[
        "study".as_ref(),
        "scene".as_ref(),
        dir.join("missing.json").as_os_str(),
        "--out".as_ref(),
        dir.join("sc").as_os_str(),
    ]);
    assert_eq!(code, 2, "{err}");
    // 2: a scene the study cannot use (a static analysis)
    let st = common::root().join("examples/cantilever-static.json");
    let (code, _, err) = fdem(&[
        "study".as_ref(),
        "scene".as_ref(),
        st.as_os_str(),
        "--out".as_ref(),
        dir.join("sc").as_os_str(),
    ]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn exit_codes_are_documented_in_help() {
    for args in [
        vec!["--help"],
        vec!["run", "--help"],
        vec!["check", "--help"],
        vec!["info", "--help"],
        vec!["plot", "--help"],
        vec!["study", "--help"],
    ] {
        let a: Vec<&std::ffi::OsStr> = args.iter().map(|s| s.as_ref()).collect();
        let (code, out, _) = fdem(&a);
        assert_eq!(code, 0);
        for line in [
            "Exit codes",
            "0  success",
            "2  bad input",
            "3  the run did not reach its goal",
            "1  anything else",
        ] {
            assert!(out.contains(line), "{args:?}: lacks {line:?}:\n{out}");
        }
    }
}

/// `mpirun -np 2 fdem run SCENE` (or `srun -n 2`) would start two processes that each run the
/// whole scene and write the same files: each is refused (exit code 2, nothing written),
/// whichever launcher's variable says so; a launch of one process runs as usual.
#[test]
fn a_run_started_as_one_of_several_launcher_processes_is_refused() {
    let scene = common::root().join("examples/cantilever-static.json");
    let dir = common::temp_dir("parallel-launch");
    // `fdem run SCENE --out OUT` with the launcher variable `var` set to `n`
    let launch = |var: &str, n: &str, out: &Path| {
        Command::new(env!("CARGO_BIN_EXE_fdem"))
            .args([
                "run".as_ref(),
                scene.as_os_str(),
                "--out".as_ref(),
                out.as_os_str(),
            ])
            .env(var, n)
            .output()
            .unwrap()
    };
    for var in ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "SLURM_STEP_NUM_TASKS"] {
        let out = dir.join(var);
        let o = launch(var, "2", &out);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{var}: {err}");
        assert!(
            err.contains(&format!("one of 2 processes ({var}=2")),
            "{err}"
        );
        assert!(
            err.contains("fix: build it with MPI") && err.contains("or start it once"),
            "{err}"
        );
        assert!(!out.exists(), "{var}: the run wrote {}", out.display());
    }
    let out = dir.join("one");
    let o = launch("OMPI_COMM_WORLD_SIZE", "1", &out);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.join("summary.json").exists());
}

/// `--rebalance` takes a ratio of at least 1 or `off`: anything else is refused before the
/// scene is read, naming the value and an example.
#[test]
fn a_rebalance_ratio_below_one_or_not_a_number_is_refused() {
    let scene = crate::common::root().join("examples/bar-pulse.json");
    for bad in ["0.5", "nan", "inf", "fast"] {
        let (code, _, err) = fdem(&[
            "run".as_ref(),
            scene.as_os_str(),
            "--rebalance".as_ref(),
            bad.as_ref(),
        ]);
        assert_eq!(code, 2, "{bad}: {err}");
        assert!(
            err.contains(&format!("`{bad}` is not a ratio of at least 1")) && err.contains("off"),
            "{bad}: {err}"
        );
    }
}
