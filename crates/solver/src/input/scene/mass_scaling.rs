//! The levers of a slow (quasi-static) run: mass scaling ([`MassScaling`], the optional
//! `mass_scaling` section) and the loading rate ([`Loading`], the optional `loading`
//! section). Neither present: nothing changes.
//!
//! Mass scaling multiplies every lumped mass by a factor `f >= 1` (the same for every
//! node): every frequency bound (elements, contact, joints) falls by `sqrt(f)`, so the
//! stable step grows by `sqrt(f)`. The weight `m g` keeps the true mass.
//!
//! The loading rate `r` scales every prescribed velocity and wall velocity by `r` and
//! stretches every time of the loading by `1 / r`: the duration, the ramps, the times of the
//! history tables, the periods of the sines, the rise and hold of stepped loading
//! ([`apply_rate`]). A run at rate `r` follows the same load path as at rate 1, `1 / r` times
//! slower.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::conditions::BoundaryCondition;
use super::contact::ContactSection;
use super::integrator::{Analysis, TimeStep};
use super::load_history::{HistorySpec, Shape};
use crate::error::SceneError;

/// Mass scaling: either a factor on every mass, or the time step it should give.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MassScaling {
    /// The factor on every lumped mass (>= 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub factor: Option<f64>,
    /// The time step wanted [s]: the factor is `(target_step / h)^2`, `h` the unscaled step
    /// (not below `h`; not with `factor`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target_step: Option<f64>,
}

/// The loading rate of a run.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Loading {
    /// Factor on every prescribed velocity and wall velocity; the times of the loading
    /// (duration, ramps, histories) are divided by it (> 0, default 1).
    #[serde(default = "one")]
    pub rate: f64,
    /// The warning threshold of the quasi-static indicator, the kinetic to stored energy
    /// ratio while loading (default [`KINETIC_RATIO_LIMIT`]).
    #[serde(default = "ratio_limit")]
    pub kinetic_ratio_limit: f64,
}

fn one() -> f64 {
    1.0
}

fn ratio_limit() -> f64 {
    KINETIC_RATIO_LIMIT
}

/// The default warning threshold of the quasi-static indicator (kinetic energy over stored
/// energy, the largest before the peak of the stored energy): docs/speed-vs-accuracy.md
/// relates it to the error of the peak load.
pub const KINETIC_RATIO_LIMIT: f64 = 0.1;

/// The scene's parts that the sections are checked against.
pub struct Context<'a> {
    /// The kind of analysis.
    pub analysis: Analysis,
    /// The integrator's step.
    pub time_step: &'a TimeStep,
    /// The duration as written [s].
    pub duration: Option<f64>,
}

/// Checks the sections: `mass_scaling` has one of `factor` (finite, >= 1) and `target_step`
/// (finite, > 0, not with a fixed step), and no static analysis; `loading.rate` is finite
/// and positive and the stretched duration finite; `loading.kinetic_ratio_limit` positive.
pub fn validate(
    mass_scaling: Option<&MassScaling>,
    loading: Option<&Loading>,
    cx: &Context,
    file: &Path,
) -> Result<(), SceneError> {
    let bad =
        |path: &str, message: String, fix: &str| SceneError::invalid(file, path, message, fix);
    if let Some(m) = mass_scaling {
        if cx.analysis == Analysis::Static {
            return Err(bad(
                "mass_scaling",
                "mass scaling has no effect on a static analysis".into(),
                "remove the mass_scaling section, or run a dynamic analysis",
            ));
        }
        match (m.factor, m.target_step) {
            (Some(_), Some(_)) => {
                return Err(bad(
                    "mass_scaling",
                    "both factor and target_step are given".into(),
                    "give either \"factor\" or \"target_step\", not both",
                ));
            }
            (None, None) => {
                return Err(bad(
                    "mass_scaling",
                    "neither factor nor target_step is given".into(),
                    "give \"factor\": <f >= 1> or \"target_step\": <seconds>",
                ));
            }
            (Some(f), None) if !(f.is_finite() && f >= 1.0) => {
                return Err(bad(
                    "mass_scaling.factor",
                    format!("mass scaling factor {f} is not a finite number >= 1"),
                    "give a factor >= 1 (1: no scaling; the step grows by sqrt(factor))",
                ));
            }
            (None, Some(h)) if !(h.is_finite() && h > 0.0) => {
                return Err(bad(
                    "mass_scaling.target_step",
                    format!("target step {h} is not a positive finite time"),
                    "give the wanted time step in seconds",
                ));
            }
            _ => {}
        }
        if m.target_step.is_some() && matches!(cx.time_step, TimeStep::Fixed(_)) {
            return Err(bad(
                "mass_scaling.target_step",
                "a target step with a fixed integrator.time_step".into(),
                "set integrator.time_step to \"auto\", or give mass_scaling.factor",
            ));
        }
    }
    if let Some(l) = loading {
        let r = l.rate;
        if !(r.is_finite() && r > 0.0) {
            return Err(bad(
                "loading.rate",
                format!("loading rate {r} is not a positive finite number"),
                "give the factor on the loading speed (1: as written, 0.5: half as fast)",
            ));
        }
        if let Some(d) = cx.duration
            && !(d / r).is_finite()
        {
            return Err(bad(
                "loading.rate",
                format!("loading rate {r} stretches the duration {d} s past any finite time"),
                "give a larger rate",
            ));
        }
        let k = l.kinetic_ratio_limit;
        if !(k.is_finite() && k > 0.0) {
            return Err(bad(
                "loading.kinetic_ratio_limit",
                format!("kinetic ratio limit {k} is not a positive finite number"),
                "give the largest acceptable kinetic / stored energy ratio, e.g. 0.1",
            ));
        }
    }
    Ok(())
}

/// The factor of a `target_step` on a scene whose unscaled step is `h`: `(target / h)^2`;
/// a target below `h` is an error.
pub fn factor_for_target(target: f64, h: f64, file: &Path) -> Result<f64, SceneError> {
    if target < h {
        return Err(SceneError::invalid(
            file,
            "mass_scaling.target_step",
            format!("target step {target:.4e} s is below the unscaled step {h:.4e} s"),
            "give a target above the unscaled step (mass scaling only lengthens the step), or remove mass_scaling",
        ));
    }
    Ok((target / h) * (target / h))
}

/// Applies the loading rate of a `loading` section (nothing at rate 1) to the scene's
/// duration, conditions and contact walls: every
/// prescribed velocity and wall velocity times `r`; the duration, the ramps and the times
/// of the histories divided by `r`. Initial velocities, fixed time steps and step counts
/// are left as they are.
pub fn apply_rate(
    loading: Option<&Loading>,
    duration: &mut Option<f64>,
    conditions: &mut [BoundaryCondition],
    contact: Option<&mut ContactSection>,
) {
    let r = match loading {
        Some(l) if l.rate != 1.0 => l.rate,
        _ => return,
    };
    let stretch = |t: &mut f64| *t /= r;
    if let Some(d) = duration {
        stretch(d);
    }
    for bc in conditions {
        let (ramp, history) = match bc {
            BoundaryCondition::Fixed(_) => continue,
            BoundaryCondition::Velocity(v) => {
                for c in [&mut v.x, &mut v.y].into_iter().flatten() {
                    *c *= r;
                }
                (&mut v.ramp, &mut v.history)
            }
            BoundaryCondition::Displacement(b) => (&mut b.ramp, &mut b.history),
            BoundaryCondition::Pressure(b) => (&mut b.ramp, &mut b.history),
            BoundaryCondition::Traction(b) => (&mut b.ramp, &mut b.history),
            BoundaryCondition::PointLoad(b) => (&mut b.ramp, &mut b.history),
        };
        stretch(ramp);
        if let Some(h) = history {
            stretch_history(h, r);
        }
    }
    for w in contact.into_iter().flat_map(|c| c.walls.iter_mut()) {
        w.velocity = w.velocity.map(|v| v * r);
        stretch(&mut w.ramp);
        if let Some(h) = &mut w.history {
            stretch_history(h, r);
        }
    }
}

/// Divides the times of a history by `r`.
fn stretch_history(h: &mut HistorySpec, r: f64) {
    match h {
        HistorySpec::Table(t) => t.iter_mut().for_each(|p| p[0] /= r),
        HistorySpec::Shape(Shape::Repeat(s)) => s.table.iter_mut().for_each(|p| p[0] /= r),
        HistorySpec::Shape(Shape::Sine(s)) => s.period /= r,
        HistorySpec::Shape(Shape::Steps(s)) => {
            s.rise /= r;
            s.hold /= r;
        }
    }
}
