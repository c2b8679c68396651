//! The `fdem` command-line program: a thin dispatcher to the subcommands.
//!
//! - `fdem study oscillator [--out DIR]`: the time-integration study (`src/study/`).

mod plot;
mod study;

use std::path::Path;

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

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Study(cmd) => study::run(cmd),
    };
    if let Err(e) = result {
        // The whole chain of causes on one line, no backtrace: the message says the fix.
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
