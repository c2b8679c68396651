//! `fdem study oscillator`: the comparison of the reference (seed eqs 5.116-5.120).
//!
//! Every scheme integrates `x'' + omega^2 x = 0`, `omega = 1`, `x(0) = 0`, `v(0) = 1`
//! (exact `x = sin t`) for 40 periods (`t_e = 80 pi ~ 251 s`) with each step `h` of a grid
//! (0.01 to 7.00 by 0.01 by default). A run takes `ceil(t_e / h)` steps and is compared
//! with the exact solution at each step. For each scheme and `h` it records: bounded or
//! not (`|x| <= 100` throughout: a stable scheme near its limit may exceed the exact
//! amplitude 1 by its discrete invariant, 10 for central difference at `h = 1.99`), the
//! amplitude growth (largest `|x|` over the last quarter of the steps over that over the
//! first quarter; informative only: near a limit the discrete orbit beats slowly and the
//! ratio can exceed 1 without any instability), the
//! error of `x` at the last step and the largest over the run, the largest relative energy
//! error, the force and gradient evaluations, the spectral radius of the one-step operator
//! and the wall time of the run (without the error bookkeeping; the fastest of at least
//! three repeats lasting 1 ms in all).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use fdem_time::stability::spectral_radius;
use fdem_time::systems::Oscillator;
use fdem_time::{SchemeKind, State};
use serde::Serialize;

use crate::plot::{Plot, Scale, Series};

/// Settings of the oscillator study.
#[derive(Args, Clone, Debug)]
pub struct OscillatorArgs {
    /// Output folder (created if missing).
    #[arg(long, default_value = "out/study-oscillator")]
    pub out: PathBuf,
    /// Schemes to run, comma separated (default: all): central-difference, pc3, pc4, pc5,
    /// chin, omf30, omf32, forest-ruth.
    #[arg(long, value_delimiter = ',')]
    pub schemes: Vec<String>,
    /// Smallest time step (s).
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub h_min: f64,
    /// Largest time step (s).
    #[arg(long, default_value_t = 7.0, allow_negative_numbers = true)]
    pub h_max: f64,
    /// Increment of the time step (s).
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    pub h_step: f64,
    /// Length of each run in periods of the oscillator (2 pi s each).
    #[arg(long, default_value_t = 40.0, allow_negative_numbers = true)]
    pub periods: f64,
}

/// A run is bounded while `|x|` stays at or below this (the exact amplitude is 1).
const BOUND: f64 = 100.0;
/// Each timed run is repeated at least 3 times and until this much wall time has passed
/// (s); the fastest repeat is kept (robust to preemption on a shared machine).
const MIN_TIMED: f64 = 1e-3;

/// One scheme at one step.
#[derive(Clone, Debug, Serialize)]
struct Run {
    h: f64,
    bounded: bool,
    /// Largest |x| over the last quarter of the steps over that over the first quarter
    /// (None when the run left the bound).
    amplitude_growth: Option<f64>,
    steps: u64,
    forces: u64,
    gradients: u64,
    /// |x - sin t| at the last step (None when unbounded).
    err_x_end: Option<f64>,
    /// Largest |x - sin t| over the run (None when unbounded).
    err_x_max: Option<f64>,
    /// Largest |E - E0| / E0 over the run (None when unbounded).
    err_energy_max: Option<f64>,
    /// Spectral radius of the one-step operator at this h.
    spectral_radius: f64,
    /// Wall time of one run (s).
    wall_s: f64,
}

/// The cheapest run that reached a target accuracy.
#[derive(Clone, Debug, Serialize)]
struct Cheapest {
    h: f64,
    evaluations: u64,
    wall_s: f64,
}

/// Everything about one scheme.
#[derive(Clone, Debug, Serialize)]
struct SchemeResult {
    name: &'static str,
    forces_per_step: u32,
    gradients_per_step: u32,
    symplectic: bool,
    /// Order of the largest error, fitted over the bounded runs with 0.01 <= h <= 0.5 and
    /// 1e-10 < error < 1e-2 (the asymptotic range, above round-off).
    fitted_order: Option<f64>,
    /// Largest stable h from the spectral radius (long-run criterion).
    computed_limit: f64,
    /// Largest h of the grid below which every run stayed bounded.
    observed_limit: Option<f64>,
    /// Intervals of h above the first unbounded one where runs are bounded again.
    bounded_again: Vec<(f64, f64)>,
    /// Largest error over the run at h = 0.1 (if on the grid).
    err_x_max_at_0_1: Option<f64>,
    /// Fewest force + gradient evaluations for a largest error <= 1e-2.
    cheapest_1e_2: Option<Cheapest>,
    /// Fewest force + gradient evaluations for a largest error <= 1e-6.
    cheapest_1e_6: Option<Cheapest>,
    runs: Vec<Run>,
}

/// The JSON document.
#[derive(Serialize)]
struct Report<'a> {
    study: &'static str,
    omega: f64,
    x0: f64,
    v0: f64,
    periods: f64,
    t_end: f64,
    bound: f64,
    schemes: &'a [SchemeResult],
}

fn positive(name: &str, v: f64) -> Result<f64> {
    if !v.is_finite() || v <= 0.0 {
        return Err(crate::bad_input(format!(
            "--{name} must be a positive, finite number, got {v}"
        )));
    }
    Ok(v)
}

/// Validated settings: the schemes and the grid of steps.
fn validate(args: &OscillatorArgs) -> Result<(Vec<SchemeKind>, Vec<f64>, f64)> {
    let kinds = if args.schemes.is_empty() {
        SchemeKind::ALL.to_vec()
    } else {
        args.schemes
            .iter()
            .map(|s| s.trim().parse::<SchemeKind>())
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| crate::bad_input(e.to_string()))?
    };
    let h_min = positive("h-min", args.h_min)?;
    let h_max = positive("h-max", args.h_max)?;
    let h_step = positive("h-step", args.h_step)?;
    let periods = positive("periods", args.periods)?;
    if h_min > h_max {
        return Err(crate::bad_input(format!(
            "--h-min ({h_min}) must not exceed --h-max ({h_max})"
        )));
    }
    let n = ((h_max - h_min) / h_step + 1e-9).floor();
    if n > 1e5 {
        return Err(crate::bad_input(format!(
            "--h-step {h_step} gives {n} steps between {h_min} and {h_max}: at most 100000 are allowed"
        )));
    }
    let round = |h: f64| (h * 1e12).round() / 1e12;
    let hs = (0..=n as usize)
        .map(|k| round(h_min + k as f64 * h_step))
        .collect();
    Ok((kinds, hs, periods * std::f64::consts::TAU))
}

/// Runs one scheme at one step with the error bookkeeping.
fn run_one(kind: SchemeKind, h: f64, t_end: f64) -> Run {
    let steps = (t_end / h).ceil() as u64;
    let mut sys = Oscillator::new(1, 1.0);
    let mut st = State::new(0.0, vec![0.0], vec![1.0]);
    let mut scheme = kind.build(1);
    let e0 = 0.5;
    let (mut emax, mut en_max, mut e_end) = (0.0_f64, 0.0_f64, 0.0);
    let mut bounded = true;
    let quarter = steps.div_ceil(4);
    let (mut first_q, mut last_q) = (0.0_f64, 0.0_f64);
    for i in 0..steps {
        scheme.step(&mut sys, &mut st, h);
        let x = st.x[0];
        if x.is_nan() || x.abs() > BOUND {
            bounded = false;
            break;
        }
        if i < quarter {
            first_q = first_q.max(x.abs());
        }
        if i >= steps - quarter {
            last_q = last_q.max(x.abs());
        }
        e_end = (x - st.t.sin()).abs();
        emax = emax.max(e_end);
        en_max = en_max.max((sys.energy(&st.x, &st.v) - e0).abs() / e0);
    }
    let growth = bounded.then(|| last_q / first_q.max(f64::MIN_POSITIVE));
    let c = scheme.counters();
    Run {
        h,
        bounded,
        amplitude_growth: growth,
        steps: c.steps,
        forces: c.forces,
        gradients: c.gradients,
        err_x_end: bounded.then_some(e_end),
        err_x_max: bounded.then_some(emax),
        err_energy_max: bounded.then_some(en_max),
        spectral_radius: spectral_radius(kind, h),
        wall_s: time_run(kind, h, steps),
    }
}

/// Wall time of a plain run of `steps` steps (stopping early if it leaves the bound):
/// the fastest of at least 3 repeats lasting `MIN_TIMED` in all.
fn time_run(kind: SchemeKind, h: f64, steps: u64) -> f64 {
    let (mut best, mut total) = (f64::INFINITY, 0.0);
    let mut reps = 0u32;
    loop {
        let start = Instant::now();
        let mut sys = Oscillator::new(1, 1.0);
        let mut st = State::new(0.0, vec![0.0], vec![1.0]);
        let mut scheme = kind.build(1);
        for _ in 0..steps {
            scheme.step(&mut sys, &mut st, h);
            if st.x[0].is_nan() || st.x[0].abs() > BOUND {
                break;
            }
        }
        std::hint::black_box(&st);
        let el = start.elapsed().as_secs_f64();
        best = best.min(el);
        total += el;
        reps += 1;
        if (reps >= 3 && total >= MIN_TIMED) || reps >= 10_000 {
            return best;
        }
    }
}

fn slope(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 3 {
        return None;
    }
    let n = points.len() as f64;
    let (mx, my) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + x.ln() / n, b + y.ln() / n)
    });
    let sxy: f64 = points
        .iter()
        .map(|(x, y)| (x.ln() - mx) * (y.ln() - my))
        .sum();
    let sxx: f64 = points.iter().map(|(x, _)| (x.ln() - mx).powi(2)).sum();
    Some(sxy / sxx)
}

fn summarise(kind: SchemeKind, runs: Vec<Run>) -> SchemeResult {
    let cost = kind.cost();
    let fit: Vec<(f64, f64)> = runs
        .iter()
        .filter(|r| (0.01..=0.5).contains(&r.h))
        .filter_map(|r| {
            r.err_x_max
                .filter(|e| *e > 1e-10 && *e < 1e-2)
                .map(|e| (r.h, e))
        })
        .collect();
    let first_bad = runs.iter().position(|r| !r.bounded);
    let observed_limit = match first_bad {
        Some(0) => None,
        Some(i) => Some(runs[i - 1].h),
        None => runs.last().map(|r| r.h),
    };
    let mut bounded_again = Vec::new();
    if let Some(i) = first_bad {
        let mut open: Option<(f64, f64)> = None;
        for r in &runs[i..] {
            match (r.bounded, open.as_mut()) {
                (true, Some(iv)) => iv.1 = r.h,
                (true, None) => open = Some((r.h, r.h)),
                (false, Some(_)) => bounded_again.extend(open.take()),
                (false, None) => {}
            }
        }
        bounded_again.extend(open);
    }
    let err_x_max_at_0_1 = runs
        .iter()
        .find(|r| (r.h - 0.1).abs() < 1e-9)
        .and_then(|r| r.err_x_max);
    let cheapest = |target: f64| {
        runs.iter()
            .filter(|r| r.bounded && r.err_x_max.is_some_and(|e| e <= target))
            .min_by_key(|r| r.forces + r.gradients)
            .map(|r| Cheapest {
                h: r.h,
                evaluations: r.forces + r.gradients,
                wall_s: r.wall_s,
            })
    };
    let (cheapest_1e_2, cheapest_1e_6) = (cheapest(1e-2), cheapest(1e-6));
    SchemeResult {
        name: kind.name(),
        forces_per_step: cost.forces,
        gradients_per_step: cost.gradients,
        symplectic: kind.is_symplectic(),
        fitted_order: slope(&fit),
        computed_limit: kind.stability_limit(),
        observed_limit,
        bounded_again,
        err_x_max_at_0_1,
        cheapest_1e_2,
        cheapest_1e_6,
        runs,
    }
}

fn opt(v: Option<f64>) -> String {
    v.map(|v| format!("{v:e}")).unwrap_or_default()
}

fn csv(results: &[SchemeResult]) -> String {
    let mut s = String::from(
        "scheme,h,bounded,amplitude_growth,steps,forces,gradients,err_x_end,err_x_max,err_energy_max,spectral_radius,wall_s\n",
    );
    for r in results {
        for run in &r.runs {
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{},{},{},{},{:e},{:e}",
                r.name,
                run.h,
                run.bounded,
                opt(run.amplitude_growth),
                run.steps,
                run.forces,
                run.gradients,
                opt(run.err_x_end),
                opt(run.err_x_max),
                opt(run.err_energy_max),
                run.spectral_radius,
                run.wall_s
            );
        }
    }
    s
}

fn plots(results: &[SchemeResult], out: &Path) -> Result<Vec<PathBuf>> {
    let series = |f: &dyn Fn(&Run) -> Option<(f64, f64)>| -> Vec<Series> {
        results
            .iter()
            .map(|r| Series {
                name: r.name.to_string(),
                points: r.runs.iter().filter_map(f).collect(),
            })
            .collect()
    };
    let evals = |r: &Run| (r.forces + r.gradients) as f64;
    // Errors above 2 mean a run that is bounded but wholly wrong: cut at 10.
    let log_log = |title: &str, x: &str, y: &str, s: Vec<Series>| {
        let lo = s
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.1))
            .filter(|e| *e > 0.0)
            .fold(f64::INFINITY, f64::min);
        let lo = if lo.is_finite() {
            10f64.powf(lo.log10().floor())
        } else {
            1e-16
        };
        Plot {
            title: title.into(),
            x_label: x.into(),
            y_label: y.into(),
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            series: s,
            y_range: Some((lo, 10.0)),
            lines: true,
        }
    };
    let mut written = Vec::new();
    let plots = [
        (
            "error_vs_h",
            log_log(
                "Oscillator, 40 periods: largest error of x over the run",
                "time step h (s), omega = 1",
                "max |x - sin t|",
                series(&|r| r.err_x_max.map(|e| (r.h, e))),
            ),
        ),
        (
            "error_end_vs_h",
            log_log(
                "Oscillator: error of x at t_e = 40 periods",
                "time step h (s), omega = 1",
                "|x(t_e) - sin t_e|",
                series(&|r| r.err_x_end.map(|e| (r.h, e))),
            ),
        ),
        (
            "error_vs_evaluations",
            log_log(
                "Oscillator, 40 periods: error against cost",
                "force + gradient evaluations",
                "max |x - sin t|",
                series(&|r| r.err_x_max.map(|e| (evals(r), e))),
            ),
        ),
        (
            "error_vs_seconds",
            Plot {
                lines: false,
                ..log_log(
                    "Oscillator, 40 periods: error against wall time (1 DOF)",
                    "wall time of the run (s, fastest of the repeats)",
                    "max |x - sin t|",
                    series(&|r| r.err_x_max.map(|e| (r.wall_s, e))),
                )
            },
        ),
        (
            "energy_error_vs_h",
            log_log(
                "Oscillator, 40 periods: largest relative energy error",
                "time step h (s), omega = 1",
                "max |E - E0| / E0",
                series(&|r| r.err_energy_max.map(|e| (r.h, e))),
            ),
        ),
        (
            "spectral_radius",
            Plot {
                title: "Spectral radius of the one-step operator (clipped to [0.5, 2])".into(),
                x_label: "h omega".into(),
                y_label: "rho(T(h))".into(),
                x_scale: Scale::Linear,
                y_scale: Scale::Linear,
                series: series(&|r| Some((r.h, r.spectral_radius.clamp(0.5, 2.0)))),
                y_range: Some((0.5, 2.0)),
                lines: true,
            },
        ),
    ];
    for (name, p) in plots {
        written.extend(p.write(&out.join(name))?);
    }
    Ok(written)
}

fn table(results: &[SchemeResult]) -> String {
    let mut s = String::new();
    let head = [
        (
            "scheme", "", "f+g", "/step", "order", "(fit)", "limit", "computed", "observed",
            "40 per.",
        ),
        ("", "", "", "", "", "", "", "", "", ""),
    ];
    let (h1, h2) = (head[0], head[1]);
    let _ = h2;
    let _ = writeln!(
        s,
        "{:<19} {:>5} {:>6} {:>9} {:>9} {:>10} {:>25} {:>25}",
        h1.0,
        h1.2,
        h1.4,
        h1.6,
        h1.8,
        "max err",
        "cheapest max err <= 1e-2",
        "cheapest max err <= 1e-6"
    );
    let _ = writeln!(
        s,
        "{:<19} {:>5} {:>6} {:>9} {:>9} {:>10} {:>25} {:>25}",
        "", h1.3, h1.5, h1.7, h1.9, "at h=0.1", "h / evals / seconds", "h / evals / seconds"
    );
    let cheap = |c: &Option<Cheapest>| {
        c.as_ref()
            .map(|c| format!("{:.2} / {} / {:.1e}", c.h, c.evaluations, c.wall_s))
            .unwrap_or_else(|| "-".into())
    };
    for r in results {
        let _ = writeln!(
            s,
            "{:<19} {:>5} {:>6} {:>9.4} {:>9} {:>10} {:>25} {:>25}",
            r.name,
            format!("{}+{}", r.forces_per_step, r.gradients_per_step),
            r.fitted_order
                .map(|p| format!("{p:.2}"))
                .unwrap_or_else(|| "-".into()),
            r.computed_limit,
            r.observed_limit
                .map(|h| format!("{h:.2}"))
                .unwrap_or_else(|| "-".into()),
            r.err_x_max_at_0_1
                .map(|e| format!("{e:.2e}"))
                .unwrap_or_else(|| "-".into()),
            cheap(&r.cheapest_1e_2),
            cheap(&r.cheapest_1e_6)
        );
        if !r.bounded_again.is_empty() {
            let iv: Vec<String> = r
                .bounded_again
                .iter()
                .map(|(a, b)| format!("[{a:.2}, {b:.2}]"))
                .collect();
            let _ = writeln!(s, "{:<19} bounded again for h in {}", "", iv.join(", "));
        }
    }
    s
}

/// Runs the study and writes its files.
pub fn run(args: &OscillatorArgs) -> Result<()> {
    let (kinds, hs, t_end) = validate(args)?;
    let started = Instant::now();
    let results: Vec<SchemeResult> = kinds
        .iter()
        .map(|&kind| summarise(kind, hs.iter().map(|&h| run_one(kind, h, t_end)).collect()))
        .collect();
    let out = &args.out;
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let mut written = Vec::new();
    let csv_path = out.join("oscillator.csv");
    crate::write_atomically(&csv_path, csv(&results).as_bytes())?;
    written.push(csv_path);
    let json_path = out.join("oscillator.json");
    let report = Report {
        study: "oscillator",
        omega: 1.0,
        x0: 0.0,
        v0: 1.0,
        periods: args.periods,
        t_end,
        bound: BOUND,
        schemes: &results,
    };
    crate::write_atomically(
        &json_path,
        serde_json::to_string_pretty(&report)?.as_bytes(),
    )?;
    written.push(json_path);
    written.extend(plots(&results, out)?);
    print!("{}", table(&results));
    println!(
        "{} schemes x {} steps h in [{}, {}], {:.1} s; wrote:",
        results.len(),
        hs.len(),
        hs[0],
        hs[hs.len() - 1],
        started.elapsed().as_secs_f64()
    );
    for p in written {
        println!("  {}", p.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args() -> OscillatorArgs {
        OscillatorArgs {
            out: PathBuf::from("unused"),
            schemes: vec![],
            h_min: 0.01,
            h_max: 7.0,
            h_step: 0.01,
            periods: 40.0,
        }
    }

    #[test]
    fn default_grid_is_0_01_to_7_by_0_01() {
        let (kinds, hs, t_end) = validate(&args()).unwrap();
        assert_eq!(kinds.len(), 8);
        assert_eq!(hs.len(), 700);
        assert_eq!((hs[0], hs[299], hs[699]), (0.01, 3.0, 7.0));
        assert!((t_end - 80.0 * std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn bad_input_is_an_error_that_says_what_is_wrong() {
        let mut a = args();
        a.schemes = vec!["verlet".into()];
        let e = validate(&a).unwrap_err().to_string();
        assert!(
            e.contains("verlet") && e.contains("central-difference"),
            "{e}"
        );
        for (field, v) in [
            ("h-min", 0.0),
            ("h-min", -1.0),
            ("h-max", f64::NAN),
            ("h-step", f64::INFINITY),
        ] {
            let mut a = args();
            match field {
                "h-min" => a.h_min = v,
                "h-max" => a.h_max = v,
                _ => a.h_step = v,
            }
            let e = validate(&a).unwrap_err().to_string();
            assert!(e.contains(field), "{e}");
        }
    }

    #[test]
    fn central_difference_run_matches_the_closed_form_error() {
        // Central difference on x'' = -x has phase per step 2 asin(h/2): at h = 0.1 the
        // largest error over 40 periods is close to the phase lag (h^2/24) t_e = 0.1047
        // times the amplitude (within 2 %, the amplitude factor being 1 + O(h^2)).
        let r = run_one(
            SchemeKind::CentralDifference,
            0.1,
            80.0 * std::f64::consts::PI,
        );
        assert!(r.bounded);
        let lag = 0.01 / 24.0 * 80.0 * std::f64::consts::PI;
        let e = r.err_x_max.unwrap();
        assert!((e - lag).abs() < 0.02 * lag, "{e} vs {lag}");
        assert_eq!(r.forces, 1 + r.steps);
    }
}
