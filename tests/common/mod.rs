//! Helpers shared by the whole-solver tests: run an example scene (possibly modified) into a
//! fresh temporary folder and read its histories.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use fdem_solver::driver::{self, Outcome, RunOptions};

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A fresh, empty temporary folder named after `tag`, of its own even if another test of the
/// binary (running in parallel) asks for the same tag. Every folder of a test run lies under
/// `$TMPDIR/fdem-tests/PID`; the first call of a run removes the folders of earlier runs whose
/// process has ended, so repeated test runs do not fill the disk.
pub fn temp_dir(tag: &str) -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    static SWEPT: std::sync::Once = std::sync::Once::new();
    let runs = std::env::temp_dir().join("fdem-tests");
    SWEPT.call_once(|| remove_ended_runs(&runs));
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let d = runs
        .join(std::process::id().to_string())
        .join(format!("{tag}-{n}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Removes `runs/PID` for every PID that is not a running process (where `/proc` tells).
fn remove_ended_runs(runs: &Path) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(runs) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let ended = name
            .to_str()
            .and_then(|s| s.parse::<u32>().ok())
            .is_some_and(|pid| !Path::new("/proc").join(pid.to_string()).exists());
        if ended {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

/// Loads an example scene as JSON, applies `edit`, makes mesh paths absolute, and writes it
/// into a temporary folder; returns the new scene path.
pub fn edited_example(name: &str, tag: &str, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let src = root().join("examples").join(name);
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&src).unwrap()).unwrap();
    for b in v["bodies"].as_array_mut().unwrap() {
        let m = b["mesh"].as_str().unwrap().to_string();
        b["mesh"] =
            serde_json::Value::String(root().join("examples").join(m).display().to_string());
    }
    edit(&mut v);
    let dir = temp_dir(tag);
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    p
}

/// Runs a scene into `<scene folder>/out` and returns the outcome.
pub fn run(scene: &Path) -> (Outcome, PathBuf) {
    run_into(scene, false)
}

/// [`run`], also writing the raw JSON dump of every frame.
pub fn run_raw(scene: &Path) -> (Outcome, PathBuf) {
    run_into(scene, true)
}

fn run_into(scene: &Path, raw: bool) -> (Outcome, PathBuf) {
    let mut l = driver::load(scene).unwrap_or_else(|e| panic!("{e}"));
    let out = scene.parent().unwrap().join("out");
    let o = driver::run_outcome(
        &mut l,
        &RunOptions {
            out_dir: out.clone(),
            raw,
            ..Default::default()
        },
        &mut |_| {},
    )
    .unwrap_or_else(|e| panic!("{e}"));
    (o, out)
}

/// Reads `histories.csv`: column names and rows.
pub fn histories(out: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(out.join("histories.csv")).unwrap();
    let mut lines = text.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (head, rows)
}

/// Column `name` of the histories.
pub fn column(head: &[String], rows: &[Vec<f64>], name: &str) -> Vec<f64> {
    let i = head
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    rows.iter().map(|r| r[i]).collect()
}

/// Reference node positions of a frame.
pub fn reference_points(f: &fdem_solver::output::FrameData) -> Vec<[f64; 2]> {
    f.points
        .iter()
        .zip(&f.displacement)
        .map(|(p, u)| [p[0] - u[0], p[1] - u[1]])
        .collect()
}

/// Triangle centroids in the reference configuration.
pub fn centroids(f: &fdem_solver::output::FrameData) -> Vec<[f64; 2]> {
    let x0 = reference_points(f);
    f.triangles
        .iter()
        .map(|t| {
            let p = t.map(|i| x0[i as usize]);
            [
                (p[0][0] + p[1][0] + p[2][0]) / 3.0,
                (p[0][1] + p[1][1] + p[2][1]) / 3.0,
            ]
        })
        .collect()
}

/// Stress (sxx, syy, sxy) recovered at point `q`: a least-squares quadratic fit of the
/// triangles' constant stresses at their centroids, over the `n` centroids nearest to `q`
/// (a patch recovery in the spirit of Zienkiewicz-Zhu; exact for quadratic fields).
pub fn recovered_stress(
    f: &fdem_solver::output::FrameData,
    cen: &[[f64; 2]],
    q: [f64; 2],
    n: usize,
) -> [f64; 3] {
    let mut idx: Vec<(f64, usize)> = cen
        .iter()
        .enumerate()
        .map(|(i, c)| ((c[0] - q[0]).powi(2) + (c[1] - q[1]).powi(2), i))
        .collect();
    idx.select_nth_unstable_by(n, |a, b| a.0.total_cmp(&b.0));
    let near = &idx[..n];
    let scale = near.iter().map(|p| p.0).fold(0.0, f64::max).sqrt();
    let mut out = [0.0; 3];
    for comp in 0..3 {
        let mut ata = [[0.0; 6]; 6];
        let mut atb = [0.0; 6];
        for &(_, i) in near {
            let (x, y) = ((cen[i][0] - q[0]) / scale, (cen[i][1] - q[1]) / scale);
            let row = [1.0, x, y, x * x, x * y, y * y];
            for r in 0..6 {
                for c in 0..6 {
                    ata[r][c] += row[r] * row[c];
                }
                atb[r] += row[r] * f.stress[i][comp];
            }
        }
        // Gaussian elimination with partial pivoting.
        for p in 0..6 {
            let piv = (p..6)
                .max_by(|a, b| ata[*a][p].abs().total_cmp(&ata[*b][p].abs()))
                .unwrap();
            ata.swap(p, piv);
            atb.swap(p, piv);
            for r in p + 1..6 {
                let l = ata[r][p] / ata[p][p];
                for c in p..6 {
                    ata[r][c] -= l * ata[p][c];
                }
                atb[r] -= l * atb[p];
            }
        }
        let mut sol = [0.0; 6];
        for r in (0..6).rev() {
            let s: f64 = (r + 1..6).map(|c| ata[r][c] * sol[c]).sum();
            sol[r] = (atb[r] - s) / ata[r][r];
        }
        out[comp] = sol[0];
    }
    out
}

/// The loading of [`diagonal_pair_scene`].
#[derive(Debug, Clone, Copy)]
pub struct PairScene {
    /// Joint penalty, normal and tangential [Pa].
    pub penalty: f64,
    /// Platen speed [m/s].
    pub speed: f64,
    /// Ramp of the platen speed [s].
    pub ramp: f64,
    /// Safety factor on the automatic step.
    pub safety: f64,
    /// Duration [s].
    pub duration: f64,
    /// Frames written.
    pub frames: u32,
    /// History rows every this many steps.
    pub every: u32,
}

/// Two triangles (a 10 mm square cut along its diagonal) bonded by one joint, between a fixed
/// frictionless floor and a frictionless platen moving down at `speed` (ramped over `ramp`):
/// the diagonal fails in shear under compression at `sigma = 2 c/(1 - tan(phi))` = 4.73 MPa
/// and the two wedges slide apart. Fully damaged, the joint stays closed (compression only,
/// no friction) while the wedges slide, and breaks when it opens (or has slid by a tenth of
/// its length): contact takes over.
pub fn diagonal_pair_scene(tag: &str, s: &PairScene) -> PathBuf {
    let PairScene {
        penalty,
        speed,
        ramp,
        safety,
        duration,
        frames,
        every,
    } = *s;
    let dir = temp_dir(tag);
    let l = 0.01;
    let mesh = serde_json::json!({
        "nodes": [[0.0, 0.0], [l, 0.0], [l, l], [0.0, l]],
        "triangles": [[0, 1, 2], [0, 2, 3]],
    });
    std::fs::write(dir.join("pair.json"), mesh.to_string()).unwrap();
    let scene = serde_json::json!({
        "title": "two triangles, one diagonal joint, in compression",
        "bodies": [{
            "name": "pair",
            "mesh": dir.join("pair.json").display().to_string(),
            "materials": { "*": { "young": 30e9, "poisson": 0.2, "density": 2500.0, "plane": "stress" } },
            "thickness": 0.01
        }],
        "fracture": {
            "regions": [ { "body": "pair" } ],
            "material": {
                "tensile_strength": 3e6, "cohesion": 1e6, "friction_angle_deg": 30.0,
                "fracture_energy_i": 10.0, "fracture_energy_ii": 10.0,
                "penalty_normal": penalty, "penalty_tangential": penalty
            }
        },
        "contact": {
            "walls": [
                { "name": "top", "point": [0.0, l], "normal": [0.0, -1.0], "velocity": [0.0, -speed], "ramp": ramp },
                { "name": "bottom", "point": [0.0, 0.0], "normal": [0.0, 1.0] }
            ]
        },
        "integrator": { "scheme": "central-difference", "time_step": "auto", "safety": safety },
        "duration": duration,
        "output": { "frames": frames },
        "histories": { "every": every, "probes": [ "energy" ] }
    });
    let p = dir.join("pair.scene.json");
    std::fs::write(&p, scene.to_string()).unwrap();
    p
}

/// A structured `nx` x `ny`-cell rectangle `[0, lx] x [0, ly]`, each cell cut into two CCW
/// triangles along its rising diagonal: nodes (row by row from the bottom) and triangles, with
/// `id(i, j) = j (nx + 1) + i` the node of column `i`, row `j`.
pub fn structured_rectangle(
    nx: usize,
    ny: usize,
    lx: f64,
    ly: f64,
) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut nodes = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            nodes.push([lx * i as f64 / nx as f64, ly * j as f64 / ny as f64]);
        }
    }
    let mut tris = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (nodes, tris)
}

/// Writes `block.json` into `dir` (an `n` x `n`-cell square of side `l`, group `b`) and returns
/// the `bodies` of two such blocks (E = 10 GPa, nu = 0.25, rho = 2500, plane strain), the
/// second one offset by `gap_x` along x: the pressed-blocks contact scenes.
pub fn two_blocks(dir: &Path, n: usize, l: f64, gap_x: f64) -> serde_json::Value {
    let (nodes, tris) = structured_rectangle(n, n, l, l);
    let mesh = serde_json::json!({
        "nodes": nodes, "triangles": tris,
        "groups": [{"name": "b", "dim": 2, "triangles": (0..tris.len()).collect::<Vec<_>>()}]
    });
    std::fs::write(dir.join("block.json"), mesh.to_string()).unwrap();
    let mat = serde_json::json!({ "b": { "young": 10e9, "poisson": 0.25, "density": 2500.0, "plane": "strain" } });
    serde_json::json!([
        { "name": "left", "mesh": "block.json", "materials": mat },
        { "name": "right", "mesh": "block.json", "materials": mat, "offset": [gap_x, 0.0] }
    ])
}

/// Writes a structured `nx` x `ny` rectangle `lx` x `ly` (surface group `rock`, edge groups
/// `left`, `right`, `bottom`, `top`) as `rect.json` into `dir`.
pub fn rectangle_with_sides(dir: &Path, nx: usize, ny: usize, lx: f64, ly: f64) {
    let (nodes, tris) = structured_rectangle(nx, ny, lx, ly);
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let bottom: Vec<[u32; 2]> = (0..nx).map(|i| [id(i, 0), id(i + 1, 0)]).collect();
    let top: Vec<[u32; 2]> = (0..nx).map(|i| [id(i + 1, ny), id(i, ny)]).collect();
    let left: Vec<[u32; 2]> = (0..ny).map(|j| [id(0, j + 1), id(0, j)]).collect();
    let right: Vec<[u32; 2]> = (0..ny).map(|j| [id(nx, j), id(nx, j + 1)]).collect();
    let mesh = serde_json::json!({
        "nodes": nodes, "triangles": tris,
        "groups": [
            {"name": "rock", "dim": 2, "triangles": (0..tris.len()).collect::<Vec<_>>()},
            {"name": "bottom", "dim": 1, "edges": bottom},
            {"name": "top", "dim": 1, "edges": top},
            {"name": "left", "dim": 1, "edges": left},
            {"name": "right", "dim": 1, "edges": right}
        ]
    });
    std::fs::write(dir.join("rect.json"), mesh.to_string()).unwrap();
}

/// Tractions `sigma n` of the uniform stress `s = [sxx, syy, sxy]` on the four sides of
/// [`rectangle_with_sides`] (outward normals +x, -x, +y, -y): a body in that stress is then in
/// equilibrium.
pub fn matching_tractions(s: [f64; 3]) -> Vec<serde_json::Value> {
    vec![
        serde_json::json!({"traction": {"group": "right", "value": [s[0], s[2]]}}),
        serde_json::json!({"traction": {"group": "left", "value": [-s[0], -s[2]]}}),
        serde_json::json!({"traction": {"group": "top", "value": [s[2], s[1]]}}),
        serde_json::json!({"traction": {"group": "bottom", "value": [-s[2], -s[1]]}}),
    ]
}

/// The bits of the last frame's displacements and velocities: equal for two runs that are
/// the same run bit for bit (threads, resumes).
pub fn state_bits(o: &fdem_solver::driver::Outcome) -> Vec<u64> {
    o.last_frame
        .displacement
        .iter()
        .chain(&o.last_frame.velocity)
        .flat_map(|d| [d[0].to_bits(), d[1].to_bits()])
        .collect()
}

/// A small deterministic generator (splitmix64), for the fuzzers.
pub struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    /// An element of `v` (not empty).
    pub fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

/// Runs `fdem ARGS`; returns (exit code, -1 for a signal; stdout; stderr).
pub fn fdem(args: &[&std::ffi::OsStr]) -> (i32, String, String) {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_fdem"))
        .args(args)
        .output()
        .unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// `fdem run SCENE --out OUT` ([`fdem`]).
pub fn fdem_run(scene: &Path, out: &Path) -> (i32, String, String) {
    fdem(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ])
}

/// Runs `cmd` with stdout discarded, killed after `limit`: `Some((exit code, stderr))`, the
/// code `None` when a signal ended it; `None` when it was killed at the limit.
pub fn run_limited(
    cmd: &mut std::process::Command,
    limit: std::time::Duration,
) -> Option<(Option<i32>, String)> {
    use std::io::Read;
    let mut child = cmd
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    // stderr read on a thread of its own: a child that writes much never blocks on the pipe
    let mut pipe = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut err = String::new();
        let _ = pipe.read_to_string(&mut err);
        err
    });
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return Some((status.code(), reader.join().unwrap_or_default()));
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}

/// Every file of a folder with its bytes.
pub fn snapshot(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .map(|n| (n.clone(), std::fs::read(dir.join(&n)).unwrap()))
        .collect()
}
