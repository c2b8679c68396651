//! The builds of fdem share their compiled libraries: the main job (`cargo run --release`, the
//! root package alone), the test command's build (`cargo test --workspace`, every member with
//! its dev-dependencies), the Python package's (maturin builds `fdem-python` alone) and the
//! MPI build (the root package with the `mpi` feature) turn on the same features of every
//! library they have in common, so that none of them compiles that library, and everything
//! above it (serde's derive, serde_json, the solver, ...), a second time. Known answer:
//! `cargo tree`'s feature sets of each library, one build's contained in the other's (a build
//! may add libraries of its own, such as the host-side libraries of the MPI bindings).

use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

/// Each library of one build (`name version`) with its feature sets as `cargo tree` prints
/// them (one set per distinct compiled unit: host and target may differ).
fn feature_sets(args: &[&str]) -> BTreeMap<String, BTreeSet<String>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let o = Command::new(cargo)
        .current_dir(crate::common::root())
        .args(["tree", "--locked", "--prefix", "none", "-f", "{p} [{f}]"])
        .args(args)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "cargo tree {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let mut sets: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for line in String::from_utf8(o.stdout).unwrap().lines() {
        let line = line.trim_end_matches(" (*)");
        let Some((package, features)) = line.rsplit_once(" [") else {
            continue;
        };
        let mut words = package.split_whitespace();
        let (Some(name), Some(version)) = (words.next(), words.next()) else {
            continue;
        };
        sets.entry(format!("{name} {version}"))
            .or_default()
            .insert(features.trim_end_matches(']').to_string());
    }
    sets
}

/// The libraries whose feature sets differ between the two builds (neither build's sets
/// contained in the other's), but for the packages named in `own` (whose features the build
/// turns on itself).
fn differing(
    a: &BTreeMap<String, BTreeSet<String>>,
    b: &BTreeMap<String, BTreeSet<String>>,
    own: &[&str],
) -> Vec<String> {
    a.iter()
        .filter(|(lib, _)| !own.iter().any(|p| lib.split(' ').next() == Some(*p)))
        .filter_map(|(lib, fa)| {
            let fb = b.get(lib)?;
            (!fa.is_subset(fb) && !fb.is_subset(fa))
                .then(|| format!("{lib}: {fa:?} against {fb:?}"))
        })
        .collect()
}

/// The main job, the test command's build, the Python package's and the MPI build turn on
/// the same features of every library they share (the dependencies of the root package and of
/// `crates/python` that no code uses are there for it).
#[test]
fn the_main_job_test_python_and_mpi_builds_turn_on_the_same_features_of_shared_libraries() {
    let main = feature_sets(&["-p", "fdem", "-e", "normal,build"]);
    assert!(
        main.keys().any(|k| k.starts_with("serde_json ")),
        "{main:?}"
    );
    let none: &[&str] = &[];
    for (build, args, own) in [
        (
            "the test command's",
            &["--workspace", "-e", "normal,build,dev"][..],
            none,
        ),
        (
            "the Python package's",
            &["-p", "fdem-python", "-e", "normal,build"],
            none,
        ),
        (
            "the MPI",
            &["-p", "fdem", "--features", "mpi", "-e", "normal,build"],
            &["fdem", "fdem-mpi"],
        ),
    ] {
        let other = feature_sets(args);
        let d = differing(&main, &other, own);
        assert!(
            d.is_empty(),
            "{build} build turns on other features than the main job's (`cargo run --release`) \
             of these libraries, and so compiles them and all above them again: {d:#?}\n  fix: \
             turn the same features on in the root Cargo.toml's (and crates/python's) unused \
             dependencies"
        );
    }
}
