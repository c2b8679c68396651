//! How a scene is run: the kind of analysis, the time integration (scheme, time step, safety
//! factor) and the damping.

use std::fmt;
use std::path::Path;

use serde::de::{self, Deserializer, Visitor};
use serde::{Deserialize, Serialize};

use crate::error::{Range, SceneError};

/// The kind of analysis.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Analysis {
    /// Explicit dynamics over `duration`.
    #[default]
    Dynamic,
    /// Small-strain linear-elastic solve (sparse Cholesky) with the full loads.
    Static,
    /// Dynamic relaxation: explicit pseudo-dynamics, damped by `integrator.relaxation`
    /// (kinetic damping by default; mass-proportional damping when the scene gives
    /// `damping.mass_proportional`), until the out-of-balance force falls below
    /// `integrator.relaxation_tolerance` times the applied load (or the round-off floor).
    Relaxation,
}

/// How a relaxation analysis takes the energy out of its pseudo-dynamics
/// (`integrator.relaxation`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RelaxationMethod {
    /// Kinetic damping: undamped steps; at each peak of the kinetic energy the velocities are
    /// zeroed and the positions moved back to the peak.
    Kinetic,
    /// Mass-proportional damping `2 omega` set after every step from the Rayleigh quotient
    /// `omega^2` of the secant stiffness on the present displacement (Underwood).
    Adaptive,
    /// Mass-proportional damping `damping.mass_proportional` (> 0) throughout.
    Viscous,
    /// No pseudo-dynamics: a nonlinear conjugate-gradient minimisation of the total
    /// potential energy (Polak-Ribiere+, a secant line search), preconditioned by the lumped
    /// masses, one iteration per step.
    ConjugateGradient,
}

impl RelaxationMethod {
    /// The method's name in the scene and the summary.
    pub fn name(self) -> &'static str {
        match self {
            RelaxationMethod::Kinetic => "kinetic",
            RelaxationMethod::Adaptive => "adaptive",
            RelaxationMethod::Viscous => "viscous",
            RelaxationMethod::ConjugateGradient => "conjugate-gradient",
        }
    }
}

/// The masses of a relaxation's pseudo-dynamics (`integrator.relaxation_masses`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RelaxationMasses {
    /// Each triangle's mass proportional to its `E t` (the total kept): every triangle's
    /// stable step the same, however graded the mesh.
    EqualStep,
    /// The true masses `rho A t`.
    True,
}

/// Time step: `"auto"`, `"adaptive"` or a number of seconds.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum TimeStep {
    /// The scheme's stability limit over the highest element frequency bound, times `safety`.
    #[default]
    Auto,
    /// A fixed step [s]; it must not exceed the stability limit.
    Fixed(f64),
    /// Central difference only: the step recomputed every `adapt_every` steps (default 1)
    /// from the
    /// active frequency bound (the contact engaged now and within a look-ahead, the elements
    /// and the joints), times `safety` (docs/speed-vs-accuracy.md, "Adaptive step").
    Adaptive,
}

impl Serialize for TimeStep {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            TimeStep::Auto => s.serialize_str("auto"),
            TimeStep::Adaptive => s.serialize_str("adaptive"),
            TimeStep::Fixed(h) => s.serialize_f64(*h),
        }
    }
}

impl<'de> Deserialize<'de> for TimeStep {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = TimeStep;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("\"auto\", \"adaptive\" or a positive number of seconds")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<TimeStep, E> {
                if v == "auto" {
                    Ok(TimeStep::Auto)
                } else if v == "adaptive" {
                    Ok(TimeStep::Adaptive)
                } else {
                    Err(E::invalid_value(de::Unexpected::Str(v), &self))
                }
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<TimeStep, E> {
                Ok(TimeStep::Fixed(v))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<TimeStep, E> {
                Ok(TimeStep::Fixed(v as f64))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<TimeStep, E> {
                Ok(TimeStep::Fixed(v as f64))
            }
        }
        d.deserialize_any(V)
    }
}

/// The valid range of `integrator.safety`.
pub const SAFETY: Range = Range::open_closed(0.0, 1.0);

/// The valid range of `integrator.relaxation_tolerance`: a fraction of the load; at 1 or more
/// the residual of the unloaded state, the load itself, passes.
pub const RELAXATION_TOLERANCE: Range = Range::open(0.0, 1.0);

/// Time integration settings.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Integrator {
    /// Scheme name: `central-difference`, `pc3`, `pc4`, `pc5`, `chin`, `omf30`, `omf32`,
    /// `forest-ruth` (default `central-difference`).
    #[serde(default = "default_scheme")]
    pub scheme: String,
    /// Time step (default `"auto"`).
    #[serde(default)]
    pub time_step: TimeStep,
    /// Safety factor on the stability limit for `"auto"` and `"adaptive"` (default 0.5; in
    /// (0, 1]).
    #[serde(default = "default_safety")]
    pub safety: f64,
    /// Steps between recomputations of an `"adaptive"` step (default 1: every step; the
    /// bound costs about one contact pass over the detected couples).
    #[serde(default = "default_adapt_every")]
    pub adapt_every: u64,
    /// Relaxation analysis: stop when |residual| <= tolerance * |applied load| (default 1e-8;
    /// in (0, 1)).
    #[serde(default = "default_tol")]
    pub relaxation_tolerance: f64,
    /// Relaxation analysis: `"kinetic"`, `"adaptive"`, `"viscous"` or
    /// `"conjugate-gradient"` (default: `"viscous"` when
    /// `damping.mass_proportional` > 0, else `"kinetic"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relaxation: Option<RelaxationMethod>,
    /// Relaxation analysis: the masses of the pseudo-dynamics, `"equal-step"` or `"true"`
    /// (default: `"equal-step"` for the kinetic, adaptive and conjugate-gradient methods,
    /// `"true"` for viscous).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relaxation_masses: Option<RelaxationMasses>,
}

fn default_scheme() -> String {
    "central-difference".into()
}
fn default_safety() -> f64 {
    0.5
}
fn default_tol() -> f64 {
    1e-8
}
fn default_adapt_every() -> u64 {
    1
}

impl Default for Integrator {
    fn default() -> Self {
        Self {
            scheme: default_scheme(),
            time_step: TimeStep::Auto,
            safety: default_safety(),
            adapt_every: default_adapt_every(),
            relaxation_tolerance: default_tol(),
            relaxation: None,
            relaxation_masses: None,
        }
    }
}

/// Damping.
#[derive(Debug, Clone, Copy, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Damping {
    /// Element viscosity as a damping ratio xi: eta = 2 xi h sqrt(E rho) (default 0).
    #[serde(default)]
    pub viscosity_ratio: f64,
    /// Mass-proportional damping coefficient alpha [1/s]: f = -alpha m v (default 0).
    #[serde(default)]
    pub mass_proportional: f64,
}

impl Integrator {
    /// The relaxation method of a scene with damping `damping`, `conservative` when its
    /// energy is a potential ([`crate::input::scene::Scene::relaxation_choice`]): the one
    /// named, else viscous when the scene gives a mass-proportional damping, else conjugate
    /// gradient for a conservative scene and kinetic damping for any other.
    pub fn relaxation_method(&self, damping: &Damping, conservative: bool) -> RelaxationMethod {
        self.relaxation
            .unwrap_or(if damping.mass_proportional > 0.0 {
                RelaxationMethod::Viscous
            } else if conservative {
                RelaxationMethod::ConjugateGradient
            } else {
                RelaxationMethod::Kinetic
            })
    }

    /// Whether a scene of kind `analysis` relaxing by `method` does so with the equal-step
    /// masses: the ones named, else for the kinetic, adaptive and conjugate-gradient methods.
    pub fn equal_step_masses(&self, analysis: Analysis, method: RelaxationMethod) -> bool {
        analysis == Analysis::Relaxation
            && match self.relaxation_masses {
                Some(m) => m == RelaxationMasses::EqualStep,
                None => method != RelaxationMethod::Viscous,
            }
    }

    /// Checks `integrator.relaxation` against the damping: viscous relaxation needs
    /// `damping.mass_proportional` > 0, kinetic damping none; and the equal-step masses are
    /// not for a viscous relaxation (its coefficient is set for the true masses).
    pub(crate) fn validate_relaxation(
        &self,
        damping: &Damping,
        file: &Path,
    ) -> Result<(), SceneError> {
        let alpha = damping.mass_proportional;
        if self.relaxation_masses == Some(RelaxationMasses::EqualStep)
            && self.relaxation_method(damping, false) == RelaxationMethod::Viscous
        {
            return Err(SceneError::invalid(
                file,
                "integrator.relaxation_masses",
                "\"equal-step\" masses with a viscous relaxation, whose `damping.mass_proportional` is set for the true masses",
                "use \"kinetic\" or \"adaptive\" relaxation (they set their own damping), or \"relaxation_masses\": \"true\"",
            ));
        }
        match self.relaxation {
            Some(RelaxationMethod::Viscous) if alpha <= 0.0 => Err(SceneError::invalid(
                file,
                "integrator.relaxation",
                "\"viscous\" relaxation needs a mass-proportional damping, and `damping.mass_proportional` is 0",
                "set `damping.mass_proportional` (about twice the lowest natural frequency, 1/s), or use \"kinetic\"",
            )),
            Some(
                m @ (RelaxationMethod::Kinetic
                | RelaxationMethod::Adaptive
                | RelaxationMethod::ConjugateGradient),
            ) if alpha > 0.0 => Err(SceneError::invalid(
                file,
                "integrator.relaxation",
                format!(
                    "{} relaxation sets its own damping, and `damping.mass_proportional` is {alpha}",
                    m.name()
                ),
                "remove `damping.mass_proportional`, or use \"viscous\"",
            )),
            _ => Ok(()),
        }
    }

    /// Checks the settings that the JSON types cannot (safety factor, a positive fixed step,
    /// `"adaptive"` only for central difference in a dynamic `analysis`, a known scheme);
    /// `file` names the scene in errors.
    pub(crate) fn validate(&self, analysis: Analysis, file: &Path) -> Result<(), SceneError> {
        let bad = |path: String, message: String, fix: &str| {
            SceneError::invalid(file, path, message, fix)
        };

        SceneError::check_range(
            file,
            "integrator.safety",
            "safety factor",
            self.safety,
            SAFETY,
            "use a safety factor between 0.5 and 0.9",
        )?;
        SceneError::check_range(
            file,
            "integrator.relaxation_tolerance",
            "relaxation tolerance",
            self.relaxation_tolerance,
            RELAXATION_TOLERANCE,
            "give the out-of-balance force to stop at as a fraction of the load, e.g. 1e-8 (the default); at 1 or more the unloaded state passes",
        )?;
        if let TimeStep::Fixed(h) = self.time_step
            && !(h > 0.0 && h.is_finite())
        {
            return Err(bad(
                "integrator.time_step".into(),
                format!("time step {h} is not positive"),
                "use \"auto\" or a positive number of seconds",
            ));
        }
        if self.time_step == TimeStep::Adaptive {
            if analysis != Analysis::Dynamic
                || crate::input::schemes::scheme_by_name(&self.scheme)
                    .is_some_and(|k| k != fdem_time::SchemeKind::CentralDifference)
            {
                return Err(bad(
                    "integrator.time_step".into(),
                    format!(
                        "\"adaptive\" is for central-difference in a dynamic analysis, not {} in a {:?} one",
                        self.scheme, analysis
                    ),
                    "use \"auto\", or the central-difference scheme",
                ));
            }
            if self.adapt_every == 0 {
                return Err(bad(
                    "integrator.adapt_every".into(),
                    "must be at least 1".into(),
                    "use e.g. 10",
                ));
            }
        }
        if crate::input::schemes::scheme_by_name(&self.scheme).is_none() {
            return Err(bad(
                "integrator.scheme".into(),
                format!("unknown scheme '{}'", self.scheme),
                &format!("use one of {}", crate::input::schemes::scheme_names()),
            ));
        }
        Ok(())
    }
}

impl Damping {
    /// Checks that the coefficients are finite and >= 0, each at its path; `file` names the
    /// scene in errors.
    pub(crate) fn validate(&self, file: &Path) -> Result<(), SceneError> {
        SceneError::check_range(
            file,
            "damping.viscosity_ratio",
            "viscosity ratio",
            self.viscosity_ratio,
            Range::at_least(0.0),
            "give the damping ratio of the highest element mode, >= 0 (0: no viscosity)",
        )?;
        SceneError::check_range(
            file,
            "damping.mass_proportional",
            "mass-proportional damping",
            self.mass_proportional,
            Range::at_least(0.0),
            "give the coefficient alpha in 1/s, >= 0 (0: none)",
        )
    }
}
