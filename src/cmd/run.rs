//! `fdem run SCENE [--out DIR]`: runs a scene and writes its results (the run owns the
//! folder: fdem's files of an earlier run there are removed first); `fdem run --resume DIR`
//! continues a run from its checkpoint. SIGINT/SIGTERM stop a run with a checkpoint.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize};
use std::time::Instant;

use anyhow::Result;
use fdem_solver::driver::{self, Progress, RunOptions};

/// What `fdem run` was given.
pub struct RunArgs {
    /// The scene (with `resume`: the checkpointed run's scene by default).
    pub scene: Option<PathBuf>,
    /// The output folder.
    pub out: Option<PathBuf>,
    /// Also write raw JSON frames.
    pub raw: bool,
    /// `--checkpoint-every`.
    pub checkpoint_every: Option<fdem_solver::checkpoint::Every>,
    /// `--resume DIR`.
    pub resume: Option<PathBuf>,
    /// `--stop-after STEPS`.
    pub stop_after: Option<u64>,
    /// `--rebalance RATIO|off` (distributed runs).
    pub rebalance: Option<f64>,
}

/// SIGINT and SIGTERM: the first sets `stop` to the signal's number (the run stops after its
/// step with a checkpoint), a second one ends the process at once (code 128 + the number).
pub(super) fn stop_on_signals() -> Result<Arc<AtomicUsize>> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let stop = Arc::new(AtomicUsize::new(0));
    let armed = Arc::new(AtomicBool::new(false));
    for sig in [SIGINT, SIGTERM] {
        signal_hook::flag::register_conditional_shutdown(sig, 128 + sig, Arc::clone(&armed))?;
        signal_hook::flag::register(sig, Arc::clone(&armed))?;
        signal_hook::flag::register_usize(sig, Arc::clone(&stop), sig as usize)?;
    }
    Ok(stop)
}

/// The scene of a resumed run: the one given, else the one the checkpoint names.
pub(super) fn resumed_scene(dir: &Path, scene: Option<PathBuf>) -> Result<PathBuf> {
    if let Some(s) = scene {
        return Ok(s);
    }
    let file = dir.join(fdem_solver::checkpoint::FILE_NAME);
    let cp = fdem_solver::checkpoint::read(&file).map_err(fdem_solver::RunError::from)?;
    let scene = cp.header.scene_file;
    if !scene.exists() {
        return Err(crate::bad_input(format!(
            "{}: the checkpoint's scene {} is not there any more\n  fix: give it: fdem run SCENE --resume {}",
            file.display(),
            scene.display(),
            dir.display()
        )));
    }
    Ok(scene)
}

/// A resume of `loaded` from the checkpoint in `dir`, checked before anything is written
/// (`driver::open_checkpoint`: the scene, the end, the folder) and with the checkpoint's time
/// step kept, so that the scene's description gives the step the run takes; returns the line
/// that says where the run goes on from. A static analysis is refused by the run itself.
pub(super) fn open_resumed(
    loaded: &mut fdem_solver::Problem,
    dir: &Path,
) -> Result<Option<String>, fdem_solver::RunError> {
    if loaded.scene.analysis == fdem_solver::input::scene::Analysis::Static {
        return Ok(None);
    }
    let cp = driver::open_checkpoint(loaded, dir)?;
    Ok(Some(driver::describe_resume(loaded, &cp.header)))
}

/// Fracturing scenes: the load-displacement curve of the run in `out`, when the run has one
/// (platens, or a group with reaction and displacement probes).
pub(super) fn plot_curve(out: &Path) {
    if out.join("fractures.csv").exists() {
        match super::plot::load_displacement(
            std::slice::from_ref(&out.to_path_buf()),
            None,
            None,
            None,
            None,
        ) {
            Ok(files) => {
                // a specimen between platens: its stress-strain curve too
                let specimen = std::fs::read_to_string(out.join("summary.json"))
                    .ok()
                    .and_then(|s| serde_json::from_str::<serde_json::Value>(&s).ok())
                    .is_some_and(|v| v.pointer("/result/specimen").is_some());
                match specimen.then(|| super::plot::stress_strain(&[out.to_path_buf()], None, None))
                {
                    Some(Ok(ss)) => {
                        println!("curves: {} and {}", files[0].display(), ss[0].display())
                    }
                    Some(Err(e)) => {
                        println!("load-displacement curve: {}", files[0].display());
                        eprintln!("no stress-strain curve: {e:#}");
                    }
                    None => println!("load-displacement curve: {}", files[0].display()),
                }
            }
            Err(e) => eprintln!("no load-displacement curve: {e:#}"),
        }
    }
}

/// The progress without a terminal: a line on stderr every tenth of the run and at its end.
pub fn progress_lines() -> impl FnMut(&Progress) {
    let start = Instant::now();
    let mut last = -1.0f64;
    move |p: &Progress| {
        let f = p.fraction();
        if f - last >= 0.1 || f >= 1.0 && last < 1.0 {
            last = f;
            eprintln!(
                "{:5.1}%  t = {:.4e} s  step {}  wall {:.1} s",
                100.0 * f,
                p.time,
                p.step,
                start.elapsed().as_secs_f64()
            );
        }
    }
}

/// Runs a scene (or resumes a run) in this process, writing into `out` (default
/// `results/<scene name>`).
pub fn run(args: RunArgs) -> Result<()> {
    let RunArgs {
        scene,
        out,
        raw,
        checkpoint_every,
        resume,
        stop_after,
        rebalance,
    } = args;
    let scene = match &resume {
        Some(dir) => resumed_scene(dir, scene)?,
        None => scene.expect("clap requires a scene without --resume"),
    };
    let scene = scene.as_path();
    let out = resume.clone().or(out).unwrap_or_else(|| {
        let stem = scene
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into());
        PathBuf::from("results").join(stem)
    });
    let mut loaded = driver::load(scene)?;
    let resumed = resume
        .as_deref()
        .map(|dir| open_resumed(&mut loaded, dir))
        .transpose()?
        .flatten();
    eprintln!("{}", loaded.describe());
    if let Some(line) = &resumed {
        eprintln!("{line}");
    }
    let options = RunOptions {
        out_dir: out.clone(),
        raw,
        checkpoint_every,
        // a static solve is one step: a signal stops it at once, as by default
        stop: if loaded.scene.analysis == fdem_solver::input::scene::Analysis::Static {
            None
        } else {
            Some(stop_on_signals()?)
        },
        stop_after,
        resume: resume.is_some(),
        rebalance,
    };
    let outcome = if std::io::stderr().is_terminal() {
        let bar = indicatif::ProgressBar::new(1000);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {percent:>3}% t = {msg} [{elapsed_precise}, ETA {eta}]",
            )
            .expect("valid template"),
        );
        let s = driver::run_outcome(&mut loaded, &options, &mut |p: &Progress| {
            bar.set_position((1000.0 * p.fraction()) as u64);
            bar.set_message(format!("{:.4e} s, step {}", p.time, p.step));
        });
        bar.finish_and_clear();
        s
    } else {
        driver::run_outcome(&mut loaded, &options, &mut progress_lines())
    };
    let outcome = match outcome {
        Ok(o) => o,
        Err(e) => {
            // a run stopped as unstable: its files so far, the curve included
            if matches!(e, fdem_solver::RunError::Unstable { .. }) {
                plot_curve(&out);
            }
            return Err(e.into());
        }
    };
    let summary = &outcome.summary;
    println!("{}", summary.describe());
    let c = &outcome.checkpoints;
    if c.written > 0 {
        println!(
            "checkpoint: {} ({:.1} MB, written {} times; the run waited {:.3} s for each, the writes took {:.3} s each on their own thread)",
            out.join(fdem_solver::checkpoint::FILE_NAME).display(),
            c.bytes as f64 / 1e6,
            c.written,
            c.encode_time / c.written as f64,
            c.write_time / c.written as f64
        );
    }
    plot_curve(&out);
    println!("results in {}", out.display());
    // A relaxation that did not reach its tolerance: its output is written, and the exit
    // code (3) says the goal was not reached.
    if let Some(e) = fdem_solver::run::diagnosis::not_converged(&loaded.scene, summary) {
        return Err(e.into());
    }
    Ok(())
}
