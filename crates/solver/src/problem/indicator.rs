//! One accuracy indicator ([`Indicator`]: its value, threshold, meaning and warning) and the
//! console block of a list of them ([`describe`]); [`crate::problem::accuracy`] and
//! [`crate::problem::plausibility`] make them, `crate::run::accuracy` adds the run's.

use std::fmt::Write as _;

use serde::Serialize;

/// Which side of its threshold an indicator's value must lie on.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Good {
    /// At least the threshold.
    AtLeast,
    /// At most the threshold.
    AtMost,
}

/// One accuracy indicator of a run.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Indicator {
    /// Its name (`process_zone_i`, `process_zone_ii`, `joint_compliance`, `mesh_quality`,
    /// `units`, `time_step`, `energy_error`, `quasi_static`, `contact_penetration`,
    /// `static_strain`).
    pub name: String,
    /// What it is about: a JSON path of the scene (`fracture.material`), `mesh` or `run`.
    pub subject: String,
    /// What the value is, in words (`l_ch / median joint length`).
    pub measure: String,
    /// The value.
    pub value: f64,
    /// The threshold.
    pub threshold: f64,
    /// The side of the threshold that passes.
    pub good: Good,
    /// What it means.
    pub meaning: String,
    /// When it fails: what is wrong and the fix, in plain words.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warning: Option<String>,
    /// The figures behind the value.
    pub details: serde_json::Value,
}

impl Indicator {
    /// Whether the value lies on the good side of the threshold.
    pub fn passes(&self) -> bool {
        match self.good {
            Good::AtLeast => self.value >= self.threshold,
            Good::AtMost => self.value <= self.threshold,
        }
    }
}

/// A length in the unit that reads best (m, mm or um), 3 significant digits.
pub fn length(x: f64) -> String {
    let a = x.abs();
    if a >= 0.1 || a == 0.0 {
        format!("{x:.3} m")
    } else if a >= 1e-4 {
        format!("{:.3} mm", x * 1e3)
    } else {
        format!("{:.3} um", x * 1e6)
    }
}

/// The console block of `indicators`: one line each, `ok` or `WARN` with the warning and its
/// fix on the next line.
pub fn describe(indicators: &[Indicator]) -> String {
    let mut s = String::new();
    for i in indicators {
        let side = match i.good {
            Good::AtLeast => ">=",
            Good::AtMost => "<=",
        };
        let tag = if i.passes() { "ok  " } else { "WARN" };
        let _ = write!(
            s,
            "\n  {tag} {:<20} {}: {} = {} ({side} {})",
            i.name,
            i.subject,
            short(&i.measure),
            number(i.value),
            number(i.threshold)
        );
        if let Some(w) = &i.warning {
            let _ = write!(s, "\n       {w}");
        }
    }
    s
}

/// The part of a measure before its parenthesis.
fn short(measure: &str) -> &str {
    measure.split(" (").next().unwrap_or(measure).trim()
}

/// A number in 3 significant digits, fixed or scientific as it reads best.
pub fn number(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 {
        "0".into()
    } else if x.fract() == 0.0 && a < 1e6 {
        format!("{x:.0}")
    } else if (1e-2..1e4).contains(&a) {
        let digits = (2 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.2e}")
    }
}

/// The accuracy section of a run summary.
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct Accuracy {
    /// How many indicators warn.
    pub warnings: usize,
    /// Every indicator, in the order of the console block.
    pub indicators: Vec<Indicator>,
}

impl Accuracy {
    /// Collects `indicators` and counts their warnings.
    pub fn new(indicators: Vec<Indicator>) -> Self {
        let warnings = indicators.iter().filter(|i| !i.passes()).count();
        Accuracy {
            warnings,
            indicators,
        }
    }
}
