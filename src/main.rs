//! The `fdem` command-line program. Subcommands arrive with the crates that implement them.

use clap::Parser;

/// fdem: a 2D combined finite-discrete element solver.
#[derive(Parser)]
#[command(version, about)]
struct Cli {}

fn main() {
    let _cli = Cli::parse();
}
