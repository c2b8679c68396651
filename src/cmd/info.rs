//! `fdem info MESH`: counts, groups, sizes and quality of a mesh file.

use std::path::Path;

use anyhow::Result;

/// Prints a description of the mesh; a mesh that cannot be read is bad input (exit code 2).
pub fn info(mesh: &Path) -> Result<()> {
    println!(
        "{}",
        fdem_solver::problem::mesh_adapter::describe_file(mesh).map_err(crate::bad_input)?
    );
    Ok(())
}
