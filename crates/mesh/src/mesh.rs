//! The mesh data: nodes, CCW triangles, physical groups, material regions, edges and their
//! adjacency, and the validation that every reader goes through ([`Mesh::from_parts`]).

use crate::error::MeshError;
use crate::ids::{EdgeId, NodeId, RegionId, TriId};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// A named physical group of the mesh (a Gmsh physical group, or a JSON group).
///
/// `nodes` holds every node of the group's entities (sorted, unique), also for groups of
/// edges and triangles. `edges` holds the 2-node line elements of a dimension-1 group, each
/// oriented as in the triangle that owns it where it lies on the boundary (so that the
/// outward normal is `(e_y, -e_x)/|e|`). `triangles` holds the triangles of a dimension-2 group.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhysicalGroup {
    /// The group's name (from `$PhysicalNames`; `"<dim>:<tag>"` where the file gives none).
    pub name: String,
    /// Dimension: 0 points, 1 edges, 2 triangles.
    pub dim: u8,
    /// The Gmsh physical tag (or the position in a JSON file).
    pub tag: i64,
    /// Nodes of the group, sorted and unique.
    pub nodes: Vec<NodeId>,
    /// Edges of the group (dimension 1).
    pub edges: Vec<[NodeId; 2]>,
    /// Triangles of the group (dimension 2), sorted and unique.
    pub triangles: Vec<TriId>,
}

/// An edge of the mesh with the triangles on each side.
///
/// `nodes` runs counter-clockwise around `left` (it is `left`'s local edge `k`, from local node
/// `k` to `k+1`); `right` is the neighbour across it, `None` on the boundary.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct MeshEdge {
    /// End nodes, CCW around `left`.
    pub nodes: [NodeId; 2],
    /// The triangle that owns the edge in this direction.
    pub left: TriId,
    /// The triangle across the edge, if any.
    pub right: Option<TriId>,
}

/// A triangle mesh ready for the solver: validated, CCW, with groups and adjacency.
///
/// Invariants (checked by [`Mesh::from_parts`]): every triangle has positive area with its
/// nodes counter-clockwise, every node belongs to a triangle, no two nodes coincide, each
/// edge has at most two triangles.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Mesh {
    /// Reference node positions (m).
    pub nodes: Vec<[f64; 2]>,
    /// Triangles as node indices, counter-clockwise.
    pub triangles: Vec<[u32; 3]>,
    /// Material region of each triangle (index into `regions`).
    pub tri_region: Vec<RegionId>,
    /// Names of the material regions: the dimension-2 groups in tag order that are the first
    /// group of at least one triangle, then `"default"` if some triangle is in no dimension-2
    /// group. A triangle's region is the first dimension-2 group that holds it.
    pub regions: Vec<String>,
    /// Physical groups, in order of (dimension, tag).
    pub groups: Vec<PhysicalGroup>,
    /// Unique edges with their adjacent triangles.
    pub edges: Vec<MeshEdge>,
    /// Edges of each triangle: local edge `k` runs from local node `k` to `k+1`.
    pub tri_edges: Vec<[EdgeId; 3]>,
    /// Boundary edges (one triangle), in edge order; each runs CCW around the body.
    pub boundary_edges: Vec<EdgeId>,
    /// Node tag in the source file of each node (for messages).
    pub node_tags: Vec<u64>,
    /// Element tag in the source file of each triangle (for messages).
    pub tri_tags: Vec<u64>,
    /// The file the mesh came from (or a description).
    pub source: String,
    /// How many triangles were given clockwise and had their node order reversed.
    pub reoriented: usize,
}

/// The raw content of a mesh file, before validation.
#[derive(Clone, Debug, Default)]
pub struct RawMesh {
    /// The file (for messages).
    pub path: String,
    /// Node tags in the file.
    pub node_tags: Vec<u64>,
    /// Node positions.
    pub nodes: Vec<[f64; 2]>,
    /// Triangles as node indices (any orientation).
    pub triangles: Vec<[u32; 3]>,
    /// Element tags of the triangles.
    pub tri_tags: Vec<u64>,
    /// Groups (node sets need not be filled for dimension 1 and 2; edges in any direction).
    pub groups: Vec<PhysicalGroup>,
}

impl Mesh {
    /// Validates raw content and builds the mesh: reverses clockwise triangles, rejects zero
    /// areas, unused and duplicate nodes and non-finite coordinates, builds edges, adjacency,
    /// boundary, regions and group node sets.
    ///
    /// Groups are sets: a node, an edge (in either direction) or a triangle listed twice in
    /// one group is refused ([`MeshError::RepeatedInGroup`]), never counted twice.
    pub fn from_parts(raw: RawMesh) -> Result<Mesh, MeshError> {
        check_groups_are_sets(&raw)?;
        Mesh::build(raw, true)
    }

    /// As [`Mesh::from_parts`]; `check_coincident` false allows coincident nodes (exploded
    /// meshes, where each triangle owns its nodes).
    pub(crate) fn build(raw: RawMesh, check_coincident: bool) -> Result<Mesh, MeshError> {
        let RawMesh {
            path,
            node_tags,
            nodes,
            mut triangles,
            tri_tags,
            mut groups,
        } = raw;
        check_finite(&path, &nodes, &node_tags)?;
        if triangles.is_empty() {
            return Err(MeshError::NoTriangles { path });
        }
        let reoriented = orient_triangles(&path, &nodes, &mut triangles, &node_tags, &tri_tags)?;
        check_every_node_used(&path, &nodes, &triangles, &node_tags)?;
        if check_coincident {
            check_duplicates(&path, &nodes, &node_tags)?;
        }
        let (edges, tri_edges) = build_edges(&path, &triangles, &tri_tags)?;
        let boundary_edges = edges
            .iter()
            .enumerate()
            .filter(|(_, e)| e.right.is_none())
            .map(|(i, _)| EdgeId(i as u32))
            .collect();
        complete_groups(&mut groups, &edges, &triangles);
        let (regions, tri_region) = regions_of(&groups, triangles.len());
        Ok(Mesh {
            nodes,
            triangles,
            tri_region,
            regions,
            groups,
            edges,
            tri_edges,
            boundary_edges,
            node_tags,
            tri_tags,
            source: path,
            reoriented,
        })
    }

    /// Builds a mesh from node positions and triangles alone (no groups, one region
    /// `"default"`), with the same validation.
    pub fn from_nodes_triangles(
        nodes: Vec<[f64; 2]>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Mesh, MeshError> {
        let n = nodes.len();
        let nt = triangles.len();
        for (t, tri) in triangles.iter().enumerate() {
            for &k in tri {
                if k as usize >= n {
                    return Err(MeshError::UnknownNode {
                        path: "<memory>".into(),
                        element: t as u64,
                        node: k as u64,
                    });
                }
            }
        }
        Mesh::from_parts(RawMesh {
            path: "<memory>".into(),
            node_tags: (0..n as u64).collect(),
            nodes,
            triangles,
            tri_tags: (0..nt as u64).collect(),
            groups: Vec::new(),
        })
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Number of triangles.
    pub fn n_triangles(&self) -> usize {
        self.triangles.len()
    }

    /// The physical group with this name, or an error listing the names there are.
    pub fn group(&self, name: &str) -> Result<&PhysicalGroup, MeshError> {
        self.groups
            .iter()
            .find(|g| g.name == name)
            .ok_or_else(|| MeshError::MissingGroup {
                name: name.to_string(),
                available: self.groups.iter().map(|g| g.name.clone()).collect(),
            })
    }

    /// The region id of a region name, or an error listing the regions.
    pub fn region(&self, name: &str) -> Result<RegionId, MeshError> {
        self.regions
            .iter()
            .position(|r| r == name)
            .map(|i| RegionId(i as u32))
            .ok_or_else(|| MeshError::MissingGroup {
                name: name.to_string(),
                available: self.regions.clone(),
            })
    }

    /// Signed reference area of a triangle (positive).
    pub fn area(&self, t: TriId) -> f64 {
        tri_area(&self.nodes, self.triangles[t.idx()])
    }
}

/// Twice the signed area of `tri`, or `None` when the triangle is flat (`|2A| <= 1e-10` times
/// its longest edge squared) or not finite.
fn doubled_area(nodes: &[[f64; 2]], tri: [u32; 3]) -> Option<f64> {
    let [a, b, c] = tri.map(|n| nodes[n as usize]);
    let e1 = [b[0] - a[0], b[1] - a[1]];
    let e2 = [c[0] - a[0], c[1] - a[1]];
    let e3 = [c[0] - b[0], c[1] - b[1]];
    let a2 = e1[0] * e2[1] - e1[1] * e2[0];
    let lmax2 = [e1, e2, e3]
        .iter()
        .map(|e| e[0] * e[0] + e[1] * e[1])
        .fold(0.0, f64::max);
    (a2.abs() > 1e-10 * lmax2 && a2.is_finite()).then_some(a2)
}

/// Signed area of triangle `tri` with positions `x`: `cross(x1-x0, x2-x0)/2`.
#[inline]
pub fn tri_area(x: &[[f64; 2]], tri: [u32; 3]) -> f64 {
    let [a, b, c] = tri.map(|n| x[n as usize]);
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

fn check_duplicates(path: &str, nodes: &[[f64; 2]], tags: &[u64]) -> Result<(), MeshError> {
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in nodes {
        for d in 0..2 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    let tol = 1e-10 * ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt();
    let mut order: Vec<u32> = (0..nodes.len() as u32).collect();
    order.sort_unstable_by(|&a, &b| nodes[a as usize][0].total_cmp(&nodes[b as usize][0]));
    for i in 0..order.len() {
        let a = order[i] as usize;
        for &bj in &order[i + 1..] {
            let b = bj as usize;
            if nodes[b][0] - nodes[a][0] > tol {
                break;
            }
            if (nodes[b][1] - nodes[a][1]).abs() <= tol {
                let (a, b) = (a.min(b), a.max(b));
                return Err(MeshError::DuplicateNodes {
                    path: path.to_string(),
                    a: NodeId(a as u32),
                    b: NodeId(b as u32),
                    tag_a: tags[a],
                    tag_b: tags[b],
                    x: nodes[a][0],
                    y: nodes[a][1],
                });
            }
        }
    }
    Ok(())
}

type Edges = (Vec<MeshEdge>, Vec<[EdgeId; 3]>);

/// Triangles per rayon task in the build's per-triangle loops.
const TRI_CHUNK: usize = 4096;

/// An edge key: (min node, max node, triangle, local edge).
type EdgeKey = (u32, u32, u32, u8);

/// The keys of every triangle's three edges, sorted. Each key is unique (its triangle and
/// local edge are), so the parallel unstable sort gives the one sorted order whatever the
/// number of threads.
pub(crate) fn edge_keys(tris: &[[u32; 3]]) -> Vec<EdgeKey> {
    let mut keys: Vec<EdgeKey> = Vec::with_capacity(3 * tris.len());
    keys.par_extend(
        tris.par_iter()
            .with_min_len(TRI_CHUNK)
            .enumerate()
            .flat_map_iter(|(t, tri)| {
                (0..3).map(move |k| {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    (a.min(b), a.max(b), t as u32, k as u8)
                })
            }),
    );
    keys.par_sort_unstable();
    keys
}

/// Refuses a group that lists an entity twice, naming the group and the entity by its file
/// tags (node tags, or the element tag of a triangle).
fn check_groups_are_sets(raw: &RawMesh) -> Result<(), MeshError> {
    let tag = |n: NodeId| raw.node_tags.get(n.idx()).copied().unwrap_or(n.0 as u64);
    for g in &raw.groups {
        let repeated = |entity: String| MeshError::RepeatedInGroup {
            path: raw.path.clone(),
            group: g.name.clone(),
            entity,
        };
        if g.dim == 0 {
            let mut seen = std::collections::HashSet::with_capacity(g.nodes.len());
            if let Some(&n) = g.nodes.iter().find(|&&n| !seen.insert(n)) {
                return Err(repeated(format!("node {}", tag(n))));
            }
        }
        let mut seen = std::collections::HashSet::with_capacity(g.edges.len());
        if let Some(e) = g
            .edges
            .iter()
            .find(|e| !seen.insert((e[0].min(e[1]), e[0].max(e[1]))))
        {
            return Err(repeated(format!(
                "the edge between nodes {} and {} (in either direction)",
                tag(e[0]),
                tag(e[1])
            )));
        }
        let mut seen = std::collections::HashSet::with_capacity(g.triangles.len());
        if let Some(&t) = g.triangles.iter().find(|&&t| !seen.insert(t)) {
            let element = raw.tri_tags.get(t.idx()).copied().unwrap_or(t.0 as u64);
            return Err(repeated(format!("triangle {element} (file element tag)")));
        }
    }
    Ok(())
}

/// Every node position is finite.
fn check_finite(path: &str, nodes: &[[f64; 2]], node_tags: &[u64]) -> Result<(), MeshError> {
    for (i, p) in nodes.iter().enumerate() {
        if !p[0].is_finite() || !p[1].is_finite() {
            return Err(MeshError::NonFinite {
                path: path.to_string(),
                tag: node_tags[i],
            });
        }
    }
    Ok(())
}

/// Reverses the clockwise triangles and refuses a flat one; returns how many were reversed.
/// Per triangle in parallel: the count of reversed triangles and the first flat one (in
/// triangle order) do not depend on the threads.
fn orient_triangles(
    path: &str,
    nodes: &[[f64; 2]],
    triangles: &mut [[u32; 3]],
    node_tags: &[u64],
    tri_tags: &[u64],
) -> Result<usize, MeshError> {
    let (flat, reoriented) = triangles
        .par_iter_mut()
        .with_min_len(TRI_CHUNK)
        .enumerate()
        .map(|(t, tri)| match doubled_area(nodes, *tri) {
            None => (Some(t), 0),
            Some(a2) if a2 < 0.0 => {
                tri.swap(1, 2);
                (None, 1)
            }
            Some(_) => (None, 0),
        })
        .reduce(
            || (None, 0),
            |a, b| (a.0.into_iter().chain(b.0).min(), a.1 + b.1),
        );
    if let Some(t) = flat {
        let tri = triangles[t];
        return Err(MeshError::ZeroArea {
            path: path.to_string(),
            tri: TriId(t as u32),
            element: tri_tags[t],
            area: tri_area(nodes, tri),
            nodes: tri.map(|n| node_tags[n as usize]),
        });
    }
    Ok(reoriented)
}

/// Every node belongs to a triangle.
fn check_every_node_used(
    path: &str,
    nodes: &[[f64; 2]],
    triangles: &[[u32; 3]],
    node_tags: &[u64],
) -> Result<(), MeshError> {
    let mut used = vec![false; nodes.len()];
    for tri in triangles {
        for &n in tri {
            used[n as usize] = true;
        }
    }
    if let Some(n) = used.iter().position(|u| !u) {
        return Err(MeshError::UnusedNode {
            path: path.to_string(),
            node: NodeId(n as u32),
            tag: node_tags[n],
            x: nodes[n][0],
            y: nodes[n][1],
        });
    }
    Ok(())
}

/// Sorts the groups by (dimension, tag) and completes each: its edges oriented as the
/// boundary runs, its triangles sorted and unique, its node set holding the nodes of its
/// edges and triangles.
fn complete_groups(groups: &mut [PhysicalGroup], edges: &[MeshEdge], triangles: &[[u32; 3]]) {
    groups.sort_by_key(|g| (g.dim, g.tag));
    // The boundary edges reversed, for the groups' edges (none asked: none built).
    let mut edge_dir = std::collections::HashSet::new();
    if groups.iter().any(|g| !g.edges.is_empty()) {
        edge_dir.extend(
            (edges.iter())
                .filter(|e| e.right.is_none())
                .map(|e| (e.nodes[1], e.nodes[0])),
        );
    }
    for g in groups {
        let mut ns: Vec<NodeId> = g.nodes.clone();
        for e in &mut g.edges {
            if edge_dir.contains(&(e[0], e[1])) {
                e.swap(0, 1);
            }
            ns.extend_from_slice(e);
        }
        g.triangles.sort_unstable();
        g.triangles.dedup();
        for t in &g.triangles {
            ns.extend(triangles[t.idx()].map(NodeId));
        }
        ns.sort_unstable();
        ns.dedup();
        g.nodes = ns;
    }
}

/// The material regions ([`Mesh::regions`]) and the region of each of `n_tris` triangles:
/// the dimension-2 groups, in order, that are the first group of some triangle, then
/// `"default"` for the triangles in none.
fn regions_of(groups: &[PhysicalGroup], n_tris: usize) -> (Vec<String>, Vec<RegionId>) {
    let mut regions: Vec<String> = Vec::new();
    let mut first = vec![usize::MAX; n_tris];
    for (gi, g) in groups.iter().enumerate().filter(|(_, g)| g.dim == 2) {
        for t in &g.triangles {
            if first[t.idx()] == usize::MAX {
                first[t.idx()] = gi;
            }
        }
    }
    let mut used_group = vec![false; groups.len()];
    for &gi in first.iter().filter(|&&gi| gi != usize::MAX) {
        used_group[gi] = true;
    }
    let mut region_of_group = vec![u32::MAX; groups.len()];
    for (gi, g) in groups.iter().enumerate() {
        if used_group[gi] {
            region_of_group[gi] = regions.len() as u32;
            regions.push(g.name.clone());
        }
    }
    let mut tri_region: Vec<RegionId> = first
        .iter()
        .map(|&gi| {
            RegionId(if gi == usize::MAX {
                u32::MAX
            } else {
                region_of_group[gi]
            })
        })
        .collect();
    if tri_region.iter().any(|r| r.0 == u32::MAX) {
        let r = RegionId(regions.len() as u32);
        regions.push("default".to_string());
        for x in &mut tri_region {
            if x.0 == u32::MAX {
                *x = r;
            }
        }
    }
    (regions, tri_region)
}

fn build_edges(path: &str, tris: &[[u32; 3]], tri_tags: &[u64]) -> Result<Edges, MeshError> {
    let keys = edge_keys(tris);
    let mut edges = Vec::with_capacity(keys.len() / 2 + 1);
    let mut tri_edges = vec![[EdgeId(0); 3]; tris.len()];
    let mut i = 0;
    while i < keys.len() {
        let mut j = i + 1;
        while j < keys.len() && keys[j].0 == keys[i].0 && keys[j].1 == keys[i].1 {
            j += 1;
        }
        if j - i > 2 {
            return Err(MeshError::Parse {
                path: path.to_string(),
                line: 0,
                message: format!(
                    "edge between nodes {} and {} is shared by {} triangles (elements {:?}): the mesh overlaps itself",
                    keys[i].0,
                    keys[i].1,
                    j - i,
                    keys[i..j]
                        .iter()
                        .map(|k| tri_tags[k.2 as usize])
                        .collect::<Vec<_>>()
                ),
            });
        }
        let (_, _, t, k) = keys[i];
        let tri = tris[t as usize];
        let id = EdgeId(edges.len() as u32);
        let right = if j - i == 2 {
            let (_, _, t2, k2) = keys[i + 1];
            tri_edges[t2 as usize][k2 as usize] = id;
            Some(TriId(t2))
        } else {
            None
        };
        tri_edges[t as usize][k as usize] = id;
        edges.push(MeshEdge {
            nodes: [NodeId(tri[k as usize]), NodeId(tri[(k as usize + 1) % 3])],
            left: TriId(t),
            right,
        });
        i = j;
    }
    Ok((edges, tri_edges))
}
