//! Per-triangle precomputation: reference inverse edge matrix `G0^-1`, reference area, element
//! size, viscosity, material constants, lumped masses, and the node -> (triangle, corner) list
//! used to gather element forces in a fixed order.

use crate::error::MeshError;
use crate::ids::TriId;
use crate::material::{ElasticLaw, Material};
use crate::mesh::Mesh;
use crate::triangle::{Mat2, Sym2, det, edge_matrix, inv};

/// Precomputed data of one triangle (64 bytes: one cache line).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TriData {
    /// Node indices, counter-clockwise.
    pub nodes: [u32; 3],
    /// Material index (the mesh region).
    pub material: u32,
    /// Reference inverse edge matrix `G0^-1`, row-major.
    pub ginv: Mat2,
    /// Reference area `A0` (m^2).
    pub area0: f64,
    /// Viscosity `eta = 2 xi h sqrt(E rho)` (Pa s).
    pub eta: f64,
}

/// Material constants in the form the kernels use.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct MaterialConsts {
    /// Elastic law.
    pub law: ElasticLaw,
    /// Shear modulus (Pa).
    pub mu: f64,
    /// 2D Lame modulus lam* (Pa).
    pub lam: f64,
    /// Half the thickness, `t/2` (m).
    pub half_t: f64,
    /// Density (kg/m^3).
    pub rho: f64,
    /// The material as given.
    pub material: Material,
}

/// The triangles of a mesh prepared for the force kernels. Immutable during a run; the
/// per-call scratch is a separate [`crate::ForceScratch`]. The default is the empty set (no
/// triangles, no nodes).
#[derive(Clone, Debug, Default)]
pub struct Elements {
    /// Per-triangle data, in mesh order.
    pub tris: Vec<TriData>,
    /// Material constants by material index.
    pub materials: Vec<MaterialConsts>,
    /// Element size `h = 2 A0 / longest reference edge` (m).
    pub size: Vec<f64>,
    /// Number of nodes.
    pub n_nodes: usize,
    /// True if some triangle has a viscosity (the kernels then read velocities).
    pub viscous: bool,
    /// CSR offsets of the node -> slot list (length `n_nodes + 1`).
    pub gather_offsets: Vec<u32>,
    /// Slots `3 t + a` (triangle t, corner a) of each node, in increasing order.
    pub gather_slots: Vec<u32>,
    /// Nodes per block of the owner-computes kernel (the last block may be shorter).
    pub block_nodes: usize,
    /// CSR offsets of the block -> triangle lists (length `n_blocks + 1`).
    pub block_offsets: Vec<u32>,
    /// Triangles with at least one node in each block, in increasing order (a triangle whose
    /// nodes lie in two or three blocks is listed, and evaluated, in each).
    pub block_tris: Vec<u32>,
    /// True when triangle `t` has the nodes `3t, 3t+1, 3t+2` and there are no other nodes (a
    /// wholly exploded mesh: each node belongs to one triangle): the force kernels then add
    /// each triangle's forces to its own nodes directly (no buffer, no gather).
    pub owned_nodes: bool,
    /// Initial stress of each triangle, `[xx, yy, xy]` [Pa], tension positive: a constant
    /// second Piola-Kirchhoff stress `S0` of the reference state (see [`crate::forces`]).
    /// Empty (the default): no triangle has one, and the kernels take the path without it.
    pub initial_stress: Vec<Sym2>,
}

impl Elements {
    /// Prepares the triangles of `mesh`; `materials[r]` is the material of region `r`
    /// (`mesh.regions[r]`).
    pub fn new(mesh: &Mesh, materials: &[Material]) -> Result<Elements, MeshError> {
        if materials.len() != mesh.regions.len() {
            return Err(MeshError::MaterialCount {
                regions: mesh.regions.len(),
                names: mesh.regions.clone(),
                given: materials.len(),
            });
        }
        let mat: Vec<u32> = mesh.tri_region.iter().map(|r| r.0).collect();
        Elements::from_arrays(&mesh.nodes, &mesh.triangles, &mat, materials)
    }

    /// Prepares triangles given as arrays: reference positions, CCW triangles, material index
    /// of each triangle. Errors if a triangle is not CCW with positive area.
    pub fn from_arrays(
        x0: &[[f64; 2]],
        triangles: &[[u32; 3]],
        tri_material: &[u32],
        materials: &[Material],
    ) -> Result<Elements, MeshError> {
        for (i, m) in materials.iter().enumerate() {
            m.validate(i)?;
        }
        let consts: Vec<MaterialConsts> = materials
            .iter()
            .map(|m| MaterialConsts {
                law: m.law,
                mu: m.mu(),
                lam: m.lambda(),
                half_t: 0.5 * m.thickness,
                rho: m.density,
                material: *m,
            })
            .collect();
        let n_nodes = x0.len();
        if tri_material.len() != triangles.len() {
            return Err(MeshError::Parse {
                path: "<elements>".into(),
                line: 0,
                message: format!(
                    "{} material indices for {} triangles",
                    tri_material.len(),
                    triangles.len()
                ),
            });
        }
        let mut tris = Vec::with_capacity(triangles.len());
        let mut size = Vec::with_capacity(triangles.len());
        for (t, (&tri, &mi)) in triangles.iter().zip(tri_material).enumerate() {
            let bad = |msg: String| MeshError::Parse {
                path: "<elements>".into(),
                line: 0,
                message: format!("triangle {t}: {msg}"),
            };
            if tri.iter().any(|&n| n as usize >= n_nodes) {
                return Err(bad(format!("node index out of range in {tri:?}")));
            }
            let m = materials
                .get(mi as usize)
                .ok_or_else(|| bad(format!("material {mi} does not exist")))?;
            let [p0, p1, p2] = tri.map(|n| x0[n as usize]);
            let g0 = edge_matrix(p0, p1, p2);
            let a2 = det(g0);
            if a2.is_nan() || a2 <= 0.0 {
                return Err(bad(format!("reference area {} is not positive", a2 / 2.0)));
            }
            let lmax = [(p0, p1), (p1, p2), (p2, p0)]
                .iter()
                .map(|(a, b)| ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt())
                .fold(0.0, f64::max);
            let h = a2 / lmax;
            size.push(h);
            tris.push(TriData {
                nodes: tri,
                material: mi,
                ginv: inv(g0),
                area0: 0.5 * a2,
                eta: 2.0 * m.damping_ratio * h * (m.youngs_modulus * m.density).sqrt(),
            });
        }
        Ok(Elements::assemble(tris, consts, size, n_nodes, Vec::new()))
    }

    /// The elements of the triangles `keep` (increasing ids) of `self`, on the same nodes
    /// (global node numbering, the same materials and initial stresses): the force pass of
    /// a part of the mesh. A node's force sums its slots in increasing triangle order, as in
    /// `self`, so a node all of whose triangles are kept gets the same force bit for bit.
    /// Panics if `keep` is not increasing or names a triangle that does not exist.
    pub fn subset(&self, keep: &[u32]) -> Elements {
        assert!(
            keep.windows(2).all(|w| w[0] < w[1]),
            "triangles in increasing order"
        );
        let tris = keep.iter().map(|&t| self.tris[t as usize]).collect();
        let size = keep.iter().map(|&t| self.size[t as usize]).collect();
        let s0 = if self.initial_stress.is_empty() {
            Vec::new()
        } else {
            keep.iter()
                .map(|&t| self.initial_stress[t as usize])
                .collect()
        };
        let mut e = Elements::assemble(tris, self.materials.clone(), size, self.n_nodes, s0);
        // a part never takes the kernel of a wholly exploded mesh: its node ids are not 3t..3t+3
        e.owned_nodes = false;
        e
    }

    /// The elements from their triangles: the node -> slot list of the gather and the node
    /// blocks of the owner-computes kernel.
    fn assemble(
        tris: Vec<TriData>,
        consts: Vec<MaterialConsts>,
        size: Vec<f64>,
        n_nodes: usize,
        initial_stress: Vec<Sym2>,
    ) -> Elements {
        // Node -> slot CSR, slots in increasing order (counting sort).
        let mut offsets = vec![0u32; n_nodes + 1];
        for td in &tris {
            for &n in &td.nodes {
                offsets[n as usize + 1] += 1;
            }
        }
        for i in 0..n_nodes {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut slots = vec![0u32; 3 * tris.len()];
        for (t, td) in tris.iter().enumerate() {
            for (a, &n) in td.nodes.iter().enumerate() {
                slots[fill[n as usize] as usize] = (3 * t + a) as u32;
                fill[n as usize] += 1;
            }
        }
        let viscous = tris.iter().any(|t| t.eta > 0.0);
        // Node blocks for the owner-computes kernel: a size that depends on the mesh only.
        let block_nodes = (n_nodes / 32).max(1024);
        let n_blocks = n_nodes.div_ceil(block_nodes);
        let mut block_offsets = vec![0u32; n_blocks + 1];
        let blocks_of = |td: &TriData| {
            let mut b = td.nodes.map(|n| n as usize / block_nodes);
            b.sort_unstable();
            b
        };
        for td in &tris {
            let b = blocks_of(td);
            for k in 0..3 {
                if k == 0 || b[k] != b[k - 1] {
                    block_offsets[b[k] + 1] += 1;
                }
            }
        }
        for i in 0..n_blocks {
            block_offsets[i + 1] += block_offsets[i];
        }
        let mut fill = block_offsets.clone();
        let mut block_tris = vec![0u32; block_offsets[n_blocks] as usize];
        for (t, td) in tris.iter().enumerate() {
            let b = blocks_of(td);
            for k in 0..3 {
                if k == 0 || b[k] != b[k - 1] {
                    block_tris[fill[b[k]] as usize] = t as u32;
                    fill[b[k]] += 1;
                }
            }
        }
        let owned_nodes = n_nodes == 3 * tris.len()
            && tris.iter().enumerate().all(|(t, td)| {
                let b = 3 * t as u32;
                td.nodes == [b, b + 1, b + 2]
            });
        Elements {
            tris,
            materials: consts,
            size,
            n_nodes,
            viscous,
            gather_offsets: offsets,
            gather_slots: slots,
            block_nodes,
            block_offsets,
            block_tris,
            owned_nodes,
            initial_stress,
        }
    }

    /// Sets the initial stress of every triangle (`[xx, yy, xy]` [Pa] each, in triangle
    /// order); an empty vector or one of zeros only removes it (the kernels then cost what
    /// they cost without). Panics if the length is not the number of triangles.
    pub fn set_initial_stress(&mut self, s0: Vec<Sym2>) {
        assert!(
            s0.is_empty() || s0.len() == self.tris.len(),
            "one initial stress per triangle"
        );
        self.initial_stress = if s0.iter().all(|s| *s == [0.0; 3]) {
            Vec::new()
        } else {
            s0
        };
    }

    /// True if some triangle has an initial stress.
    pub fn prestressed(&self) -> bool {
        !self.initial_stress.is_empty()
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    /// True if there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// Lumped nodal masses `m_a = sum over triangles of rho A0 t / 3` (kg).
    pub fn lumped_masses(&self) -> Vec<f64> {
        let mut m = vec![0.0; self.n_nodes];
        for td in &self.tris {
            let c = &self.materials[td.material as usize];
            let ma = c.rho * td.area0 * 2.0 * c.half_t / 3.0;
            for &n in &td.nodes {
                m[n as usize] += ma;
            }
        }
        m
    }

    /// The first triangle (lowest id) whose current signed area is not positive, if any.
    /// Call it at a fixed check point of the time loop.
    pub fn first_inverted(&self, x: &[[f64; 2]]) -> Option<TriId> {
        self.tris
            .iter()
            .position(|td| {
                let [p0, p1, p2] = td.nodes.map(|n| x[n as usize]);
                let a2 = det(edge_matrix(p0, p1, p2));
                a2.is_nan() || a2 <= 0.0
            })
            .map(|t| TriId(t as u32))
    }
}
