//! The internal-force kernel and its exact directional derivative.
//!
//! Two kernels, both parallel and both independent of the number of threads.
//! [`Elements::internal_forces_owner`] is "owner computes": the node array is cut into fixed blocks
//! of consecutive nodes, and one rayon task per block evaluates every triangle that has a node
//! in the block (in increasing triangle order) and adds the forces of the corners that lie in
//! the block. Each node thus receives its triangles' forces in increasing triangle order, a
//! fixed order whatever the number of threads, so the result is identical bit for bit. The
//! triangles that straddle two blocks (a few per cent with a locality-preserving numbering)
//! are evaluated twice; there is no per-triangle buffer and no second pass.
//!
//! [`Elements::internal_forces_buffered`] (the one [`Elements::internal_forces`] uses, faster
//! per core on the development machine) has two passes:
//! 1. each triangle writes its three nodal forces into its own slots of a preallocated buffer;
//! 2. each node sums its slots in increasing slot order (a fixed CSR list) and adds the sum.
//!
//! Neither allocates per call (the buffer lives in a [`ForceScratch`] made once). On a wholly
//! exploded mesh (triangle `t` owns the nodes `3t..3t+3`, [`Elements::owned_nodes`]) each
//! triangle adds its forces to its own nodes directly, in parallel over fixed chunks of
//! triangles: no buffer and no gather, and the same sums as the two-pass kernel bit for bit
//! (each node has one slot: `f_i += 0 + f_slot`).

use crate::elements::{Elements, MaterialConsts, TriData};
use crate::material::ElasticLaw;
use crate::triangle::{
    Mat2, Sym2, det, edge_matrix, elastic_stress, initial_stress_cauchy,
    initial_stress_cauchy_derivative, inv, mul, nodal_forces, rate_of_deformation,
};
use rayon::prelude::*;

/// Triangles per rayon task in the element pass.
const TRI_CHUNK: usize = 8192;
/// Nodes per rayon task in the gather pass.
const NODE_CHUNK: usize = 8192;
/// Triangles per range handed to the `then` of [`Elements::set_internal_forces_then`] on a
/// wholly exploded mesh: their 1 536 nodes' forces (24 KiB) stay in the first-level cache.
const THEN_TRIS: usize = 512;

/// Scratch memory of the force kernels: three nodal forces per triangle.
#[derive(Clone, Debug, Default)]
pub struct ForceScratch {
    /// Per-triangle nodal forces.
    pub per_tri: Vec<[[f64; 2]; 3]>,
}

impl ForceScratch {
    /// Scratch for `elements`.
    pub fn new(elements: &Elements) -> ForceScratch {
        ForceScratch {
            per_tri: vec![[[0.0; 2]; 3]; elements.len()],
        }
    }
}

#[inline(always)]
fn corners(td: &TriData, x: &[[f64; 2]]) -> [[f64; 2]; 3] {
    [
        x[td.nodes[0] as usize],
        x[td.nodes[1] as usize],
        x[td.nodes[2] as usize],
    ]
}

/// Cauchy stress (elastic + viscous, + the initial stress `s0` when given) of one triangle.
#[inline(always)]
pub(crate) fn tri_stress<const VISCOUS: bool>(
    td: &TriData,
    c: &MaterialConsts,
    xs: [[f64; 2]; 3],
    v: &[[f64; 2]],
    s0: Option<&Sym2>,
) -> (Sym2, Mat2) {
    let g = edge_matrix(xs[0], xs[1], xs[2]);
    let f = mul(g, td.ginv);
    let mut s = elastic_stress(c.law, c.mu, c.lam, f);
    if let Some(s0) = s0 {
        let sp = initial_stress_cauchy(*s0, f);
        s[0] += sp[0];
        s[1] += sp[1];
        s[2] += sp[2];
    }
    if VISCOUS && td.eta != 0.0 {
        let vs = corners(td, v);
        let d = rate_of_deformation(g, edge_matrix(vs[0], vs[1], vs[2]));
        s[0] += td.eta * d[0];
        s[1] += td.eta * d[1];
        s[2] += td.eta * d[2];
    }
    (s, f)
}

#[inline(always)]
fn tri_force<const VISCOUS: bool>(
    td: &TriData,
    mats: &[MaterialConsts],
    x: &[[f64; 2]],
    v: &[[f64; 2]],
    s0: Option<&Sym2>,
) -> [[f64; 2]; 3] {
    let c = &mats[td.material as usize];
    let xs = corners(td, x);
    let (s, _) = tri_stress::<VISCOUS>(td, c, xs, v, s0);
    nodal_forces(s, c.half_t, xs)
}

impl Elements {
    /// Adds the internal nodal forces (elastic + viscous) at positions `x` and velocities `v`
    /// to `f`: `f_a += -(t/2) sigma rot(x_c - x_b)` for each triangle.
    ///
    /// Parallel (rayon), bit-identical for any number of threads, no allocation: each triangle
    /// writes its three forces into `scratch`, then each node sums its slots in a fixed order
    /// ([`Elements::internal_forces_buffered`]). `v` is read only if some triangle has damping. Panics if the slices are shorter than the node count
    /// or `scratch` was made for other elements (programming errors, not input errors).
    pub fn internal_forces(
        &self,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        f: &mut [[f64; 2]],
        scratch: &mut ForceScratch,
    ) {
        if self.owned_nodes {
            if self.prestressed() {
                self.owned::<false, true, _>(x, v, f, &|_, _| {});
            } else {
                self.owned::<false, false, _>(x, v, f, &|_, _| {});
            }
        } else {
            self.internal_forces_buffered(x, v, f, scratch);
        }
    }

    /// Sets `f` to the internal nodal forces: [`Elements::internal_forces`] into a zeroed
    /// array, bit for bit, without the separate zeroing pass on a wholly exploded mesh.
    pub fn set_internal_forces(
        &self,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        f: &mut [[f64; 2]],
        scratch: &mut ForceScratch,
    ) {
        self.set_internal_forces_then(x, v, f, scratch, |_, _| {});
    }

    /// [`Elements::set_internal_forces`], then `then(i0, fc)` on each range `fc` of the forces
    /// of nodes `i0..i0 + fc.len()`, the ranges covering the mesh's nodes once, in parallel. On
    /// a wholly exploded mesh each range is the nodes of one chunk of triangles, handed over
    /// right after the chunk's forces are written, while they are in cache: a force term that
    /// adds per node (the joints) joins the pass instead of making a trip of its own through
    /// the node array. The result is that of `then` run on the whole array afterwards.
    pub fn set_internal_forces_then<G>(
        &self,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        f: &mut [[f64; 2]],
        scratch: &mut ForceScratch,
        then: G,
    ) where
        G: Fn(usize, &mut [[f64; 2]]) + Sync,
    {
        if self.owned_nodes {
            if self.prestressed() {
                self.owned::<true, true, G>(x, v, f, &then);
            } else {
                self.owned::<true, false, G>(x, v, f, &then);
            }
        } else {
            f.fill([0.0; 2]);
            self.internal_forces_buffered(x, v, f, scratch);
            f[..self.n_nodes]
                .par_chunks_mut(3 * TRI_CHUNK)
                .enumerate()
                .for_each(|(ci, fc)| then(ci * 3 * TRI_CHUNK, fc));
        }
    }

    /// The kernel of a wholly exploded mesh: each triangle adds (`SET`: writes, as if onto
    /// zero) its forces to its own three nodes, in parallel over fixed chunks; `PRE`: with
    /// the triangles' initial stresses. Then `then(i0, fc)` on each chunk's nodes.
    fn owned<const SET: bool, const PRE: bool, G>(
        &self,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        f: &mut [[f64; 2]],
        then: &G,
    ) where
        G: Fn(usize, &mut [[f64; 2]]) + Sync,
    {
        assert!(x.len() >= self.n_nodes && f.len() >= self.n_nodes);
        let mats = &self.materials[..];
        let viscous = self.viscous;
        if viscous {
            assert!(v.len() >= self.n_nodes);
        }
        let pre = &self.initial_stress[..];
        f[..self.n_nodes]
            .par_chunks_mut(3 * TRI_CHUNK)
            .zip(x[..self.n_nodes].par_chunks(3 * TRI_CHUNK))
            .zip(self.tris.par_chunks(TRI_CHUNK))
            .enumerate()
            .for_each(|(ci, ((fc, xc), tc))| {
                // sub-blocks of the chunk, each handed to `then` while its forces are in the
                // core's first-level cache
                let blocks = fc
                    .chunks_mut(3 * THEN_TRIS)
                    .zip(xc.chunks(3 * THEN_TRIS))
                    .zip(tc.chunks(THEN_TRIS));
                for (b, ((fb, xb), tb)) in blocks.enumerate() {
                    let t0 = ci * TRI_CHUNK + b * THEN_TRIS;
                    let pc = if PRE { &pre[t0..] } else { pre };
                    for (k, ((fa, xa), td)) in fb
                        .chunks_exact_mut(3)
                        .zip(xb.chunks_exact(3))
                        .zip(tb)
                        .enumerate()
                    {
                        // the triangle's own nodes 3t..3t+3 (`owned_nodes`): read in order, no
                        // node ids
                        let xs = [xa[0], xa[1], xa[2]];
                        let c = &mats[td.material as usize];
                        let s0 = if PRE { Some(&pc[k]) } else { None };
                        let ft = if viscous {
                            let (s, _) = tri_stress::<true>(td, c, xs, v, s0);
                            nodal_forces(s, c.half_t, xs)
                        } else {
                            let (s, _) = tri_stress::<false>(td, c, xs, v, s0);
                            nodal_forces(s, c.half_t, xs)
                        };
                        for (fi, p) in fa.iter_mut().zip(ft) {
                            // the gather's node sum over one slot, `0 + f_slot`, then
                            // `f_i += sum`
                            let s = [0.0 + p[0], 0.0 + p[1]];
                            if SET {
                                *fi = [0.0 + s[0], 0.0 + s[1]];
                            } else {
                                fi[0] += s[0];
                                fi[1] += s[1];
                            }
                        }
                    }
                    then(3 * t0, fb);
                }
            });
    }

    /// The owner-computes variant of [`Elements::internal_forces`] (node blocks, one pass, no
    /// buffer, a few per cent of triangles evaluated twice); same result up to round-off and
    /// also independent of the thread count. Kept for comparison: it moves fewer bytes but
    /// measured slower per core on the development machine (docs/mesh.md).
    pub fn internal_forces_owner(&self, x: &[[f64; 2]], v: &[[f64; 2]], f: &mut [[f64; 2]]) {
        let s0 = |t: usize| self.initial_stress.get(t);
        if self.viscous {
            assert!(v.len() >= self.n_nodes);
            self.owner_computes(f, |t, td| {
                tri_force::<true>(td, &self.materials, x, v, s0(t))
            });
        } else {
            self.owner_computes(f, |t, td| {
                tri_force::<false>(td, &self.materials, x, v, s0(t))
            });
        }
    }

    /// Runs `force` on each block's triangles and adds the forces of the corners in the block.
    #[inline(always)]
    fn owner_computes<K>(&self, f: &mut [[f64; 2]], force: K)
    where
        K: Fn(usize, &TriData) -> [[f64; 2]; 3] + Sync,
    {
        assert!(f.len() >= self.n_nodes);
        let bn = self.block_nodes;
        let off = &self.block_offsets;
        let list = &self.block_tris;
        let tris = &self.tris;
        f[..self.n_nodes]
            .par_chunks_mut(bn)
            .enumerate()
            .for_each(|(b, fb)| {
                let base = (b * bn) as u32;
                let len = fb.len() as u32;
                for &t in &list[off[b] as usize..off[b + 1] as usize] {
                    let td = &tris[t as usize];
                    let ft = force(t as usize, td);
                    for a in 0..3 {
                        let i = td.nodes[a].wrapping_sub(base);
                        if i < len {
                            let p = &mut fb[i as usize];
                            p[0] += ft[a][0];
                            p[1] += ft[a][1];
                        }
                    }
                }
            });
    }

    /// The two-pass kernel behind [`Elements::internal_forces`]: per-triangle forces into the
    /// buffer of `scratch` (parallel over triangles), then a parallel per-node gather over the
    /// fixed node -> slot list.
    pub fn internal_forces_buffered(
        &self,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        f: &mut [[f64; 2]],
        scratch: &mut ForceScratch,
    ) {
        assert!(x.len() >= self.n_nodes && f.len() >= self.n_nodes);
        assert_eq!(scratch.per_tri.len(), self.tris.len());
        let mats = &self.materials[..];
        let buf = &mut scratch.per_tri;
        if self.prestressed() {
            let viscous = self.viscous;
            if viscous {
                assert!(v.len() >= self.n_nodes);
            }
            buf.par_iter_mut()
                .zip(self.tris.par_iter())
                .zip(self.initial_stress.par_iter())
                .with_min_len(TRI_CHUNK)
                .for_each(|((o, td), s0)| {
                    *o = if viscous {
                        tri_force::<true>(td, mats, x, v, Some(s0))
                    } else {
                        tri_force::<false>(td, mats, x, v, Some(s0))
                    }
                });
        } else if self.viscous {
            assert!(v.len() >= self.n_nodes);
            buf.par_iter_mut()
                .zip(self.tris.par_iter())
                .with_min_len(TRI_CHUNK)
                .for_each(|(o, td)| *o = tri_force::<true>(td, mats, x, v, None));
        } else {
            buf.par_iter_mut()
                .zip(self.tris.par_iter())
                .with_min_len(TRI_CHUNK)
                .for_each(|(o, td)| *o = tri_force::<false>(td, mats, x, v, None));
        }
        self.gather(&scratch.per_tri, f);
    }

    /// Adds the per-triangle forces in `per_tri` to the node array `f`, each node summing its
    /// slots in a fixed order.
    pub fn gather(&self, per_tri: &[[[f64; 2]; 3]], f: &mut [[f64; 2]]) {
        let slots = per_tri.as_flattened();
        let off = &self.gather_offsets;
        let list = &self.gather_slots;
        f[..self.n_nodes]
            .par_chunks_mut(NODE_CHUNK)
            .enumerate()
            .for_each(|(ci, chunk)| {
                let base = ci * NODE_CHUNK;
                for (k, fi) in chunk.iter_mut().enumerate() {
                    let i = base + k;
                    let (mut sx, mut sy) = (0.0, 0.0);
                    for &s in &list[off[i] as usize..off[i + 1] as usize] {
                        let p = slots[s as usize];
                        sx += p[0];
                        sy += p[1];
                    }
                    fi[0] += sx;
                    fi[1] += sy;
                }
            });
    }

    /// Adds to `out` (per DOF, flat) the magnitudes of the terms whose rounding makes up the
    /// rounding error of the internal force at `(x, v)`, serially in triangle order: each
    /// triangle's contribution `|f_e,i|` and, for each of its corner coordinates `x_j`, the
    /// force `|K_e,ij x_j|` of its small-strain stiffness on that coordinate (the positions
    /// are stored absolute: a rounding of `eps |x_j|` in `x_j` moves the force by
    /// `K_ij eps |x_j|`). The force of DOF `i` is resolved to about `eps out_i` at best: the
    /// floor below which an out-of-balance force is round-off.
    pub fn add_round_off_terms(&self, x: &[[f64; 2]], v: &[[f64; 2]], out: &mut [f64]) {
        let mats = &self.materials[..];
        for (k, td) in self.tris.iter().enumerate() {
            let s0 = self.initial_stress.get(k);
            let ft = if self.viscous {
                tri_force::<true>(td, mats, x, v, s0)
            } else {
                tri_force::<false>(td, mats, x, v, s0)
            };
            let ke = self.element_stiffness(k);
            let xs = corners(td, x);
            for (a, p) in ft.iter().enumerate() {
                for c in 0..2 {
                    let mut s = p[c].abs();
                    for (b, xb) in xs.iter().enumerate() {
                        for (e, xbe) in xb.iter().enumerate() {
                            s += (ke[2 * a + c][2 * b + e] * xbe).abs();
                        }
                    }
                    out[2 * td.nodes[a] as usize + c] += s;
                }
            }
        }
    }

    /// Adds the nodal forces of the initial stresses alone, taken as Cauchy stresses at the
    /// positions `x`, `f_a += -(t/2) S0 rot(x_c - x_b)`, to `f` (serially, in triangle order).
    /// At the reference positions this is `-int B^T S0`, the right-hand side the initial
    /// stress adds to the small-strain static solve. Nothing happens without initial stress.
    pub fn add_initial_stress_forces(&self, x: &[[f64; 2]], f: &mut [[f64; 2]]) {
        for (td, s0) in self.tris.iter().zip(&self.initial_stress) {
            let c = &self.materials[td.material as usize];
            let ft = nodal_forces(*s0, c.half_t, corners(td, x));
            for (a, p) in ft.iter().enumerate() {
                let n = td.nodes[a] as usize;
                f[n][0] += p[0];
                f[n][1] += p[1];
            }
        }
    }

    /// Power dissipated by the element viscosity at positions `x` and velocities `v` [W]:
    /// `-sum_a f_v,a . v_a` over the viscous part `f_v` of the internal nodal forces (the
    /// viscous stress `eta D` of each triangle through the same nodal-force formula as
    /// [`Elements::internal_forces`]), which equals `sum_e t A_e eta_e D_e : D_e >= 0`.
    ///
    /// Returns 0 at once, reading nothing, when no triangle has a viscosity. Parallel over
    /// fixed chunks of triangles whose partial sums go into `sums` (resized to the number of
    /// chunks on the first call, so a caller that keeps it allocates once) and are added in
    /// chunk order: the same result for any number of threads.
    pub fn viscous_power(&self, x: &[[f64; 2]], v: &[[f64; 2]], sums: &mut Vec<f64>) -> f64 {
        if !self.viscous {
            return 0.0;
        }
        assert!(x.len() >= self.n_nodes && v.len() >= self.n_nodes);
        let mats = &self.materials[..];
        let n_chunks = self.tris.len().div_ceil(TRI_CHUNK);
        sums.resize(n_chunks, 0.0);
        sums.par_iter_mut()
            .zip(self.tris.par_chunks(TRI_CHUNK))
            .for_each(|(s, chunk)| {
                *s = chunk
                    .iter()
                    .filter(|td| td.eta != 0.0)
                    .map(|td| {
                        let c = &mats[td.material as usize];
                        let xs = corners(td, x);
                        let vs = corners(td, v);
                        let g = edge_matrix(xs[0], xs[1], xs[2]);
                        let d = rate_of_deformation(g, edge_matrix(vs[0], vs[1], vs[2]));
                        let sv = [td.eta * d[0], td.eta * d[1], td.eta * d[2]];
                        let fv = nodal_forces(sv, c.half_t, xs);
                        -(0..3)
                            .map(|a| fv[a][0] * vs[a][0] + fv[a][1] * vs[a][1])
                            .sum::<f64>()
                    })
                    .sum();
            });
        sums.iter().sum()
    }

    /// Adds the exact directional derivative of the internal force with respect to the
    /// positions, `df += (d f_int / d x)[x, v] . dx` (velocities held fixed), to `df`.
    ///
    /// Per triangle, with `dG = [dx1-dx0 | dx2-dx0]`, `dF = dG G0^-1`,
    /// `dB = dF F^T + F dF^T`, `c = tr(F^-1 dF)`:
    /// Munjiza `d sigma = mu dB + lam*/2 tr(dB) I`; neo-Hookean
    /// `d sigma = (mu dB + lam* c I)/J - c sigma_e`; viscous `d sigma_v = eta sym(-L dG G^-1)`;
    /// initial stress `d sigma_0 = (dF S0 F^T + F S0 dF^T)/J - c sigma_0`;
    /// then `df_a = -(t/2)(d sigma rot(x_c-x_b) + sigma rot(dx_c-dx_b))`.
    pub fn force_derivative(
        &self,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        dx: &[[f64; 2]],
        df: &mut [[f64; 2]],
        scratch: &mut ForceScratch,
    ) {
        assert!(x.len() >= self.n_nodes && dx.len() >= self.n_nodes && df.len() >= self.n_nodes);
        assert_eq!(scratch.per_tri.len(), self.tris.len());
        let mats = &self.materials[..];
        let viscous = self.viscous;
        let pre = &self.initial_stress;
        scratch
            .per_tri
            .par_iter_mut()
            .zip(self.tris.par_iter())
            .enumerate()
            .with_min_len(TRI_CHUNK)
            .for_each(|(t, (o, td))| {
                *o = tri_force_derivative(td, mats, x, v, dx, viscous, pre.get(t));
            });
        self.gather(&scratch.per_tri, df);
    }
}

#[inline(always)]
fn tri_force_derivative(
    td: &TriData,
    mats: &[MaterialConsts],
    x: &[[f64; 2]],
    v: &[[f64; 2]],
    dx: &[[f64; 2]],
    viscous: bool,
    s0: Option<&Sym2>,
) -> [[f64; 2]; 3] {
    let c = &mats[td.material as usize];
    let xs = corners(td, x);
    let dxs = corners(td, dx);
    let g = edge_matrix(xs[0], xs[1], xs[2]);
    let dg = edge_matrix(dxs[0], dxs[1], dxs[2]);
    let f = mul(g, td.ginv);
    let dfm = mul(dg, td.ginv);
    let mut s = elastic_stress(c.law, c.mu, c.lam, f);
    // dB = dF F^T + F dF^T
    let db = [
        2.0 * (dfm[0] * f[0] + dfm[1] * f[1]),
        2.0 * (dfm[2] * f[2] + dfm[3] * f[3]),
        dfm[0] * f[2] + dfm[1] * f[3] + f[0] * dfm[2] + f[1] * dfm[3],
    ];
    let mut ds = match c.law {
        ElasticLaw::Munjiza => {
            let tr = 0.5 * c.lam * (db[0] + db[1]);
            [c.mu * db[0] + tr, c.mu * db[1] + tr, c.mu * db[2]]
        }
        ElasticLaw::NeoHookean => {
            let j = det(f);
            let fi = inv(f);
            let cc = fi[0] * dfm[0] + fi[1] * dfm[2] + fi[2] * dfm[1] + fi[3] * dfm[3];
            let rj = 1.0 / j;
            [
                (c.mu * db[0] + c.lam * cc) * rj - cc * s[0],
                (c.mu * db[1] + c.lam * cc) * rj - cc * s[1],
                c.mu * db[2] * rj - cc * s[2],
            ]
        }
    };
    if let Some(s0) = s0 {
        let sp = initial_stress_cauchy(*s0, f);
        let dsp = initial_stress_cauchy_derivative(*s0, f, dfm, sp);
        for k in 0..3 {
            s[k] += sp[k];
            ds[k] += dsp[k];
        }
    }
    if viscous && td.eta != 0.0 {
        let vs = corners(td, v);
        let gv = edge_matrix(vs[0], vs[1], vs[2]);
        let gi = inv(g);
        let l = mul(gv, gi);
        // dL = -L dG G^-1
        let dl = mul(mul(l, dg), gi);
        let d = rate_of_deformation(g, gv);
        s[0] += td.eta * d[0];
        s[1] += td.eta * d[1];
        s[2] += td.eta * d[2];
        ds[0] -= td.eta * dl[0];
        ds[1] -= td.eta * dl[3];
        ds[2] -= td.eta * 0.5 * (dl[1] + dl[2]);
    }
    let a = nodal_forces(ds, c.half_t, xs);
    let b = nodal_forces(s, c.half_t, dxs);
    [
        [a[0][0] + b[0][0], a[0][1] + b[0][1]],
        [a[1][0] + b[1][0], a[1][1] + b[1][1]],
        [a[2][0] + b[2][0], a[2][1] + b[2][1]],
    ]
}
