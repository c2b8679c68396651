//! The bodies of a scene: each a mesh, a material per physical surface group, a thickness,
//! an initial velocity and an offset.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use fdem_fracture::Distribution;
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
    /// Young's modulus E [Pa], > 0. Absent (read as NaN) when `heterogeneity` draws it per
    /// triangle: exactly one of the two is given.
    #[serde(default = "absent", skip_serializing_if = "is_absent")]
    pub young: f64,
    /// Poisson's ratio nu, in [0, 0.5).
    pub poisson: f64,
    /// Density rho [kg/m^3], > 0.
    pub density: f64,
    /// Plane stress or plane strain (default `stress`).
    #[serde(default)]
    pub plane: Plane,
    /// Young's modulus drawn per triangle (default none: every triangle of the group has
    /// `young`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heterogeneity: Option<BulkHeterogeneity>,
}

fn absent() -> f64 {
    f64::NAN
}

fn is_absent(x: &f64) -> bool {
    x.is_nan()
}

/// The stream of the per-triangle Young's modulus in the field of a seed
/// (`fdem_fracture::heterogeneity::stream_seed`): apart from the joints' streams 0-3, so one
/// seed used for both gives independent fields.
pub const YOUNG_STREAM: u64 = 16;

/// The bulk constants drawn per triangle. In JSON (`deny_unknown_fields`): `{"seed": 7,
/// "young": {"weibull": {"modulus": 8, "scale": 30e9}}}` (or `normal` / `lognormal`, as the
/// joints' heterogeneity).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BulkHeterogeneity {
    /// Seed of the field (the same seed, the same values on any number of threads).
    pub seed: u64,
    /// Distribution of Young's modulus E [Pa].
    pub young: Distribution,
}

impl BulkHeterogeneity {
    /// Young's modulus of the triangle with global index `triangle` in the model (all
    /// bodies' triangles in scene order): the draw of `(seed, triangle)` on [`YOUNG_STREAM`].
    pub fn young(&self, triangle: u64) -> f64 {
        let seed = fdem_fracture::heterogeneity::stream_seed(self.seed, YOUNG_STREAM);
        self.young.sample(seed, triangle)
    }
}

impl MaterialSpec {
    /// The material of the triangle with global index `triangle`: `self` with Young's modulus
    /// drawn when the material has a heterogeneity (and no heterogeneity left).
    pub fn row(&self, triangle: u64) -> MaterialSpec {
        match &self.heterogeneity {
            Some(h) => MaterialSpec {
                young: h.young(triangle),
                heterogeneity: None,
                ..*self
            },
            None => *self,
        }
    }

    /// Checks Young's modulus at `p` (`bodies[i].materials.GROUP`): given and positive, or
    /// drawn from a valid distribution (exactly one of the two).
    fn validate_young(&self, file: &Path, p: &str) -> Result<(), SceneError> {
        let bad = |path: String, message: String, fix: String| {
            SceneError::invalid(file, path, message, fix)
        };
        match (&self.heterogeneity, self.young.is_nan()) {
            (None, true) => Err(bad(
                p.into(),
                "missing field `young`".into(),
                format!(
                    "add \"young\": <value in Pa>, or draw it per triangle under \
                     {p}.heterogeneity.young"
                ),
            )),
            (Some(_), false) => Err(bad(
                format!("{p}.young"),
                format!("`young` is given a value and also drawn by {p}.heterogeneity.young"),
                format!("remove {p}.young or {p}.heterogeneity"),
            )),
            (Some(h), true) => h.young.validate().map_err(|e| {
                let sub = match &e {
                    fdem_fracture::FractureError::InvalidDistribution { field, .. } => {
                        format!(".{field}")
                    }
                    _ => String::new(),
                };
                bad(
                    format!("{p}.heterogeneity.young.{}{sub}", h.young.law()),
                    e.to_string(),
                    "give every parameter of the distribution a positive finite value".into(),
                )
            }),
            (None, false) if !(self.young > 0.0 && self.young.is_finite()) => Err(bad(
                format!("{p}.young"),
                format!("Young's modulus {} is not positive", self.young),
                "set young to a positive value in Pa".into(),
            )),
            (None, false) => Ok(()),
        }
    }
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
            m.validate_young(file, &p)?;
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
