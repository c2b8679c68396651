//! The integration tests of `fdem-time`, compiled into one test binary: each file of `tests/` is
//! a module of it (tests are named `<file>::<test>`, e.g.
//! `cargo test --release -p fdem-time --test all -- active::`). One binary links the crate
//! once instead of once per file, and its tests run in parallel with each other. A new test
//! file needs a line here (`autotests` is off in Cargo.toml, so a file missing here is not
//! compiled; `every_test_file_is_compiled` fails while one is missing).

#[path = "active.rs"]
mod active;
#[path = "constraints.rs"]
mod constraints;
#[path = "convergence.rs"]
mod convergence;
#[path = "damping.rs"]
mod damping;
#[path = "energy.rs"]
mod energy;
#[path = "parallel.rs"]
mod parallel;
#[path = "restore.rs"]
mod restore;
#[path = "rigid_rotation.rs"]
mod rigid_rotation;
#[path = "stability.rs"]
mod stability;

/// Every `.rs` file directly under `tests/` is a module of this binary or a test binary of
/// its own in Cargo.toml: with `autotests` off, a file left out of both would silently never
/// run.
#[test]
fn every_test_file_is_compiled() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let this = std::fs::read_to_string(root.join("tests/all.rs")).unwrap();
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap();
    for e in std::fs::read_dir(root.join("tests")).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        if name.ends_with(".rs") && name != "all.rs" {
            assert!(
                this.contains(&format!("#[path = \"{name}\"]"))
                    || manifest.contains(&format!("path = \"tests/{name}\"")),
                "tests/{name} is neither a module of tests/all.rs nor a [[test]] of Cargo.toml"
            );
        }
    }
}
