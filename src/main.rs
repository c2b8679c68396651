//! The `fdem` command-line program: a thin dispatcher to the subcommands.
//!
//! - `fdem run SCENE [--out DIR] [--raw]`: run a scene (`src/cmd/run.rs`).
//! - `fdem check SCENE`: validate a scene, stable steps, estimated time (`src/cmd/check.rs`).
//! - `fdem info MESH`: describe a mesh file (`src/cmd/info.rs`).
//! - `fdem plot load-displacement DIR...`: load-displacement curves of runs (`src/cmd/plot.rs`).
//! - `fdem study oscillator [--out DIR]`: the time-integration study (`src/study/`).

mod cmd;
mod plot;
mod study;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

/// fdem: a 2D combined finite-discrete element solver.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene: writes a ParaView collection (.pvd + .vtu), histories.csv and summary.json.
    Run {
        /// The scene file (JSON, see docs/scene-format.md).
        scene: PathBuf,
        /// Output folder (default results/<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Also write each frame's arrays as JSON (frame_NNNN.json), for independent checks.
        #[arg(long)]
        raw: bool,
    },
    /// Validate a scene: report the mesh, each scheme's stable time step and the run time.
    Check {
        /// The scene file.
        scene: PathBuf,
    },
    /// Describe a mesh file: counts, physical groups, element sizes.
    Info {
        /// The mesh file (.msh or .json).
        mesh: PathBuf,
    },
    /// Plots of run results (PNG and SVG).
    #[command(subcommand)]
    Plot(cmd::plot::PlotCommand),
    /// Numerical studies that reproduce and extend the reference's comparisons.
    #[command(subcommand)]
    Study(study::StudyCommand),
}

/// Writes `bytes` to `path` whole or not at all: a temporary file beside it, then a rename.
pub(crate) fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".part");
    std::fs::write(&tmp, bytes)
        .with_context(|| format!("writing {}", Path::new(&tmp).display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("writing {}", path.display()))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run { scene, out, raw } => cmd::run::run(&scene, out, raw),
        Command::Check { scene } => cmd::check::check(&scene),
        Command::Info { mesh } => cmd::info::info(&mesh),
        Command::Plot(cmd) => cmd::plot::run(cmd),
        Command::Study(cmd) => study::run(cmd),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // The whole chain of causes on one line, no backtrace: the message says the fix.
            eprintln!("error: {e:#}");
            // 2: the input (scene, mesh) is invalid; 1: the run itself failed.
            let input = e.downcast_ref::<fdem_solver::SceneError>().is_some()
                || matches!(
                    e.downcast_ref::<fdem_solver::RunError>(),
                    Some(fdem_solver::RunError::Scene(_))
                );
            ExitCode::from(if input { 2 } else { 1 })
        }
    }
}
