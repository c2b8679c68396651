//! The plain JSON mesh format.
//!
//! ```json
//! { "nodes": [[0,0],[1,0],[0,1]],
//!   "triangles": [[0,1,2]],
//!   "groups": [ {"name": "body", "dim": 2, "triangles": [0]},
//!               {"name": "bottom", "dim": 1, "edges": [[0,1]]},
//!               {"name": "corner", "dim": 0, "nodes": [0]} ] }
//! ```
//! Node and triangle indices are 0-based. Fields of a group that do not apply may be left out.

use crate::error::MeshError;
use crate::ids::{NodeId, TriId};
use crate::mesh::{Mesh, PhysicalGroup, RawMesh};
use serde::{Deserialize, Serialize};

/// A group in a JSON mesh file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JsonGroup {
    /// Name.
    pub name: String,
    /// Dimension (0, 1, 2).
    pub dim: u8,
    /// Node indices (dimension 0).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub nodes: Vec<u32>,
    /// Edges as node index pairs (dimension 1).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub edges: Vec<[u32; 2]>,
    /// Triangle indices (dimension 2).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub triangles: Vec<u32>,
}

/// A JSON mesh file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JsonMesh {
    /// Node positions.
    pub nodes: Vec<[f64; 2]>,
    /// Triangles as node indices (either orientation).
    pub triangles: Vec<[u32; 3]>,
    /// Named groups.
    #[serde(default)]
    pub groups: Vec<JsonGroup>,
}

impl JsonMesh {
    /// The JSON form of a mesh (groups keep their nodes, edges and triangles).
    pub fn from_mesh(m: &Mesh) -> JsonMesh {
        JsonMesh {
            nodes: m.nodes.clone(),
            triangles: m.triangles.clone(),
            groups: m
                .groups
                .iter()
                .map(|g| JsonGroup {
                    name: g.name.clone(),
                    dim: g.dim,
                    nodes: if g.dim == 0 {
                        g.nodes.iter().map(|n| n.0).collect()
                    } else {
                        Vec::new()
                    },
                    edges: g.edges.iter().map(|e| [e[0].0, e[1].0]).collect(),
                    triangles: g.triangles.iter().map(|t| t.0).collect(),
                })
                .collect(),
        }
    }
}

pub(crate) fn read_json(bytes: &[u8], path: &str) -> Result<RawMesh, MeshError> {
    let j: JsonMesh = serde_json::from_slice(bytes).map_err(|e| MeshError::Json {
        path: path.to_string(),
        source: e,
    })?;
    let n = j.nodes.len() as u32;
    let nt = j.triangles.len() as u32;
    let bad_node = |element: usize, node: u32| MeshError::UnknownNode {
        path: path.to_string(),
        element: element as u64,
        node: node as u64,
    };
    for (t, tri) in j.triangles.iter().enumerate() {
        if let Some(&k) = tri.iter().find(|&&k| k >= n) {
            return Err(bad_node(t, k));
        }
    }
    let mut groups = Vec::new();
    for (gi, g) in j.groups.into_iter().enumerate() {
        let field_err = |what: &str, v: u32| MeshError::Parse {
            path: path.to_string(),
            line: 0,
            message: format!(
                "group \"{}\": {what} {v} does not exist",
                crate::excerpt::excerpt(&g.name)
            ),
        };
        if g.dim > 2 {
            return Err(field_err("dimension", g.dim as u32));
        }
        if let Some(&k) = g
            .nodes
            .iter()
            .chain(g.edges.iter().flatten())
            .find(|&&k| k >= n)
        {
            return Err(field_err("node", k));
        }
        if let Some(&t) = g.triangles.iter().find(|&&t| t >= nt) {
            return Err(field_err("triangle", t));
        }
        groups.push(PhysicalGroup {
            name: g.name,
            dim: g.dim,
            tag: gi as i64 + 1,
            nodes: g.nodes.into_iter().map(NodeId).collect(),
            edges: g.edges.into_iter().map(|e| e.map(NodeId)).collect(),
            triangles: g.triangles.into_iter().map(TriId).collect(),
        });
    }
    Ok(RawMesh {
        path: path.to_string(),
        node_tags: (0..n as u64).collect(),
        nodes: j.nodes,
        triangles: j.triangles,
        tri_tags: (0..nt as u64).collect(),
        groups,
    })
}
