//! The JSON scene format: what a user writes to describe a specimen, its loading and the run.
//!
//! Every struct denies unknown fields, and [`Scene::from_file`] / [`Scene::from_str`] report
//! each error with the JSON path of the offending field (e.g. `bodies[0].materials.disc.young`),
//! the file, and what to change. Units are SI throughout (m, kg, s, N, Pa). The complete format,
//! with an example per specimen, is documented in `docs/scene-format.md`.

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

use serde::de::{self, Deserializer, Visitor};
use serde::{Deserialize, Serialize};

use crate::error::SceneError;

/// A whole scene: bodies, boundary conditions, loads, integrator, run length and output.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Free text shown in summaries.
    #[serde(default)]
    pub title: String,
    /// Kind of analysis (default `dynamic`).
    #[serde(default)]
    pub analysis: Analysis,
    /// The deformable bodies (at least one).
    pub bodies: Vec<Body>,
    /// Boundary conditions and loads on named groups of the bodies' meshes.
    #[serde(default)]
    pub boundary_conditions: Vec<BoundaryCondition>,
    /// Gravity acceleration [m/s^2] applied to every node (default none).
    #[serde(default)]
    pub gravity: Option<[f64; 2]>,
    /// Time integration (ignored by the static analysis).
    #[serde(default)]
    pub integrator: Integrator,
    /// Simulated time [s] (dynamic and relaxation analyses; must be > 0 there).
    #[serde(default)]
    pub duration: Option<f64>,
    /// Damping (default none).
    #[serde(default)]
    pub damping: Damping,
    /// Field output (`.pvd` + `.vtu` frames).
    #[serde(default)]
    pub output: Output,
    /// History probes written to `histories.csv`.
    #[serde(default)]
    pub histories: Histories,
    /// Contact between bodies and with rigid walls (default none: costs nothing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<crate::contact_stage::ContactSection>,
    /// Fracturing regions and the joint material (default none: costs nothing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fracture: Option<crate::fracture_stage::FractureSection>,
}

/// The kind of analysis.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Analysis {
    /// Explicit dynamics over `duration`.
    #[default]
    Dynamic,
    /// Small-strain linear-elastic solve (sparse Cholesky) with the full loads.
    Static,
    /// Dynamic relaxation: explicit dynamics with mass-proportional damping until the
    /// out-of-balance force falls below `integrator.relaxation_tolerance` times the applied load.
    Relaxation,
}

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
    /// Out-of-plane thickness [m] (default 1; plane strain always uses a unit thickness per metre).
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
    /// Relaxation analysis: stop when |residual| <= tolerance * |applied load| (default 1e-8).
    #[serde(default = "default_tol")]
    pub relaxation_tolerance: f64,
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

/// Field output.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// Number of frames over the run, besides the initial one (default 20; 0 turns output
    /// off except the summary).
    #[serde(default = "default_frames")]
    pub frames: usize,
    /// zlib compression level 0-9 (default 6).
    #[serde(default = "default_level")]
    pub compression: u32,
}

fn default_frames() -> usize {
    20
}
fn default_level() -> u32 {
    6
}

impl Default for Output {
    fn default() -> Self {
        Self {
            frames: default_frames(),
            compression: default_level(),
        }
    }
}

/// History probes.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Histories {
    /// Record every this many steps (default: 1000 rows over the run).
    #[serde(default)]
    pub every: Option<usize>,
    /// The probes (columns of `histories.csv`).
    #[serde(default)]
    pub probes: Vec<Probe>,
}

/// One history probe.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Probe {
    /// Mean displacement (x, y) of a group's nodes.
    Displacement(GroupProbe),
    /// Mean velocity (x, y) of a group's nodes.
    Velocity(GroupProbe),
    /// Total reaction force (x, y) on a group's constrained nodes.
    Reaction(GroupProbe),
    /// Kinetic, strain and external-work energies of the whole scene.
    Energy,
}

/// A probe on a named group.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GroupProbe {
    /// Group name.
    pub group: String,
    /// Body name (needed only when ambiguous).
    #[serde(default)]
    pub body: Option<String>,
}

impl Scene {
    /// Parses a scene from JSON text; `file` names the source in errors.
    pub fn from_json(text: &str, file: &Path) -> Result<Scene, SceneError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let scene: Scene = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            SceneError::Parse {
                file: file.to_path_buf(),
                path: if path == "." {
                    "(top level)".into()
                } else {
                    path
                },
                line: inner.line(),
                column: inner.column(),
                fix: fix_hint(&inner.to_string()),
                message: inner.to_string(),
            }
        })?;
        scene.validate(file)?;
        Ok(scene)
    }

    /// Reads and parses a scene file.
    pub fn from_file(file: &Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(file).map_err(|e| SceneError::Io {
            file: file.to_path_buf(),
            message: e.to_string(),
        })?;
        Self::from_json(&text, file)
    }

    /// Checks the values that the JSON types cannot: positive constants, known schemes, ...
    fn validate(&self, file: &Path) -> Result<(), SceneError> {
        let bad = |path: String, message: String, fix: &str| SceneError::Invalid {
            file: file.to_path_buf(),
            path,
            message,
            fix: fix.to_string(),
        };
        if self.bodies.is_empty() {
            return Err(bad(
                "bodies".into(),
                "the scene has no body".into(),
                "add at least one body with a mesh and materials",
            ));
        }
        for (i, b) in self.bodies.iter().enumerate() {
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
        for (i, bc) in self.boundary_conditions.iter().enumerate() {
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
        if !(self.integrator.safety > 0.0 && self.integrator.safety <= 1.0) {
            return Err(bad(
                "integrator.safety".into(),
                format!("safety factor {} is outside (0, 1]", self.integrator.safety),
                "use a safety factor between 0.5 and 0.9",
            ));
        }
        if let TimeStep::Fixed(h) = self.integrator.time_step
            && !(h > 0.0 && h.is_finite())
        {
            return Err(bad(
                "integrator.time_step".into(),
                format!("time step {h} is not positive"),
                "use \"auto\" or a positive number of seconds",
            ));
        }
        if self.integrator.time_step == TimeStep::Adaptive {
            if self.analysis != Analysis::Dynamic
                || crate::schemes::scheme_by_name(&self.integrator.scheme)
                    .is_some_and(|k| k != fdem_time::SchemeKind::CentralDifference)
            {
                return Err(bad(
                    "integrator.time_step".into(),
                    format!(
                        "\"adaptive\" is for central-difference in a dynamic analysis, not {} in a {:?} one",
                        self.integrator.scheme, self.analysis
                    ),
                    "use \"auto\", or the central-difference scheme",
                ));
            }
            if self.integrator.adapt_every == 0 {
                return Err(bad(
                    "integrator.adapt_every".into(),
                    "must be at least 1".into(),
                    "use e.g. 10",
                ));
            }
        }
        if crate::schemes::scheme_by_name(&self.integrator.scheme).is_none() {
            return Err(bad(
                "integrator.scheme".into(),
                format!("unknown scheme '{}'", self.integrator.scheme),
                &format!("use one of {}", crate::schemes::scheme_names()),
            ));
        }
        if self.analysis != Analysis::Static {
            match self.duration {
                Some(d) if d > 0.0 && d.is_finite() => {}
                Some(d) => {
                    return Err(bad(
                        "duration".into(),
                        format!("duration {d} is not positive"),
                        "set duration to the simulated time in seconds",
                    ));
                }
                None => {
                    return Err(bad(
                        "duration".into(),
                        "a dynamic or relaxation analysis needs a duration".into(),
                        "add \"duration\": <seconds>",
                    ));
                }
            }
        }
        if self.damping.viscosity_ratio < 0.0 || self.damping.mass_proportional < 0.0 {
            return Err(bad(
                "damping".into(),
                "damping coefficients must be >= 0".into(),
                "set viscosity_ratio and mass_proportional to values >= 0",
            ));
        }
        if self.output.compression > 9 {
            return Err(bad(
                "output.compression".into(),
                format!("compression level {} is above 9", self.output.compression),
                "use a zlib level from 0 (none) to 9",
            ));
        }
        if self.histories.every == Some(0) {
            return Err(bad(
                "histories.every".into(),
                "history interval 0".into(),
                "record every 1 or more steps",
            ));
        }
        Ok(())
    }
}

/// A short fix for the common serde messages.
fn fix_hint(msg: &str) -> String {
    if msg.starts_with("unknown field") {
        "remove or correct the misspelled field (the allowed names are listed above)".into()
    } else if msg.starts_with("missing field") {
        "add the missing field".into()
    } else if msg.starts_with("invalid type") {
        "give a value of the expected type".into()
    } else if msg.starts_with("unknown variant") {
        "use one of the listed names".into()
    } else if msg.contains("EOF") || msg.starts_with("expected") || msg.contains("trailing") {
        "fix the JSON syntax at the line and column shown".into()
    } else {
        "correct the value as described".into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"{
        "bodies": [{"mesh": "m.msh", "materials": {"*": {"young": 1e9, "poisson": 0.25, "density": 2000}}}],
        "boundary_conditions": [{"fixed": {"group": "left", "x": true}}],
        "integrator": {"scheme": "pc4", "time_step": "auto"},
        "duration": 1e-3
    }"#;

    fn err(text: &str) -> String {
        Scene::from_json(text, Path::new("s.json"))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn good_scene_parses_with_defaults() {
        let s = Scene::from_json(GOOD, Path::new("s.json")).unwrap();
        assert_eq!(s.integrator.safety, 0.5);
        assert_eq!(s.integrator.time_step, TimeStep::Auto);
        assert_eq!(s.output.frames, 20);
        assert_eq!(s.bodies[0].thickness, 1.0);
    }

    #[test]
    fn unknown_nested_field_is_named_by_its_path() {
        let e = err(&GOOD.replace("\"x\": true", "\"xx\": true"));
        assert!(e.contains("boundary_conditions[0].fixed.xx"), "{e}");
        assert!(
            e.contains("unknown field `xx`") && e.contains("s.json"),
            "{e}"
        );
    }

    #[test]
    fn wrong_type_names_path_and_fix() {
        let e = err(&GOOD.replace("\"young\": 1e9", "\"young\": \"stiff\""));
        assert!(e.contains("bodies[0].materials.*.young"), "{e}");
        assert!(e.contains("fix:"), "{e}");
    }

    #[test]
    fn negative_constant_and_bad_scheme_are_rejected() {
        let e = err(&GOOD.replace("\"poisson\": 0.25", "\"poisson\": -0.1"));
        assert!(e.contains("poisson"), "{e}");
        let e = err(&GOOD.replace("1e9", "0"));
        assert!(e.contains("young") && e.contains("not positive"), "{e}");
        let e = err(&GOOD.replace("pc4", "leapfrog"));
        assert!(
            e.contains("integrator.scheme") && e.contains("omf32"),
            "{e}"
        );
        let e = err(&GOOD.replace("\"auto\"", "\"fast\""));
        assert!(e.contains("integrator.time_step"), "{e}");
    }

    #[test]
    fn bad_json_reports_line_and_column() {
        let e = err("{\n \"bodies\": [,]\n}");
        assert!(e.contains("s.json:2:"), "{e}");
    }
}
