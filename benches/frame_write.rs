//! One frame (triangles and joints) of the fracturing disc of about 10^5 triangles (`benches/common/disc.rs`, its
//! exploded mesh: every triangle has its own three nodes), after 300 steps of loading: the
//! time to encode and write its `.vtu` file and the file's size, with the raw appended
//! writer (`fdem_solver::output::vtu`) at zlib levels 0, 1 (the default) and 6 on the
//! current rayon pool, against vtkio's inline base64 encoder that wrote the files before
//! (level 6, its default then, and 1). Median of `FRAME_REPEAT` (default 5) writes each.
//! `FRAME_STEPS` sets the steps before the frame (default 2000); `FRAME_CACHE=FILE` keeps the
//! frame (its raw JSON) in FILE and reads it from there on later runs.
//!
//! `RAYON_NUM_THREADS=2 cargo bench --bench frame_write`

use std::path::{Path, PathBuf};
use std::time::Instant;

use fdem_solver::driver::{RunOptions, load, run_outcome};
use fdem_solver::output::{ArraySet, FrameData, JointFrame, write_atomic};

#[path = "common/disc.rs"]
mod disc;

/// The encoder the files had before, for the comparison (it names its siblings `frame` and
/// `joint_frame` through `super`).
#[allow(dead_code, unused_imports)]
#[path = "../crates/solver/src/output/vtu_vtkio.rs"]
mod vtu_vtkio;
#[allow(unused_imports)]
use fdem_solver::output::{frame, joint_frame, joints, vtu};

fn pairs(v: &serde_json::Value) -> Vec<[f64; 2]> {
    serde_json::from_value(v.clone()).unwrap()
}

fn f64s(v: &serde_json::Value) -> Vec<f64> {
    serde_json::from_value(v.clone()).unwrap()
}

/// The joints of the raw JSON dump.
fn joints_of(j: &serde_json::Value) -> JointFrame {
    let i32s = |v: &serde_json::Value| -> Vec<i32> { serde_json::from_value(v.clone()).unwrap() };
    JointFrame {
        points: pairs(&j["points"]),
        damage: f64s(&j["damage"]),
        mode: i32s(&j["mode"]),
        mode_mix: f64s(&j["mode_mix"]),
        broken: i32s(&j["broken"]),
        time_of_failure: f64s(&j["time_of_failure"]),
        opening: f64s(&j["opening"]),
        sliding: f64s(&j["sliding"]),
        normal_traction: f64s(&j["normal_traction"]),
        shear_traction: f64s(&j["shear_traction"]),
        properties: None,
        fluid: None,
    }
}

/// The frame of the raw JSON dump (`--raw`).
fn frame_of(json: &serde_json::Value) -> FrameData {
    let named = |v: &serde_json::Value| -> Vec<(String, serde_json::Value)> {
        serde_json::from_value(v.clone()).unwrap_or_default()
    };
    FrameData {
        time: json["time"].as_f64().unwrap(),
        points: pairs(&json["points"]),
        triangles: serde_json::from_value(json["triangles"].clone()).unwrap(),
        displacement: pairs(&json["displacement"]),
        velocity: pairs(&json["velocity"]),
        force: pairs(&json["force"]),
        reaction: pairs(&json["reaction"]),
        stress: serde_json::from_value(json["stress"].clone()).unwrap(),
        principal: pairs(&json["principal"]),
        von_mises: f64s(&json["von_mises"]),
        energy_density: f64s(&json["energy_density"]),
        material: serde_json::from_value(json["material"].clone()).unwrap(),
        body: serde_json::from_value(json["body"].clone()).unwrap(),
        nodal_stress: serde_json::from_value(json["nodal_stress"].clone()).unwrap_or_default(),
        nodal_principal: serde_json::from_value(json["nodal_principal"].clone())
            .unwrap_or_default(),
        nodal_von_mises: serde_json::from_value(json["nodal_von_mises"].clone())
            .unwrap_or_default(),
        extra_point_vectors: named(&json["extra_point_vectors"])
            .into_iter()
            .map(|(n, v)| (n, pairs(&v)))
            .collect(),
        extra_cell_scalars: named(&json["extra_cell_scalars"])
            .into_iter()
            .map(|(n, v)| (n, f64s(&v)))
            .collect(),
        joints: json.get("joints").map(joints_of),
    }
}

/// Median times [s] of `FRAME_REPEAT` (default 5) writes of `frame` and its joints with
/// `write` (the whole, and the encoding alone as `write` returns it), and the two files' size.
fn time(
    frame: &FrameData,
    dir: &Path,
    write: impl Fn(&FrameData, &Path) -> (f64, usize),
) -> (f64, f64, usize) {
    let repeat = std::env::var("FRAME_REPEAT").map_or(5, |s| s.parse().unwrap());
    let (mut t, mut te) = (Vec::new(), Vec::new());
    let mut size = 0;
    for _ in 0..repeat {
        let s = Instant::now();
        let (e, n) = write(frame, dir);
        t.push(s.elapsed().as_secs_f64());
        te.push(e);
        size = n;
    }
    t.sort_by(f64::total_cmp);
    te.sort_by(f64::total_cmp);
    (t[repeat / 2], te[repeat / 2], size)
}

/// Writes the frame and its joints with the raw appended writer (every array) as a run
/// writes them: their blocks compressed together, the encoded pieces streamed to the two
/// files at the same time; the encoding time and the bytes.
fn write_raw(frame: &FrameData, dir: &Path, level: u32) -> (f64, usize) {
    let all = ArraySet::all();
    let grids = [
        vtu::frame_grid(frame, &all),
        joints::grid(frame.joints.as_ref().unwrap(), &all),
    ];
    let s = Instant::now();
    let encoded = vtu::encode_all(&[&grids[0], &grids[1]], level).unwrap();
    let enc = s.elapsed().as_secs_f64();
    let paths = [dir.join("frame.vtu"), dir.join("joints.vtu")];
    let files: Vec<_> = encoded
        .iter()
        .zip(paths.iter().map(|p| p.as_path()))
        .collect();
    vtu::write_encoded(&files).unwrap();
    (enc, encoded.iter().map(|e| e.len()).sum())
}

/// Writes the frame and its joints with vtkio's encoder at `level`.
fn write_vtkio(frame: &FrameData, dir: &Path, level: u32) -> (f64, usize) {
    let s = Instant::now();
    let bytes = vtu_vtkio::encode(frame, level).unwrap();
    let j = vtu_vtkio::encode_joints(frame.joints.as_ref().unwrap(), level).unwrap();
    let enc = s.elapsed().as_secs_f64();
    write_atomic(&dir.join("frame.vtu"), &bytes).unwrap();
    write_atomic(&dir.join("joints.vtu"), &j).unwrap();
    (enc, bytes.len() + j.len())
}

/// The frame after `FRAME_STEPS` steps, from the file `FRAME_CACHE` when it names one that
/// exists (else computed, and kept there when it is set).
fn the_frame(dir: &Path) -> (FrameData, u64) {
    let steps = std::env::var("FRAME_STEPS").map_or(2000, |s| s.parse().unwrap());
    let cache = std::env::var_os("FRAME_CACHE").map(PathBuf::from);
    if let Some(text) = cache.as_ref().and_then(|c| std::fs::read(c).ok()) {
        return (frame_of(&serde_json::from_slice(&text).unwrap()), steps);
    }
    let mut l = load(&dir.join("disc.scene.json")).unwrap();
    l.n_steps = steps;
    l.scene.output.frames = 1;
    let out = dir.join("out");
    let options = RunOptions {
        out_dir: out.clone(),
        raw: true,
        ..Default::default()
    };
    run_outcome(&mut l, &options, &mut |_| {}).unwrap();
    let text = std::fs::read(out.join("frame_0001.json")).unwrap();
    if let Some(c) = &cache {
        std::fs::write(c, &text).unwrap();
    }
    (frame_of(&serde_json::from_slice(&text).unwrap()), steps)
}

fn main() {
    let dir = disc::scene_dir();
    let (frame, steps) = the_frame(&dir);
    let j = frame.joints.as_ref().unwrap();
    println!(
        "frame after {steps} steps: {} points, {} triangles, {} joints ({} broken), {} threads; frame + joints file:",
        frame.points.len(),
        frame.triangles.len(),
        j.len(),
        j.broken.iter().filter(|b| **b == 1).count(),
        rayon::current_num_threads()
    );
    for level in [0, 1, 6] {
        let (t, te, size) = time(&frame, &dir, |f, d| write_raw(f, d, level));
        println!(
            "raw appended, level {level}: {t:.3} s (encoding {te:.3} s), {:.1} MB",
            size as f64 / 1e6
        );
    }
    for level in [6, 1] {
        let (t, te, size) = time(&frame, &dir, |f, d| write_vtkio(f, d, level));
        println!(
            "vtkio inline base64, level {level}: {t:.3} s (encoding {te:.3} s), {:.1} MB",
            size as f64 / 1e6
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
