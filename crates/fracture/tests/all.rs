//! The integration tests of `fdem-fracture`, compiled into one test binary: each file of `tests/` is
//! a module of it (tests are named `<file>::<test>`, e.g.
//! `cargo test --release -p fdem-fracture --test all -- bar_dynamic::`). One binary links the crate
//! once instead of once per file, and its tests run in parallel with each other. A new test
//! file needs a line here (`autotests` is off in Cargo.toml, so a file missing here is not
//! compiled; the structure test's `every_test_file_is_compiled` fails while one is missing).

#[path = "common/mod.rs"]
mod common;

#[path = "bar_dynamic.rs"]
mod bar_dynamic;
#[path = "bar_mesh_time.rs"]
mod bar_mesh_time;
#[path = "bar_tension.rs"]
mod bar_tension;
#[path = "joint_pass.rs"]
mod joint_pass;
#[path = "set_threads.rs"]
mod set_threads;
#[path = "single_joint.rs"]
mod single_joint;
