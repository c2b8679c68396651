//! The optional `"initial_stress"` list: the in-situ stress of bodies or of surface groups of
//! a body's mesh at the start of the run, uniform or growing linearly with depth. Each entry
//! names its body (optional when the scene has one) and surface groups (default: the whole
//! body); where entries overlap their stresses add. `crate::problem::prestress` turns the list into
//! one stress per triangle.
//!
//! Stresses are Cauchy stresses of the reference state, `[sxx, syy, sxy]` [Pa], tension
//! positive (compression, as in the ground, is negative).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::SceneError;

/// One entry of `"initial_stress"`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct InitialStress {
    /// Body name (needed when the scene has several bodies and no `groups` name one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body: Option<String>,
    /// Surface groups of the body's mesh (default: every triangle of the body).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub groups: Option<Vec<String>>,
    /// A uniform stress `[sxx, syy, sxy]` [Pa], tension positive.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uniform: Option<[f64; 3]>,
    /// A stress growing linearly with depth below a level surface.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<GravityStress>,
}

/// The geostatic stress `syy = -rho g (surface_y - y)`, `sxx = k0 syy`, `sxy = 0`, evaluated
/// at each triangle's reference centroid (the exact mean of the linear field over the
/// triangle).
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GravityStress {
    /// The level of the ground surface, where the stress is zero [m], in the scene's
    /// coordinates (after the body's offset). No node of the entry's triangles may lie above it.
    pub surface_y: f64,
    /// Density of the overburden [kg/m^3] (default: each triangle's own material density).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Gravity acceleration [m/s^2], pointing in -y (>= 0).
    pub g: f64,
    /// Ratio of the horizontal to the vertical stress, `sxx / syy` (>= 0).
    pub k0: f64,
}

/// Checks the values the JSON types cannot: one of `uniform` or `gravity`, finite numbers,
/// `g >= 0`, `k0 >= 0`, a positive density, a non-empty group list.
pub(crate) fn validate(entries: &[InitialStress], file: &Path) -> Result<(), SceneError> {
    let bad =
        |path: String, message: String, fix: &str| SceneError::invalid(file, path, message, fix);
    for (i, e) in entries.iter().enumerate() {
        let p = format!("initial_stress[{i}]");
        match (&e.uniform, &e.gravity) {
            (Some(_), Some(_)) | (None, None) => {
                return Err(bad(
                    p,
                    "an initial stress entry needs exactly one of \"uniform\" and \"gravity\""
                        .into(),
                    "give \"uniform\": [sxx, syy, sxy] (Pa) or \"gravity\": {\"surface_y\", \"g\", \"k0\"}; use two entries to add both",
                ));
            }
            (Some(u), None) => {
                for (k, v) in u.iter().enumerate() {
                    if !v.is_finite() {
                        return Err(bad(
                            format!("{p}.uniform[{k}]"),
                            format!("the stress component {v} is not finite"),
                            "give a finite stress in Pa (tension positive)",
                        ));
                    }
                }
            }
            (None, Some(g)) => {
                let gp = format!("{p}.gravity");
                if !g.surface_y.is_finite() {
                    return Err(bad(
                        format!("{gp}.surface_y"),
                        format!("surface_y {} is not finite", g.surface_y),
                        "give the level of the ground surface in m",
                    ));
                }
                if !(g.g.is_finite() && g.g >= 0.0) {
                    return Err(bad(
                        format!("{gp}.g"),
                        format!("g {} is negative or not finite", g.g),
                        "give the magnitude of gravity in m/s^2 (it points in -y), e.g. 9.81",
                    ));
                }
                if !(g.k0.is_finite() && g.k0 >= 0.0) {
                    return Err(bad(
                        format!("{gp}.k0"),
                        format!("k0 {} is negative or not finite", g.k0),
                        "give the ratio of horizontal to vertical stress, >= 0 (e.g. nu/(1-nu) for a laterally confined elastic ground)",
                    ));
                }
                if let Some(d) = g.density
                    && !(d.is_finite() && d > 0.0)
                {
                    return Err(bad(
                        format!("{gp}.density"),
                        format!("density {d} is not positive"),
                        "give the overburden density in kg/m^3, or leave it out to use each triangle's material density",
                    ));
                }
            }
        }
        if let Some(gs) = &e.groups
            && gs.is_empty()
        {
            return Err(bad(
                format!("{p}.groups"),
                "the group list is empty".into(),
                "name surface groups of the body's mesh, or leave \"groups\" out for the whole body",
            ));
        }
    }
    Ok(())
}
