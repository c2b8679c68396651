//! `output.arrays` (only the asked arrays written, each bit for bit the array of a full
//! frame; names the scene cannot give refused with their JSON path) and `output.writer_thread`
//! (frames written in the background give the same files, and a failed write ends the run
//! with the same error as a write in the loop).

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use fdem_solver::driver::{self, RunOptions};
use fdem_solver::output::vtu;

/// The fracturing block between platens (contact and joints), shortened to 3 frames over
/// 60 us, with `edit` applied.
fn block(tag: &str, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    common::edited_example("block-compression-fracture.json", tag, |v| {
        v["duration"] = serde_json::json!(6e-5);
        v["output"]["frames"] = serde_json::json!(3);
        edit(v);
    })
}

/// The arrays of a `.vtu` file by name, with their type, components and bytes.
fn arrays(path: &Path) -> BTreeMap<String, (String, usize, Vec<u8>)> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    vtu::read(&bytes)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_iter()
        .map(|a| (a.name, (a.ty.to_string(), a.components, a.bytes)))
        .collect()
}

const GEOMETRY: [&str; 4] = ["Points", "connectivity", "offsets", "types"];

#[test]
fn a_reduced_list_writes_exactly_its_arrays_bit_for_bit_as_a_full_frame() {
    let full = block("arrays-full", |_| {});
    let (_, full_out) = common::run(&full);
    let asked = [
        "velocity",
        "contact_force",
        "von_mises",
        "contact_active",
        "damage",
        "opening",
    ];
    let reduced = block("arrays-reduced", |v| {
        v["output"]["arrays"] = serde_json::json!(asked);
    });
    let (_, out) = common::run(&reduced);
    let mut compared = 0;
    for k in 0..=3 {
        for (file, names) in [
            (format!("frame_{k:04}.vtu"), &asked[..4]),
            (format!("joints_{k:04}.vtu"), &asked[4..]),
        ] {
            let a = arrays(&out.join(&file));
            let b = arrays(&full_out.join(&file));
            let mut want: Vec<&str> = names.iter().chain(&GEOMETRY).copied().collect();
            want.sort();
            let got: Vec<&str> = a.keys().map(String::as_str).collect();
            assert_eq!(got, want, "{file}: the arrays written");
            for (name, v) in &a {
                assert!(
                    b[name] == *v,
                    "{file}: {name} differs from the full frame's"
                );
                compared += 1;
            }
            assert!(b.len() > a.len(), "{file}: the full frame has more arrays");
        }
    }
    assert_eq!(compared, 4 * (4 + 2 + 2 * GEOMETRY.len()));
    // the collections list the same frames at the same times
    for pvd in ["results.pvd", "joints.pvd"] {
        assert_eq!(
            std::fs::read_to_string(out.join(pvd)).unwrap(),
            std::fs::read_to_string(full_out.join(pvd)).unwrap()
        );
    }
    // a list without a joint array writes no joint series; a nodal stress array alone (no
    // cell stress, no joint array) is the full frame's, its patches cut by the same joints
    let no_joints = block("arrays-no-joints", |v| {
        v["output"]["arrays"] = serde_json::json!(["displacement", "nodal_von_mises"]);
    });
    let (_, out) = common::run(&no_joints);
    let names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.starts_with("joints")), "{names:?}");
    let a = arrays(&out.join("frame_0003.vtu"));
    assert_eq!(a.len(), 2 + GEOMETRY.len());
    let full = arrays(&full_out.join("frame_0003.vtu"));
    assert!(a["displacement"] == full["displacement"]);
    assert!(a["nodal_von_mises"] == full["nodal_von_mises"]);
    fdem_figures::record_part(92, 1, format!("equal ({compared} arrays compared)"));
}

/// The error of loading the cantilever example with `output.arrays` set to `arrays`.
fn load_error(tag: &str, arrays: serde_json::Value) -> String {
    let scene = common::edited_example("cantilever-vibration.json", tag, |v| {
        v["output"]["arrays"] = arrays;
    });
    match driver::load(&scene) {
        Ok(_) => panic!("{tag}: loaded"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn unknown_arrays_and_arrays_the_scene_cannot_give_are_refused_with_their_path() {
    let e = load_error("arrays-unknown", serde_json::json!(["stress", "strain"]));
    assert!(e.contains("output.arrays[1]"), "{e}");
    assert!(e.contains("unknown array 'strain'"), "{e}");
    // the valid names of this scene: no contact, no joints
    assert!(
        e.contains(
            "displacement, velocity, force, reaction, nodal_stress, nodal_principal_stress, \
             nodal_von_mises, stress"
        ),
        "{e}"
    );
    assert!(!e.contains("contact_force") && !e.contains("damage"), "{e}");
    let e = load_error(
        "arrays-contact",
        serde_json::json!(["displacement", "velocity", "force", "contact_active"]),
    );
    assert!(e.contains("output.arrays[3]"), "{e}");
    assert!(e.contains("'contact_active' needs contact"), "{e}");
    let e = load_error("arrays-joint", serde_json::json!(["damage"]));
    assert!(
        e.contains("output.arrays[0]") && e.contains("no \"fracture\" section"),
        "{e}"
    );
    let e = load_error("arrays-twice", serde_json::json!(["body", "body"]));
    assert!(
        e.contains("output.arrays[1]") && e.contains("listed twice"),
        "{e}"
    );
    let e = load_error("arrays-word", serde_json::json!("everything"));
    assert!(e.contains("output.arrays") && e.contains("\"all\""), "{e}");
    fdem_figures::record_part(92, 2, "errors as stated");
}

/// `v` without the timings (`timers`, `wall_time`, throughput, the stages' `*_s` seconds)
/// and the scene's path.
fn untimed(v: &mut serde_json::Value) {
    if let Some(o) = v.as_object_mut() {
        o.retain(|k, _| {
            !(k.ends_with("_s")
                || ["timers", "wall_time", "triangle_steps_per_second", "scene"]
                    .contains(&k.as_str()))
        });
        o.values_mut().for_each(untimed);
    }
}

/// Every file of `out` (the summary without its timings).
fn files(out: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut m = BTreeMap::new();
    for e in std::fs::read_dir(out).unwrap() {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        let mut bytes = std::fs::read(e.path()).unwrap();
        if name == "summary.json" {
            let mut v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
            untimed(&mut v);
            bytes = v.to_string().into_bytes();
        }
        m.insert(name, bytes);
    }
    m
}

#[test]
fn frames_written_in_the_background_are_the_files_written_in_the_loop() {
    let on = block("thread-on", |_| {});
    let off = block("thread-off", |v| {
        v["output"]["writer_thread"] = serde_json::json!(false);
    });
    let (a, out_on) = common::run(&on);
    let (b, out_off) = common::run(&off);
    assert_eq!((a.summary.frames, b.summary.frames), (4, 4));
    let (fa, fb) = (files(&out_on), files(&out_off));
    assert_eq!(fa.keys().collect::<Vec<_>>(), fb.keys().collect::<Vec<_>>());
    for (name, bytes) in &fa {
        assert!(fb[name] == *bytes, "{name} differs");
    }
    assert!(fa.contains_key("joints_0003.vtu") && fa.contains_key("results.pvd"));
    fdem_figures::record_part(93, 1, format!("identical ({} files)", fa.len()));
}

/// The run of `scene` with a folder named `frame_0002.vtu` in the way of its third frame (a
/// run leaves folders alone): the error.
fn blocked_run(scene: &Path) -> String {
    let mut l = driver::load(scene).unwrap();
    let out = scene.parent().unwrap().join("out");
    std::fs::create_dir_all(out.join("frame_0002.vtu").join("x")).unwrap();
    let r = driver::run_outcome(
        &mut l,
        &RunOptions {
            out_dir: out.clone(),
            ..Default::default()
        },
        &mut |_| {},
    );
    let e = r.err().expect("the run fails").to_string();
    let names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.iter().all(|n| !n.contains(".tmp")),
        "a temporary file was left: {names:?}"
    );
    // the collection lists the frames written before, whole
    let pvd = std::fs::read_to_string(out.join("results.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 2, "{pvd}");
    e.replace(&scene.parent().unwrap().display().to_string(), "DIR")
}

#[test]
fn a_failed_background_write_ends_the_run_with_the_error_of_a_write_in_the_loop() {
    let on = block("fail-on", |_| {});
    let off = block("fail-off", |v| {
        v["output"]["writer_thread"] = serde_json::json!(false);
    });
    let (a, b) = (blocked_run(&on), blocked_run(&off));
    assert!(a.contains("frame_0002.vtu"), "{a}");
    assert_eq!(a, b);
    fdem_figures::record_part(93, 2, "as stated");
}
