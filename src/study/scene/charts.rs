//! The charts of the scene study, as PNG and SVG: `work_precision` (error against wall time),
//! `error_vs_step` (x = `h / h_pred`, the predicted limit at 1, each scheme's observed limit
//! in its legend), the same two with the error against the reference (`*_reference`, when the
//! primary error is analytical or a measure) and `energy_vs_step` (final energy over energy
//! put in).

use std::path::{Path, PathBuf};

use anyhow::Result;
use fdem_time::SchemeKind;

use super::ladder::Limit;
use super::runs::Run;
use crate::plot::{Plot, Scale, Series};

/// Which error the first pair of charts shows.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Primary {
    /// Against the scene's analytical answer.
    Analytical,
    /// A scalar measure (named) against the reference run's.
    Measure(&'static str),
    /// The displacements against the reference run.
    Reference,
}

/// Picks one error of a run.
type ErrorOf = fn(&Run) -> Option<f64>;

/// The runs and limits the charts draw.
struct Data<'a> {
    stem: &'a str,
    kinds: &'a [SchemeKind],
    runs: &'a [Run],
    limits: &'a [Limit],
}

/// Writes the charts into `out` (file names without the scene's `stem`, which titles them);
/// returns the files written.
pub(super) fn plots(
    out: &Path,
    stem: &str,
    kinds: &[SchemeKind],
    runs: &[Run],
    limits: &[Limit],
    primary: Primary,
    r_active: f64,
) -> Result<Vec<PathBuf>> {
    let data = Data {
        stem,
        kinds,
        runs,
        limits,
    };
    let mut plots = Vec::new();
    for (suffix, what, pick) in kinds_of_error(primary) {
        plots.extend(data.error_charts(suffix, &what, pick, r_active));
    }
    plots.push(data.energy_chart());
    let mut files = Vec::new();
    for (name, p) in plots {
        files.extend(p.write(&out.join(name))?);
    }
    Ok(files)
}

/// The errors charted, each with its file-name suffix and axis label: the primary error
/// (analytical when declared), and the error against the reference run as a second pair of
/// charts when the primary one is not that.
fn kinds_of_error(primary: Primary) -> Vec<(&'static str, String, ErrorOf)> {
    let mut kinds_of_error: Vec<(&str, String, ErrorOf)> = Vec::new();
    match primary {
        Primary::Analytical => kinds_of_error.push((
            "",
            "relative error against the analytical answer".into(),
            |r| r.error_analytical,
        )),
        Primary::Measure(what) => kinds_of_error.push((
            "",
            format!("relative error of the {what} against the reference run"),
            |r| r.error_measure,
        )),
        Primary::Reference => {}
    }
    kinds_of_error.push((
        if primary == Primary::Reference {
            ""
        } else {
            "_reference"
        },
        "relative error of the displacements against the reference run".into(),
        |r| r.error_vs_reference,
    ));
    kinds_of_error
}

impl Data<'_> {
    /// A scheme's legend entry: its name and, with `limits`, its observed limit.
    fn label(&self, k: &SchemeKind) -> String {
        let l = self.limits.iter().find(|l| l.scheme == k.name());
        match l {
            Some(Limit {
                observed_at_least,
                observed_below: Some(b),
                ..
            }) => format!(
                "{} (observed limit in [{observed_at_least}, {b}) h_pred)",
                k.name()
            ),
            Some(l) => format!(
                "{} (observed limit > {} h_pred)",
                k.name(),
                l.observed_at_least
            ),
            None => k.name().into(),
        }
    }

    /// One series a scheme: the points `pick` takes from its stable runs.
    fn series(&self, pick: &dyn Fn(&Run) -> Option<(f64, f64)>, with_label: bool) -> Vec<Series> {
        self.kinds
            .iter()
            .map(|k| Series {
                name: if with_label {
                    self.label(k)
                } else {
                    k.name().into()
                },
                points: self
                    .runs
                    .iter()
                    .filter(|r| r.scheme == k.name() && r.stable)
                    .filter_map(pick)
                    .collect(),
            })
            .collect()
    }

    /// `work_precision{suffix}` and `error_vs_step{suffix}` for the error `pick` (axis label
    /// `what`), the latter with the predicted step (and the active one, `r_active` times it,
    /// when it differs) as vertical lines.
    fn error_charts(
        &self,
        suffix: &str,
        what: &str,
        pick: ErrorOf,
        r_active: f64,
    ) -> [(String, Plot); 2] {
        let stem = self.stem;
        let mut err_vs_step = self.series(&|r| pick(r).map(|e| (r.fraction, e)), true);
        let ys: Vec<f64> = self
            .runs
            .iter()
            .filter_map(pick)
            .filter(|e| *e > 0.0)
            .collect();
        let (lo, hi) = ys
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(*v), b.max(*v)));
        if lo.is_finite() {
            err_vs_step.push(Series {
                name: "predicted stable step (all schemes)".into(),
                points: vec![(1.0, lo), (1.0, hi)],
            });
            if r_active != 1.0 {
                err_vs_step.push(Series {
                    name: format!("active prediction ({r_active:.3} h_pred, all schemes)"),
                    points: vec![(r_active, lo), (r_active, hi)],
                });
            }
        }
        [
            (
                format!("work_precision{suffix}"),
                Plot {
                    title: format!("{stem}: work-precision (stable runs)"),
                    x_label: "wall time of the run (s)".into(),
                    y_label: what.to_string(),
                    x_scale: Scale::Log,
                    y_scale: Scale::Log,
                    series: self.series(&|r| pick(r).map(|e| (r.wall_time, e)), false),
                    y_range: None,
                    lines: false,
                },
            ),
            (
                format!("error_vs_step{suffix}"),
                Plot {
                    title: format!("{stem}: error against the time step"),
                    x_label: "h / h_pred (h_pred: scheme limit over the element frequency bound)"
                        .into(),
                    y_label: what.to_string(),
                    x_scale: Scale::Log,
                    y_scale: Scale::Log,
                    series: err_vs_step,
                    y_range: None,
                    lines: true,
                },
            ),
        ]
    }

    /// `energy_vs_step`: final energy over energy put in, against the step.
    fn energy_chart(&self) -> (String, Plot) {
        let mut energy = self.series(&|r| r.energy_ratio.map(|e| (r.fraction, e)), true);
        energy.push(Series {
            name: "predicted stable step (all schemes)".into(),
            points: vec![(1.0, 0.1), (1.0, 10.0)],
        });
        (
            "energy_vs_step".to_string(),
            Plot {
                title: format!("{}: final energy / energy put in (stable runs)", self.stem),
                x_label: "h / h_pred".into(),
                y_label: "(K + U) / (work in + K0)".into(),
                x_scale: Scale::Log,
                y_scale: Scale::Log,
                series: energy,
                y_range: None,
                lines: true,
            },
        )
    }
}
