//! The integration tests of `fdem-mesh`, compiled into one test binary: each file of `tests/` is
//! a module of it (tests are named `<file>::<test>`, e.g.
//! `cargo test --release -p fdem-mesh --test all -- bad_meshes::`). One binary links the crate
//! once instead of once per file, and its tests run in parallel with each other. A new test
//! file needs a line here (`autotests` is off in Cargo.toml, so a file missing here is not
//! compiled; the structure test's `every_test_file_is_compiled` fails while one is missing).
//!
//! `no_allocation.rs` is a binary of its own (a `[[test]]` in Cargo.toml): its counting
//! global allocator sees every thread of the process, so no other test may run beside it.

#[path = "common/mod.rs"]
mod common;

#[path = "bad_meshes.rs"]
mod bad_meshes;
#[path = "explode.rs"]
mod explode;
#[path = "initial_stress.rs"]
mod initial_stress;
#[path = "kinematics.rs"]
mod kinematics;
#[path = "meshes.rs"]
mod meshes;
#[path = "outputs.rs"]
mod outputs;
#[path = "parallel_build.rs"]
mod parallel_build;
#[path = "static_validation.rs"]
mod static_validation;
#[path = "stiffness_frequency.rs"]
mod stiffness_frequency;
