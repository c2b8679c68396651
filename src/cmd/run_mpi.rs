//! `mpirun -np N fdem run SCENE` (or `srun -n N`): one distributed run over the job's
//! processes (`fdem_solver::distributed`), through MPI (`fdem-mpi`, built with the `mpi`
//! feature). Rank 0 prints and writes (the checkpoints too); the other ranks compute their
//! parts and stay quiet. `--resume`, `--stop-after` and `--checkpoint-every` work as for one
//! process, and a checkpoint resumes on any number of processes.

use std::sync::atomic::AtomicBool;

use anyhow::Result;

use super::run::RunArgs;

/// Set on the ranks other than 0 of a distributed run: they print no error (rank 0 prints it
/// once).
pub static QUIET: AtomicBool = AtomicBool::new(false);

/// Runs `args` as one of the `n` processes the launcher's variable `var` announced.
pub fn run(args: RunArgs, n: usize, var: &str) -> Result<()> {
    // the launcher's rank of this process: only rank 0 prints an error
    let rank = ["OMPI_COMM_WORLD_RANK", "PMI_RANK", "SLURM_PROCID"]
        .iter()
        .find_map(|v| std::env::var(v).ok()?.trim().parse::<u64>().ok());
    QUIET.store(
        rank.is_some_and(|r| r > 0),
        std::sync::atomic::Ordering::Relaxed,
    );
    if !fdem_mpi::BUILT_WITH_MPI {
        return Err(crate::bad_input(format!(
            "fdem was started as one of {n} processes ({var}={n}: `mpirun -np {n}` or \
             `srun -n {n}`), but this fdem was built without MPI: the {n} processes would each \
             run the whole scene and write the same files at once\n  fix: build it with MPI \
             (`cargo build --release --features mpi`, with Open MPI's development files and \
             libclang installed: docs/howto-distributed.md), or start it once (`fdem run \
             SCENE`); its threads are the cores (RAYON_NUM_THREADS sets them)"
        )));
    }
    let mpi = fdem_mpi::Mpi::init().map_err(anyhow::Error::msg)?;
    run_on(&mpi, args)
}

#[cfg(feature = "mpi")]
fn run_on(mpi: &fdem_mpi::Mpi, args: RunArgs) -> Result<()> {
    use fdem_solver::distributed::Comm;
    use fdem_solver::driver::{self, Progress, RunOptions};
    use std::path::PathBuf;
    use std::sync::atomic::Ordering;
    let comm = mpi.comm();
    let (rank, size) = (comm.rank(), comm.size());
    QUIET.store(rank != 0, Ordering::Relaxed);
    let scene = match &args.resume {
        Some(dir) => super::run::resumed_scene(dir, args.scene.clone())?,
        None => args
            .scene
            .clone()
            .expect("clap requires a scene without --resume"),
    };
    let out = args.resume.clone().or(args.out.clone()).unwrap_or_else(|| {
        let stem = scene
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into());
        PathBuf::from("results").join(stem)
    });
    // every rank loads the scene (the same checks, so a bad scene fails on every rank alike)
    let mut loaded = driver::load(&scene)?;
    let resumed = match &args.resume {
        Some(dir) => super::run::open_resumed(&mut loaded, dir)?,
        None => None,
    };
    if rank == 0 {
        eprintln!("{}", loaded.describe());
        if let Some(line) = &resumed {
            eprintln!("{line}");
        }
        eprintln!("distributed over {size} processes");
    }
    // SIGINT and SIGTERM (mpirun passes them to every process): rank 0's stop is taken up
    // by every rank within a few steps, with a checkpoint (exit code 4)
    let options = RunOptions {
        out_dir: out.clone(),
        raw: args.raw,
        checkpoint_every: args.checkpoint_every,
        stop: Some(super::run::stop_on_signals()?),
        stop_after: args.stop_after,
        resume: args.resume.is_some(),
        rebalance: args.rebalance,
    };
    // rank 0 reports the progress
    let mut lines = super::run::progress_lines();
    let mut progress = |p: &Progress| {
        if rank == 0 {
            lines(p)
        }
    };
    match driver::run_distributed(&mut loaded, &options, Box::new(comm), &mut progress) {
        Ok(outcome) => {
            if rank == 0 {
                println!("{}", outcome.summary.describe());
                // the load-displacement curve of a fracturing scene, as a single process draws it
                super::run::plot_curve(&out);
                println!("results in {}", out.display());
            }
            Ok(())
        }
        // a file rank 0 could not write: the other ranks do not know, so the job ends here
        Err(e @ fdem_solver::RunError::Output { .. }) => {
            eprintln!("error: {e}");
            mpi.abort(1)
        }
        // the scene's refusals and the run's checks fail on every rank alike; a run stopped
        // as unstable has its curve so far, as a single process's
        Err(e) => {
            if rank == 0 && matches!(e, fdem_solver::RunError::Unstable { .. }) {
                super::run::plot_curve(&out);
            }
            Err(e.into())
        }
    }
}

#[cfg(not(feature = "mpi"))]
fn run_on(_: &fdem_mpi::Mpi, _: RunArgs) -> Result<()> {
    unreachable!("Mpi::init fails without the mpi feature")
}
