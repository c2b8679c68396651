//! One body's mesh as the solver needs it: nodes, triangles and the named physical groups,
//! filled by the mesh adapter from a Gmsh or JSON mesh; names are resolved against it
//! ([`crate::input::resolve`]) and the model is assembled from it ([`crate::problem::model`]).

use std::collections::BTreeMap;

/// One body's mesh as the solver needs it (filled by the mesh adapter).
#[derive(Debug, Clone, Default)]
pub struct MeshInput {
    /// Node positions [m].
    pub nodes: Vec<[f64; 2]>,
    /// Triangles (CCW node indices).
    pub triangles: Vec<[u32; 3]>,
    /// Name of the physical surface group of each triangle ("" when it has none).
    pub triangle_group: Vec<String>,
    /// Nodes of every named physical group (points, edges and surfaces), sorted, unique.
    pub node_groups: BTreeMap<String, Vec<u32>>,
    /// Edges (node pairs) of every named physical edge group.
    pub edge_groups: BTreeMap<String, Vec<[u32; 2]>>,
}
