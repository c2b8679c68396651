//! The solver's subcommands: `run`, `check`, `info`.

pub mod check;
pub mod info;
pub mod run;
