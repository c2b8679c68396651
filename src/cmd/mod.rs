//! The solver's subcommands: `run`, `check`, `info`, `plot`.

pub mod check;
pub mod info;
pub mod plot;
pub mod run;
pub mod run_mpi;
