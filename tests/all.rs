//! The whole-solver tests of the `fdem` package, compiled into one test binary: each file of
//! `tests/` is a module of it (tests are named `<file>::<test>`, e.g.
//! `cargo test --release --test all -- cantilever::`). One binary links the solver once instead
//! of once per file, and its tests run in parallel with each other. The shared helpers are in
//! `tests/common/mod.rs`. A new test file under `tests/` needs a line here (and `autotests` is
//! off in Cargo.toml, so a file missing here is not compiled).

#[path = "common/mod.rs"]
mod common;

/// The binary's plotting (`fracture_scenes` draws with it).
#[path = "../src/plot.rs"]
#[allow(dead_code, missing_docs)]
mod plot;

/// The binary's atomic write, which `plot.rs` calls (temporary file, then rename).
fn write_atomically(path: &std::path::Path, bytes: &[u8]) -> anyhow::Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".part");
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path)?;
    Ok(())
}

#[path = "accuracy.rs"]
mod accuracy;
#[path = "adaptive_step.rs"]
mod adaptive_step;
#[path = "bar_pulse.rs"]
mod bar_pulse;
#[path = "block_compression.rs"]
mod block_compression;
#[path = "build_units.rs"]
mod build_units;
#[path = "bulk_heterogeneity.rs"]
mod bulk_heterogeneity;
#[path = "cantilever.rs"]
mod cantilever;
#[path = "contact_scenes.rs"]
mod contact_scenes;
#[path = "cracks.rs"]
mod cracks;
#[path = "disc_relaxation.rs"]
mod disc_relaxation;
#[path = "distributed.rs"]
mod distributed;
#[path = "extremes.rs"]
mod extremes;
#[path = "fluid.rs"]
mod fluid;
#[path = "fracture_extremes.rs"]
mod fracture_extremes;
#[path = "fracture_restart.rs"]
mod fracture_restart;
#[path = "fracture_scenes.rs"]
mod fracture_scenes;
#[path = "fracture_specimens.rs"]
mod fracture_specimens;
#[path = "fuzz.rs"]
mod fuzz;
#[path = "histories.rs"]
mod histories;
#[path = "initial_stress.rs"]
mod initial_stress;
#[path = "joint_materials.rs"]
mod joint_materials;
#[path = "malformed_scenes.rs"]
mod malformed_scenes;
#[path = "nodal_stress.rs"]
mod nodal_stress;
#[path = "oracle.rs"]
mod oracle;
#[path = "output_arrays.rs"]
mod output_arrays;
#[path = "parity.rs"]
mod parity;
#[path = "prestressed_joints.rs"]
mod prestressed_joints;
#[path = "quasi_static.rs"]
mod quasi_static;
#[path = "relaxation_cg.rs"]
mod relaxation_cg;
#[path = "relaxation_masses.rs"]
mod relaxation_masses;
#[path = "relaxation_methods.rs"]
mod relaxation_methods;
#[path = "restart.rs"]
mod restart;
#[path = "setup_threads.rs"]
mod setup_threads;
#[path = "stable_step_bounds.rs"]
mod stable_step_bounds;
#[path = "stress_fields.rs"]
mod stress_fields;
#[path = "study_oscillator.rs"]
mod study_oscillator;
#[path = "study_scene.rs"]
mod study_scene;
#[path = "trust_energy.rs"]
mod trust_energy;
#[path = "trust_exits.rs"]
mod trust_exits;
#[path = "trust_input.rs"]
mod trust_input;
#[path = "trust_names.rs"]
mod trust_names;
#[path = "trust_output.rs"]
mod trust_output;
#[path = "trust_resume.rs"]
mod trust_resume;
#[path = "trust_rules.rs"]
mod trust_rules;
#[path = "velocity_dependence.rs"]
mod velocity_dependence;

/// Every `.rs` file directly under `tests/` is a module of this binary: with `autotests` off,
/// a file left out here would silently never run.
#[test]
fn every_test_file_is_a_module_of_this_binary() {
    let dir = common::root().join("tests");
    let this = std::fs::read_to_string(dir.join("all.rs")).unwrap();
    for e in std::fs::read_dir(&dir).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        if name.ends_with(".rs") && name != "all.rs" {
            assert!(
                this.contains(&format!("#[path = \"{name}\"]")),
                "tests/{name} is not a module of tests/all.rs"
            );
        }
    }
}
