//! The integration tests of `fdem-contact`, compiled into one test binary: each file of `tests/` is
//! a module of it (tests are named `<file>::<test>`, e.g.
//! `cargo test --release -p fdem-contact --test all -- detection::`). One binary links the crate
//! once instead of once per file, and its tests run in parallel with each other. A new test
//! file needs a line here (`autotests` is off in Cargo.toml, so a file missing here is not
//! compiled; the structure test's `every_test_file_is_compiled` fails while one is missing).
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
