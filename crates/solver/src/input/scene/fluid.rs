//! The optional `"fluid"` section: a fluid in the crack network of the fracturing bodies
//! (`fdem_flow`): its properties, the apertures' bounds, Carter's leak-off, how the pressure
//! is stepped, the injections and the prescribed pressures. The load resolves the injection
//! points and the pressure groups to joints (`crate::problem::fluid`).

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::load_history::{self, HistorySpec};
use crate::error::SceneError;

/// How the cavities' pressures are stepped.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FlowStepping {
    /// One backward-Euler pressure solve per mechanical step (the default: stable at any
    /// step).
    #[default]
    Implicit,
    /// Explicit sub-steps below the flow's own stable step within each mechanical step.
    Explicit,
}

/// The scene's `"fluid"` section.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSection {
    /// Dynamic viscosity [Pa s], > 0.
    pub viscosity: f64,
    /// Bulk modulus [Pa], > 0.
    pub bulk_modulus: f64,
    /// Density [kg/m^3], > 0 (default 1000).
    #[serde(default = "default_density")]
    pub density: f64,
    /// Residual aperture [m], > 0 (default 1e-6): a closed crack still stores and conducts
    /// this much.
    #[serde(default = "default_residual")]
    pub residual_aperture: f64,
    /// Maximum aperture [m], >= the residual one (default 0.01).
    #[serde(default = "default_max")]
    pub max_aperture: f64,
    /// Carter's leak-off coefficient [m/s^0.5], >= 0 (default 0: impermeable rock).
    #[serde(default)]
    pub leak_off: f64,
    /// `"implicit"` (default) or `"explicit"`.
    #[serde(default)]
    pub stepping: FlowStepping,
    /// The fluid enters a joint from its first softening (damage above 0: the process zone
    /// ahead of a crack) instead of from its break (default false).
    #[serde(default)]
    pub wet_damaged: bool,
    /// Injections at points of the crack network (default none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub injections: Vec<Injection>,
    /// Prescribed pressures on edge groups of cracks or joints (default none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pressures: Vec<FluidPressure>,
}

fn default_density() -> f64 {
    1000.0
}
fn default_residual() -> f64 {
    1e-6
}
fn default_max() -> f64 {
    0.01
}

/// An injection at a vertex of a crack or joint.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Injection {
    /// The point [m]: the nearest vertex of a joint, within half that joint's length.
    pub at: [f64; 2],
    /// Body name (needed when several bodies fracture).
    #[serde(default)]
    pub body: Option<String>,
    /// Volume rate [m^3/s] through the model's thickness (m^2/s per unit thickness in plane
    /// strain), >= 0.
    pub rate: f64,
    /// Ramp time [s] (default 0: a step).
    #[serde(default)]
    pub ramp: f64,
    /// Time history of the factor on the rate (default none: the `ramp`); not with `ramp`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history: Option<HistorySpec>,
}

/// A pressure held in the cavities of an edge group's joints (a pressurised crack, a
/// borehole's wall, a drained boundary at 0).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FluidPressure {
    /// Edge group whose edges are joints.
    pub group: String,
    /// Body name (needed when several bodies have the group).
    #[serde(default)]
    pub body: Option<String>,
    /// Pressure [Pa], >= 0.
    pub value: f64,
    /// Ramp time [s] (default 0: a step).
    #[serde(default)]
    pub ramp: f64,
    /// Time history of the factor on the value (default none: the `ramp`); not with `ramp`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history: Option<HistorySpec>,
}

impl FluidSection {
    /// The fluid's properties as the flow crate takes them.
    pub fn fluid(&self) -> fdem_flow::Fluid {
        fdem_flow::Fluid {
            viscosity: self.viscosity,
            bulk_modulus: self.bulk_modulus,
            density: self.density,
            residual_aperture: self.residual_aperture,
            max_aperture: self.max_aperture,
            leak_off: self.leak_off,
        }
    }

    /// Checks every number of the section, each error at its JSON path.
    pub fn validate(&self, file: &Path) -> Result<(), SceneError> {
        let bad = |path: String, message: String, fix: &str| {
            Err(SceneError::invalid(file, path, message, fix))
        };
        let positive = [
            ("viscosity", self.viscosity, "Pa s, e.g. 1e-3 for water"),
            (
                "bulk_modulus",
                self.bulk_modulus,
                "Pa, e.g. 2.2e9 for water",
            ),
            ("density", self.density, "kg/m^3, e.g. 1000 for water"),
            ("residual_aperture", self.residual_aperture, "m, e.g. 1e-6"),
        ];
        for (name, v, unit) in positive {
            if !(v.is_finite() && v > 0.0) {
                return bad(
                    format!("fluid.{name}"),
                    format!("{name} {v} must be a finite number > 0"),
                    &format!("give a positive {name} in {unit}"),
                );
            }
        }
        if !(self.max_aperture.is_finite() && self.max_aperture >= self.residual_aperture) {
            return bad(
                "fluid.max_aperture".into(),
                format!(
                    "max_aperture {} is below residual_aperture {}",
                    self.max_aperture, self.residual_aperture
                ),
                "give a maximum aperture at least the residual one, in m",
            );
        }
        if !(self.leak_off.is_finite() && self.leak_off >= 0.0) {
            return bad(
                "fluid.leak_off".into(),
                format!("leak_off {} must be a finite number >= 0", self.leak_off),
                "give Carter's coefficient in m/s^0.5, or 0 for impermeable rock",
            );
        }
        for (i, inj) in self.injections.iter().enumerate() {
            let p = format!("fluid.injections[{i}]");
            if !inj.at.iter().all(|v| v.is_finite()) {
                return bad(
                    format!("{p}.at"),
                    "the point must be two finite coordinates".into(),
                    "give [x, y] in m",
                );
            }
            if !(inj.rate.is_finite() && inj.rate >= 0.0) {
                return bad(
                    format!("{p}.rate"),
                    format!("rate {} must be a finite number >= 0", inj.rate),
                    "give the volume rate in m^3/s (a drained boundary is a pressure of 0)",
                );
            }
            check_ramp(inj.ramp, &p, file)?;
            load_history::check_with_ramp(inj.history.as_ref(), inj.ramp, &p, file)?;
        }
        for (i, pr) in self.pressures.iter().enumerate() {
            let p = format!("fluid.pressures[{i}]");
            if !(pr.value.is_finite() && pr.value >= 0.0) {
                return bad(
                    format!("{p}.value"),
                    format!("pressure {} must be a finite number >= 0", pr.value),
                    "give the pressure in Pa (the fluid cannot pull on the faces)",
                );
            }
            check_ramp(pr.ramp, &p, file)?;
            load_history::check_with_ramp(pr.history.as_ref(), pr.ramp, &p, file)?;
        }
        Ok(())
    }
}

/// A ramp time at `path.ramp`: finite and >= 0.
fn check_ramp(ramp: f64, path: &str, file: &Path) -> Result<(), SceneError> {
    if ramp.is_finite() && ramp >= 0.0 {
        return Ok(());
    }
    Err(SceneError::invalid(
        file,
        format!("{path}.ramp"),
        format!("ramp {ramp} must be a finite number >= 0"),
        "give the ramp time in s, or 0 for a step",
    ))
}
