//! The optional `"contact"` section: contact between the bodies (and between pieces of one
//! body) and with rigid walls, its laws per pair of bodies, the detection buffer and the
//! limits of a run with contact. The contact stage (`crate::stages::contact`) reads it.

use std::path::Path;

use fdem_contact::ContactLaw;
use serde::{Deserialize, Serialize};

use super::load_history::HistorySpec;
use crate::error::{Range, SceneError};

/// The scene's `"contact"` section. Present and `enabled` (default true): contact between all
/// bodies (and between separate pieces of one body, e.g. crack faces), and with the walls.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSection {
    /// Contact switched on (default true).
    #[serde(default = "yes")]
    pub enabled: bool,
    /// The law between every pair of bodies not listed in `pairs`.
    #[serde(default)]
    pub default: LawSpec,
    /// Laws for particular pairs of bodies (by body name; a body with itself is allowed).
    #[serde(default)]
    pub pairs: Vec<PairSpec>,
    /// Rigid walls, floors and moving platens.
    #[serde(default)]
    pub walls: Vec<WallSpec>,
    /// Detection buffer [m], >= 0 (default 0: 0.2 times the mean triangle radius).
    #[serde(default)]
    pub buffer: f64,
    /// Largest allowed `phi = 3 d / H` on a contact before the run stops as too deep a
    /// penetration (default 0.5).
    #[serde(default = "default_max_phi")]
    pub max_phi: f64,
    /// Steps between the samples of the active frequency bound recorded over the run
    /// (`omega_active_max` in the summary; default 10; 1: every step, as `fdem study scene`'s
    /// bound run takes it; 0: never). Each sample costs about a contact pass over the
    /// couples that carry load.
    #[serde(default = "default_active_every")]
    pub active_bound_every: u64,
}

/// The valid range of `contact.max_phi`.
pub const MAX_PHI: Range = Range::open_closed(0.0, 1.0);

fn yes() -> bool {
    true
}
fn default_max_phi() -> f64 {
    0.5
}
fn default_active_every() -> u64 {
    10
}
fn default_factor() -> f64 {
    ContactLaw::DEFAULT_PENALTY_FACTOR
}

/// One contact law.
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LawSpec {
    /// Normal penalty `p` [Pa] (default: `penalty_factor` times the larger Young's modulus of
    /// the two bodies).
    #[serde(default)]
    pub penalty: Option<f64>,
    /// Penalty as a multiple of Young's modulus when `penalty` is not given (default 10).
    #[serde(default = "default_factor")]
    pub penalty_factor: f64,
    /// Coulomb friction coefficient (default 0).
    #[serde(default)]
    pub friction: f64,
    /// Tangential penalty `k_t` [Pa] (default: the normal penalty).
    #[serde(default)]
    pub tangential_penalty: Option<f64>,
    /// Normal contact damping [Pa s/m] (default 0).
    #[serde(default)]
    pub damping: f64,
}

impl Default for LawSpec {
    fn default() -> Self {
        Self {
            penalty: None,
            penalty_factor: default_factor(),
            friction: 0.0,
            tangential_penalty: None,
            damping: 0.0,
        }
    }
}

/// A contact law for one pair of bodies.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PairSpec {
    /// The two body names.
    pub bodies: [String; 2],
    /// The law.
    #[serde(default)]
    pub law: LawSpec,
    /// Set false to switch contact off between these bodies (default true).
    #[serde(default = "yes")]
    pub enabled: bool,
    /// The two bodies may overlap at t = 0 (a deliberate press fit; default false: an
    /// initial overlap is refused at load, `crate::problem::input_checks`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub allow_initial_overlap: bool,
}

/// A rigid wall (half-space): the solid lies behind the line through `point`, `normal` points
/// into the free side. With a `velocity` it is a platen moving as `point + velocity r(t)`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    /// Name (in `walls.csv`).
    #[serde(default)]
    pub name: Option<String>,
    /// A point of the wall at t = 0 [m].
    pub point: [f64; 2],
    /// Outward normal (normalised here).
    pub normal: [f64; 2],
    /// Prescribed velocity [m/s] (default at rest).
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Ramp time of the velocity [s] (default 0: a step).
    #[serde(default)]
    pub ramp: f64,
    /// Time history of the factor on the velocity (default none: the `ramp`); not with
    /// `ramp`. The wall moves as `point + velocity F(t)`, `F` the history's integral.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history: Option<HistorySpec>,
    /// The wall's contact law (penalty default: `penalty_factor` times the largest Young's
    /// modulus of the scene).
    #[serde(default)]
    pub law: LawSpec,
    /// Bodies may start behind the wall (a deliberate initial indentation; default false: a
    /// node behind the wall at t = 0 is refused at load, `crate::problem::input_checks`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub allow_initial_overlap: bool,
}

impl ContactSection {
    /// Refuses a law with friction (a conjugate-gradient relaxation minimises a potential
    /// energy, and Coulomb friction has none: its slip depends on the path), naming the
    /// first such law's `friction`; `file` names the scene.
    /// The first law (its JSON path and the law) that makes contact non-conservative:
    /// friction or damping; `None` when contact is off or every law is frictionless and
    /// undamped.
    pub fn dissipative_law(&self) -> Option<(String, &LawSpec)> {
        if !self.enabled {
            return None;
        }
        self.laws()
            .find(|(_, l)| l.friction > 0.0 || l.damping > 0.0)
    }

    /// Every law in force: the default, the enabled pairs', the walls' (with JSON paths).
    fn laws(&self) -> impl Iterator<Item = (String, &LawSpec)> {
        std::iter::once(("contact.default".to_string(), &self.default))
            .chain(
                self.pairs
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| p.enabled)
                    .map(|(i, p)| (format!("contact.pairs[{i}].law"), &p.law)),
            )
            .chain(
                self.walls
                    .iter()
                    .enumerate()
                    .map(|(i, w)| (format!("contact.walls[{i}].law"), &w.law)),
            )
    }

    pub(crate) fn refuse_friction(&self, file: &Path) -> Result<(), SceneError> {
        for (path, law) in self.laws() {
            if law.friction > 0.0 {
                return Err(SceneError::invalid(
                    file,
                    format!("{path}.friction"),
                    format!(
                        "friction {} with a \"conjugate-gradient\" relaxation, which minimises a potential energy: friction has none (its slip depends on the path)",
                        law.friction
                    ),
                    "use \"kinetic\" relaxation (`integrator.relaxation`), or frictionless contact",
                ));
            }
        }
        Ok(())
    }

    /// Checks the values, each against its range (the body names are resolved by
    /// [`crate::input::resolve`]); `file` names the scene in errors.
    pub fn validate(&self, file: &Path) -> Result<(), SceneError> {
        let range = |path: String, what: &str, v: f64, r: Range, fix: &str| {
            SceneError::check_range(file, path, what, v, r, fix)
        };
        let check_law = |path: String, l: &LawSpec| -> Result<(), SceneError> {
            if let Some(p) = l.penalty {
                range(
                    format!("{path}.penalty"),
                    "penalty",
                    p,
                    Range::above(0.0),
                    "give a positive penalty [Pa], e.g. 10 times Young's modulus",
                )?;
            }
            range(
                format!("{path}.penalty_factor"),
                "penalty factor",
                l.penalty_factor,
                Range::above(0.0),
                "use e.g. 10 (the penalty is this times Young's modulus)",
            )?;
            range(
                format!("{path}.friction"),
                "friction coefficient",
                l.friction,
                Range::at_least(0.0),
                "use a Coulomb coefficient such as 0.5 (0: frictionless)",
            )?;
            if let Some(k) = l.tangential_penalty {
                range(
                    format!("{path}.tangential_penalty"),
                    "tangential penalty",
                    k,
                    Range::above(0.0),
                    "leave it out to use the normal penalty",
                )?;
            }
            range(
                format!("{path}.damping"),
                "contact damping",
                l.damping,
                Range::at_least(0.0),
                "use 0, or 2 xi sqrt(6 p rho) for a damping ratio of about xi",
            )
        };
        check_law("contact.default".into(), &self.default)?;
        for (i, p) in self.pairs.iter().enumerate() {
            check_law(format!("contact.pairs[{i}].law"), &p.law)?;
        }
        for (i, w) in self.walls.iter().enumerate() {
            check_law(format!("contact.walls[{i}].law"), &w.law)?;
            let n = (w.normal[0].powi(2) + w.normal[1].powi(2)).sqrt();
            if !(n > 0.0 && n.is_finite()) {
                return Err(SceneError::invalid(
                    file,
                    format!("contact.walls[{i}].normal"),
                    "the normal must be a nonzero vector",
                    "give the outward normal, e.g. [0, 1] for a floor",
                ));
            }
            range(
                format!("contact.walls[{i}].ramp"),
                "ramp",
                w.ramp,
                Range::at_least(0.0),
                "set ramp to a time >= 0 in seconds",
            )?;
        }
        range(
            "contact.buffer".into(),
            "detection buffer",
            self.buffer,
            Range::at_least(0.0),
            "give the buffer in m, or 0 for 0.2 times the mean triangle radius",
        )?;
        range(
            "contact.max_phi".into(),
            "largest penetration ratio",
            self.max_phi,
            MAX_PHI,
            "use 0.5",
        )
    }
}
