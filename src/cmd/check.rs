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
    println!("{}", fdem_solver::run::accuracy::check_block(&predicted));
    Ok(())
}
