//! The integration tests of `fdem-time`, compiled into one test binary: each file of `tests/` is
//! a module of it (tests are named `<file>::<test>`, e.g.
//! `cargo test --release -p fdem-time --test all -- active::`). One binary links the crate
//! once instead of once per file, and its tests run in parallel with each other. A new test
//! file needs a line here (`autotests` is off in Cargo.toml, so a file missing here is not
//! compiled; the structure test's `every_test_file_is_compiled` fails while one is missing).

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
