//! The `fdem` command-line program. Subcommands arrive with the crates that implement them.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod cmd;

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
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run { scene, out, raw } => cmd::run::run(&scene, out, raw),
        Command::Check { scene } => cmd::check::check(&scene),
        Command::Info { mesh } => cmd::info::info(&mesh),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            // 2: the input (scene, mesh) is invalid; 1: the run itself failed.
            let input = e.downcast_ref::<fdem_solver::SceneError>().is_some()
                || matches!(
                    e.downcast_ref::<fdem_solver::RunError>(),
                    Some(fdem_solver::RunError::Scene(_))
                )
                || e.downcast_ref::<clap::Error>().is_some();
            ExitCode::from(if input { 2 } else { 1 })
        }
    }
}
