//! The solver's subcommands: `run`, `check`, `info`, `plot`.

pub mod check;
pub mod info;
pub mod plot;
pub mod run;
pub mod run_mpi;

/// `fdem run`: as one of several processes of a parallel launcher (`mpirun -np N`, `srun -n
/// N`), a distributed run (or its refusal in a build without MPI); otherwise a run in this
/// process.
pub fn run_scene(args: run::RunArgs) -> anyhow::Result<()> {
    if let Some((n, var)) = fdem_mpi::launched_among().filter(|&(n, _)| n > 1) {
        return run_mpi::run(args, n, var);
    }
    run::run(args)
}
