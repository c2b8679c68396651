//! The whole input is consumed or refused, and what the scene asks for acts on something:
//! text after the scene's object and byte-order marks (class 1), groups that repeat an entity
//! (class 2), loads on internal edges (class 3), sections that act on nothing (class 4) and
//! bodies that overlap at t = 0 (class 5). Every refusal is exit code 2 with nothing written,
//! and `fdem check` refuses with the same message as `fdem run`.

use crate::common;

use std::path::{Path, PathBuf};

use serde_json::json;

use crate::common::fdem;

/// A scene refused alike by `fdem check` and `fdem run`: exit code 2 from both, the same
/// message, no output folder; returns the message.
fn refused(scene: &Path) -> String {
    let out = scene.with_extension("out");
    let (code_check, _, err_check) = fdem(&["check".as_ref(), scene.as_os_str()]);
    let (code_run, _, err_run) = fdem(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert_eq!(code_check, 2, "check: {err_check}");
    assert_eq!(code_run, 2, "run: {err_run}");
    assert_eq!(err_check, err_run, "check and run differ");
    assert!(!out.exists(), "{} was created", out.display());
    assert!(!err_run.contains("panicked"), "{err_run}");
    err_run
}

/// A 2 x 1-cell rectangle 20 mm x 10 mm of four triangles (surface group `rock`; edge groups
/// `left`, `right`, `top`, `bottom` on the outline and `middle`, the internal vertical line
/// x = 10 mm), written as `rect.json` into `dir`; `edit` changes the mesh's JSON first.
fn two_cells(dir: &Path, edit: impl FnOnce(&mut serde_json::Value)) {
    let (nodes, tris) = common::structured_rectangle(2, 1, 0.02, 0.01);
    // nodes: 0 1 2 along the bottom, 3 4 5 along the top
    let mut mesh = json!({
        "nodes": nodes, "triangles": tris,
        "groups": [
            {"name": "rock", "dim": 2, "triangles": [0, 1, 2, 3]},
            {"name": "left", "dim": 1, "edges": [[3, 0]]},
            {"name": "right", "dim": 1, "edges": [[2, 5]]},
            {"name": "bottom", "dim": 1, "edges": [[0, 1], [1, 2]]},
            {"name": "top", "dim": 1, "edges": [[5, 4], [4, 3]]},
            {"name": "middle", "dim": 1, "edges": [[1, 4]]}
        ]
    });
    edit(&mut mesh);
    std::fs::write(dir.join("rect.json"), mesh.to_string()).unwrap();
}

/// A dynamic scene of the rectangle of [`two_cells`] held on its left side, with `bcs` added
/// and `edit` applied; written into a fresh folder, which holds `rect.json`.
fn rect_scene(
    tag: &str,
    mesh_edit: impl FnOnce(&mut serde_json::Value),
    edit: impl FnOnce(&mut serde_json::Value),
) -> PathBuf {
    let dir = common::temp_dir(&format!("trust-input-{tag}"));
    two_cells(&dir, mesh_edit);
    let mut v = json!({
        "bodies": [{
            "name": "rock", "mesh": "rect.json",
            "materials": { "*": { "young": 10e9, "poisson": 0.25, "density": 2500.0 } }
        }],
        "boundary_conditions": [ { "fixed": { "group": "left", "x": true, "y": true } } ],
        "integrator": { "scheme": "central-difference", "time_step": "auto" },
        "duration": 1e-5,
        "output": { "frames": 1 }
    });
    edit(&mut v);
    let file = dir.join("scene.json");
    std::fs::write(&file, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    file
}

/// The fracture section of the rectangle (the whole body fracturing) and contact, for cracks.
fn fracture_section() -> serde_json::Value {
    json!({
        "regions": [ {} ],
        "material": {
            "tensile_strength": 3e6, "cohesion": 10e6, "friction_angle_deg": 30.0,
            "fracture_energy_i": 50.0, "fracture_energy_ii": 250.0,
            "penalty_normal": 300e9, "penalty_tangential": 300e9
        }
    })
}

#[test]
fn class1_text_after_the_scene_object_is_refused_by_check_and_run() {
    // a damping section pasted after the closing brace: dropped unread before
    let good = rect_scene("class1-good", |_| {}, |_| {});
    let text = std::fs::read_to_string(&good).unwrap();
    let bad = good.with_file_name("trailing.json");
    std::fs::write(
        &bad,
        format!("{text}\n{{\"damping\": {{\"mass_proportional\": 1e3}}}}\n"),
    )
    .unwrap();
    let err = refused(&bad);
    assert!(
        err.contains("trailing.json:") && err.contains("text follows it"),
        "{err}"
    );
    // a byte-order mark before the object
    let bom = good.with_file_name("bom.json");
    std::fs::write(&bom, format!("\u{feff}{text}")).unwrap();
    let err = refused(&bom);
    assert!(err.contains("byte-order mark"), "{err}");
    // the good scene checks
    let (code, _, err) = fdem(&["check".as_ref(), good.as_os_str()]);
    assert_eq!(code, 0, "{err}");
    fdem_figures::record(135, "refused");
}

#[test]
fn class2_an_edge_listed_twice_in_a_loaded_group_is_refused() {
    // `right` lists its one edge twice, the second time reversed: loaded twice before
    let s = rect_scene(
        "class2",
        |m| m["groups"][2]["edges"] = json!([[2, 5], [5, 2]]),
        |v| {
            v["boundary_conditions"]
                .as_array_mut()
                .unwrap()
                .push(json!({ "traction": { "group": "right", "value": [1e6, 0.0] } }));
        },
    );
    let err = refused(&s);
    assert!(
        err.contains("group \"right\" lists the edge between nodes 5 and 2")
            && err.contains("twice")
            && err.contains("bodies[0].mesh"),
        "{err}"
    );
}

#[test]
fn class3_a_pressure_on_internal_edges_is_refused() {
    for kind in ["pressure", "traction"] {
        let s = rect_scene(
            &format!("class3-{kind}"),
            |_| {},
            |v| {
                let load = if kind == "pressure" {
                    json!({ "pressure": { "group": "middle", "value": 1e6 } })
                } else {
                    json!({ "traction": { "group": "middle", "value": [1e6, 0.0] } })
                };
                v["boundary_conditions"].as_array_mut().unwrap().push(load);
            },
        );
        let err = refused(&s);
        assert!(
            err.contains(&format!("boundary_conditions[1].{kind}.group"))
                && err.contains("internal edge")
                && err.contains("between nodes 1 and 4")
                && err.contains("fracture.cracks"),
            "{err}"
        );
    }
    fdem_figures::record_part(136, 1, "refused");
}

#[test]
fn class3_a_pressure_on_a_crack_loads_both_faces() {
    let s = rect_scene(
        "class3-crack",
        |_| {},
        |v| {
            let mut f = fracture_section();
            f["cracks"] = json!([{ "group": "middle" }]);
            v["fracture"] = f;
            v["contact"] = json!({});
            v["boundary_conditions"]
                .as_array_mut()
                .unwrap()
                .push(json!({ "pressure": { "group": "middle", "value": 1e6 } }));
        },
    );
    let l = fdem_solver::load(&s).unwrap();
    let forces: Vec<(u32, f64)> = l
        .model
        .loads
        .iter()
        .flat_map(|r| r.forces.clone())
        .collect();
    // the crack x = 10 mm is 10 mm long, the thickness 1 m: each face carries p L t = 1e4 N,
    // the left face pushed to -x, the right one to +x, on four different nodes
    let fx: Vec<f64> = forces
        .iter()
        .filter(|(d, _)| d % 2 == 0)
        .map(|f| f.1)
        .collect();
    let neg: f64 = fx.iter().filter(|f| **f < 0.0).sum();
    let pos: f64 = fx.iter().filter(|f| **f > 0.0).sum();
    assert!(
        (neg + 1e4).abs() < 1e-8 && (pos - 1e4).abs() < 1e-8,
        "{fx:?}"
    );
    let nodes: std::collections::BTreeSet<u32> = forces.iter().map(|f| f.0 / 2).collect();
    assert_eq!(nodes.len(), 4, "{forces:?}");
    fdem_figures::record_part(
        136,
        2,
        format!("{pos:.0e} N on each face, on {} nodes", nodes.len()),
    );
}

#[test]
fn class4_fracture_sections_that_act_on_nothing_are_refused() {
    let cases: [(&str, serde_json::Value, &str); 3] = [
        ("no-region", json!([]), "fracture.regions"),
        (
            "empty-groups",
            json!([{ "groups": [] }]),
            "fracture.regions[0].groups",
        ),
        // a body of a single triangle: no internal edge, no joint
        ("one-triangle", json!([{}]), "fracture.regions[0]"),
    ];
    for (tag, regions, path) in cases {
        let s = rect_scene(
            &format!("class4-{tag}"),
            |m| {
                if tag == "one-triangle" {
                    *m = json!({
                        "nodes": [[0.0, 0.0], [0.02, 0.0], [0.0, 0.01]],
                        "triangles": [[0, 1, 2]],
                        "groups": [{"name": "left", "dim": 1, "edges": [[2, 0]]}]
                    });
                }
            },
            |v| {
                let mut f = fracture_section();
                f["regions"] = regions;
                v["fracture"] = f;
            },
        );
        let err = refused(&s);
        assert!(err.contains(path) && err.contains("fix:"), "{tag}: {err}");
    }
    fdem_figures::record_part(137, 1, "refused");
}

#[test]
fn class4_a_joint_material_that_nothing_uses_is_a_warning() {
    let s = rect_scene(
        "class4-unused",
        |_| {},
        |v| {
            let mut f = fracture_section();
            f["materials"] = json!({ "weak": f["material"].clone() });
            v["fracture"] = f;
        },
    );
    let (code, out, err) = fdem(&["check".as_ref(), s.as_os_str()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("warning: fracture.materials.weak: no region or interface uses"),
        "{out}"
    );
    let dir = s.with_extension("out");
    let (code, _, err) = fdem(&[
        "run".as_ref(),
        s.as_os_str(),
        "--out".as_ref(),
        dir.as_os_str(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("warning: fracture.materials.weak"), "{err}");
    fdem_figures::record_part(137, 2, "warned");
}

/// The disc collision with the right disc's offset set to `x` (the left one at -0.0255, both
/// of radius 25 mm), and `edit` applied.
fn discs(tag: &str, x: f64, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    common::edited_example("disc-collision.json", tag, |v| {
        v["bodies"][1]["offset"] = json!([x, 0.0]);
        v["duration"] = json!(2e-5);
        edit(v);
    })
}

#[test]
fn class5_bodies_that_overlap_at_the_start_are_refused() {
    // coincident discs, and discs overlapping by 5 mm
    for (tag, x, depth) in [("coincident", -0.0255, 0.02), ("5mm", 0.0205, 0.003)] {
        let s = discs(&format!("class5-{tag}"), x, |_| {});
        let err = refused(&s);
        assert!(
            err.contains("body 'left' and body 'right' overlap at t = 0") && err.contains("fix:"),
            "{tag}: {err}"
        );
        let d: f64 = err
            .split("the deepest ")
            .nth(1)
            .and_then(|r| r.split(' ').next())
            .and_then(|d| d.parse().ok())
            .unwrap_or_else(|| panic!("no depth in {err}"));
        assert!(d > depth, "{tag}: depth {d}");
    }
    // 1 mm apart, and touching at one point: accepted
    for (tag, x) in [("gap", 0.0265), ("touching", 0.0245)] {
        let s = discs(&format!("class5-{tag}"), x, |_| {});
        let (code, _, err) = fdem(&["check".as_ref(), s.as_os_str()]);
        assert_eq!(code, 0, "{tag}: {err}");
    }
    // a deliberate overlap, said so in the pair
    let s = discs("class5-allowed", 0.0205, |v| {
        v["contact"] = json!({ "pairs": [
            { "bodies": ["left", "right"], "allow_initial_overlap": true }
        ] });
    });
    let (code, _, err) = fdem(&["check".as_ref(), s.as_os_str()]);
    assert_eq!(code, 0, "{err}");
    fdem_figures::record(138, "refused; accepted");
}

#[test]
fn class5_a_body_that_starts_behind_a_wall_is_refused() {
    let s = discs("class5-wall", 0.0265, |v| {
        v["contact"] = json!({ "walls": [
            { "name": "floor", "point": [0.0, -0.024], "normal": [0.0, 1.0] }
        ] });
    });
    let err = refused(&s);
    assert!(
        err.contains("contact.walls[0].point")
            && err.contains("starts behind wall 'floor'")
            && err.contains("allow_initial_overlap"),
        "{err}"
    );
    let s = discs("class5-wall-allowed", 0.0265, |v| {
        v["contact"] = json!({ "walls": [
            { "name": "floor", "point": [0.0, -0.024], "normal": [0.0, 1.0], "allow_initial_overlap": true }
        ] });
    });
    let (code, _, err) = fdem(&["check".as_ref(), s.as_os_str()]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn class6_a_static_solve_with_loads_near_the_top_of_the_number_range_is_not_refused() {
    // a thickness of 1e300 m: loads and stiffness near the top of the floating-point range;
    // the balance check squared them and refused a correct solution as singular (exit 2
    // from `fdem run`, while `fdem check` passed it)
    let tip = |thickness: f64| {
        let s = common::edited_example("cantilever-static.json", "class6-static", |v| {
            v["bodies"][0]["mesh"] = json!(
                common::root()
                    .join("examples/meshes/cantilever-coarse.json")
                    .display()
                    .to_string()
            );
            v["bodies"][0]["thickness"] = json!(thickness);
        });
        let out = s.with_file_name("out");
        let (code, _, err) = fdem(&[
            "run".as_ref(),
            s.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ]);
        assert_eq!(code, 0, "thickness {thickness}: {err}");
        let (head, rows) = common::histories(&out);
        *common::column(&head, &rows, "u_y[tip]").last().unwrap()
    };
    // the deflection does not depend on the thickness (loads and stiffness scale alike)
    let (a, b) = (tip(1.0), tip(1e300));
    assert!(a < -1e-3 && ((b - a) / a).abs() < 1e-9, "{a} against {b}");
    let d = ((b - a) / a).abs();
    fdem_figures::record_part(
        139,
        1,
        if d == 0.0 {
            "equal".to_string()
        } else {
            format!("within {d:.1e}")
        },
    );
}

#[test]
fn class10_a_static_load_that_would_overflow_is_refused_at_its_path() {
    // a traction of 1e300 Pa on the static cantilever: the run stopped as unstable (exit 3,
    // no summary) with advice to lower the time step of an analysis that has none
    let s = common::edited_example("cantilever-static.json", "class10-static-load", |v| {
        v["bodies"][0]["mesh"] = json!(
            common::root()
                .join("examples/meshes/cantilever-coarse.json")
                .display()
                .to_string()
        );
        v["boundary_conditions"][1]["traction"]["value"] = json!([0.0, 1e300]);
    });
    let err = refused(&s);
    assert!(
        err.contains("at `boundary_conditions[1]`")
            && err.contains("overflow")
            && !err.contains("time step"),
        "{err}"
    );
    // its mirror, 1e-300 Pa on a modulus of 1e300 Pa: displacements that underflow to 0 were
    // refused by the solve as a singular stiffness (exit 2 from `fdem run` alone)
    let s = common::edited_example("cantilever-static.json", "class10-static-tiny", |v| {
        v["bodies"][0]["mesh"] = json!(
            common::root()
                .join("examples/meshes/cantilever-coarse.json")
                .display()
                .to_string()
        );
        v["bodies"][0]["materials"]["beam"]["young"] = json!(1e300);
        v["boundary_conditions"][1]["traction"]["value"] = json!([0.0, 1e-300]);
    });
    let err = refused(&s);
    assert!(
        err.contains("at `boundary_conditions[1]`") && err.contains("underflow"),
        "{err}"
    );
    fdem_figures::record_part(139, 2, "refused at `boundary_conditions[1]`");
}
