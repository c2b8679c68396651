//! The ghost nodes of a set of items ([`Ghosts`]): an item (a joint, a contact couple) is
//! evaluated on every rank that owns one of its nodes, and each of those ranks needs all its
//! nodes. Every rank derives the same lists from the same items, so the lengths of the
//! messages are known to both sides.

use super::comm::Comm;

/// What this rank sends to and receives from each peer so that it holds every node of the
/// items it evaluates.
#[derive(Debug, Clone, Default)]
pub struct Ghosts {
    /// The ranks this rank exchanges with, increasing.
    pub peers: Vec<usize>,
    /// Per peer: this rank's nodes the peer needs, increasing.
    pub send_nodes: Vec<Vec<u32>>,
    /// Per peer: the peer's nodes this rank needs, increasing.
    pub recv_nodes: Vec<Vec<u32>>,
    send: Vec<Vec<f64>>,
    recv: Vec<Vec<f64>>,
}

impl Ghosts {
    /// The lists of `rank` out of `size` for `items` (each a list of nodes), the nodes owned
    /// as `node_owner` says.
    pub fn new<'a>(
        rank: usize,
        size: usize,
        node_owner: &[u32],
        items: impl IntoIterator<Item = &'a [u32]>,
    ) -> Ghosts {
        let mut recv: Vec<Vec<u32>> = vec![Vec::new(); size];
        let mut send: Vec<Vec<u32>> = vec![Vec::new(); size];
        let mut owners = Vec::with_capacity(8);
        for nodes in items {
            owners.clear();
            owners.extend(nodes.iter().map(|&k| node_owner[k as usize] as usize));
            for (a, &q) in owners.iter().enumerate() {
                if owners[..a].contains(&q) || (q != rank && !owners.contains(&rank)) {
                    continue;
                }
                // the item is evaluated on rank q, which needs every node of it
                for (&k, &r) in nodes.iter().zip(&owners) {
                    if r == q {
                        continue;
                    }
                    if q == rank {
                        recv[r].push(k);
                    } else if r == rank {
                        send[q].push(k);
                    }
                }
            }
        }
        let mut g = Ghosts::default();
        for (p, (mut s, mut r)) in send.into_iter().zip(recv).enumerate() {
            s.sort_unstable();
            s.dedup();
            r.sort_unstable();
            r.dedup();
            if !s.is_empty() || !r.is_empty() {
                g.peers.push(p);
                g.send_nodes.push(s);
                g.recv_nodes.push(r);
            }
        }
        g.send = vec![Vec::new(); g.peers.len()];
        g.recv = vec![Vec::new(); g.peers.len()];
        g
    }

    /// The ghost nodes (counted once per peer).
    pub fn len(&self) -> usize {
        self.recv_nodes.iter().map(Vec::len).sum()
    }

    /// No ghosts.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Sends this rank's nodes to the peers that need them and writes the peers' nodes into
    /// `x` (and, with `with_v`, `v`). Every rank calls it with the same `with_v`.
    pub fn exchange(
        &mut self,
        comm: &mut dyn Comm,
        x: &mut [[f64; 2]],
        v: &mut [[f64; 2]],
        with_v: bool,
    ) {
        let w = if with_v { 4 } else { 2 };
        for (s, nodes) in self.send.iter_mut().zip(&self.send_nodes) {
            s.clear();
            for &k in nodes {
                s.extend_from_slice(&x[k as usize]);
                if with_v {
                    s.extend_from_slice(&v[k as usize]);
                }
            }
        }
        for (r, nodes) in self.recv.iter_mut().zip(&self.recv_nodes) {
            r.resize(w * nodes.len(), 0.0);
        }
        comm.exchange(&self.peers, &self.send, &mut self.recv);
        for (r, nodes) in self.recv.iter().zip(&self.recv_nodes) {
            for (c, &k) in r.chunks_exact(w).zip(nodes) {
                x[k as usize] = [c[0], c[1]];
                if with_v {
                    v[k as usize] = [c[2], c[3]];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_rank_receives_exactly_what_its_peers_send_it() {
        // nodes 0..6 owned by ranks 0,0,1,1,2,2; items across the cuts
        let owner = [0, 0, 1, 1, 2, 2];
        let items: Vec<Vec<u32>> = vec![vec![0, 2], vec![1, 3, 4], vec![5, 4], vec![0, 1]];
        let g: Vec<Ghosts> = (0..3)
            .map(|r| Ghosts::new(r, 3, &owner, items.iter().map(Vec::as_slice)))
            .collect();
        assert_eq!(g[0].peers, vec![1, 2]);
        assert_eq!(g[0].recv_nodes, vec![vec![2, 3], vec![4]]);
        assert_eq!(g[0].send_nodes, vec![vec![0, 1], vec![1]]);
        for a in 0..3 {
            for (i, &b) in g[a].peers.iter().enumerate() {
                let j = g[b].peers.iter().position(|&p| p == a).unwrap();
                assert_eq!(g[a].send_nodes[i], g[b].recv_nodes[j]);
            }
        }
        // rank 2 evaluates items 1 and 2: it needs nodes 1 and 3
        assert_eq!(g[2].peers, vec![0, 1]);
        assert_eq!(g[2].recv_nodes, vec![vec![1], vec![3]]);
    }
}
