//! Which rank does what ([`Layout`]): the triangles cut into parts by recursive coordinate
//! bisection, each node owned by the rank of its lowest-numbered triangle, and what each rank
//! must receive from the others to evaluate the forces on its own nodes exactly.

use fdem_mesh::Elements;

use super::ghosts::Ghosts;
use super::partition::rcb;
use crate::problem::model::Model;

/// The decomposition of a model over `size` ranks, as seen from `rank`. Every rank derives
/// the same decomposition from the same model, so the lengths of all messages are known to
/// both sides.
#[derive(Debug, Clone)]
pub struct Layout {
    /// This rank.
    pub rank: usize,
    /// The number of ranks.
    pub size: usize,
    /// The part of each triangle (recursive coordinate bisection of the centroids).
    pub tri_part: Vec<u32>,
    /// The rank that owns each node: the part of its lowest-numbered triangle (rank 0 for a
    /// node of no triangle).
    pub node_owner: Vec<u32>,
    /// The nodes of each rank, increasing.
    pub owned_by: Vec<Vec<u32>>,
    /// The triangles this rank evaluates: every triangle with a node of its own, increasing.
    /// A node's triangles are then all evaluated on its owner, in the serial order.
    pub local_tris: Vec<u32>,
    /// The nodes of the triangles this rank evaluates that other ranks own (its ghosts), and
    /// the nodes of its own that other ranks' triangles use.
    pub ghosts: Ghosts,
    /// Nodes whose state and force every rank keeps current after every step (the loaded and
    /// the prescribed DOFs' nodes, which the energy books read every step), per owning rank,
    /// increasing.
    pub watched_by: Vec<Vec<u32>>,
    /// The DOFs of this rank's nodes, as increasing ranges: the only ones its scheme moves.
    pub active: Vec<std::ops::Range<usize>>,
    /// The constrained DOFs of this rank's nodes, increasing (held by its scheme).
    pub held_dofs: Vec<usize>,
}

impl Layout {
    /// The decomposition of `model` (with its `elements`) over `size` ranks, seen from `rank`:
    /// the triangles cut at their initial centroids, each of the same weight.
    pub fn new(model: &Model, elements: &Elements, rank: usize, size: usize) -> Layout {
        let centroids = centroids(elements, &model.x0);
        let tri_part = rcb(&centroids, &vec![1.0; centroids.len()], size);
        Layout::with_parts(model, elements, rank, size, tri_part)
    }

    /// The decomposition with the triangles of each part given (`tri_part[t]`: the part of
    /// triangle `t`).
    pub fn with_parts(
        model: &Model,
        elements: &Elements,
        rank: usize,
        size: usize,
        tri_part: Vec<u32>,
    ) -> Layout {
        assert!(rank < size);
        let n = model.n_nodes();
        let mut node_owner = vec![u32::MAX; n];
        for (t, td) in elements.tris.iter().enumerate() {
            for &k in &td.nodes {
                if node_owner[k as usize] == u32::MAX {
                    node_owner[k as usize] = tri_part[t];
                }
            }
        }
        for o in &mut node_owner {
            if *o == u32::MAX {
                *o = 0;
            }
        }
        let mut owned_by: Vec<Vec<u32>> = vec![Vec::new(); size];
        for (k, &o) in node_owner.iter().enumerate() {
            owned_by[o as usize].push(k as u32);
        }
        let mine = |k: &u32| node_owner[*k as usize] as usize == rank;
        let local_tris = (0..elements.tris.len() as u32)
            .filter(|&t| elements.tris[t as usize].nodes.iter().any(mine))
            .collect();
        let ghosts = Ghosts::new(
            rank,
            size,
            &node_owner,
            elements.tris.iter().map(|t| t.nodes.as_slice()),
        );
        let mut watched: Vec<u32> = model
            .loads
            .iter()
            .flat_map(|ld| ld.forces.iter().map(|(d, _)| d / 2))
            .chain(model.prescribed.iter().map(|p| p.dof / 2))
            .collect();
        watched.sort_unstable();
        watched.dedup();
        let mut watched_by: Vec<Vec<u32>> = vec![Vec::new(); size];
        for k in watched {
            watched_by[node_owner[k as usize] as usize].push(k);
        }
        let mut active: Vec<std::ops::Range<usize>> = Vec::new();
        for &k in &owned_by[rank] {
            let d = 2 * k as usize;
            match active.last_mut() {
                Some(r) if r.end == d => r.end = d + 2,
                _ => active.push(d..d + 2),
            }
        }
        let held_dofs = owned_by[rank]
            .iter()
            .flat_map(|&k| [2 * k as usize, 2 * k as usize + 1])
            .filter(|&d| model.constrained[d])
            .collect();
        Layout {
            rank,
            size,
            tri_part,
            node_owner,
            owned_by,
            local_tris,
            ghosts,
            watched_by,
            active,
            held_dofs,
        }
    }

    /// The nodes of this rank.
    pub fn owned(&self) -> &[u32] {
        &self.owned_by[self.rank]
    }
}

/// The centroid of each triangle of `elements` at node positions `x`.
pub fn centroids(elements: &Elements, x: &[[f64; 2]]) -> Vec<[f64; 2]> {
    elements
        .tris
        .iter()
        .map(|t| {
            let p = t.nodes.map(|k| x[k as usize]);
            [
                (p[0][0] + p[1][0] + p[2][0]) / 3.0,
                (p[0][1] + p[1][1] + p[2][1]) / 3.0,
            ]
        })
        .collect()
}
