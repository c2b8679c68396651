//! The `fdem` command-line program: a thin dispatcher to the subcommands.
//!
//! - `fdem run SCENE [--out DIR] [--raw] [--checkpoint-every N|TIME] [--stop-after N] [--rebalance R|off]`, or
//!   `fdem run [SCENE] --resume DIR`: run a scene, or continue a run (`src/cmd/run.rs`).
//! - `fdem check SCENE`: validate a scene, stable steps, estimated time (`src/cmd/check.rs`).
//! - `fdem info MESH`: describe a mesh file (`src/cmd/info.rs`).
//! - `fdem plot load-displacement DIR...`: load-displacement curves of runs (`src/cmd/plot.rs`).
//! - `fdem study oscillator [--out DIR]`: the time-integration study (`src/study/`).
//!
//! Exit codes ([`EXIT_CODES`], from the typed error: [`exit_code`]): 0 success, 2 bad input,
//! 3 a run that did not reach its goal, 4 a run interrupted (resumable), 1 anything else.

mod atomic;
mod cmd;
mod input_error;
mod plot;
mod study;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};

// the helpers every command uses, as `crate::bad_input` and `crate::write_atomically`
use atomic::write_atomically;
use input_error::{BadInput, bad_input};

/// The exit codes, as `--help` shows them (README.md, "Exit codes", says the same).
const EXIT_CODES: &str = "\
Exit codes (every subcommand):
  0  success
  2  bad input: the scene, a mesh, a run folder or an argument is invalid (nothing is written)
  3  the run did not reach its goal: a relaxation that did not converge, or a run stopped as
     unstable (its output so far is written)
  4  the run was interrupted (SIGINT or SIGTERM, or --stop-after): it wrote a checkpoint and a
     summary marked interrupted; `fdem run --resume DIR` continues it (a second signal ends
     the process at once, with code 128 + the signal's number)
  1  anything else (e.g. a file that cannot be written)";

/// fdem: a 2D combined finite-discrete element solver.
#[derive(Parser)]
#[command(version, about, after_help = EXIT_CODES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene: writes a ParaView collection (.pvd + .vtu), histories.csv and summary.json.
    #[command(after_help = EXIT_CODES)]
    Run {
        /// The scene file (JSON, see docs/scene-format.md); with --resume, the scene of the
        /// checkpointed run by default.
        #[arg(required_unless_present = "resume")]
        scene: Option<PathBuf>,
        /// Output folder (default results/<scene name>); the files an earlier run wrote
        /// there are removed first, other files are kept.
        #[arg(long, conflicts_with = "resume")]
        out: Option<PathBuf>,
        /// Also write each frame's arrays as JSON (frame_NNNN.json), for independent checks.
        #[arg(long)]
        raw: bool,
        /// Write a checkpoint (checkpoint.fdem) every N steps, or every wall-clock time
        /// (90s, 30min, 2h), or `off`; default: the scene's output.checkpoint_every, else 10min.
        #[arg(long, value_name = "STEPS|TIME", value_parser = parse_every)]
        checkpoint_every: Option<fdem_solver::checkpoint::Every>,
        /// Continue the run in DIR from its checkpoint; its frames, CSV files and summary
        /// go on as if it had never stopped. Refused: a checkpoint of another run than the
        /// one whose files DIR holds (run_id.txt), a folder without a file written before
        /// the checkpoint, a `duration` that ends at or before the checkpoint.
        #[arg(long, value_name = "DIR")]
        resume: Option<PathBuf>,
        /// Stop after this many steps in all, with a checkpoint, as if interrupted (exit
        /// code 4); a later --resume goes on.
        #[arg(long, value_name = "STEPS")]
        stop_after: Option<u64>,
        /// On several processes: repartition when the largest part's work exceeds RATIO
        /// times the mean (checked every 100 steps), or `off`; default 1.25.
        #[arg(long, value_name = "RATIO|off", value_parser = parse_rebalance)]
        rebalance: Option<f64>,
    },
    /// Validate a scene: report the mesh, each scheme's stable time step and the run time.
    #[command(after_help = EXIT_CODES)]
    Check {
        /// The scene file.
        scene: PathBuf,
    },
    /// Describe a mesh file: counts, physical groups, element sizes.
    #[command(after_help = EXIT_CODES)]
    Info {
        /// The mesh file (.msh or .json).
        mesh: PathBuf,
    },
    /// Plots of run results (PNG and SVG).
    #[command(subcommand, after_help = EXIT_CODES)]
    Plot(cmd::plot::PlotCommand),
    /// Numerical studies that reproduce and extend the reference's comparisons.
    #[command(subcommand, after_help = EXIT_CODES)]
    Study(study::StudyCommand),
}

/// `--checkpoint-every`: steps, a wall-clock time or `off`.
fn parse_every(s: &str) -> Result<fdem_solver::checkpoint::Every, String> {
    fdem_solver::checkpoint::Every::parse(s)
}

/// `--rebalance`: a ratio of at least 1, or `off` (never).
fn parse_rebalance(s: &str) -> Result<f64, String> {
    if s == "off" {
        return Ok(f64::INFINITY);
    }
    match s.parse::<f64>() {
        Ok(r) if r.is_finite() && r >= 1.0 => Ok(r),
        _ => Err(format!(
            "`{s}` is not a ratio of at least 1 (the largest part's work over the mean) nor \
             `off`: e.g. --rebalance 1.25"
        )),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run {
            scene,
            out,
            raw,
            checkpoint_every,
            resume,
            stop_after,
            rebalance,
        } => cmd::run_scene(cmd::run::RunArgs {
            scene,
            out,
            raw,
            checkpoint_every,
            resume,
            stop_after,
            rebalance,
        }),
        Command::Check { scene } => cmd::check::check(&scene),
        Command::Info { mesh } => cmd::info::info(&mesh),
        Command::Plot(cmd) => cmd::plot::run(cmd),
        Command::Study(cmd) => study::run(cmd),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // The whole chain of causes on one line, no backtrace: the message says the fix.
            // (Messages quote input through `fdem_solver::excerpt`; `shorten` is a last guard.)
            // (a distributed run's error is printed by rank 0 only)
            if !cmd::run_mpi::QUIET.load(std::sync::atomic::Ordering::Relaxed) {
                eprintln!(
                    "error: {}",
                    fdem_solver::shorten_to(&format!("{e:#}"), 4000)
                );
            }
            ExitCode::from(exit_code(&e))
        }
    }
}

/// The exit code of an error (the table in [`EXIT_CODES`]), from the first typed error in
/// its chain of causes: 2 for bad input (a scene, mesh or argument error, a static analysis
/// that the supports do not hold), 3 for a run that did not reach its goal, 1 otherwise.
fn exit_code(e: &anyhow::Error) -> u8 {
    use fdem_solver::RunError;
    for cause in e.chain() {
        if let Some(r) = cause.downcast_ref::<RunError>() {
            return match r {
                RunError::Scene(_) | RunError::Static { .. } | RunError::Checkpoint(_) => 2,
                RunError::Unstable { .. } | RunError::NotConverged { .. } => 3,
                RunError::Interrupted { .. } => 4,
                RunError::Output { .. } => 1,
            };
        }
        if cause.is::<fdem_solver::SceneError>() || cause.is::<BadInput>() {
            return 2;
        }
    }
    1
}
