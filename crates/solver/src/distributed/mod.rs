//! Distributed runs: one scene on several processes (ranks), with results identical bit for
//! bit to the single-process run.
//!
//! Every rank loads the whole scene. The triangles are cut into parts by recursive coordinate
//! bisection ([`partition::rcb`]); each node is owned by the rank of its lowest-numbered
//! triangle ([`Layout`]). A rank evaluates the forces of every triangle with a node of its own
//! (its own triangles and one layer of ghost triangles), so that each of its nodes sums the
//! forces of all its triangles in the serial order, and it integrates only its own nodes (the
//! scheme moves only their DOFs: `SecondOrderSystem::active_dofs`). The joints and contact
//! couples are evaluated the same way by the stages, on the ranks that own one of their
//! nodes. Before each force evaluation the ranks exchange the positions (and, where the
//! forces read them, the velocities) of the nodes their ghost triangles share
//! ([`Distribution::patch`]) and that their joints and couples read ([`Ghosts`]). After every
//! step the nodes of the loads and prescribed motions are shared with every rank (the energy
//! books read them), and after each step that an observer reads (checks, histories, frames,
//! the last step) the whole state is ([`Distribution::sync`]): every rank then holds the
//! serial run's state, bit for bit, and the observers run on it unchanged. At the checks the
//! parts are cut again when their costs are unbalanced ([`balance`]).
//!
//! The transport is a [`Comm`]: MPI in the `fdem-mpi` crate, or threads of one process
//! ([`ThreadComm`]).

pub mod balance;
mod comm;
mod ghosts;
mod layout;
pub mod partition;

pub use comm::{Comm, ThreadComm};
pub use ghosts::Ghosts;
pub use layout::Layout;

use fdem_mesh::Elements;

/// A system's part in a distributed run: its layout, transport, the elements it evaluates and
/// the buffers of the exchanges.
pub struct Distribution {
    /// Who owns what.
    pub layout: Layout,
    comm: Box<dyn Comm>,
    /// The triangles this rank evaluates (global node numbering).
    pub local: Elements,
    /// Positions as the force evaluation reads them: this rank's DOFs from the scheme's
    /// state, the ghosts' from their owners.
    pub xp: Vec<f64>,
    /// Velocities, likewise (only when the forces read them).
    pub vp: Vec<f64>,
    mine: Vec<f64>,
    all: Vec<f64>,
    /// The whole state is shared after every step (the energy books sum over every node in
    /// every step: mass damping, element viscosity, the work of the element forces).
    pub every_step: bool,
    /// Exchanges done: ghost patches, watched-node and whole-state shares.
    pub counts: [u64; 3],
    /// The imbalance above which the run repartitions
    /// ([`balance::DEFAULT_THRESHOLD`] unless the run gives its own; infinite: never).
    pub rebalance: f64,
    /// Repartitions done.
    pub repartitions: u64,
    /// The imbalance of the cost at the last check, and after the last repartition.
    pub imbalance: [f64; 2],
}

impl Distribution {
    /// The part of `layout`'s rank, talking through `comm`, of a system with the elements
    /// `elements` (all triangles).
    pub fn new(layout: Layout, comm: Box<dyn Comm>, elements: &Elements) -> Distribution {
        assert_eq!(comm.rank(), layout.rank);
        assert_eq!(comm.size(), layout.size);
        let local = elements.subset(&layout.local_tris);
        let n = elements.n_nodes;
        Distribution {
            layout,
            comm,
            local,
            xp: vec![0.0; 2 * n],
            vp: vec![0.0; 2 * n],
            mine: Vec::new(),
            all: Vec::new(),
            every_step: false,
            counts: [0; 3],
            rebalance: balance::DEFAULT_THRESHOLD,
            repartitions: 0,
            imbalance: [1.0; 2],
        }
    }

    /// Takes the new `layout` (a repartition; the same ranks): the triangles it evaluates
    /// out of `elements` and the buffers of its exchanges.
    pub fn repartition(&mut self, layout: Layout, elements: &Elements) {
        assert_eq!(self.layout.size, layout.size);
        self.local = elements.subset(&layout.local_tris);
        self.layout = layout;
        self.repartitions += 1;
    }

    /// Gathers the whole positions and velocities from their owners into
    /// [`Distribution::xp`] and [`Distribution::vp`] (`with_v`: the velocities too).
    pub fn gather_all(&mut self, x: &[f64], v: &[f64], with_v: bool) {
        let w = if with_v { 4 } else { 2 };
        let by = std::mem::take(&mut self.layout.owned_by);
        let all = self.gather_nodes(&by, w, |d, out| {
            out.extend_from_slice(&x[d..d + 2]);
            if with_v {
                out.extend_from_slice(&v[d..d + 2]);
            }
        });
        each_gathered(&by, &all, w, |_, d, c| {
            self.xp[d..d + 2].copy_from_slice(&c[..2]);
            if with_v {
                self.vp[d..d + 2].copy_from_slice(&c[2..4]);
            }
        });
        (self.layout.owned_by, self.all) = (by, all);
        self.counts[0] += 1;
    }

    /// The summary's `distributed` part: the ranks, rank 0's nodes, triangles evaluated and
    /// ghost nodes, the largest of each over the ranks, and the exchanges.
    pub fn report(&self) -> serde_json::Value {
        let l = &self.layout;
        let ghosts = l.ghosts.len();
        let largest = l.owned_by.iter().map(Vec::len).max().unwrap_or(0);
        serde_json::json!({
            "ranks": l.size,
            "partition": "recursive coordinate bisection of the triangles",
            "nodes_per_rank_max": largest,
            "nodes_per_rank_min": l.owned_by.iter().map(Vec::len).min().unwrap_or(0),
            "rank0_nodes": l.owned().len(),
            "rank0_triangles_evaluated": l.local_tris.len(),
            "rank0_ghost_nodes": ghosts,
            "rank0_peers": l.ghosts.peers.len(),
            "ghost_exchanges": self.counts[0],
            "watched_shares": self.counts[1],
            "whole_state_shares": self.counts[2],
            "rebalance_threshold": self.rebalance.is_finite().then_some(self.rebalance),
            "repartitions": self.repartitions,
            "imbalance_last_check": self.imbalance[0],
            "imbalance_after_repartition": (self.repartitions > 0).then_some(self.imbalance[1]),
        })
    }

    /// The positions and velocities the forces read, with the transport (for the stages'
    /// own exchanges and end of step).
    pub fn parts(&mut self) -> (&mut [[f64; 2]], &mut [[f64; 2]], &mut dyn Comm) {
        (
            self.xp.as_chunks_mut::<2>().0,
            self.vp.as_chunks_mut::<2>().0,
            &mut *self.comm,
        )
    }

    /// The transport (for the stages' own exchanges).
    pub fn comm(&mut self) -> &mut dyn Comm {
        &mut *self.comm
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.layout.rank
    }

    /// Fills [`Distribution::xp`] (and, with `with_v`, [`Distribution::vp`]) for a force
    /// evaluation at `(x, v)`: this rank's nodes from `x` and `v`, the ghosts from their
    /// owners' calls.
    pub fn patch(&mut self, x: &[f64], v: &[f64], with_v: bool) {
        self.patch_owned(x, v, with_v);
        let (xp, vp) = (
            self.xp.as_chunks_mut::<2>().0,
            self.vp.as_chunks_mut::<2>().0,
        );
        self.layout.ghosts.exchange(&mut *self.comm, xp, vp, with_v);
        self.counts[0] += 1;
    }

    /// Copies this rank's nodes from `x` (and, with `with_v`, `v`) into
    /// [`Distribution::xp`] (and [`Distribution::vp`]).
    pub fn patch_owned(&mut self, x: &[f64], v: &[f64], with_v: bool) {
        for &k in self.layout.owned() {
            let d = 2 * k as usize;
            self.xp[d] = x[d];
            self.xp[d + 1] = x[d + 1];
            if with_v {
                self.vp[d] = v[d];
                self.vp[d + 1] = v[d + 1];
            }
        }
    }

    /// Shares the whole state after a step: every node's position, velocity and force (and
    /// the kept internal force `fi`, when there is one) from its owner to every rank.
    pub fn sync(&mut self, x: &mut [f64], v: &mut [f64], f: &mut [[f64; 2]], fi: &mut [[f64; 2]]) {
        let by = std::mem::take(&mut self.layout.owned_by);
        self.share(&by, x, v, f, fi);
        self.layout.owned_by = by;
        self.counts[2] += 1;
    }

    /// Shares a per-DOF array (two values per node, e.g. the scheme's cached acceleration)
    /// from each node's owner to every rank.
    pub fn share_dofs(&mut self, a: &mut [f64]) {
        let by = std::mem::take(&mut self.layout.owned_by);
        let all = self.gather_nodes(&by, 2, |d, out| out.extend_from_slice(&a[d..d + 2]));
        each_gathered(&by, &all, 2, |_, d, c| a[d..d + 2].copy_from_slice(c));
        (self.layout.owned_by, self.all) = (by, all);
    }

    /// Rank 0's `flags` on every rank (rank 0's decisions: a wall-clock checkpoint due, a
    /// stop signal).
    pub fn from_rank0(&mut self, flags: &mut [f64]) {
        let mut counts = vec![0; self.layout.size];
        counts[0] = flags.len();
        let mine: Vec<f64> = if self.layout.rank == 0 {
            flags.to_vec()
        } else {
            Vec::new()
        };
        self.comm.all_gather(&mine, &counts, flags);
    }

    /// Shares the watched nodes' state and force (the loads' and prescribed motions' nodes)
    /// after a step.
    pub fn sync_watched(&mut self, x: &mut [f64], v: &mut [f64], f: &mut [[f64; 2]]) {
        if self.layout.watched_by.iter().all(Vec::is_empty) {
            return;
        }
        let by = std::mem::take(&mut self.layout.watched_by);
        self.share(&by, x, v, f, &mut []);
        self.layout.watched_by = by;
        self.counts[1] += 1;
    }

    /// Each rank's nodes `by[rank]` from that rank to every rank.
    fn share(
        &mut self,
        by: &[Vec<u32>],
        x: &mut [f64],
        v: &mut [f64],
        f: &mut [[f64; 2]],
        fi: &mut [[f64; 2]],
    ) {
        let w = if fi.is_empty() { 6 } else { 8 };
        let all = self.gather_nodes(by, w, |d, out| {
            out.extend_from_slice(&x[d..d + 2]);
            out.extend_from_slice(&v[d..d + 2]);
            out.extend_from_slice(&f[d / 2]);
            if !fi.is_empty() {
                out.extend_from_slice(&fi[d / 2]);
            }
        });
        let rank = self.layout.rank;
        each_gathered(by, &all, w, |r, d, c| {
            if r != rank {
                x[d..d + 2].copy_from_slice(&c[..2]);
                v[d..d + 2].copy_from_slice(&c[2..4]);
                f[d / 2] = [c[4], c[5]];
                if !fi.is_empty() {
                    fi[d / 2] = [c[6], c[7]];
                }
            }
        });
        self.all = all;
    }

    /// Each rank's nodes `by[rank]`, `w` values each (`pack` gets the node's first DOF and
    /// appends them), gathered on every rank in rank order ([`each_gathered`] reads them).
    fn gather_nodes(
        &mut self,
        by: &[Vec<u32>],
        w: usize,
        mut pack: impl FnMut(usize, &mut Vec<f64>),
    ) -> Vec<f64> {
        self.mine.clear();
        for &k in &by[self.layout.rank] {
            pack(2 * k as usize, &mut self.mine);
        }
        let counts: Vec<usize> = by.iter().map(|b| w * b.len()).collect();
        let mut all = std::mem::take(&mut self.all);
        all.resize(counts.iter().sum(), 0.0);
        self.comm.all_gather(&self.mine, &counts, &mut all);
        all
    }
}

/// Calls `put(rank, first DOF, values)` for each node of [`Distribution::gather_nodes`]'s
/// result `all` (`w` values per node, the nodes `by[rank]` in rank order).
fn each_gathered(
    by: &[Vec<u32>],
    all: &[f64],
    w: usize,
    mut put: impl FnMut(usize, usize, &[f64]),
) {
    let mut at = 0;
    for (r, nodes) in by.iter().enumerate() {
        for &k in nodes {
            put(r, 2 * k as usize, &all[at..at + w]);
            at += w;
        }
    }
}

/// Each rank's nodes `by[rank]`, `w` values per node (`mine`: this rank's, in the order of
/// `by[rank]`), from that rank to every rank: `put(node, values)` for every node of every
/// rank, in rank order. `all` is the message buffer.
pub fn share_nodes(
    comm: &mut dyn Comm,
    by: &[Vec<u32>],
    w: usize,
    mine: &[f64],
    all: &mut Vec<f64>,
    mut put: impl FnMut(usize, &[f64]),
) {
    let counts: Vec<usize> = by.iter().map(|b| w * b.len()).collect();
    all.resize(counts.iter().sum(), 0.0);
    comm.all_gather(mine, &counts, all);
    each_gathered(by, all, w, |_, d, c| put(d / 2, c));
}

/// Every rank's entries, merged ([`Entries::gather`]), with the buffers kept from one call
/// to the next.
#[derive(Debug, Default)]
pub struct Entries {
    head: Vec<f64>,
    heads: Vec<f64>,
    per_rank: Vec<usize>,
    counts: Vec<usize>,
    flat: Vec<f64>,
    all: Vec<f64>,
    starts: Vec<Vec<(f64, usize)>>,
}

impl Entries {
    /// `mine[s]` holds this rank's entries of section `s`, `widths[s]` values each, the
    /// first the entry's key; `out[s]` gets every rank's entries of section `s` ordered by
    /// key (equal keys in rank order). Two collective calls.
    pub fn gather(
        &mut self,
        comm: &mut dyn Comm,
        mine: &[Vec<f64>],
        widths: &[usize],
        out: &mut [Vec<f64>],
    ) {
        let ns = mine.len();
        let size = comm.size();
        self.head.clear();
        self.head
            .extend(mine.iter().zip(widths).map(|(m, w)| (m.len() / w) as f64));
        self.heads.resize(ns * size, 0.0);
        self.per_rank.clear();
        self.per_rank.resize(size, ns);
        comm.all_gather(&self.head, &self.per_rank, &mut self.heads);
        self.flat.clear();
        for m in mine {
            self.flat.extend_from_slice(m);
        }
        self.counts.clear();
        self.counts.extend(self.heads.chunks_exact(ns).map(|h| {
            h.iter()
                .zip(widths)
                .map(|(n, w)| *n as usize * w)
                .sum::<usize>()
        }));
        self.all.resize(self.counts.iter().sum(), 0.0);
        comm.all_gather(&self.flat, &self.counts, &mut self.all);
        // per section, (key, start) of every entry, then sorted stably by key
        self.starts.resize(ns, Vec::new());
        self.starts.iter_mut().for_each(Vec::clear);
        let mut at = 0;
        for h in self.heads.chunks_exact(ns) {
            for (s, (&n, &w)) in h.iter().zip(widths).enumerate() {
                for _ in 0..n as usize {
                    self.starts[s].push((self.all[at], at));
                    at += w;
                }
            }
        }
        for ((st, o), &w) in self.starts.iter_mut().zip(out.iter_mut()).zip(widths) {
            st.sort_by(|a, b| a.0.total_cmp(&b.0));
            o.clear();
            for &(_, k) in st.iter() {
                o.extend_from_slice(&self.all[k..k + w]);
            }
        }
    }
}
