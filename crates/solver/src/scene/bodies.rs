//! The bodies of a scene: each a mesh, a material per physical surface group, a thickness,
//! an initial velocity and an offset.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::SceneError;

/// One deformable body: a mesh and a material for each of its physical surface groups.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// Name used by boundary conditions when a scene has several bodies.
    #[serde(default)]
    pub name: Option<String>,
    /// Mesh file (Gmsh `.msh` or fdem JSON mesh), relative to the scene file.
    pub mesh: PathBuf,
    /// Material of each physical surface group, by group name. The key `"*"` applies to every
    /// triangle whose group has no entry of its own.
    pub materials: BTreeMap<String, MaterialSpec>,
    /// Out-of-plane thickness [m] (default 1), in plane stress and plane strain alike: forces,
    /// masses and energies are those of a slab this thick.
    #[serde(default = "one")]
    pub thickness: f64,
    /// Initial velocity of every node [m/s] (default zero).
    #[serde(default)]
    pub initial_velocity: [f64; 2],
    /// Rigid offset added to the mesh coordinates [m] (default zero).
    #[serde(default)]
    pub offset: [f64; 2],
}

fn one() -> f64 {
    1.0
}

/// Material law of a region.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Law {
    /// Munjiza's objective linear law (small strain, finite rotation).
    #[default]
    LinearElastic,
    /// Compressible neo-Hookean law (large strain).
    NeoHookean,
}

/// Plane stress or plane strain.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Plane {
    /// Thin plate: sigma_zz = 0.
    #[default]
    Stress,
    /// Long body: eps_zz = 0.
    Strain,
}

/// Elastic (and viscous) constants of a region.
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Material law (default `linear-elastic`).
    #[serde(default)]
    pub law: Law,
    /// Young's modulus E [Pa], > 0.
    pub young: f64,
    /// Poisson's ratio nu, in [0, 0.5).
    pub poisson: f64,
    /// Density rho [kg/m^3], > 0.
    pub density: f64,
    /// Plane stress or plane strain (default `stress`).
    #[serde(default)]
    pub plane: Plane,
}

/// Checks the values of the bodies that the JSON types cannot (at least one body, positive
/// constants); `file` names the scene in errors.
pub(crate) fn validate(bodies: &[Body], file: &Path) -> Result<(), SceneError> {
    let bad =
        |path: String, message: String, fix: &str| SceneError::invalid(file, path, message, fix);
    if bodies.is_empty() {
        return Err(bad(
            "bodies".into(),
            "the scene has no body".into(),
            "add at least one body with a mesh and materials",
        ));
    }
    for (i, b) in bodies.iter().enumerate() {
        if b.materials.is_empty() {
            return Err(bad(
                format!("bodies[{i}].materials"),
                "no material given".into(),
                "give a material per physical surface group, or one under \"*\"",
            ));
        }
        if !(b.thickness > 0.0 && b.thickness.is_finite()) {
            return Err(bad(
                format!("bodies[{i}].thickness"),
                format!("thickness {} is not positive", b.thickness),
                "set a positive thickness in metres",
            ));
        }
        for (g, m) in &b.materials {
            let p = format!("bodies[{i}].materials.{g}");
            if !(m.young > 0.0 && m.young.is_finite()) {
                return Err(bad(
                    format!("{p}.young"),
                    format!("Young's modulus {} is not positive", m.young),
                    "set young to a positive value in Pa",
                ));
            }
            if !(m.density > 0.0 && m.density.is_finite()) {
                return Err(bad(
                    format!("{p}.density"),
                    format!("density {} is not positive", m.density),
                    "set density to a positive value in kg/m^3",
                ));
            }
            if !(0.0..0.5).contains(&m.poisson) {
                return Err(bad(
                    format!("{p}.poisson"),
                    format!("Poisson's ratio {} is outside [0, 0.5)", m.poisson),
                    "set poisson in [0, 0.5)",
                ));
            }
        }
    }
    Ok(())
}
