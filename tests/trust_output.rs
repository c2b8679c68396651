//! What a run writes and what `fdem check` predicts, as a user relies on them: the frames'
//! cell connectivity is VTK's Int64 (so meshio gives integer cells that index the points),
//! and the run-time estimate counts contact and joints.

use crate::common;

use std::process::Command;

use fdem_solver::output::vtu;

/// The tests of this file one at a time: the timing of case 12 must not share the machine
/// with another run of this file.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// The `type` of the `<DataArray>` named `name` inside the `<Cells>` of a `.vtu` file.
fn cells_array_type(text: &str, name: &str) -> String {
    let cells = &text[text.find("<Cells>").unwrap()..text.find("</Cells>").unwrap()];
    let key = format!("Name=\"{name}\"");
    let head = cells
        .split("<DataArray")
        .find(|h| h.contains(&key))
        .unwrap_or_else(|| panic!("no {name} array"));
    let t = head.split("type=\"").nth(1).unwrap();
    t[..t.find('"').unwrap()].to_string()
}

/// Connectivity and offsets of a `.vtu` file, decoded by the writer's own reader.
fn cells(path: &std::path::Path) -> (Vec<u64>, Vec<u64>) {
    let bytes = std::fs::read(path).unwrap();
    let arrays = vtu::read(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let get = |name: &str| -> Vec<u64> {
        let a = arrays.iter().find(|a| a.name == name).unwrap();
        a.to_i64().into_iter().map(|v| v as u64).collect()
    };
    (get("connectivity"), get("offsets"))
}

#[test]
fn case11_frame_connectivity_and_offsets_are_int64_in_both_series() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    // A fracturing disc, long enough for two frames: both series (triangles, joints).
    let scene = common::edited_example("brazilian-disc-fracture.json", "case11", |v| {
        v["duration"] = serde_json::json!(2e-5);
        v["output"]["frames"] = serde_json::json!(2);
    });
    let (o, out) = common::run(&scene);
    let tris = &o.last_frame.triangles;
    let n_joints = o.last_frame.joints.as_ref().unwrap().len();
    assert!(!tris.is_empty() && n_joints > 0);
    for (file, verts, expected_conn) in [
        (
            "frame_0002.vtu",
            3,
            tris.iter()
                .flatten()
                .map(|&i| u64::from(i))
                .collect::<Vec<_>>(),
        ),
        ("joints_0002.vtu", 2, (0..2 * n_joints as u64).collect()),
    ] {
        let path = out.join(file);
        let bytes = std::fs::read(&path).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        assert_eq!(cells_array_type(&text, "connectivity"), "Int64", "{file}");
        assert_eq!(cells_array_type(&text, "offsets"), "Int64", "{file}");
        // the cell types stay UInt8
        assert_eq!(cells_array_type(&text, "types"), "UInt8", "{file}");
        let (conn, offsets) = cells(&path);
        assert_eq!(conn, expected_conn, "{file}: connectivity");
        let n = expected_conn.len() as u64 / verts;
        assert_eq!(
            offsets,
            (1..=n).map(|i| verts * i).collect::<Vec<_>>(),
            "{file}: offsets"
        );
    }
}

/// `fdem check`'s estimated time of the scene's scheme (the `<- scene` row) [s].
fn check_estimate(scene: &std::path::Path) -> (f64, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_fdem"))
        .arg("check")
        .arg(scene)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "{text}");
    let row = text
        .lines()
        .find(|l| l.contains("<- scene"))
        .unwrap_or_else(|| panic!("no scene row:\n{text}"));
    let est = row
        .split_whitespace()
        .rev()
        .find(|w| w.ends_with('s') && w[..w.len() - 1].parse::<f64>().is_ok())
        .unwrap();
    (est[..est.len() - 1].parse().unwrap(), text)
}

#[test]
fn case12_check_estimate_counts_contact_and_joints_within_a_factor_two() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    // The fracturing disc with platens ten times faster (0.2 m/s each, ramped over 10 us):
    // it peaks and splits within 0.25 ms, about 7700 steps, with contact at the platens and
    // along the crack and 1260 joints, most of the step's cost.
    let scene = common::edited_example("brazilian-disc-fracture.json", "case12", |v| {
        v["duration"] = serde_json::json!(2.5e-4);
        v["output"]["frames"] = serde_json::json!(1);
        for w in v["contact"]["walls"].as_array_mut().unwrap() {
            let vy = w["velocity"][1].as_f64().unwrap();
            w["velocity"][1] = serde_json::json!(10.0 * vy);
            w["ramp"] = serde_json::json!(1e-5);
        }
    });
    let run = |out: &std::path::Path| -> serde_json::Value {
        let o = Command::new(env!("CARGO_BIN_EXE_fdem"))
            .arg("run")
            .arg(&scene)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
    };
    // `check` then `run`; on a machine shared with other work the load can change between
    // the two, so a pair outside the factor is measured once more (both pairs are printed).
    let mut pairs = Vec::new();
    for attempt in 0..2 {
        let (est, report) = check_estimate(&scene);
        let out = scene.parent().unwrap().join(format!("out{attempt}"));
        let s = run(&out);
        let broken = s["stages"]["fracture"]["broken"].as_u64().unwrap();
        assert!(broken > 0, "the scene must fracture");
        // the run's time without writing frames (stepping, histories, checks)
        let actual = s["wall_time"].as_f64().unwrap() - s["timers"]["output"].as_f64().unwrap();
        let ratio = est / actual;
        println!(
            "estimate {est:.3} s, run without output {actual:.3} s, ratio {ratio:.2}, {broken} joints broken\n{report}"
        );
        pairs.push(format!(
            "estimate {est:.3} s, run {actual:.3} s, ratio {ratio:.2}"
        ));
        if (0.5..=2.0).contains(&ratio) {
            return;
        }
    }
    panic!(
        "the estimate is not within a factor 2 of the run:\n{}",
        pairs.join("\n")
    );
}
