//! What a distributed run needs of its transport ([`Comm`]), and an in-process transport
//! ([`ThreadComm`]: one thread per rank, channels between them) that runs the same
//! decomposition without MPI. The MPI transport lives in its own crate (`fdem-mpi`), so that
//! the solver gains no dependency on MPI.

use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, channel};
use std::time::Duration;

/// The messages of a distributed run, between ranks `0..size()`. Every rank calls the same
/// operations in the same order; the lengths of the messages are agreed beforehand (both sides
/// derive them from the same partition), so a length that does not match is a programming
/// error (a panic).
pub trait Comm {
    /// This process's rank.
    fn rank(&self) -> usize;
    /// The number of ranks.
    fn size(&self) -> usize;
    /// Sends `send[k]` to rank `peers[k]` and fills `recv[k]` (sized by the caller) with what
    /// rank `peers[k]` sends to this rank in its own call. The relation is symmetric: this
    /// rank is among the peers of each of its peers.
    fn exchange(&mut self, peers: &[usize], send: &[Vec<f64>], recv: &mut [Vec<f64>]);
    /// Every rank's `mine` (`counts[r]` values from rank `r`) concatenated in rank order into
    /// `out` (sized by the caller to the sum of `counts`).
    fn all_gather(&mut self, mine: &[f64], counts: &[usize], out: &mut [f64]);
}

/// How long a [`ThreadComm`] rank waits for a message before it calls the run hung.
const PATIENCE: Duration = Duration::from_secs(120);

/// One rank of an in-process transport: ranks are threads of one process, messages go
/// through channels. For tests and for comparing the decomposition with the serial run
/// without an MPI installation.
pub struct ThreadComm {
    rank: usize,
    to: Vec<Sender<Vec<f64>>>,
    from: Vec<Receiver<Vec<f64>>>,
}

impl ThreadComm {
    /// The `size` ranks of one in-process transport (hand one to each thread).
    pub fn ranks(size: usize) -> Vec<ThreadComm> {
        // channel (a -> b) at index a * size + b
        let (mut tx, mut rx): (Vec<_>, Vec<_>) = (0..size * size).map(|_| channel()).unzip();
        let mut out: Vec<ThreadComm> = (0..size)
            .map(|rank| ThreadComm {
                rank,
                to: Vec::with_capacity(size),
                from: Vec::with_capacity(size),
            })
            .collect();
        // the receivers of rank b: from every a, in rank order
        let mut rx_by_dest: Vec<Vec<Receiver<Vec<f64>>>> = (0..size).map(|_| Vec::new()).collect();
        for (k, r) in rx.drain(..).enumerate() {
            rx_by_dest[k % size].push(r);
        }
        for (k, t) in tx.drain(..).enumerate() {
            out[k / size].to.push(t);
        }
        for (c, r) in out.iter_mut().zip(rx_by_dest) {
            c.from = r;
        }
        out
    }

    fn send(&self, to: usize, data: &[f64]) {
        // a rank that ended (a panic) drops its receivers: the next receive reports it
        let _ = self.to[to].send(data.to_vec());
    }

    fn recv(&self, from: usize) -> Vec<f64> {
        match self.from[from].recv_timeout(PATIENCE) {
            Ok(v) => v,
            Err(RecvTimeoutError::Timeout) => {
                panic!("rank {} waited {PATIENCE:?} for rank {from}", self.rank)
            }
            Err(RecvTimeoutError::Disconnected) => {
                panic!("rank {from} ended before sending to rank {}", self.rank)
            }
        }
    }
}

impl Comm for ThreadComm {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.to.len()
    }

    fn exchange(&mut self, peers: &[usize], send: &[Vec<f64>], recv: &mut [Vec<f64>]) {
        for (&p, s) in peers.iter().zip(send) {
            self.send(p, s);
        }
        for (&p, r) in peers.iter().zip(recv.iter_mut()) {
            let got = self.recv(p);
            assert_eq!(got.len(), r.len(), "message length from rank {p}");
            r.copy_from_slice(&got);
        }
    }

    fn all_gather(&mut self, mine: &[f64], counts: &[usize], out: &mut [f64]) {
        assert_eq!(mine.len(), counts[self.rank], "this rank's count");
        for p in 0..self.size() {
            if p != self.rank {
                self.send(p, mine);
            }
        }
        let mut at = 0;
        for (p, &c) in counts.iter().enumerate() {
            let dst = &mut out[at..at + c];
            if p == self.rank {
                dst.copy_from_slice(mine);
            } else {
                let got = self.recv(p);
                assert_eq!(got.len(), c, "gathered length from rank {p}");
                dst.copy_from_slice(&got);
            }
            at += c;
        }
    }
}
