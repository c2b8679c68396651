//! `fdem study scene SCENE`: the speed/accuracy trade of every time-integration scheme on a
//! real scene.
//!
//! Each scheme runs the scene at fractions `f` of its own predicted stable step
//! `h_pred = (h omega)_scheme / omega_max` ([`runs`]): error (analytical, a measure, or against
//! the finest run: [`reference`]), cost, and the observed stability limit, found by climbing a
//! ladder of steps ([`ladder`]) with stability probes from the highest modes ([`probes`],
//! [`seeds`]); on scenes with contact the limit is also read against the active prediction
//! ([`active`]). A side file `SCENE.study.json` declares the answer and the study's settings
//! ([`side_file`]). Output (in `--out`): `runs.csv`, `study.json` ([`report`]) and the charts
//! ([`charts`]).
//!
//! The steps of [`run`]: read the side file and the settings; write the studied scene; the
//! active-bound run; the probes' start state; each scheme up its ladder; the errors against
//! the reference run; the files, the charts and the table.

mod active;
mod charts;
mod ladder;
mod measures;
mod probes;
mod reference;
mod report;
mod runs;
mod seeds;
mod side_file;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use fdem_solver::driver;
use fdem_time::SchemeKind;

use active::Active;
use charts::Primary;
use probes::{PROBE_AMPLITUDE, ProbeStart};
use report::Report;
use side_file::{Analytical, ProbeFrom, ProbeFromName, SideFile};

/// Settings of the scene study.
#[derive(Args, Clone, Debug)]
pub struct SceneArgs {
    /// The scene file (a dynamic analysis).
    pub scene: PathBuf,
    /// Output folder (default out/study-<scene name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Schemes, comma separated (default: all).
    #[arg(long, value_delimiter = ',')]
    pub schemes: Vec<String>,
    /// Fractions of each scheme's predicted stable step, comma separated (default: the side
    /// file's `fractions`, else 0.1,0.2,0.4,0.7,0.9,0.99,1.01,1.05).
    #[arg(long, value_delimiter = ',')]
    pub fractions: Vec<f64>,
}

/// The default fractions of the predicted stable step.
const DEFAULT_FRACTIONS: [f64; 8] = [0.1, 0.2, 0.4, 0.7, 0.9, 0.99, 1.01, 1.05];

/// What every run of the study shares.
struct Study {
    /// The scene as studied (the side file's `set` applied).
    scene: PathBuf,
    /// The output folder.
    out: PathBuf,
    /// The answer the runs are measured against (side file `"reference"`).
    analytical: Option<Analytical>,
    /// The active prediction (scenes with contact).
    active: Option<Active>,
    /// `h_active / h_pred` (1 without contact).
    r_active: f64,
    /// Where the probes start (`None`: the reference state, at rest).
    start: Option<ProbeStart>,
    /// The probes' field amplitude, relative to the model size.
    amplitude: f64,
}

/// Runs the study.
pub fn run(args: &SceneArgs) -> Result<()> {
    let side = side_file::read(&args.scene)?;
    let (kinds, fractions) = settings(args, side.as_ref())?;
    let stem = args
        .scene
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("scene")
        .to_string();
    let study = prepare(args, side, &stem)?;
    let l0 = driver::load(&study.scene)?;
    let (nodes, triangles) = (l0.model.n_nodes(), l0.model.triangles.len());
    drop(l0);

    // The reference: the highest-order scheme at the smallest fraction.
    let ref_kind = reference::reference_scheme(&kinds);
    let bar = progress_bar((kinds.len() * fractions.len()) as u64);
    let mut raws = Vec::new();
    let mut limits = Vec::new();
    for &k in &kinds {
        limits.push(ladder::scheme_ladder(
            &study, k, &fractions, &bar, &mut raws,
        )?);
    }
    bar.finish_and_clear();
    let f_min = fractions[0];
    let analytical = study.analytical.as_ref();
    let runs = reference::errors(raws, ref_kind, f_min, analytical);
    let start = study.start.as_ref();
    let report = Report {
        scene: args.scene.display().to_string(),
        analytical,
        reference_run: format!("{} at {f_min} h_pred", ref_kind.name()),
        nodes,
        triangles,
        active: study.active.as_ref(),
        probe_from: start.map(|s| s.time),
        probe_start_broken: start.and_then(|s| s.joints.as_ref()).map(|j| j.n_broken),
        probe_frozen: start.is_some_and(|s| s.frozen),
        probe_amplitude: study.amplitude,
        limits: &limits,
        runs: &runs,
    };
    report::write(&study.out, &report)?;
    let primary = match analytical {
        Some(a) if a.is_analytical() => Primary::Analytical,
        Some(Analytical::Collision {}) => Primary::Measure("kinetic energy ratio after/before"),
        Some(_) => Primary::Measure("peak load"),
        None => Primary::Reference,
    };
    let files = charts::plots(
        &study.out,
        &stem,
        &kinds,
        &runs,
        &limits,
        primary,
        study.r_active,
    )?;
    report::print_table(&stem, &report, &study.out);
    for f in files {
        println!("wrote {}", f.display());
    }
    Ok(())
}

/// The schemes and the fractions (sorted, without repeats): the command line's, else the
/// side file's, else all schemes and [`DEFAULT_FRACTIONS`].
fn settings(args: &SceneArgs, side: Option<&SideFile>) -> Result<(Vec<SchemeKind>, Vec<f64>)> {
    let kinds = match side.and_then(|s| s.schemes.clone()) {
        Some(list) if args.schemes.is_empty() => schemes(&list)?,
        _ => schemes(&args.schemes)?,
    };
    let mut fractions = if !args.fractions.is_empty() {
        args.fractions.clone()
    } else if let Some(f) = side.and_then(|s| s.fractions.clone()) {
        f
    } else {
        DEFAULT_FRACTIONS.to_vec()
    };
    if fractions.is_empty() || fractions.iter().any(|f| !(*f > 0.0 && f.is_finite())) {
        return Err(crate::bad_input(
            "--fractions must be positive numbers, e.g. 0.1,0.5,0.9",
        ));
    }
    fractions.sort_by(f64::total_cmp);
    fractions.dedup();
    Ok((kinds, fractions))
}

fn schemes(names: &[String]) -> Result<Vec<SchemeKind>> {
    if names.is_empty() {
        return Ok(SchemeKind::ALL.to_vec());
    }
    names
        .iter()
        .map(|n| {
            n.parse::<SchemeKind>().map_err(|_| {
                crate::bad_input(format!(
                    "unknown scheme '{}': use one of {}",
                    fdem_solver::excerpt(n),
                    SchemeKind::valid_names()
                ))
            })
        })
        .collect()
}

/// Everything before the runs: the scene checked (bad input, exit code 2: it must load, as
/// a dynamic analysis; checked before anything is written unless the side file edits the
/// scene, then on the edited scene), the output folder, the studied scene, the active-bound
/// run, the probes' start and amplitude.
fn prepare(args: &SceneArgs, side: Option<SideFile>, stem: &str) -> Result<Study> {
    let validate = |scene: &Path| -> Result<()> {
        let l0 = driver::load(scene)?;
        if l0.scene.analysis != fdem_solver::input::scene::Analysis::Dynamic {
            return Err(crate::bad_input(format!(
                "{}: the study needs a dynamic analysis with a positive duration",
                args.scene.display()
            )));
        }
        Ok(())
    };
    let edits = side.as_ref().is_some_and(|s| !s.set.is_empty());
    if !edits {
        validate(&args.scene)?;
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("out/study-{stem}")));
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let scene = side_file::study_scene(&args.scene, side.as_ref(), &out)?;
    if edits {
        validate(&scene)?;
    }
    let active = active::active_bound_run(&scene, &out.join("runs").join("active-bound"))?;
    let r_active = active.as_ref().map(|a| a.ratio).unwrap_or(1.0);
    let probe_from = side.as_ref().and_then(|s| s.probe_from);
    let start = start_state(args, probe_from, &scene, active.as_ref(), &out)?;
    let amplitude = side
        .as_ref()
        .and_then(|s| s.probe_amplitude)
        .unwrap_or(PROBE_AMPLITUDE);
    if !(amplitude > 0.0 && amplitude < 1e-2) {
        return Err(crate::bad_input(format!(
            "`probe_amplitude` must be in (0, 1e-2) of the model size (default {PROBE_AMPLITUDE})"
        )));
    }
    Ok(Study {
        scene,
        out,
        analytical: side.and_then(|s| s.reference),
        active,
        r_active,
        start,
        amplitude,
    })
}

/// The probes' start state ([`ProbeStart`]) the side file asks for, run into
/// `OUT/runs/probe-start`.
fn start_state(
    args: &SceneArgs,
    probe_from: Option<ProbeFrom>,
    scene: &Path,
    active: Option<&Active>,
    out: &Path,
) -> Result<Option<ProbeStart>> {
    let start_dir = out.join("runs").join("probe-start");
    Ok(match probe_from {
        Some(ProbeFrom::Time(t)) => Some(probes::probe_start(scene, t, None, &start_dir)?),
        Some(ProbeFrom::Named(ProbeFromName::Active)) => {
            let (t, w) = active
                .filter(|a| a.omega_contact_active > 0.0)
                .map(|a| (a.omega_contact_active_time, a.omega_active))
                .with_context(|| {
                    format!(
                        "{}: `\"probe_from\": \"active\"` needs contact engaged during the scene (none was): leave it out to probe from rest",
                        args.scene.with_extension("study.json").display()
                    )
                })?;
            Some(probes::probe_start(scene, t, Some(w), &start_dir)?)
        }
        None => None,
    })
}

/// The progress bar over `len` runs (hidden when stderr is not a terminal).
fn progress_bar(len: u64) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} runs {msg} [{elapsed_precise}, ETA {eta}]",
        )
        .expect("valid template"),
    );
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    bar
}
