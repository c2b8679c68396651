//! The JSON scene format: what a user writes to describe a specimen, its loading and the run.
//!
//! Every struct denies unknown fields, and [`Scene::from_file`] / [`Scene::from_str`] report
//! each error with the JSON path of the offending field (e.g. `bodies[0].materials.disc.young`),
//! the file, and what to change. Units are SI throughout (m, kg, s, N, Pa). The complete format,
//! with an example per specimen, is documented in `docs/scene-format.md`.
//!
//! One file per part of the format: [`bodies`] (meshes and materials), [`conditions`]
//! (boundary conditions and loads), [`load_history`] (their time histories), [`integrator`] (analysis, time integration, damping),
//! [`output`] (frames and history probes), [`contact`] and [`fracture`] (the optional
//! sections). The scene depends on nothing of the stages that read it.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::SceneError;

pub mod bodies;
pub mod conditions;
pub mod contact;
pub mod cracks;
pub mod fluid;
pub mod fracture;
pub mod initial_stress;
pub mod integrator;
pub mod joint_materials;
pub mod load_history;
pub mod mass_scaling;
pub mod output;

pub use bodies::{Body, BulkHeterogeneity, Law, MaterialSpec, Plane};
pub use conditions::{
    BoundaryCondition, Fixed, PointLoad, PrescribedDisplacement, PrescribedVelocity, PressureLoad,
    TractionLoad,
};
pub use contact::ContactSection;
pub use fracture::FractureSection;
pub use initial_stress::{GravityStress, InitialStress};
pub use integrator::{Analysis, Damping, Integrator, RelaxationMasses, RelaxationMethod, TimeStep};
pub use load_history::HistorySpec;
pub use mass_scaling::{Loading, MassScaling};
pub use output::{GroupProbe, Histories, Output, Probe};

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
    pub contact: Option<ContactSection>,
    /// Fracturing regions and the joint material (default none: costs nothing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fracture: Option<FractureSection>,
    /// A fluid in the crack network: injections, pressures (default none: costs nothing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fluid: Option<fluid::FluidSection>,
    /// In-situ (initial) stress of bodies or surface groups (default none: costs nothing).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub initial_stress: Vec<InitialStress>,
    /// Mass scaling of a slow run (default none: the true masses).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_scaling: Option<MassScaling>,
    /// The loading rate of a slow run (default none: the loading as written).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub loading: Option<Loading>,
}

impl Scene {
    /// A relaxation's method and why: the one `integrator.relaxation` names; else viscous
    /// with a mass-proportional damping; else conjugate gradient when the scene's energy is a
    /// potential (no friction or damping in contact, no element viscosity, no joints that
    /// soften), the fastest there; else kinetic damping, with what rules the potential out.
    pub fn relaxation_choice(&self) -> (integrator::RelaxationMethod, String) {
        let why_not = self.not_conservative();
        let m = self
            .integrator
            .relaxation_method(&self.damping, why_not.is_none());
        let why = if self.integrator.relaxation.is_some() {
            "named by integrator.relaxation".to_string()
        } else if self.damping.mass_proportional > 0.0 {
            "the default with damping.mass_proportional > 0".to_string()
        } else if let Some(w) = why_not {
            format!("the default where the energy is not a potential: {w}")
        } else {
            "the default for a conservative scene, the fewest iterations (no friction, damping \
             or softening joints)"
                .to_string()
        };
        (m, why)
    }

    /// What makes the scene's energy not a potential, in words; `None` when it is one.
    fn not_conservative(&self) -> Option<String> {
        if self.damping.viscosity_ratio > 0.0 {
            return Some("damping.viscosity_ratio > 0".into());
        }
        if self.fracture.is_some() {
            return Some("joints that soften (fracture)".into());
        }
        let (path, law) = self.contact.as_ref()?.dissipative_law()?;
        Some(if law.friction > 0.0 {
            format!("{path}.friction > 0")
        } else {
            format!("{path}.damping > 0")
        })
    }

    /// Parses a scene from JSON text; `file` names the source in errors.
    ///
    /// Every byte of the text is consumed or refused: a UTF-8 byte-order mark is refused as
    /// such, and so is anything but white space after the top-level object (a second object,
    /// a section pasted after the closing brace), which would otherwise be dropped unread.
    pub fn from_json(text: &str, file: &Path) -> Result<Scene, SceneError> {
        if text.starts_with('\u{feff}') {
            return Err(SceneError::Parse {
                file: file.to_path_buf(),
                path: "(top level)".into(),
                line: 1,
                column: 1,
                message: "the file starts with a UTF-8 byte-order mark (bytes EF BB BF)".into(),
                fix: "save the file as UTF-8 without a byte-order mark (BOM)".into(),
            });
        }
        let de = &mut serde_json::Deserializer::from_str(text);
        let scene: Scene = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
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
        de.end().map_err(|e| SceneError::Parse {
            file: file.to_path_buf(),
            path: "(after the top-level object)".into(),
            line: e.line(),
            column: e.column(),
            message: format!(
                "the scene's top-level object has ended, but text follows it ({e}); \
                 it would be ignored"
            ),
            fix: "remove the text after the closing brace, or move what it holds into the \
                  top-level object"
                .into(),
        })?;
        let mut scene = scene;
        scene.validate(file)?;
        mass_scaling::apply_rate(
            scene.loading.as_ref(),
            &mut scene.duration,
            &mut scene.boundary_conditions,
            scene.contact.as_mut(),
        );
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
        let bad = |path: String, message: String, fix: &str| {
            SceneError::invalid(file, path, message, fix)
        };
        bodies::validate(&self.bodies, file)?;
        conditions::validate(&self.boundary_conditions, file)?;
        if self.analysis == Analysis::Static {
            conditions::validate_static(&self.boundary_conditions, self.duration, file)?;
        }
        for (i, w) in self.contact.iter().flat_map(|c| c.walls.iter().enumerate()) {
            let path = format!("contact.walls[{i}]");
            load_history::check_with_ramp(w.history.as_ref(), w.ramp, &path, file)?;
        }
        self.integrator.validate(self.analysis, file)?;
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
        self.damping.validate(file)?;
        if self.analysis == Analysis::Relaxation {
            self.integrator.validate_relaxation(&self.damping, file)?;
            if self.relaxation_choice().0 == integrator::RelaxationMethod::ConjugateGradient
                && let Some(c) = self.contact.as_ref().filter(|c| c.enabled)
            {
                c.refuse_friction(file)?;
            }
        } else if let Some(path) = [
            (
                "integrator.relaxation",
                self.integrator.relaxation.is_some(),
            ),
            (
                "integrator.relaxation_masses",
                self.integrator.relaxation_masses.is_some(),
            ),
        ]
        .into_iter()
        .find_map(|(p, given)| given.then_some(p))
        {
            return Err(bad(
                path.into(),
                format!("a {:?} analysis does not relax", self.analysis).to_lowercase(),
                &format!("remove `{path}`, or set \"analysis\": \"relaxation\""),
            ));
        }
        self.output.validate(&self.array_offer(), file)?;
        self.histories.validate(file)?;
        if let Some(f) = &self.fracture {
            f.validate(file)?;
        }
        initial_stress::validate(&self.initial_stress, file)?;
        let cx = mass_scaling::Context {
            analysis: self.analysis,
            time_step: &self.integrator.time_step,
            duration: self.duration,
        };
        mass_scaling::validate(self.mass_scaling.as_ref(), self.loading.as_ref(), &cx, file)?;
        Ok(())
    }
}

impl Scene {
    /// What the scene has that adds arrays to its frames (`output.arrays`).
    pub fn array_offer(&self) -> crate::input::arrays::Offer {
        crate::input::arrays::Offer {
            contact: self.contact.as_ref().is_some_and(|c| c.enabled),
            drawn_young: self
                .bodies
                .iter()
                .any(|b| b.materials.values().any(|m| m.heterogeneity.is_some())),
            fracture: self.fracture.is_some(),
            varied_joints: self.fracture.as_ref().is_some_and(|f| f.varied_joints()),
            fluid: self.fluid.is_some(),
        }
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
    fn class1_text_after_the_top_level_object_is_refused() {
        // a whole section pasted after the closing brace would be dropped unread
        let e = err(&format!(
            "{GOOD}\n{{\"damping\": {{\"mass_proportional\": 10}}}}"
        ));
        assert!(e.contains("s.json:7:1"), "{e}");
        assert!(e.contains("text follows it") && e.contains("fix:"), "{e}");
        let e = err(&format!("{GOOD} ,"));
        assert!(e.contains("text follows it"), "{e}");
        // white space after it is fine
        assert!(Scene::from_json(&format!("{GOOD}\n\n  \t\n"), Path::new("s.json")).is_ok());
    }

    #[test]
    fn class1_a_byte_order_mark_is_named() {
        let e = err(&format!("\u{feff}{GOOD}"));
        assert!(
            e.contains("byte-order mark") && e.contains("without"),
            "{e}"
        );
    }

    #[test]
    fn bad_json_reports_line_and_column() {
        let e = err("{\n \"bodies\": [,]\n}");
        assert!(e.contains("s.json:2:"), "{e}");
    }
}
