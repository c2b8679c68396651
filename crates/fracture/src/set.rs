//! The joint set: plain, validated data of every joint (node ids, triangles, reference
//! length, material) with the per-joint constants derived once.

use rayon::prelude::*;

use crate::error::FractureError;
use crate::material::{JointConsts, JointMaterial, JointMaterialInput, SofteningConsts};

/// Joints per rayon task in [`JointSet::new`] (its columns are collected in joint order: the
/// set does not depend on the number of threads).
const SET_CHUNK: usize = 4096;

/// Checks joint `j` (node ids below `n_nodes`, material in range, a positive length, fracture
/// energies above the pre-peak work on its edge).
fn check_joint(
    j: usize,
    jt: &Joint,
    materials: &[JointMaterial],
    n_nodes: usize,
) -> Result<(), FractureError> {
    let joint = j as u32;
    for &node in &jt.nodes {
        if node as usize >= n_nodes {
            return Err(FractureError::NodeOutOfRange {
                joint,
                node,
                n_nodes,
            });
        }
    }
    let Some(mat) = materials.get(jt.material as usize) else {
        return Err(FractureError::MaterialOutOfRange {
            joint,
            material: jt.material,
            n_materials: materials.len(),
        });
    };
    let h = jt.ref_length;
    if !(h.is_finite() && h > 0.0) {
        return Err(FractureError::BadLength { joint, h });
    }
    mat.check_edge(joint, jt.material, h)
}

/// The entries `keep` of `v`, in that order.
pub(crate) fn pick<T: Clone>(v: &[T], keep: &[u32]) -> Vec<T> {
    keep.iter().map(|&j| v[j as usize].clone()).collect()
}

/// Index of a joint in its [`JointSet`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct JointId(pub u32);

/// One joint as the mesh gives it: edge P->Q of triangle T1 bonded to edge R->S of triangle
/// T2, with P = S and Q = R in the reference state (so `nn` points from T1 to T2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Joint {
    /// Node ids P, Q, R, S.
    pub nodes: [u32; 4],
    /// Triangle ids T1 (owner of P, Q) and T2 (owner of R, S), reported when the joint breaks.
    pub triangles: [u32; 2],
    /// Reference edge length `h` (m): the joint's stiffness is `p/h`.
    pub ref_length: f64,
    /// Index into the material list.
    pub material: u32,
}

/// Every joint of a scene, validated, as structure-of-arrays.
#[derive(Debug, Clone)]
pub struct JointSet {
    /// Node ids P, Q, R, S per joint.
    pub nodes: Vec<[u32; 4]>,
    /// Triangles T1, T2 per joint.
    pub triangles: Vec<[u32; 2]>,
    /// Reference edge length `h` per joint (m).
    pub ref_length: Vec<f64>,
    /// Material index per joint.
    pub material: Vec<u32>,
    /// Derived constants per joint that only the softening branch reads (softening widths).
    pub softening: Vec<SofteningConsts>,
    /// The validated materials.
    pub materials: Vec<JointMaterial>,
    /// Out-of-plane thickness `t` (m); 1 for plane strain.
    pub thickness: f64,
    /// Number of nodes the ids refer to.
    pub n_nodes: usize,
    /// Node-to-joint map (CSR): the slots of node `i` are
    /// `node_slots[node_offsets[i]..node_offsets[i + 1]]`.
    pub node_offsets: Vec<u32>,
    /// `4 j + k` for node k (P, Q, R, S) of joint j, in increasing order per node.
    pub node_slots: Vec<u32>,
    /// Per joint, the initial offsets `[o0, s0]` (m) of the opening and the sliding that an
    /// initial (in-situ) stress gives it ([`JointSet::set_initial_tractions`]): the law is
    /// evaluated at `o + o0`, `s + s0`, so that at zero deformation the joint transmits the
    /// initial traction. Empty when there is none (the pass then takes its plain branch).
    pub initial_offsets: Vec<[f64; 2]>,
}

impl JointSet {
    /// Validates the materials and the joints (node and material ids in range, positive
    /// lengths, fracture energies above the pre-peak work on every edge) and derives the
    /// peak and critical openings.
    pub fn new(
        joints: &[Joint],
        materials: &[JointMaterialInput],
        n_nodes: usize,
        thickness: f64,
    ) -> Result<Self, FractureError> {
        if !(thickness.is_finite() && thickness > 0.0) {
            return Err(FractureError::BadThickness(thickness));
        }
        let materials = materials
            .iter()
            .enumerate()
            .map(|(i, m)| m.validate(i as u32))
            .collect::<Result<Vec<_>, _>>()?;
        // the first joint in joint order that fails (the serial loop's error)
        let first_bad = (joints.par_iter().with_min_len(SET_CHUNK).enumerate())
            .position_first(|(j, jt)| check_joint(j, jt, &materials, n_nodes).is_err());
        if let Some(j) = first_bad {
            check_joint(j, &joints[j], &materials, n_nodes)?;
        }
        // the columns, each joint on its own, collected in joint order
        let column = || joints.par_iter().with_min_len(SET_CHUNK);
        let softening = column()
            .map(|jt| materials[jt.material as usize].softening_consts(jt.ref_length))
            .collect();
        let mut set = JointSet {
            nodes: column().map(|jt| jt.nodes).collect(),
            triangles: column().map(|jt| jt.triangles).collect(),
            ref_length: column().map(|jt| jt.ref_length).collect(),
            material: column().map(|jt| jt.material).collect(),
            softening,
            materials,
            thickness,
            n_nodes,
            node_offsets: Vec::new(),
            node_slots: Vec::new(),
            initial_offsets: Vec::new(),
        };
        set.build_node_map();
        Ok(set)
    }

    /// The joints `keep` (increasing ids) of `self`, on the same nodes and materials: the
    /// joint pass of a part of the model. A node's joint forces are summed in increasing joint
    /// order, as in `self`, so a node all of whose joints are kept gets the same sum bit for
    /// bit. Panics if `keep` is not increasing or names a joint that does not exist.
    pub fn subset(&self, keep: &[u32]) -> JointSet {
        assert!(
            keep.windows(2).all(|w| w[0] < w[1]),
            "joints in increasing order"
        );
        let mut set = JointSet {
            nodes: pick(&self.nodes, keep),
            triangles: pick(&self.triangles, keep),
            ref_length: pick(&self.ref_length, keep),
            material: pick(&self.material, keep),
            softening: pick(&self.softening, keep),
            materials: self.materials.clone(),
            thickness: self.thickness,
            n_nodes: self.n_nodes,
            node_offsets: Vec::new(),
            node_slots: Vec::new(),
            initial_offsets: if self.initial_offsets.is_empty() {
                Vec::new()
            } else {
                pick(&self.initial_offsets, keep)
            },
        };
        set.build_node_map();
        set
    }

    /// The node-to-joint map ([`JointSet::node_offsets`], [`JointSet::node_slots`]): a
    /// counting sort, so the slots stay in increasing order per node.
    fn build_node_map(&mut self) {
        let (n_nodes, n) = (self.n_nodes, self.nodes.len());
        let set = &*self;
        let mut offsets = vec![0u32; n_nodes + 1];
        for nodes in &set.nodes {
            for &nd in nodes {
                offsets[nd as usize + 1] += 1;
            }
        }
        for i in 0..n_nodes {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut slots = vec![0u32; 4 * n];
        for (j, nodes) in set.nodes.iter().enumerate() {
            for (k, &nd) in nodes.iter().enumerate() {
                slots[fill[nd as usize] as usize] = (4 * j + k) as u32;
                fill[nd as usize] += 1;
            }
        }
        self.node_offsets = offsets;
        self.node_slots = slots;
    }

    /// Prestresses the joints: `t0[j] = [sigma0, tau0]` (Pa) is the traction joint `j` carries
    /// at zero deformation (normal part tension-positive along `nn`, shear part along `tt`, the
    /// traction on T1's face). Each joint gets the offsets `[o0, s0]` at which its undamaged
    /// law gives exactly that traction (docs/fracture.md, "Prestressed joints"):
    ///
    /// ```text
    /// sigma0 <= 0:  o0 = sigma0/(p/h)                         (the linear compression branch)
    /// sigma0 > 0:   o0 = o_p (1 - sqrt(1 - sigma0/ft))         (inverse of ft (2x - x^2))
    /// fs = c + <-sigma(o0)> tan(phi),  s_p = 2 h fs/p_t
    /// s0 = sign(tau0) s_p (1 - sqrt(1 - |tau0|/fs))             (inverse of fs (2y - y^2))
    /// ```
    ///
    /// Errors: a tension `sigma0 >= ft` or a shear `|tau0| >= fs` (the joint would start
    /// broken), a traction that is not finite, a list of the wrong length. All tractions zero
    /// leaves the set without offsets (its results are then bit for bit those of a set never
    /// prestressed).
    pub fn set_initial_tractions(&mut self, t0: &[[f64; 2]]) -> Result<(), FractureError> {
        if t0.len() != self.len() {
            return Err(FractureError::BadInitialTractions(format!(
                "{} tractions for {} joints",
                t0.len(),
                self.len()
            )));
        }
        if t0.iter().all(|t| *t == [0.0; 2]) {
            self.initial_offsets = Vec::new();
            return Ok(());
        }
        let mut off = Vec::with_capacity(t0.len());
        for (j, &[sigma0, tau0]) in t0.iter().enumerate() {
            if !(sigma0.is_finite() && tau0.is_finite()) {
                return Err(FractureError::BadInitialTractions(format!(
                    "joint {j}: traction [{sigma0}, {tau0}] Pa is not finite"
                )));
            }
            let material = self.material[j];
            let (m, k) = (&self.materials[material as usize], &self.consts(j));
            let o0 = if sigma0 <= 0.0 {
                sigma0 / k.kn
            } else if sigma0 < m.ft {
                // 1 - sqrt(1 - r) = r/(1 + sqrt(1 - r)), without the cancellation
                let r = sigma0 / m.ft;
                k.o_p * r / (1.0 + (1.0 - r).sqrt())
            } else {
                return Err(FractureError::InitialTractionTooHigh {
                    joint: j as u32,
                    material,
                    what: "tensile",
                    traction: sigma0,
                    strength: m.ft,
                });
            };
            // the law's shear strength and peak slip at that opening
            let (fs, s_p) = if o0 < 0.0 {
                let fs = m.shear_strength(k.kn * o0);
                (fs, k.slip_per_fs * fs)
            } else {
                (m.cohesion, k.s_p0)
            };
            if tau0.abs() >= fs {
                return Err(FractureError::InitialTractionTooHigh {
                    joint: j as u32,
                    material,
                    what: "shear",
                    traction: tau0.abs(),
                    strength: fs,
                });
            }
            let r = tau0.abs() / fs;
            let s0 = tau0.signum() * s_p * r / (1.0 + (1.0 - r).sqrt());
            off.push([o0, if tau0 == 0.0 { 0.0 } else { s0 }]);
        }
        self.initial_offsets = off;
        Ok(())
    }

    /// The initial offsets `[o0, s0]` of joint `j` (zero without an initial stress).
    #[inline]
    pub fn initial_offset(&self, j: usize) -> [f64; 2] {
        if self.initial_offsets.is_empty() {
            [0.0; 2]
        } else {
            self.initial_offsets[j]
        }
    }

    /// Number of joints.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// True when there are no joints.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The constants of joint `j` that every evaluation reads, derived from its material and
    /// reference length ([`JointMaterial::consts`]; the pass derives them as it goes rather
    /// than reading them per joint).
    #[inline(always)]
    pub fn consts(&self, j: usize) -> JointConsts {
        self.materials[self.material[j] as usize].consts(self.ref_length[j])
    }

    /// Positions of joint `j`'s nodes P, Q, R, S.
    #[inline]
    pub fn gather(&self, j: usize, x: &[[f64; 2]]) -> [[f64; 2]; 4] {
        self.nodes[j].map(|n| x[n as usize])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::joint::{PointHistory, evaluate_offset};

    /// One joint along +x (nn = -y), P = S = (0, 0), Q = R = (h, 0).
    fn one(ft: f64, c: f64) -> (JointSet, [[f64; 2]; 4]) {
        let m = JointMaterialInput {
            tensile_strength: ft,
            cohesion: c,
            friction_angle_deg: 30.0,
            fracture_energy_i: 100.0,
            fracture_energy_ii: 500.0,
            penalty_normal: 1e11,
            penalty_tangential: 5e10,
        };
        let h = 0.02;
        let j = Joint {
            nodes: [0, 1, 2, 3],
            triangles: [0, 1],
            ref_length: h,
            material: 0,
        };
        let x = [[0.0, 0.0], [h, 0.0], [h, 0.0], [0.0, 0.0]];
        (JointSet::new(&[j], &[m], 4, 1.0).unwrap(), x)
    }

    /// The offsets invert the undamaged law: at zero deformation the joint carries the given
    /// traction (to 1e-12 relative) in compression with shear and in tension with shear, its
    /// nodal forces are `A t0` on T1's nodes, and it stays undamaged; a tension at `ft` or a
    /// shear at `fs` is refused, naming the mode.
    #[test]
    fn offsets_give_the_initial_traction_at_rest() {
        let mut worst: f64 = 0.0;
        for t0 in [
            [-20e6, 5e6],
            [-20e6, -7e6],
            [3e6, 2e6],
            [0.0, -1e6],
            [-1e6, 0.0],
        ] {
            let (mut set, x) = one(5e6, 10e6);
            set.set_initial_tractions(&[t0]).unwrap();
            let m = &set.materials[0];
            let e = evaluate_offset(
                m,
                &set.consts(0),
                &set.softening[0],
                &x,
                &PointHistory::FRESH,
                1.0,
                set.initial_offsets[0],
            );
            let a = 0.5 * 0.02;
            for p in 0..2 {
                let (sig, tau) = (e.local[4 * p] / a, e.local[4 * p + 1] / a);
                assert!((sig - t0[0]).abs() <= 1e-12 * 20e6, "{t0:?}: sigma {sig}");
                assert!((tau - t0[1]).abs() <= 1e-12 * 20e6, "{t0:?}: tau {tau}");
                worst = worst.max((sig - t0[0]).abs().max((tau - t0[1]).abs()) / 20e6);
            }
            assert_eq!(e.damage, [0.0; 2]);
            // nn = -y, tt = +x: the force on P is A (sigma nn + tau tt)
            let f = e.forces[0];
            assert!((f[0] - a * t0[1]).abs() <= 1e-12 * a * 20e6, "{f:?}");
            assert!((f[1] + a * t0[0]).abs() <= 1e-12 * a * 20e6, "{f:?}");
        }
        let (mut set, _) = one(5e6, 10e6);
        let e = set.set_initial_tractions(&[[5e6, 0.0]]).unwrap_err();
        assert!(e.to_string().contains("tensile"), "{e}");
        // fs = c + 20 tan 30 = 21.55 MPa at sigma = -20 MPa
        let e = set.set_initial_tractions(&[[-20e6, 22e6]]).unwrap_err();
        assert!(e.to_string().contains("shear"), "{e}");
        assert!(set.set_initial_tractions(&[[-20e6, 21e6]]).is_ok());
        // all zero: no offsets (the plain pass)
        set.set_initial_tractions(&[[0.0; 2]]).unwrap();
        assert!(set.initial_offsets.is_empty());
        fdem_figures::record(
            78,
            format!(
                "tractions to {} of 20 MPa; tension and shear refused",
                fdem_figures::sci(worst, 1)
            ),
        );
    }
}
