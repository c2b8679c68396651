//! The explode operation: every (selected) triangle gets its own three nodes, and every
//! internal edge that is no longer shared is listed with its two triangles, for the joint
//! elements of fracture.
//!
//! Joint convention (docs/mesh.md, "Exploding a mesh for fracture"): edge `P -> Q` of `T1` (CCW in `T1`) and edge
//! `R -> S` of `T2` (CCW in `T2`), with `P = S` and `Q = R` in the reference state. The normal
//! `nn = (tt_y, -tt_x)`, `tt` along `P -> Q`, points from `T1` to `T2`.

use crate::error::MeshError;
use crate::ids::{NodeId, TriId};
use crate::mesh::{Mesh, PhysicalGroup, RawMesh};
use rayon::prelude::*;

/// Items per rayon task in the explode's parallel maps (collected in order: the result does
/// not depend on the number of threads).
const PAR_CHUNK: usize = 4096;

/// An internal edge of an exploded mesh: the two triangles and the four node ids.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct InternalEdge {
    /// `[T1, T2]`.
    pub tris: [TriId; 2],
    /// `[P, Q, R, S]`: `P -> Q` CCW in `T1`, `R -> S` CCW in `T2`, `P = S`, `Q = R` in the
    /// reference.
    pub nodes: [NodeId; 4],
    /// Local edge index of `P -> Q` in `T1` and of `R -> S` in `T2` (edge `k` runs from
    /// local node `k` to `k+1`).
    pub local_edge: [u8; 2],
}

/// An exploded mesh with its joints and the map back to the original nodes.
#[derive(Clone, Debug)]
pub struct Exploded {
    /// The exploded mesh (coincident nodes allowed; same triangles, groups and regions).
    pub mesh: Mesh,
    /// Original node of each new node.
    pub original_node: Vec<NodeId>,
    /// Internal edges whose two sides no longer share nodes, in original edge order.
    pub internal_edges: Vec<InternalEdge>,
}

/// Explodes `mesh`. With `only_groups = None` every triangle gets its own nodes; with
/// `Some(names)` only the triangles of those dimension-2 groups do, and the others keep
/// sharing nodes among themselves. Every internal edge with at least one exploded triangle
/// becomes an [`InternalEdge`]. Errors if a named group is missing or is not of dimension 2.
pub fn explode(mesh: &Mesh, only_groups: Option<&[&str]>) -> Result<Exploded, MeshError> {
    let selected = selected_triangles(mesh, only_groups)?;
    let (original_node, tris) = new_nodes(mesh, &selected);
    let new_of = |t: TriId, orig: NodeId| new_node(mesh, &tris, t, orig);
    let local = |t: TriId, orig: NodeId| local_node(mesh, t, orig);
    // In parallel over the edges, collected in edge order.
    let internal_edges: Vec<InternalEdge> = (mesh.edges.par_iter())
        .with_min_len(PAR_CHUNK)
        .filter_map(|e| {
            let (t1, t2) = (e.left, e.right?);
            if !(selected[t1.idx()] || selected[t2.idx()]) {
                return None;
            }
            let [p0, q0] = e.nodes;
            Some(InternalEdge {
                tris: [t1, t2],
                nodes: [
                    new_of(t1, p0),
                    new_of(t1, q0),
                    new_of(t2, q0),
                    new_of(t2, p0),
                ],
                local_edge: [local(t1, p0) as u8, local(t2, q0) as u8],
            })
        })
        .collect();
    let groups = exploded_groups(mesh, &original_node, &tris);
    let par_nodes = || original_node.par_iter().with_min_len(PAR_CHUNK);
    let nodes = par_nodes().map(|o| mesh.nodes[o.idx()]).collect();
    let node_tags = par_nodes().map(|o| mesh.node_tags[o.idx()]).collect();
    let exploded = Mesh::build(
        RawMesh {
            path: format!("{} (exploded)", mesh.source),
            node_tags,
            nodes,
            triangles: tris,
            tri_tags: mesh.tri_tags.clone(),
            groups,
        },
        false,
    )?;
    Ok(Exploded {
        mesh: exploded,
        original_node,
        internal_edges,
    })
}

/// Which triangles explode: all with `only_groups = None`, else those of the named
/// dimension-2 groups.
fn selected_triangles(mesh: &Mesh, only_groups: Option<&[&str]>) -> Result<Vec<bool>, MeshError> {
    let nt = mesh.triangles.len();
    let mut selected = vec![only_groups.is_none(); nt];
    if let Some(names) = only_groups {
        for name in names {
            let g = mesh.group(name)?;
            if g.dim != 2 {
                return Err(MeshError::MissingGroup {
                    name: format!(
                        "{name} (as a dimension-2 group; it has dimension {})",
                        g.dim
                    ),
                    available: mesh
                        .groups
                        .iter()
                        .filter(|g| g.dim == 2)
                        .map(|g| g.name.clone())
                        .collect(),
                });
            }
            for t in &g.triangles {
                selected[t.idx()] = true;
            }
        }
    }
    Ok(selected)
}

/// The nodes of the exploded mesh: each selected triangle gets three of its own, the others
/// share one per original node. Returns the original node of each new node and the new
/// triangles.
fn new_nodes(mesh: &Mesh, selected: &[bool]) -> (Vec<NodeId>, Vec<[u32; 3]>) {
    let nt = mesh.triangles.len();
    const NONE: u32 = u32::MAX;
    let mut shared = vec![NONE; mesh.nodes.len()];
    let mut original_node = Vec::with_capacity(3 * nt);
    let mut tris = Vec::with_capacity(nt);
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let mut nt3 = [0u32; 3];
        for k in 0..3 {
            let n = tri[k] as usize;
            if selected[t] {
                nt3[k] = original_node.len() as u32;
                original_node.push(NodeId(n as u32));
            } else {
                if shared[n] == NONE {
                    shared[n] = original_node.len() as u32;
                    original_node.push(NodeId(n as u32));
                }
                nt3[k] = shared[n];
            }
        }
        tris.push(nt3);
    }
    (original_node, tris)
}

/// The local index (0..3) of original node `orig` in triangle `t` of `mesh`.
fn local_node(mesh: &Mesh, t: TriId, orig: NodeId) -> usize {
    let tri = mesh.triangles[t.idx()];
    (0..3).find(|&k| tri[k] == orig.0).unwrap_or(0)
}

/// The new node of triangle `t` (of the new triangles `tris`) at original node `orig`.
fn new_node(mesh: &Mesh, tris: &[[u32; 3]], t: TriId, orig: NodeId) -> NodeId {
    NodeId(tris[t.idx()][local_node(mesh, t, orig)])
}

/// The groups of the exploded mesh: a point group holds every copy of its nodes, an edge
/// group the edge of each triangle beside it, a triangle group the same triangles.
fn exploded_groups(mesh: &Mesh, original_node: &[NodeId], tris: &[[u32; 3]]) -> Vec<PhysicalGroup> {
    let new_of = |t: TriId, orig: NodeId| new_node(mesh, tris, t, orig);
    // Copies of each original node (for point groups; none built without one).
    let mut copies: Vec<Vec<NodeId>> = Vec::new();
    if mesh.groups.iter().any(|g| g.dim == 0) {
        copies = vec![Vec::new(); mesh.nodes.len()];
        for (i, o) in original_node.iter().enumerate() {
            copies[o.idx()].push(NodeId(i as u32));
        }
    }
    // Edge lookup: original (min, max) -> mesh edge (for the groups' edges; none built
    // without them).
    let mut edge_of = std::collections::HashMap::new();
    if mesh.groups.iter().any(|g| !g.edges.is_empty()) {
        edge_of.reserve(mesh.edges.len());
        for e in &mesh.edges {
            let (a, b) = (
                e.nodes[0].0.min(e.nodes[1].0),
                e.nodes[0].0.max(e.nodes[1].0),
            );
            edge_of.insert((a, b), *e);
        }
    }
    mesh.groups
        .iter()
        .map(|g| {
            let mut edges = Vec::new();
            for ed in &g.edges {
                let key = (ed[0].0.min(ed[1].0), ed[0].0.max(ed[1].0));
                if let Some(me) = edge_of.get(&key) {
                    for t in std::iter::once(me.left).chain(me.right) {
                        edges.push([new_of(t, ed[0]), new_of(t, ed[1])]);
                    }
                }
            }
            PhysicalGroup {
                name: g.name.clone(),
                dim: g.dim,
                tag: g.tag,
                nodes: if g.dim == 0 {
                    g.nodes
                        .iter()
                        .flat_map(|n| copies[n.idx()].iter().copied())
                        .collect()
                } else {
                    Vec::new()
                },
                edges,
                triangles: g.triangles.clone(),
            }
        })
        .collect()
}
