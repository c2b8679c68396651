//! `fdem check SCENE`: validates a scene and reports the mesh, the stable time step of each
//! scheme and the estimated run time, without writing anything.

use std::path::Path;

use anyhow::Result;
use fdem_solver::driver;

/// Validates the scene and prints the report.
pub fn check(scene: &Path) -> Result<()> {
    let loaded = driver::load(scene)?;
    println!("{}", loaded.describe());
    println!("{}", driver::check_report(&loaded));
    let predicted = fdem_solver::run::accuracy::before_run(&loaded);
    let warnings = predicted.iter().filter(|i| !i.passes()).count();
    println!(
        "accuracy before the run: {warnings} warning{} (a run reports these again with what it measures){}",
        if warnings == 1 { "" } else { "s" },
        fdem_solver::problem::indicator::describe(&predicted)
    );
    Ok(())
}
