//! A mutation fuzzer for the three readers of user input, on stable Rust, in the test suite:
//! the Gmsh reader and the JSON mesh reader (`fdem_mesh::read_mesh_bytes`), and the scene
//! parser with everything `fdem_solver::problem::load` does after it (read the meshes, explode the
//! fracture regions, build the model, the stable step).
//!
//! Inputs are seed files of the repository (meshes/*.msh in Gmsh 2.2, 4.1 ASCII and 4.1
//! binary, examples/meshes/*.json, the example scenes with their meshes beside them) under a
//! few stacked mutations from a seeded generator: bit flips, byte replacement, inserts,
//! deletes, truncation, splices from another seed, duplicated and dropped lines, and numbers
//! replaced by extremes (`1e308`, `1e309`, `-0`, `NaN`, `inf`, `18446744073709551616`, ...).
//! Every input runs in a worker thread under `catch_unwind`: a panic is a failure, and so is
//! an input that does not answer within `FDEM_FUZZ_INPUT_SECONDS` (default 10 s; a hang).
//! A failing input is written to `target/fuzz-failures/` (a scene with its mesh) for
//! reproduction.
//!
//! `FDEM_FUZZ_SECONDS` (default 20) is the wall time of the whole run, split evenly between
//! the three targets; `FDEM_FUZZ_SEED` (default 1) seeds the generator. Run it long with
//! `FDEM_FUZZ_SECONDS=600 cargo test --release --test all -- fuzz:: --nocapture`
//! (docs/testing.md).
//!
//! The inputs kept in `tests/fuzz/regressions/<target>/` (inputs found so far and small
//! hostile inputs) are replayed by a test of their own every time. Scene regressions refer to
//! the repository's meshes by paths relative to their own folder.

use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::sync::{Mutex, Once};
use std::time::{Duration, Instant};

/// The repository root.
fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Seeds larger than this are left out (they only slow the fuzzer down).
const MAX_SEED_BYTES: u64 = 200_000;

/// The three targets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    Gmsh,
    JsonMesh,
    Scene,
}

impl Target {
    fn name(self) -> &'static str {
        match self {
            Target::Gmsh => "gmsh",
            Target::JsonMesh => "json_mesh",
            Target::Scene => "scene",
        }
    }

    fn ext(self) -> &'static str {
        match self {
            Target::Gmsh => "msh",
            Target::JsonMesh | Target::Scene => "json",
        }
    }
}

/// One seed: its bytes and, for a scene, the folder its meshes were copied into.
struct Seed {
    name: String,
    bytes: Vec<u8>,
    dir: Option<PathBuf>,
}

use crate::common::Rng;

/// Numbers put in place of a number of the input.
const EXTREMES: &[&str] = &[
    "1e308",
    "-1e308",
    "1e309",
    "-1e309",
    "1e-300",
    "5e-324",
    "-0",
    "-0.0",
    "0",
    "0.0",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "Infinity",
    "-1",
    "-2",
    "1",
    "2",
    "3",
    "4294967295",
    "4294967296",
    "2147483648",
    "-2147483649",
    "9223372036854775807",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999999",
    "1e20",
    "100000000",
    "0.5",
    "1.5e",
    "--1",
    "1e+",
    "",
];

/// Bytes put in place of or among the input's bytes.
const INTERESTING: &[u8] = b"0123456789-+.eE{}[]\",: \n\t$\\/\0\xff";

/// The numeric tokens of `b`: `(start, end)` of each run of `[-+0-9.eE]` holding a digit.
fn numbers(b: &[u8]) -> Vec<(usize, usize)> {
    let num = |c: u8| c.is_ascii_digit() || b"-+.eE".contains(&c);
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if num(b[i]) {
            let s = i;
            while i < b.len() && num(b[i]) {
                i += 1;
            }
            if b[s..i].iter().any(u8::is_ascii_digit) {
                out.push((s, i));
            }
        } else {
            i += 1;
        }
    }
    out
}

/// Start and end of each line of `b` (end excludes the newline).
fn lines(b: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut s = 0;
    for (i, &c) in b.iter().enumerate() {
        if c == b'\n' {
            out.push((s, i));
            s = i + 1;
        }
    }
    if s < b.len() {
        out.push((s, b.len()));
    }
    out
}

/// One mutation of `b` (a splice takes bytes from `other`).
fn mutate_once(b: &mut Vec<u8>, other: &[u8], rng: &mut Rng) {
    if b.is_empty() {
        b.extend_from_slice(&other[..other.len().min(64)]);
        return;
    }
    let n = b.len();
    match rng.below(12) {
        0 => {
            let i = rng.below(n);
            b[i] ^= 1 << rng.below(8);
        }
        1 => {
            let i = rng.below(n);
            b[i] = *rng.pick(INTERESTING);
        }
        2 => {
            let i = rng.below(n + 1);
            let k = 1 + rng.below(8);
            for _ in 0..k {
                let c = if rng.below(2) == 0 {
                    *rng.pick(INTERESTING)
                } else {
                    rng.next() as u8
                };
                b.insert(i, c);
            }
        }
        3 => {
            let i = rng.below(n);
            let k = (1 + rng.below(64)).min(n - i);
            b.drain(i..i + k);
        }
        4 => {
            // truncation
            b.truncate(rng.below(n));
        }
        5 if !other.is_empty() => {
            // splice a chunk of another seed
            let s = rng.below(other.len());
            let k = (1 + rng.below(256)).min(other.len() - s);
            let i = rng.below(n + 1);
            b.splice(i..i, other[s..s + k].iter().copied());
        }
        6..=8 => {
            let nums = numbers(b);
            if nums.is_empty() {
                return;
            }
            let (s, e) = *rng.pick(&nums);
            b.splice(s..e, rng.pick(EXTREMES).bytes());
        }
        9 => {
            // a line duplicated (a token repeated: a second header, a repeated key)
            let ls = lines(b);
            let (s, e) = *rng.pick(&ls);
            let copy: Vec<u8> = b[s..e].iter().copied().chain([b'\n']).collect();
            let at = rng.pick(&ls).0;
            b.splice(at..at, copy);
        }
        10 => {
            // a line dropped
            let ls = lines(b);
            let (s, e) = *rng.pick(&ls);
            b.drain(s..(e + 1).min(n));
        }
        _ => {
            // a short range duplicated in place
            let i = rng.below(n);
            let k = (1 + rng.below(32)).min(n - i);
            let copy = b[i..i + k].to_vec();
            b.splice(i..i, copy);
        }
    }
}

/// A mutated copy of `seed`: one to eight stacked mutations.
fn mutate(seed: &[u8], other: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut b = seed.to_vec();
    let k = 1 + rng.below(8);
    for _ in 0..k {
        mutate_once(&mut b, other, rng);
    }
    b
}

/// The seeds of a target. A scene's meshes are copied into a folder of its own under
/// `work` and the scene refers to them by file name.
fn seeds(target: Target, work: &Path) -> Vec<Seed> {
    let small = |p: &Path| std::fs::metadata(p).is_ok_and(|m| m.len() <= MAX_SEED_BYTES);
    let files = |dir: &str, ext: &str| -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == ext))
            .collect();
        v.sort();
        v
    };
    let named = |p: &Path, bytes: Vec<u8>, dir: Option<PathBuf>| Seed {
        name: p.file_name().unwrap().to_string_lossy().into_owned(),
        bytes,
        dir,
    };
    match target {
        Target::Gmsh => files("meshes", "msh")
            .into_iter()
            .filter(|p| small(p))
            .map(|p| named(&p, std::fs::read(&p).unwrap(), None))
            .collect(),
        Target::JsonMesh => files("examples/meshes", "json")
            .into_iter()
            .filter(|p| small(p))
            .map(|p| named(&p, std::fs::read(&p).unwrap(), None))
            .collect(),
        Target::Scene => files("examples", "json")
            .into_iter()
            .filter(|p| !p.to_string_lossy().ends_with(".study.json"))
            .map(|p| {
                let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
                let dir = work.join(format!("scene-{stem}"));
                std::fs::create_dir_all(&dir).unwrap();
                let mut v: serde_json::Value =
                    serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
                for b in v["bodies"].as_array_mut().unwrap() {
                    let m = PathBuf::from(b["mesh"].as_str().unwrap());
                    let file = m.file_name().unwrap().to_string_lossy().into_owned();
                    let target = dir.join(&file);
                    if !target.exists() {
                        std::fs::copy(root().join("examples").join(&m), &target).unwrap();
                    }
                    b["mesh"] = serde_json::Value::String(file);
                }
                let bytes = serde_json::to_vec_pretty(&v).unwrap();
                named(&p, bytes, Some(dir))
            })
            .collect(),
    }
}

thread_local! {
    static PANIC_MESSAGE: std::cell::RefCell<String> = const { std::cell::RefCell::new(String::new()) };
}

/// A panic hook that keeps the message of a panic in a fuzz worker (on the panicking thread)
/// instead of printing it: the fuzzer reports panics itself. Panics on any other thread (the
/// other tests of this binary) go to the previous hook as before.
fn quiet_panics() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            let worker = std::thread::current()
                .name()
                .is_some_and(|n| n.starts_with("fuzz-"));
            if worker {
                let msg = format!("{info}");
                PANIC_MESSAGE.with(|m| *m.borrow_mut() = msg);
            } else {
                previous(info);
            }
        }));
    });
}

/// What one input did.
#[derive(Debug)]
enum Verdict {
    /// Accepted or rejected with an error: both fine.
    Ok,
    /// A panic, with its message.
    Panic(String),
    /// No answer within the time limit.
    Hang,
}

/// Runs `target` on `input` in a worker thread under `catch_unwind`, waiting at most `limit`.
/// A scene is written to `scene.json` in `dir` (beside its meshes) and loaded from there.
fn run_input(target: Target, input: Vec<u8>, dir: Option<&Path>, limit: Duration) -> Verdict {
    let (tx, rx) = mpsc::channel();
    let dir = dir.map(Path::to_path_buf);
    let worker = std::thread::Builder::new()
        .name(format!("fuzz-{}", target.name()))
        .stack_size(64 << 20)
        .spawn(move || {
            let r = panic::catch_unwind(AssertUnwindSafe(|| match target {
                Target::Gmsh | Target::JsonMesh => {
                    let _ = fdem_mesh::read_mesh_bytes(&input, "fuzz-input");
                }
                Target::Scene => {
                    let path = dir.expect("a scene has a folder").join("scene.json");
                    std::fs::write(&path, &input).unwrap();
                    let _ = fdem_solver::load(&path);
                }
            }));
            let verdict = match r {
                Ok(()) => Verdict::Ok,
                Err(_) => Verdict::Panic(PANIC_MESSAGE.with(|m| m.borrow().clone())),
            };
            let _ = tx.send(verdict);
        })
        .expect("spawn a fuzz worker");
    match rx.recv_timeout(limit) {
        Ok(v) => {
            let _ = worker.join();
            v
        }
        // the worker is left running: the test fails and the process ends
        Err(_) => Verdict::Hang,
    }
}

/// Writes a failing input (and, for a scene, its folder's meshes) under
/// `target/fuzz-failures/` and returns the file.
fn save_failure(target: Target, seed: &Seed, input: &[u8], n: usize) -> PathBuf {
    let dir = root().join("target/fuzz-failures");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(format!(
        "{}-{}-{n}.{}",
        target.name(),
        seed.name.trim_end_matches(".json").trim_end_matches(".msh"),
        target.ext()
    ));
    std::fs::write(&file, input).unwrap();
    if let Some(src) = &seed.dir {
        for e in std::fs::read_dir(src).unwrap() {
            let p = e.unwrap().path();
            if p.file_name().is_some_and(|f| f != "scene.json") {
                let _ = std::fs::copy(&p, dir.join(p.file_name().unwrap()));
            }
        }
    }
    file
}

fn env_f64(name: &str, default: f64) -> f64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Counts of one target's run.
#[derive(Debug, Default)]
struct Tally {
    inputs: usize,
    panics: usize,
    hangs: usize,
}

/// Fuzzes `target` for `seconds` of wall time; a hang stops it at once.
fn fuzz(target: Target, seconds: f64, rng: &mut Rng, failures: &mut Vec<String>) -> Tally {
    let work = root().join("target/fuzz-work");
    let seeds = seeds(target, &work);
    assert!(!seeds.is_empty(), "no seeds for {}", target.name());
    let limit = Duration::from_secs_f64(env_f64("FDEM_FUZZ_INPUT_SECONDS", 10.0));
    let start = Instant::now();
    let mut t = Tally::default();
    // every seed once as it is, then mutated inputs
    let mut k = 0usize;
    while start.elapsed().as_secs_f64() < seconds || k < seeds.len() {
        let (seed, input) = if k < seeds.len() {
            (&seeds[k], seeds[k].bytes.clone())
        } else {
            let seed = rng.pick(&seeds);
            let other = &rng.pick(&seeds).bytes;
            (seed, mutate(&seed.bytes, other, rng))
        };
        k += 1;
        t.inputs += 1;
        match run_input(target, input.clone(), seed.dir.as_deref(), limit) {
            Verdict::Ok => {}
            Verdict::Panic(msg) => {
                t.panics += 1;
                let f = save_failure(target, seed, &input, t.inputs);
                failures.push(format!(
                    "{}: panic on {} (seed {}): {msg}",
                    target.name(),
                    f.display(),
                    seed.name
                ));
            }
            Verdict::Hang => {
                t.hangs += 1;
                let f = save_failure(target, seed, &input, t.inputs);
                failures.push(format!(
                    "{}: no answer within {:?} on {} (seed {})",
                    target.name(),
                    limit,
                    f.display(),
                    seed.name
                ));
                break;
            }
        }
    }
    println!(
        "fuzz {:<10} {:>8} inputs in {:>6.1} s ({} seeds): {} panics, {} hangs",
        target.name(),
        t.inputs,
        start.elapsed().as_secs_f64(),
        seeds.len(),
        t.panics,
        t.hangs
    );
    t
}

/// The fuzz tests share the panic hook and the work folder: one at a time.
static SERIAL: Mutex<()> = Mutex::new(());

#[test]
fn fuzz_mesh_readers_and_scene_loading_without_panics_or_hangs() {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    quiet_panics();
    let total = env_f64("FDEM_FUZZ_SECONDS", 20.0);
    let seed = env_f64("FDEM_FUZZ_SEED", 1.0) as u64;
    let mut rng = Rng(seed);
    let mut failures = Vec::new();
    let mut sum = Tally::default();
    for target in [Target::Gmsh, Target::JsonMesh, Target::Scene] {
        let t = fuzz(target, total / 3.0, &mut rng, &mut failures);
        sum.inputs += t.inputs;
        sum.panics += t.panics;
        sum.hangs += t.hangs;
        if t.hangs > 0 {
            break;
        }
    }
    println!(
        "fuzz total: {} inputs, {} panics, {} hangs (seed {seed}, {total} s)",
        sum.inputs, sum.panics, sum.hangs
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn fuzz_regressions_are_answered_without_panics_or_hangs() {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    quiet_panics();
    let limit = Duration::from_secs_f64(env_f64("FDEM_FUZZ_INPUT_SECONDS", 10.0));
    let mut failures = Vec::new();
    let mut n = 0;
    for target in [Target::Gmsh, Target::JsonMesh, Target::Scene] {
        let dir = root().join("tests/fuzz/regressions").join(target.name());
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == target.ext()))
            .collect();
        files.sort();
        assert!(!files.is_empty(), "no regressions in {}", dir.display());
        for f in files {
            let input = std::fs::read(&f).unwrap();
            n += 1;
            // A scene regression is loaded in place: its meshes are named relative to it.
            let verdict = if target == Target::Scene {
                run_scene_in_place(f.clone(), limit)
            } else {
                run_input(target, input, None, limit)
            };
            match verdict {
                Verdict::Ok => {}
                Verdict::Panic(m) => failures.push(format!("{}: panic: {m}", f.display())),
                Verdict::Hang => {
                    failures.push(format!("{}: no answer within {limit:?}", f.display()))
                }
            }
        }
    }
    println!("fuzz regressions: {n} inputs, {} failures", failures.len());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `fdem_solver::problem::load` on a scene file where it lies, in a worker thread under
/// `catch_unwind`, waiting at most `limit`.
fn run_scene_in_place(path: PathBuf, limit: Duration) -> Verdict {
    let (tx, rx) = mpsc::channel();
    std::thread::Builder::new()
        .name("fuzz-regression".into())
        .stack_size(64 << 20)
        .spawn(move || {
            let r = panic::catch_unwind(AssertUnwindSafe(|| {
                let _ = fdem_solver::load(&path);
            }));
            let _ = tx.send(match r {
                Ok(()) => Verdict::Ok,
                Err(_) => Verdict::Panic(PANIC_MESSAGE.with(|m| m.borrow().clone())),
            });
        })
        .expect("spawn a fuzz worker");
    rx.recv_timeout(limit).unwrap_or(Verdict::Hang)
}

#[test]
fn mutations_are_deterministic_and_reach_every_kind() {
    let seed = b"$Nodes\n1 2 3\n4.5 6e7 -8\n$EndNodes\n".to_vec();
    let a: Vec<Vec<u8>> = {
        let mut r = Rng(7);
        (0..50)
            .map(|_| mutate(&seed, b"{\"x\":1}", &mut r))
            .collect()
    };
    let b: Vec<Vec<u8>> = {
        let mut r = Rng(7);
        (0..50)
            .map(|_| mutate(&seed, b"{\"x\":1}", &mut r))
            .collect()
    };
    assert_eq!(a, b, "the same seed gives the same inputs");
    assert!(a.iter().any(|m| m != &seed));
    // numbers replaced by extremes appear
    let mut r = Rng(3);
    let many: Vec<Vec<u8>> = (0..2000).map(|_| mutate(&seed, b"", &mut r)).collect();
    for x in ["1e308", "NaN", "18446744073709551616", "-0"] {
        assert!(
            many.iter()
                .any(|m| m.windows(x.len()).any(|w| w == x.as_bytes())),
            "no input with {x}"
        );
    }
    assert!(
        many.iter().any(|m| m.len() < seed.len() / 2),
        "no truncation"
    );
    assert!(many.iter().any(|m| m.len() > seed.len() + 8), "no growth");
    assert_eq!(numbers(b"a 1.5e3 -2 x e"), vec![(2, 7), (8, 10)]);
}
