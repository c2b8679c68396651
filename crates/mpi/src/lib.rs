//! fdem's MPI transport: a distributed run (`fdem_solver::distributed`) whose ranks are the
//! processes of an MPI job (`mpirun -np N fdem run SCENE`, `srun -n N fdem run SCENE`).
//!
//! The transport is built with the `mpi` feature (rsmpi against the system's MPI library);
//! without it, [`Mpi::init`] says what to rebuild. The solver knows nothing of MPI: it talks
//! to its ranks through [`fdem_solver::distributed::Comm`], which [`MpiComm`] implements with
//! point-to-point messages (the ghost exchange) and a variable-count all-gather (the state
//! shared with every rank).

/// The variables a parallel launcher sets in each process it starts, with the number of
/// processes: Open MPI's `mpirun`, MPICH and Intel MPI (`PMI_SIZE`), and a Slurm job step
/// (`srun -n N`).
pub const LAUNCHER_SIZES: [&str; 3] = ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "SLURM_STEP_NUM_TASKS"];

/// The number of processes a parallel launcher started this one among, with the variable
/// that tells it (`None` when no launcher variable is set).
pub fn launched_among() -> Option<(usize, &'static str)> {
    LAUNCHER_SIZES.iter().find_map(|&var| {
        std::env::var(var)
            .ok()
            .and_then(|v| v.trim().parse::<usize>().ok())
            .map(|n| (n, var))
    })
}

/// Whether this build has the MPI transport (the `mpi` feature).
pub const BUILT_WITH_MPI: bool = cfg!(feature = "mpi");

#[cfg(feature = "mpi")]
mod transport;
#[cfg(feature = "mpi")]
pub use transport::{Mpi, MpiComm};

/// Without the `mpi` feature: MPI cannot be started.
#[cfg(not(feature = "mpi"))]
pub struct Mpi;

#[cfg(not(feature = "mpi"))]
impl Mpi {
    /// Always an error in a build without the `mpi` feature, with the fix.
    pub fn init() -> Result<Mpi, String> {
        Err("this fdem was built without MPI".into())
    }
}
