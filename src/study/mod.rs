//! `fdem study ...`: numerical studies of the building blocks.

pub mod oscillator;

use anyhow::Result;
use clap::Subcommand;

/// The studies.
#[derive(Subcommand)]
pub enum StudyCommand {
    /// Every time-integration scheme on the oscillator x'' + x = 0, x(0) = 0, v(0) = 1, over a
    /// range of steps: stability, accuracy and cost (CSV, JSON, PNG and SVG plots, a table).
    Oscillator(oscillator::OscillatorArgs),
}

/// Runs a study.
pub fn run(cmd: StudyCommand) -> Result<()> {
    match cmd {
        StudyCommand::Oscillator(args) => oscillator::run(&args),
    }
}
