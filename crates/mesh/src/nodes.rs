//! Node arrays as separate plain arrays (structure of arrays): positions, velocities, masses
//! and forces, indexed by node. The solver owns and steps them; the kernels take slices.

use crate::elements::Elements;
use crate::mesh::Mesh;

/// The state arrays of the nodes of one mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeArrays {
    /// Current positions (m).
    pub x: Vec<[f64; 2]>,
    /// Velocities (m/s).
    pub v: Vec<[f64; 2]>,
    /// Lumped masses (kg).
    pub m: Vec<f64>,
    /// Force accumulator (N).
    pub f: Vec<[f64; 2]>,
}

impl NodeArrays {
    /// Positions at the reference, zero velocities and forces, lumped masses of `elements`.
    pub fn new(mesh: &Mesh, elements: &Elements) -> NodeArrays {
        let n = mesh.n_nodes();
        NodeArrays {
            x: mesh.nodes.clone(),
            v: vec![[0.0; 2]; n],
            m: elements.lumped_masses(),
            f: vec![[0.0; 2]; n],
        }
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True if there are no nodes.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }
}
