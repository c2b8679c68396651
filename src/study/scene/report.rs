//! What the scene study writes: `runs.csv` (one line a run), `study.json` (the settings, the
//! active prediction, each scheme's limits and probes, every run) and the table on stdout.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;
use serde::Serialize;

use super::active::Active;
use super::ladder::Limit;
use super::runs::Run;
use super::side_file::Analytical;

/// `study.json`.
#[derive(Serialize)]
pub(super) struct Report<'a> {
    pub(super) scene: String,
    pub(super) analytical: Option<&'a Analytical>,
    pub(super) reference_run: String,
    pub(super) nodes: usize,
    pub(super) triangles: usize,
    /// The active prediction (scenes with contact).
    pub(super) active: Option<&'a Active>,
    /// The time of the state the probes start from [s] (None: the reference state, at rest).
    pub(super) probe_from: Option<f64>,
    /// Whether that state is frozen (`"probe_from": "active"`,
    /// [`ProbeStart`](super::probes::ProbeStart)).
    pub(super) probe_frozen: bool,
    /// Broken joints in that state (scenes with joints; their pairs are contact couples
    /// through the probes).
    pub(super) probe_start_broken: Option<usize>,
    /// The probes' field amplitude, relative to the model size.
    pub(super) probe_amplitude: f64,
    pub(super) limits: &'a [Limit],
    pub(super) runs: &'a [Run],
}

/// Writes `runs.csv` and `study.json` into `out`.
pub(super) fn write(out: &Path, report: &Report) -> Result<()> {
    crate::write_atomically(&out.join("runs.csv"), csv(report.runs).as_bytes())?;
    crate::write_atomically(
        &out.join("study.json"),
        serde_json::to_string_pretty(report)?.as_bytes(),
    )?;
    Ok(())
}

/// The table on stdout: the scene, the predictions, each scheme's observed limit, each run's
/// cost and errors.
pub(super) fn print_table(stem: &str, report: &Report, out: &Path) {
    let (nodes, triangles) = (report.nodes, report.triangles);
    let (active, limits, runs) = (report.active, report.limits, report.runs);
    println!(
        "{stem}: {nodes} nodes, {triangles} triangles; reference {}",
        report.reference_run
    );
    if let Some(a) = active {
        println!(
            "frequency bound: a priori {:.4e} rad/s, active {:.4e} rad/s (contact engaged: {:.4e} at t = {:.3e} s): h_active = {:.4} h_pred",
            a.omega_a_priori,
            a.omega_active,
            a.omega_contact_active,
            a.omega_contact_active_time,
            a.ratio
        );
    }
    println!(
        "{:<20} {:>12} {:>18} {:>12} {:>20}",
        "scheme", "h_pred (s)", "observed / h_pred", "h_active (s)", "observed / h_active"
    );
    for l in limits {
        let below = l
            .observed_below
            .map(|b| format!("{b}"))
            .unwrap_or_else(|| ">".into());
        let below_a = l
            .observed_over_active_below
            .map(|b| format!("{b:.3}"))
            .unwrap_or_else(|| ">".into());
        println!(
            "{:<20} {:>12.4e} {:>18} {:>12.4e} {:>20}",
            l.scheme,
            l.dt_predicted,
            format!("[{}, {below})", l.observed_at_least),
            l.dt_active,
            format!("[{:.3}, {below_a})", l.observed_over_active_at_least),
        );
    }
    println!(
        "{:<20} {:>6} {:>10} {:>8} {:>10} {:>12} {:>12}",
        "scheme", "h/hp", "wall (s)", "forces", "Mel-st/s", "err vs ref", "err analyt."
    );
    let o = |v: Option<f64>| v.map(|v| format!("{v:.3e}")).unwrap_or_else(|| "-".into());
    for r in runs {
        println!(
            "{:<20} {:>6} {:>10.3} {:>8} {:>10.2} {:>12} {:>12}{}",
            r.scheme,
            r.fraction,
            r.wall_time,
            r.force_evaluations,
            r.triangle_steps_per_second / 1e6,
            o(r.error_vs_reference),
            o(r.error_analytical),
            if r.stable { "" } else { "  UNSTABLE" }
        );
    }
    println!(
        "wrote {} and {}",
        out.join("runs.csv").display(),
        out.join("study.json").display()
    );
}

/// `runs.csv`: one line a run.
fn csv(runs: &[Run]) -> String {
    let mut s = String::from(
        "scheme,fraction,dt,dt_predicted,steps,stable,force_evaluations,wall_time,triangle_steps_per_second,energy_ratio,error_vs_reference,error_analytical,measured,error,measured2,error_measure,error_measure2\n",
    );
    let o = |v: Option<f64>| v.map(|v| format!("{v:e}")).unwrap_or_default();
    for r in runs {
        let _ = writeln!(
            s,
            "{},{},{:e},{:e},{},{},{},{:e},{:e},{},{},{},{},{},{},{},{}",
            r.scheme,
            r.fraction,
            r.dt,
            r.dt_predicted,
            r.steps,
            r.stable,
            r.force_evaluations,
            r.wall_time,
            r.triangle_steps_per_second,
            o(r.energy_ratio),
            o(r.error_vs_reference),
            o(r.error_analytical),
            o(r.measured),
            o(r.error),
            o(r.measured2),
            o(r.error_measure),
            o(r.error_measure2)
        );
    }
    s
}
