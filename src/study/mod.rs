//! `fdem study ...`: numerical studies of the building blocks.

pub mod oscillator;
pub mod scene;

use anyhow::Result;
use clap::Subcommand;

/// The studies.
#[derive(Subcommand)]
pub enum StudyCommand {
    /// Every time-integration scheme on the oscillator x'' + x = 0, x(0) = 0, v(0) = 1, over a
    /// range of steps: stability, accuracy and cost (CSV, JSON, PNG and SVG plots, a table).
    Oscillator(oscillator::OscillatorArgs),
    /// Every scheme on a scene at fractions of its predicted stable step: error (analytical
    /// or against the finest run), cost, observed stability limit (CSV, JSON, charts).
    Scene(scene::SceneArgs),
}

/// Runs a study.
pub fn run(cmd: StudyCommand) -> Result<()> {
    match cmd {
        StudyCommand::Oscillator(args) => oscillator::run(&args),
        StudyCommand::Scene(args) => scene::run(&args),
    }
}
