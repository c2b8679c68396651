//! Boundary conditions and loads on named groups of the bodies' meshes: fixed and prescribed
//! velocity or displacement degrees of freedom, pressure, traction and point loads, each with
//! its ramp or time history ([`super::history`]).

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::load_history::{self, HistorySpec};
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
    /// Prescribed displacement in x and/or y, `value f(t)` (velocity its rate).
    Displacement(PrescribedDisplacement),
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
    /// Time history of the factor on the value (default none: the `ramp`); not with `ramp`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history: Option<HistorySpec>,
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
    /// Time history of the factor on the value (default none: the `ramp`); not with `ramp`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history: Option<HistorySpec>,
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
    /// Traction vector [Pa] in x and y (force per unit area of the edge surface); or `local`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<[f64; 2]>,
    /// Traction [Pa] in the edge's frame, `[normal, tangential]`: normal along the outward
    /// normal `n` (positive pulls, tension), tangential along `s = (-n_y, n_x)` (`n` turned
    /// 90 degrees counter-clockwise); or `value`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub local: Option<[f64; 2]>,
    /// Ramp time [s] (default 0: a step).
    #[serde(default)]
    pub ramp: f64,
    /// Time history of the factor on the value (default none: the `ramp`); not with `ramp`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history: Option<HistorySpec>,
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
    /// Time history of the factor on the value (default none: the `ramp`); not with `ramp`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history: Option<HistorySpec>,
}

/// Prescribed displacement.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PrescribedDisplacement {
    /// Physical group name.
    pub group: String,
    /// Body name (needed only when ambiguous).
    #[serde(default)]
    pub body: Option<String>,
    /// Displacement in x [m]; absent leaves x free.
    #[serde(default)]
    pub x: Option<f64>,
    /// Displacement in y [m]; absent leaves y free.
    #[serde(default)]
    pub y: Option<f64>,
    /// Ramp time [s] from zero to the full displacement (default 0: at once).
    #[serde(default)]
    pub ramp: f64,
    /// Time history of the factor on the value (default none: the `ramp`); not with `ramp`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history: Option<HistorySpec>,
}

impl BoundaryCondition {
    /// The kind's name in the scene (`fixed`, `point-load`, ...).
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Fixed(_) => "fixed",
            Self::Velocity(_) => "velocity",
            Self::Pressure(_) => "pressure",
            Self::Traction(_) => "traction",
            Self::PointLoad(_) => "point-load",
            Self::Displacement(_) => "displacement",
        }
    }
    /// The time history of this condition, if it has one.
    pub fn history(&self) -> Option<&HistorySpec> {
        match self {
            Self::Fixed(_) => None,
            Self::Velocity(b) => b.history.as_ref(),
            Self::Pressure(b) => b.history.as_ref(),
            Self::Traction(b) => b.history.as_ref(),
            Self::PointLoad(b) => b.history.as_ref(),
            Self::Displacement(b) => b.history.as_ref(),
        }
    }
    /// The group this condition applies to.
    pub fn group(&self) -> &str {
        match self {
            Self::Fixed(b) => &b.group,
            Self::Velocity(b) => &b.group,
            Self::Pressure(b) => &b.group,
            Self::Traction(b) => &b.group,
            Self::PointLoad(b) => &b.group,
            Self::Displacement(b) => &b.group,
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
            Self::Displacement(b) => b.body.as_deref(),
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
            BoundaryCondition::Displacement(v) => {
                if v.x.is_none() && v.y.is_none() {
                    return Err(bad(
                        p,
                        format!(
                            "displacement condition on '{}' gives neither x nor y",
                            v.group
                        ),
                        "give \"x\" and/or \"y\" in m",
                    ));
                }
                for (c, val) in [("x", v.x), ("y", v.y)] {
                    if let Some(val) = val
                        && !val.is_finite()
                    {
                        return Err(bad(
                            format!("{p}.displacement.{c}"),
                            format!("displacement {val} is not finite"),
                            "give the displacement in m",
                        ));
                    }
                }
                v.ramp
            }
            BoundaryCondition::Pressure(l) => l.ramp,
            BoundaryCondition::Traction(l) => {
                if l.value.is_some() == l.local.is_some() {
                    return Err(bad(
                        format!("{p}.traction"),
                        if l.value.is_some() {
                            "both `value` and `local` are given".into()
                        } else {
                            "neither `value` nor `local` is given".into()
                        },
                        "give the traction either as \"value\": [tx, ty] (global x, y) or as \"local\": [normal, tangential] (the edge's frame), in Pa",
                    ));
                }
                l.ramp
            }
            BoundaryCondition::PointLoad(l) => l.ramp,
        };
        crate::error::SceneError::check_range(
            file,
            format!("{p}.{}.ramp", bc.kind()),
            "ramp",
            ramp,
            crate::error::Range::at_least(0.0),
            "set ramp to a time >= 0 in seconds",
        )?;
        load_history::check_with_ramp(bc.history(), ramp, &format!("{p}.{}", bc.kind()), file)?;
    }
    Ok(())
}

/// A `static` scene takes its histories at t = `duration`: one with a history needs it.
pub(crate) fn validate_static(
    conditions: &[BoundaryCondition],
    duration: Option<f64>,
    file: &Path,
) -> Result<(), SceneError> {
    if duration.is_some() {
        return Ok(());
    }
    match conditions
        .iter()
        .enumerate()
        .find(|(_, bc)| bc.history().is_some())
    {
        Some((i, bc)) => Err(SceneError::invalid(
            file,
            format!("boundary_conditions[{i}].{}.history", bc.kind()),
            "a static analysis takes each history at t = duration, and the scene has no duration",
            "add \"duration\": the time at which the static solve takes the loads and motions",
        )),
        None => Ok(()),
    }
}
