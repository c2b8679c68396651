//! A whole job of the `fdem` program on the fracturing Brazilian disc of about 10^5 triangles:
//! set-up, 300 steps and 10 frames (plus the initial one), as a user runs it, timed from the
//! start of the process to its exit, on 1 and 2 threads.
//!
//! The disc is the one of `benches/fracture_disc.rs` (`benches/common/disc.rs`: 99 846
//! triangles, 149 382 joints, platens closing at 2 x 10 m/s, brittle joints), with
//! `"output": {"frames": 10}` and the duration of 300 of its steps.
//!
//! Set `FDEM_BASE=/path/to/another/fdem` to compare with another build of the program: the runs
//! of the two programs then alternate (base, this, base, this, ...), so that both see the same
//! load on a shared machine, and the medians are compared. `RUNS` (default 3) sets the runs per
//! program and thread count; `THREADS` (default `1,2`) the thread counts. The lines give the
//! whole job's time, the stepping rate from `summary.json` (triangle-steps per second of the
//! stepping loop, frames excluded), the time the stepping spent on frames (`timers.output`)
//! and the set-up time (`timers.setup`, absent from older builds), and the ratios base / this. With `KEEP=1` the folder with
//! the mesh and the job's scene (`disc-job.scene.json`) is kept, for profiling. `RINGS`
//! (default 129) sets the rings of the disc's mesh, 6 RINGS^2 triangles: a smaller disc shows
//! how the thread scaling depends on whether the run's data fit the processor's caches.
//!
//! ```text
//! cargo bench --bench whole_run
//! FDEM_BASE=/path/to/fdem-base RUNS=5 cargo bench --bench whole_run
//! ```

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use fdem_solver::driver::load;

#[path = "common/disc.rs"]
mod disc;

/// Steps of the job.
const STEPS: f64 = 300.0;
/// Frames besides the initial one.
const FRAMES: u64 = 10;

/// One job: the process's wall time and the summary's stepping rate and frame time.
struct Job {
    wall: f64,
    rate: f64,
    output: f64,
    setup: f64,
    steps: u64,
}

fn job(bin: &Path, scene: &Path, out: &Path, threads: usize) -> Job {
    let t = Instant::now();
    let st = Command::new(bin)
        .args(["run", "--checkpoint-every", "off", "--out"])
        .arg(out)
        .arg(scene)
        .env("RAYON_NUM_THREADS", threads.to_string())
        .output()
        .expect("the fdem program starts");
    let wall = t.elapsed().as_secs_f64();
    assert!(
        st.status.success(),
        "{} failed: {}",
        bin.display(),
        String::from_utf8_lossy(&st.stderr)
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let f = |k: &str| s[k].as_f64().unwrap_or(f64::NAN);
    Job {
        wall,
        rate: f("triangle_steps_per_second"),
        output: s["timers"]["output"].as_f64().unwrap_or(f64::NAN),
        // absent from builds before the set-up timer
        setup: s["timers"]["setup"].as_f64().unwrap_or(f64::NAN),
        steps: s["steps"].as_u64().unwrap_or(0),
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    fdem_solver::problem::accuracy::median(&mut v)
}

/// The scene file of the job, written beside the bench disc's.
fn job_scene(dir: &Path) -> PathBuf {
    let file = dir.join("disc.scene.json");
    let dt = load(&file).expect("the bench disc loads").dt;
    let mut scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    // just under 300 steps of the scene's step: the run takes exactly 300
    scene["duration"] = ((STEPS - 0.1) * dt).into();
    scene["output"] = serde_json::json!({ "frames": FRAMES });
    let job = dir.join("disc-job.scene.json");
    std::fs::write(&job, scene.to_string()).unwrap();
    job
}

fn main() {
    // `cargo bench` passes `--bench`; nothing else is read from the arguments
    let rings: usize = std::env::var("RINGS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(disc::RINGS);
    let dir = disc::scene_dir_rings(rings);
    let scene = job_scene(&dir);
    let this = PathBuf::from(env!("CARGO_BIN_EXE_fdem"));
    let base = std::env::var_os("FDEM_BASE").map(PathBuf::from);
    let runs: usize = std::env::var("RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    let threads: Vec<usize> = std::env::var("THREADS")
        .unwrap_or_else(|_| "1,2".into())
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect();
    let mut programs = vec![("this", this)];
    if let Some(b) = base {
        programs.insert(0, ("base", b));
    }
    for &t in &threads {
        let mut jobs: Vec<Vec<Job>> = programs.iter().map(|_| Vec::new()).collect();
        for _ in 0..runs {
            for (k, (name, bin)) in programs.iter().enumerate() {
                let out = dir.join(format!("out-{name}"));
                jobs[k].push(job(bin, &scene, &out, t));
            }
        }
        let mut med = Vec::new();
        for ((name, _), js) in programs.iter().zip(&jobs) {
            let wall = median(js.iter().map(|j| j.wall).collect());
            let rate = median(js.iter().map(|j| j.rate).collect());
            let output = median(js.iter().map(|j| j.output).collect());
            let setup = median(js.iter().map(|j| j.setup).collect());
            let walls: Vec<String> = js.iter().map(|j| format!("{:.3}", j.wall)).collect();
            println!(
                "{name}: {t} thread(s), {} steps, {FRAMES} frames: whole job {wall:.3} s (runs {}), stepping {rate:.4e} triangle-steps/s, frames {output:.3} s, set-up {setup:.3} s",
                js[0].steps,
                walls.join(" ")
            );
            med.push((wall, rate));
        }
        if med.len() == 2 {
            println!(
                "{t} thread(s): whole job {:.2}x faster, stepping {:.2}x faster",
                med[0].0 / med[1].0,
                med[1].1 / med[0].1
            );
        }
    }
    if std::env::var_os("KEEP").is_some() {
        println!("scene kept: {}", scene.display());
    } else {
        let _ = std::fs::remove_dir_all(&dir);
    }
}
