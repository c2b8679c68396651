//! `fdem run SCENE [--out DIR]`: runs a scene and writes its results (the run owns the
//! folder: fdem's files of an earlier run there are removed first).

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;
use fdem_solver::driver::{self, Progress, RunOptions};

/// Runs the scene at `scene`, writing into `out` (default `results/<scene name>`).
pub fn run(scene: &Path, out: Option<PathBuf>, raw: bool) -> Result<()> {
    let out = out.unwrap_or_else(|| {
        let stem = scene
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into());
        PathBuf::from("results").join(stem)
    });
    let mut loaded = driver::load(scene)?;
    eprintln!("{}", loaded.describe());
    let options = RunOptions {
        out_dir: out.clone(),
        raw,
    };
    let summary = if std::io::stderr().is_terminal() {
        let bar = indicatif::ProgressBar::new(1000);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {percent:>3}% t = {msg} [{elapsed_precise}, ETA {eta}]",
            )
            .expect("valid template"),
        );
        let s = driver::run(&mut loaded, &options, &mut |p: &Progress| {
            bar.set_position((1000.0 * p.fraction()) as u64);
            bar.set_message(format!("{:.4e} s, step {}", p.time, p.step));
        });
        bar.finish_and_clear();
        s?
    } else {
        let start = Instant::now();
        let mut last = -1.0f64;
        driver::run(&mut loaded, &options, &mut |p: &Progress| {
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
        })?
    };
    println!("{}", summary.describe());
    // Fracturing scenes: the load-displacement curve, when the run has one (platens, or a
    // group with reaction and displacement probes).
    if out.join("fractures.csv").exists() {
        match super::plot::load_displacement(std::slice::from_ref(&out), None, None, None, None) {
            Ok(files) => println!("load-displacement curve: {}", files[0].display()),
            Err(e) => eprintln!("no load-displacement curve: {e:#}"),
        }
    }
    println!("results in {}", out.display());
    // A relaxation that did not reach its tolerance: its output is written, and the exit
    // code (3) says the goal was not reached.
    if let Some(e) = fdem_solver::diagnosis::not_converged(&loaded.scene, &summary) {
        return Err(e.into());
    }
    Ok(())
}
