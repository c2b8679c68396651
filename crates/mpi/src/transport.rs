//! The MPI transport (rsmpi).

use fdem_solver::distributed::Comm;
use mpi::datatype::PartitionMut;
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// The MPI library, started; it is shut down when this is dropped (after the run).
pub struct Mpi {
    universe: Universe,
}

impl Mpi {
    /// Starts MPI (once per process): an error when it cannot be started or was already.
    pub fn init() -> Result<Mpi, String> {
        mpi::initialize()
            .map(|universe| Mpi { universe })
            .ok_or_else(|| "MPI was already started in this process".into())
    }

    /// The transport over all the job's processes.
    pub fn comm(&self) -> MpiComm {
        MpiComm {
            world: self.universe.world(),
        }
    }

    /// Ends the whole job at once with `code` (every rank), after an error on one rank.
    pub fn abort(&self, code: i32) -> ! {
        self.universe.world().abort(code)
    }
}

/// The ranks of an MPI job as a [`Comm`].
pub struct MpiComm {
    world: SimpleCommunicator,
}

impl Comm for MpiComm {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }

    fn size(&self) -> usize {
        self.world.size() as usize
    }

    fn exchange(&mut self, peers: &[usize], send: &[Vec<f64>], recv: &mut [Vec<f64>]) {
        let world = &self.world;
        mpi::request::scope(|scope| {
            let sends: Vec<_> = peers
                .iter()
                .zip(send)
                .map(|(&p, s)| {
                    world
                        .process_at_rank(p as i32)
                        .immediate_send(scope, &s[..])
                })
                .collect();
            for (&p, r) in peers.iter().zip(recv.iter_mut()) {
                let status = world.process_at_rank(p as i32).receive_into(&mut r[..]);
                let got = status.count(f64::equivalent_datatype()) as usize;
                assert_eq!(got, r.len(), "message length from rank {p}");
            }
            for s in sends {
                s.wait();
            }
        });
    }

    fn all_gather(&mut self, mine: &[f64], counts: &[usize], out: &mut [f64]) {
        let c: Vec<i32> = counts.iter().map(|&n| n as i32).collect();
        let displs: Vec<i32> = c
            .iter()
            .scan(0, |at, &n| {
                let d = *at;
                *at += n;
                Some(d)
            })
            .collect();
        let mut part = PartitionMut::new(out, c, displs);
        self.world.all_gather_varcount_into(mine, &mut part);
    }
}
