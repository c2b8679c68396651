//! Time histories of loads, prescribed motions and walls (the `"history"` field): a
//! dimensionless factor `f(t)` that multiplies the condition's value, given as a table of
//! points (piecewise linear) or as a named shape (`sine`, `repeat`, `steps`).
//!
//! ```json
//! "history": [[0, 0], [1e-3, 1], [2e-3, 1], [3e-3, 0]]
//! "history": {"sine": {"period": 1e-3, "amplitude": 1, "mean": 0, "phase_deg": 0, "cycles": 3}}
//! "history": {"repeat": {"table": [[0, 0], [1e-3, 1], [2e-3, 0]], "cycles": 4}}
//! "history": {"steps": {"values": [0.5, 1.0, 0.0], "rise": 1e-4, "hold": 1e-3}}
//! ```
//!
//! A table holds its first value before its first time and its last value after its last
//! time; times are >= 0 and strictly increasing. The evaluator is
//! [`crate::problem::time_function::History`]. This file only parses and checks the values
//! ([`check`], [`check_with_ramp`]), each error at its JSON path.

use std::fmt;
use std::path::Path;

use serde::de::value::{MapAccessDeserializer, SeqAccessDeserializer};
use serde::de::{Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};

use crate::error::SceneError;

/// A time history: a table `[[t0, f0], [t1, f1], ...]` or a named shape.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[serde(untagged)]
pub enum HistorySpec {
    /// Points `(t [s], f)`, linear between them, held before the first and after the last.
    Table(Vec<[f64; 2]>),
    /// A named shape.
    Shape(Shape),
}

/// The named shapes of a history.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum Shape {
    /// `mean + amplitude sin(2 pi t / period + phase)`, for `cycles` periods (default
    /// unbounded), then held at its value at the end.
    Sine(Sine),
    /// A table repeated with the period `t_last - t_first` from its first time, for `cycles`
    /// periods (default unbounded), then held at its value at the end.
    Repeat(Repeat),
    /// Stepped loading: stage `k` rises linearly over `rise` from the level before it (0
    /// before the first) to `values[k]`, then holds it for `hold`; the last level is held.
    Steps(Steps),
}

/// A sine history.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Sine {
    /// Period [s], > 0.
    pub period: f64,
    /// Amplitude (default 1).
    #[serde(default = "one")]
    pub amplitude: f64,
    /// Mean (default 0).
    #[serde(default)]
    pub mean: f64,
    /// Phase at t = 0 [degrees] (default 0; 90 gives a cosine).
    #[serde(default)]
    pub phase_deg: f64,
    /// Number of periods (> 0, fractions allowed), after which the value is held (default:
    /// unbounded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cycles: Option<f64>,
}

/// A repeated table.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Repeat {
    /// One period as a table (at least two points).
    pub table: Vec<[f64; 2]>,
    /// Number of periods (> 0, fractions allowed), after which the value is held (default:
    /// unbounded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cycles: Option<f64>,
}

/// Stepped loading.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Steps {
    /// The levels of the stages, in order (at least one).
    pub values: Vec<f64>,
    /// Rise time of each stage [s], > 0.
    pub rise: f64,
    /// Hold time of each stage [s], >= 0 (the last level is held for ever).
    pub hold: f64,
}

fn one() -> f64 {
    1.0
}

impl<'de> Deserialize<'de> for HistorySpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = HistorySpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a table [[t0, f0], [t1, f1], ...] or one of {\"sine\": {...}}, {\"repeat\": {...}}, {\"steps\": {...}}",
                )
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<HistorySpec, A::Error> {
                Vec::<[f64; 2]>::deserialize(SeqAccessDeserializer::new(seq))
                    .map(HistorySpec::Table)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<HistorySpec, A::Error> {
                Shape::deserialize(MapAccessDeserializer::new(map)).map(HistorySpec::Shape)
            }
        }
        d.deserialize_any(V)
    }
}

impl Steps {
    /// The table of the stages: from `(0, 0)`, each stage's end of rise and end of hold (the
    /// hold point left out when `hold` = 0).
    pub fn table(&self) -> Vec<[f64; 2]> {
        let mut pts = vec![[0.0, 0.0]];
        let mut t = 0.0;
        for &v in &self.values {
            t += self.rise;
            pts.push([t, v]);
            if self.hold > 0.0 {
                t += self.hold;
                pts.push([t, v]);
            }
        }
        pts
    }
}

impl HistorySpec {
    /// The time after which the history no longer changes [s] (`f64::INFINITY` for a sine or
    /// a repeated table without `cycles`).
    pub fn settle_time(&self) -> f64 {
        let last = |pts: &[[f64; 2]]| pts.last().map_or(0.0, |p| p[0]);
        match self {
            HistorySpec::Table(pts) => last(pts),
            HistorySpec::Shape(Shape::Steps(s)) => last(&s.table()),
            HistorySpec::Shape(Shape::Repeat(r)) => r.cycles.map_or(f64::INFINITY, |n| {
                let t0 = r.table.first().map_or(0.0, |p| p[0]);
                t0 + n * (last(&r.table) - t0)
            }),
            HistorySpec::Shape(Shape::Sine(s)) => s.cycles.map_or(f64::INFINITY, |n| n * s.period),
        }
    }
}

/// Checks a history at JSON path `path` (e.g. `boundary_conditions[2].pressure.history`).
pub fn check(h: &HistorySpec, path: &str, file: &Path) -> Result<(), SceneError> {
    let bad = |p: String, message: String, fix: &str| SceneError::invalid(file, p, message, fix);
    let finite = |p: String, what: &str, v: f64| {
        if v.is_finite() {
            Ok(())
        } else {
            Err(bad(
                p,
                format!("{what} {v} is not a finite number"),
                "give a finite number",
            ))
        }
    };
    let positive = |p: String, what: &str, v: f64, fix: &str| {
        if v > 0.0 && v.is_finite() {
            Ok(())
        } else {
            Err(bad(p, format!("{what} {v} must be > 0"), fix))
        }
    };
    match h {
        HistorySpec::Table(pts) => check_table(pts, path, 1, file),
        HistorySpec::Shape(Shape::Sine(s)) => {
            let p = format!("{path}.sine");
            positive(
                format!("{p}.period"),
                "period",
                s.period,
                "give the period in seconds",
            )?;
            finite(format!("{p}.amplitude"), "amplitude", s.amplitude)?;
            finite(format!("{p}.mean"), "mean", s.mean)?;
            finite(format!("{p}.phase_deg"), "phase", s.phase_deg)?;
            if let Some(c) = s.cycles {
                positive(
                    format!("{p}.cycles"),
                    "cycles",
                    c,
                    "give the number of periods, or leave it out for no end",
                )?;
            }
            Ok(())
        }
        HistorySpec::Shape(Shape::Repeat(r)) => {
            let p = format!("{path}.repeat");
            check_table(&r.table, &format!("{p}.table"), 2, file)?;
            if let Some(c) = r.cycles {
                positive(
                    format!("{p}.cycles"),
                    "cycles",
                    c,
                    "give the number of periods, or leave it out for no end",
                )?;
            }
            Ok(())
        }
        HistorySpec::Shape(Shape::Steps(s)) => {
            let p = format!("{path}.steps");
            if s.values.is_empty() {
                return Err(bad(
                    format!("{p}.values"),
                    "no stages: the list of values is empty".into(),
                    "give the level of each stage, e.g. [0.5, 1.0]",
                ));
            }
            for (k, v) in s.values.iter().enumerate() {
                finite(format!("{p}.values[{k}]"), "value", *v)?;
            }
            positive(
                format!("{p}.rise"),
                "rise",
                s.rise,
                "give the rise time of a stage in seconds (a jump excites waves: use a short rise)",
            )?;
            if !(s.hold >= 0.0 && s.hold.is_finite()) {
                return Err(bad(
                    format!("{p}.hold"),
                    format!("hold {} must be >= 0", s.hold),
                    "give the hold time of a stage in seconds",
                ));
            }
            check_table(&s.table(), &p, 1, file)
        }
    }
}

/// A table: at least `min` points, finite, times >= 0 and strictly increasing.
fn check_table(pts: &[[f64; 2]], path: &str, min: usize, file: &Path) -> Result<(), SceneError> {
    let bad = |p: String, message: String, fix: &str| SceneError::invalid(file, p, message, fix);
    if pts.len() < min {
        return Err(bad(
            path.into(),
            if pts.is_empty() {
                "the table is empty".into()
            } else {
                format!(
                    "the table has {} point, a period needs at least 2",
                    pts.len()
                )
            },
            "give points [[t0, f0], [t1, f1], ...] with increasing times in seconds",
        ));
    }
    for (k, [t, f]) in pts.iter().enumerate() {
        if !t.is_finite() || !f.is_finite() {
            return Err(bad(
                format!("{path}[{k}]"),
                format!("point [{t}, {f}] is not finite"),
                "give finite numbers [time, factor]",
            ));
        }
        if *t < 0.0 {
            return Err(bad(
                format!("{path}[{k}]"),
                format!("time {t} s is negative"),
                "give times >= 0 (the run starts at t = 0)",
            ));
        }
        if k > 0 && *t <= pts[k - 1][0] {
            return Err(bad(
                format!("{path}[{k}]"),
                format!(
                    "time {t} s is not after the previous point's time {} s: times must increase strictly",
                    pts[k - 1][0]
                ),
                "sort the points by time; for a jump, give two points a short time apart",
            ));
        }
    }
    Ok(())
}

/// The history of a condition and its `ramp`, at JSON path `path`: the history checked, and
/// both at once refused.
pub fn check_with_ramp(
    h: Option<&HistorySpec>,
    ramp: f64,
    path: &str,
    file: &Path,
) -> Result<(), SceneError> {
    if let Some(h) = h {
        if ramp != 0.0 {
            return Err(SceneError::invalid(
                file,
                format!("{path}.history"),
                format!("both `ramp` ({ramp} s) and `history` are given"),
                "give one of them: a ramp of T seconds is the history [[0, 0], [T, 1]]",
            ));
        }
        check(h, &format!("{path}.history"), file)?;
    }
    Ok(())
}
