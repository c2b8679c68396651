//! The integration tests of `fdem-contact`, compiled into one test binary: each file of `tests/` is
//! a module of it (tests are named `<file>::<test>`, e.g.
//! `cargo test --release -p fdem-contact --test all -- detection::`). One binary links the crate
//! once instead of once per file, and its tests run in parallel with each other. A new test
//! file needs a line here (`autotests` is off in Cargo.toml, so a file missing here is not
//! compiled; `every_test_file_is_compiled` fails while one is missing).
//!
//! `no_allocation.rs` is a binary of its own (a `[[test]]` in Cargo.toml): its counting
//! global allocator sees every thread of the process, so no other test may run beside it.

#[path = "common/mod.rs"]
mod common;

#[path = "detection.rs"]
mod detection;
#[path = "hertz.rs"]
mod hertz;
#[path = "model.rs"]
mod model;
#[path = "potential.rs"]
mod potential;
#[path = "release.rs"]
mod release;
#[path = "rigid_block.rs"]
mod rigid_block;
#[path = "rigid_collision.rs"]
mod rigid_collision;
#[path = "scenes.rs"]
mod scenes;
#[path = "snapshot.rs"]
mod snapshot;

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
