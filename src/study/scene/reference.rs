//! The errors of the stable runs: against the scene's analytical answer, and against the
//! reference run (the highest-order scheme at the smallest fraction).
//!
//! - `error_vs_reference`: `max_i |u_i - u_ref,i| / max_i |u_ref,i|` over the nodes at the
//!   final time, against the reference run (OMF32 at the smallest fraction when run);
//! - `error_analytical`, when the side file declares an analytical answer (bar arrival, first
//!   frequency: [`super::side_file`]);
//! - `error_measure` (and `error_measure2`), when the side file declares a measure without an
//!   analytical value (collision, fracture), against the reference run's.
//!
//! The primary `error` is the analytical one when declared, else the measure's when declared,
//! else the displacements' against the reference.

use std::path::Path;

use anyhow::{Context, Result};
use fdem_time::SchemeKind;

use super::runs::{Raw, Run};
use super::side_file::Analytical;

/// The reference scheme: the highest-order one run. (OMF32 when it is run: of the
/// fourth-order schemes its error constant is by far the smallest, 2e-8 against 2e-6 for CHIN
/// and Forest & Ruth on the oscillator, docs/time-integration.md.)
pub(super) fn reference_scheme(kinds: &[SchemeKind]) -> SchemeKind {
    if kinds.contains(&SchemeKind::Omf32) {
        SchemeKind::Omf32
    } else {
        kinds
            .iter()
            .copied()
            .max_by_key(|k| k.measured_order())
            .unwrap_or(SchemeKind::ForestRuth)
    }
}

/// The errors of the stable runs against the reference run (`ref_kind` at the smallest
/// fraction `f_min`, when it is stable) and each run's primary `error`.
pub(super) fn errors(
    mut raws: Vec<Raw>,
    ref_kind: SchemeKind,
    f_min: f64,
    analytical: Option<&Analytical>,
) -> Vec<Run> {
    let ref_raw = raws
        .iter()
        .find(|r| r.run.scheme == ref_kind.name() && r.run.fraction == f_min && r.run.stable);
    let reference = ref_raw.map(|r| r.displacement.clone());
    let (m_ref, m2_ref) = ref_raw
        .map(|r| (r.run.measured, r.run.measured2))
        .unwrap_or((None, None));
    let by_measure = analytical.is_some_and(|a| !a.is_analytical());
    if by_measure {
        for r in raws.iter_mut().filter(|r| r.run.stable) {
            if let (Some(m), Some(mr)) = (r.run.measured, m_ref) {
                r.run.error_measure = Some((m - mr).abs() / mr.abs().max(f64::MIN_POSITIVE));
            }
            if let Some(Analytical::Fracture { .. }) = analytical
                && let (Some(c), Some(cr)) = (r.run.measured2, m2_ref)
            {
                r.run.error_measure2 = Some((c - cr).abs());
            }
        }
    }
    if let Some(u_ref) = &reference {
        let scale = u_ref
            .iter()
            .map(|u| u[0].abs().max(u[1].abs()))
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        for r in raws.iter_mut().filter(|r| r.run.stable) {
            let d = r
                .displacement
                .iter()
                .zip(u_ref)
                .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
                .fold(0.0, f64::max);
            r.run.error_vs_reference = Some(d / scale);
        }
    }
    raws.into_iter()
        .map(|mut r| {
            r.run.error = if by_measure {
                r.run.error_measure
            } else if analytical.is_some() {
                r.run.error_analytical
            } else {
                r.run.error_vs_reference
            };
            r.run
        })
        .collect()
}

/// The column named `probe` of a run's `histories.csv` in `out`, with the times.
pub(super) fn read_history(out: &Path, probe: &str) -> Result<(Vec<f64>, Vec<f64>)> {
    read_csv_column(&out.join("histories.csv"), probe)
}

/// The first column and the column named `probe` of a CSV file with a header.
pub(super) fn read_csv_column(p: &Path, probe: &str) -> Result<(Vec<f64>, Vec<f64>)> {
    let text = std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?;
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let col = head
        .iter()
        .position(|h| *h == probe)
        .with_context(|| format!("no history column '{probe}' (columns: {})", head.join(",")))?;
    let (mut t, mut u) = (Vec::new(), Vec::new());
    for l in lines {
        let f: Vec<f64> = l
            .split(',')
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect();
        if f.len() > col {
            t.push(f[0]);
            u.push(f[col]);
        }
    }
    Ok((t, u))
}

/// The analytical measure and its relative error.
pub(super) fn analytical_error(a: &Analytical, out: &Path) -> Result<Option<(f64, f64)>> {
    match a {
        Analytical::BarArrival {
            probe,
            length,
            wave_speed,
            ..
        } => {
            let (t, u) = read_history(out, probe)?;
            let tc = length / wave_speed;
            let pts: Vec<(f64, f64)> = t
                .iter()
                .zip(&u)
                .filter(|(t, _)| **t >= 1.25 * tc && **t <= 1.5 * tc)
                .map(|(t, u)| (*t, *u))
                .collect();
            if pts.len() < 2 {
                return Ok(None);
            }
            let n = pts.len() as f64;
            let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
            let sxx: f64 = pts.iter().map(|p| p.0 * p.0).sum();
            let sxy: f64 = pts.iter().map(|p| p.0 * p.1).sum();
            let b = (n * sxy - sx * sy) / (n * sxx - sx * sx);
            let a0 = (sy - b * sx) / n;
            let arr = -a0 / b;
            Ok(arr.is_finite().then(|| (arr, (arr - tc).abs() / tc)))
        }
        Analytical::FirstFrequency { probe, frequency } => {
            let (t, u) = read_history(out, probe)?;
            let mean = u.iter().sum::<f64>() / u.len().max(1) as f64;
            let mut ups = Vec::new();
            for i in 1..u.len() {
                let (a, b) = (u[i - 1] - mean, u[i] - mean);
                if a < 0.0 && b >= 0.0 {
                    ups.push(t[i - 1] + (t[i] - t[i - 1]) * (-a) / (b - a));
                }
            }
            if ups.len() < 2 {
                return Ok(None);
            }
            let f = (ups.len() - 1) as f64 / (ups[ups.len() - 1] - ups[0]);
            Ok(Some((f, (f - frequency).abs() / frequency)))
        }
        Analytical::Collision {} | Analytical::Fracture { .. } => Ok(None),
    }
}
