//! What a run's files measure: a column of its histories (or of another CSV file it
//! wrote), and the analytical measure a side file declares with its relative error.

use std::path::Path;

use anyhow::{Context, Result};

use super::side_file::Analytical;

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
