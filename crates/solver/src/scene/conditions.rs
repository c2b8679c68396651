//! Boundary conditions and loads on named groups of the bodies' meshes: fixed and prescribed
//! velocity degrees of freedom, pressure, traction and point loads, each with its ramp.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::SceneError;

/// A boundary condition or load on a named group of a body's mesh.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoundaryCondition {
    /// Fixed displacement in x and/or y on the nodes of a group (any dimension).
    Fixed(Fixed),
    /// Prescribed velocity in x and/or y, ramped linearly from 0 over `ramp` seconds.
    Velocity(PrescribedVelocity),
    /// Pressure [Pa] on the edges of an edge group, pushing into the body (negative pulls).
    Pressure(PressureLoad),
    /// Traction vector [Pa] on the edges of an edge group.
    Traction(TractionLoad),
    /// Total force [N] shared equally by the nodes of a group.
    PointLoad(PointLoad),
}

/// Fixed degrees of freedom.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Fixed {
    /// Physical group name.
    pub group: String,
    /// Body name (needed only when several bodies have a group of this name).
    #[serde(default)]
    pub body: Option<String>,
    /// Fix x (default false).
    #[serde(default)]
    pub x: bool,
    /// Fix y (default false).
    #[serde(default)]
    pub y: bool,
}

/// Prescribed velocity.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PrescribedVelocity {
    /// Physical group name.
    pub group: String,
    /// Body name (needed only when ambiguous).
    #[serde(default)]
    pub body: Option<String>,
    /// Velocity in x [m/s]; absent leaves x free.
    #[serde(default)]
    pub x: Option<f64>,
    /// Velocity in y [m/s]; absent leaves y free.
    #[serde(default)]
    pub y: Option<f64>,
    /// Ramp time [s] from zero to the full velocity (default 0: a step).
    #[serde(default)]
    pub ramp: f64,
}

/// Pressure on edges.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PressureLoad {
    /// Edge group name.
    pub group: String,
    /// Body name (needed only when ambiguous).
    #[serde(default)]
    pub body: Option<String>,
    /// Pressure [Pa], positive pushes into the body.
    pub value: f64,
    /// Ramp time [s] (default 0: a step).
    #[serde(default)]
    pub ramp: f64,
}

/// Traction on edges.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TractionLoad {
    /// Edge group name.
    pub group: String,
    /// Body name (needed only when ambiguous).
    #[serde(default)]
    pub body: Option<String>,
    /// Traction vector [Pa] (force per unit area of the edge surface).
    pub value: [f64; 2],
    /// Ramp time [s] (default 0: a step).
    #[serde(default)]
    pub ramp: f64,
}

/// Point load.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PointLoad {
    /// Group name (usually a point group).
    pub group: String,
    /// Body name (needed only when ambiguous).
    #[serde(default)]
    pub body: Option<String>,
    /// Total force [N] (per the body's thickness), shared equally by the group's nodes.
    pub force: [f64; 2],
    /// Ramp time [s] (default 0: a step).
    #[serde(default)]
    pub ramp: f64,
}

impl BoundaryCondition {
    /// The group this condition applies to.
    pub fn group(&self) -> &str {
        match self {
            Self::Fixed(b) => &b.group,
            Self::Velocity(b) => &b.group,
            Self::Pressure(b) => &b.group,
            Self::Traction(b) => &b.group,
            Self::PointLoad(b) => &b.group,
        }
    }
    /// The body named by this condition, if any.
    pub fn body(&self) -> Option<&str> {
        match self {
            Self::Fixed(b) => b.body.as_deref(),
            Self::Velocity(b) => b.body.as_deref(),
            Self::Pressure(b) => b.body.as_deref(),
            Self::Traction(b) => b.body.as_deref(),
            Self::PointLoad(b) => b.body.as_deref(),
        }
    }
}

/// Checks the conditions' values that the JSON types cannot (something fixed or prescribed,
/// ramps >= 0); `file` names the scene in errors.
pub(crate) fn validate(conditions: &[BoundaryCondition], file: &Path) -> Result<(), SceneError> {
    let bad =
        |path: String, message: String, fix: &str| SceneError::invalid(file, path, message, fix);
    for (i, bc) in conditions.iter().enumerate() {
        let p = format!("boundary_conditions[{i}]");
        let ramp = match bc {
            BoundaryCondition::Fixed(f) => {
                if !f.x && !f.y {
                    return Err(bad(
                        p,
                        format!("fixed condition on '{}' fixes neither x nor y", f.group),
                        "set \"x\": true and/or \"y\": true",
                    ));
                }
                0.0
            }
            BoundaryCondition::Velocity(v) => {
                if v.x.is_none() && v.y.is_none() {
                    return Err(bad(
                        p,
                        format!("velocity condition on '{}' gives neither x nor y", v.group),
                        "give \"x\" and/or \"y\" in m/s",
                    ));
                }
                v.ramp
            }
            BoundaryCondition::Pressure(l) => l.ramp,
            BoundaryCondition::Traction(l) => l.ramp,
            BoundaryCondition::PointLoad(l) => l.ramp,
        };
        if !(ramp >= 0.0 && ramp.is_finite()) {
            return Err(bad(
                format!("boundary_conditions[{i}].ramp"),
                format!("ramp {ramp} is negative"),
                "set ramp to a time >= 0 in seconds",
            ));
        }
    }
    Ok(())
}
