//! An upper bound on the highest frequency that the contact **engaged in a given state** adds
//! (the a-priori bound of the solver assumes every edge pressed flat along its whole
//! length; curved or sparse contact engages a small part of that).
//!
//! **Stiffness of one engaged edge.** An edge `A -> B` of body E inside triangle T carries the
//! force `F = -p Q n_E`, `Q = int phi_T ds` over its part `[s0, s1]` inside T, lumped at the
//! resultant point `sbar` with the weights `a = (1 - sbar, sbar | lam_k(sbar))` on A, B and T's
//! nodes ([`crate::potential_tri_tri`]). A small motion changes `phi_T` at the edge point
//! `x(s)` by `grad phi_T . (du_E(s) - du_T(x(s)))`, with `du_E(s) = (1 - s) du_A + s du_B` and
//! `du_T = sum_k lam_k du_k` (the barycentric coordinates of a material point of E in a
//! deforming T), while `phi_T = 0` at T's boundary makes the moving limits of the integral
//! contribute nothing. With `|grad phi_T| = 3 / H_k` on the sub-triangle of T's edge `k`
//! (altitude `H_k`), `g` the largest of these over the sub-triangles the part `[s0, s1]`
//! crosses, and `b(s) = (1 - s, s | lam_k(s))` (non-negative, linear in `s`), the linearised
//! stiffness block between nodes i and j obeys
//!
//! ```text
//! |K_ij| <= p g a_i int b_j ds = p g L a_i b_j(s_m) <= k_e c_i c_j,
//! k_e = p g L,   L = l (s1 - s0) the engaged length,   s_m = (s0 + s1)/2,   c = max(a, b(s_m))
//! ```
//!
//! (the force's direction `n_E` and the displacement's are unit vectors, so the 2 x 2 block
//! of `n_E grad phi^T` has norm `|grad phi|`). The turn of `n_E` and the motion of `sbar` add
//! terms of relative size `phi H / l`, small for the shallow overlaps the penalty keeps
//! (`phi` <= 0.5, the solver's default stop; ~1e-2 in practice). A tangential friction
//! spring (`mu > 0`) adds `k_t a a^T` on the same nodes.
//!
//! **Bound.** Gershgorin on `M^-1/2 K M^-1/2` (lumped masses `m`) over all engaged edges of
//! all couples and walls:
//!
//! ```text
//! omega_c^2 <= max_i row_i,   row_i = sum over the edges e at node i of k_e c_i / sqrt(m_i) sum_j c_j / sqrt(m_j)
//! ```
//!
//! For two faces overlapping flat (equal masses, `c = (1/2, 1/2 | 1/2, 1/2, 0)`) a face node
//! gets `2 kappa l / m` from its two edges (`kappa = 3 p (1/H_c + 1/H_t)`: the edges of both
//! sides), the Rayleigh quotient of the flat mode: the bound is tight there. A wall is a rigid
//! edge inside T: only T's nodes, `a = lam(sbar)`, `b = lam(s_m)`.
//! Derivation and measurements: docs/contact.md section 12.

use crate::geom::{V2, norm, sub};
use crate::laws::ContactLaw;
use crate::model::Contact;
use crate::potential_tri_tri::TriPotential;
use crate::walls::RigidPlane;

/// The part `[s0, s1]` of `A + s (B - A)` inside T, from the barycentric coordinates of A and
/// B in T; `None` when the edge misses T.
fn clip(la: [f64; 3], lb: [f64; 3]) -> Option<(f64, f64)> {
    let (mut s0, mut s1) = (0.0f64, 1.0f64);
    for k in 0..3 {
        let d = lb[k] - la[k];
        if d > 0.0 {
            s0 = s0.max(-la[k] / d);
        } else if d < 0.0 {
            s1 = s1.min(-la[k] / d);
        } else if la[k] < 0.0 {
            return None;
        }
    }
    (s1 > s0).then_some((s0, s1))
}

/// The engaged part of edge `A -> B` inside T: `G = int |grad phi_T| ds` over it (per unit
/// penalty: the edge's stiffness is `p G`), and the weights `c = max(a, b_g)` (module docs)
/// of A, B and T's 3 nodes, `a` the lumping weights at the resultant point and
/// `b_g = int |grad phi_T| b ds / G`; also `a` alone (for the friction spring). `None` when
/// the edge misses T. `|grad phi_T|` is constant on each piece between the points where the
/// smallest barycentric coordinate changes (the pairwise crossings), `b` linear on it.
fn edge_terms(a: V2, b: V2, t: &TriPotential) -> Option<(f64, [f64; 5], [f64; 5])> {
    let la = t.barycentric(a);
    let lb = t.barycentric(b);
    let (s0, s1) = clip(la, lb)?;
    let l = norm(sub(b, a));
    let len = l * (s1 - s0);
    if len.is_nan() || len <= 0.0 {
        return None;
    }
    let lam = |s: f64| [0, 1, 2].map(|k| la[k] + s * (lb[k] - la[k]));
    let w = |s: f64| {
        let m = lam(s).map(|v| v.max(0.0));
        [1.0 - s, s, m[0], m[1], m[2]]
    };
    let mut cuts = [s0, s1, s1, s1, s1];
    let mut n = 2;
    for (i, j) in [(0, 1), (1, 2), (2, 0)] {
        let d = (lb[i] - la[i]) - (lb[j] - la[j]);
        if d != 0.0 {
            let s = (la[j] - la[i]) / d;
            if s > s0 && s < s1 {
                cuts[n] = s;
                n += 1;
            }
        }
    }
    cuts[..n].sort_by(f64::total_cmp);
    let (mut g_len, mut bg) = (0.0, [0.0; 5]);
    for p in cuts[..n].windows(2) {
        let (sa, sb) = (p[0], p[1]);
        let mid = 0.5 * (sa + sb);
        let lm = lam(mid);
        let k = if lm[0] <= lm[1] && lm[0] <= lm[2] {
            0
        } else if lm[1] <= lm[2] {
            1
        } else {
            2
        };
        let gk = norm(t.grad_phi(k)) * l * (sb - sa);
        g_len += gk;
        let wm = w(mid);
        for i in 0..5 {
            bg[i] += gk * wm[i];
        }
    }
    if g_len.is_nan() || g_len <= 0.0 {
        return None;
    }
    // The resultant point of phi_T along the part (the contact crate's lumping point).
    let ld = crate::potential_tri_tri::edge_load(a, b, t);
    let sbar = if ld.q > 0.0 { ld.sbar } else { 0.5 * (s0 + s1) };
    let aw = w(sbar);
    let c = [0, 1, 2, 3, 4].map(|i| aw[i].max(bg[i] / g_len));
    Some((g_len, c, aw))
}

/// Node-wise Gershgorin rows of the engaged contact's `M^-1/2 K M^-1/2`, and the scratch they
/// need (owned by the caller's stage, reused from call to call: no allocation once sized).
#[derive(Debug, Default, Clone)]
pub struct ActiveBound {
    rows: Vec<f64>,
    touched: Vec<u32>,
    /// Per node: whether its row counts (one rank's nodes in a distributed run, whose rows
    /// sum all their couples; empty: every node).
    counted: Vec<bool>,
}

impl ActiveBound {
    /// An empty bound (sized at the first call).
    pub fn new() -> Self {
        Self::default()
    }

    fn add(&mut self, node: u32, v: f64) {
        let r = &mut self.rows[node as usize];
        if *r == 0.0 {
            self.touched.push(node);
        }
        *r += v;
    }

    /// Counts only the rows of the nodes marked in `counted` (a rank's own nodes, whose
    /// couples it evaluates all; the largest over the ranks is the whole bound).
    pub fn set_counted(&mut self, counted: Vec<bool>) {
        self.counted = counted;
    }

    /// Adds one engaged edge: `k` its stiffness, `nodes` and `c` the 5 (or 3, wall) nodes and
    /// weights, `inv_sqrt_m` per node of the model.
    fn add_edge(&mut self, k: f64, nodes: &[u32], c: &[f64], inv_sqrt_m: &[f64]) {
        let s: f64 = nodes
            .iter()
            .zip(c)
            .map(|(n, c)| c * inv_sqrt_m[*n as usize])
            .sum();
        for (n, ci) in nodes.iter().zip(c) {
            let v = k * ci * inv_sqrt_m[*n as usize] * s;
            if v > 0.0 {
                self.add(*n, v);
            }
        }
    }

    /// The bound `omega_c^2 <= max_i row_i` [rad^2/s^2] of the contact engaged at positions
    /// `x`: the couples whose last force pass ([`Contact::compute_forces`]) gave a normal load,
    /// and the wall candidates with a load, their geometry taken at `x`. `material` as for
    /// `compute_forces`; `inv_sqrt_mass[i] = 1/sqrt(m_i)` (0 for a node without mass). The
    /// laws' penalties are per unit thickness times the thickness, as the masses are.
    pub fn omega_sq(
        &mut self,
        contact: &Contact,
        x: &[V2],
        tris: &[[u32; 3]],
        material: &[u32],
        inv_sqrt_mass: &[f64],
    ) -> f64 {
        self.omega_sq_of(contact, x, tris, material, inv_sqrt_mass, true)
    }

    /// [`Self::omega_sq`] over **every** detected couple and wall candidate, whatever the last
    /// force pass found: the edges that overlap at `x` count. For positions other than those
    /// of the last force pass, e.g. extrapolated ones (a look-ahead for a step chosen from the
    /// bound), as long as they are within the detection buffer of the last detection.
    pub fn omega_sq_at(
        &mut self,
        contact: &Contact,
        x: &[V2],
        tris: &[[u32; 3]],
        material: &[u32],
        inv_sqrt_mass: &[f64],
    ) -> f64 {
        self.omega_sq_of(contact, x, tris, material, inv_sqrt_mass, false)
    }

    fn omega_sq_of(
        &mut self,
        contact: &Contact,
        x: &[V2],
        tris: &[[u32; 3]],
        material: &[u32],
        inv_sqrt_mass: &[f64],
        loaded_only: bool,
    ) -> f64 {
        if self.rows.len() < x.len() {
            self.rows.resize(x.len(), 0.0);
        }
        let mat = |i: u32| material.get(i as usize).copied().unwrap_or(0);
        let results = contact.couple_results();
        let flags = contact.couple_flags();
        for (k, c) in contact.couples().iter().enumerate() {
            if loaded_only {
                // the one-byte flag first: most detected couples carry no force
                if flags.get(k).is_none_or(|f| *f == 0) {
                    continue;
                }
                match results.get(k) {
                    Some(r) if r.active && !r.invalid && r.fn_total > 0.0 => {}
                    _ => continue,
                }
            }
            let law = contact.laws.get(mat(c[0]), mat(c[1]));
            let (tc, tt) = (tris[c[0] as usize], tris[c[1] as usize]);
            self.add_couple(law, tc, tt, x, inv_sqrt_mass);
        }
        let wall_results = contact.wall_results();
        for (k, w) in contact.wall_pairs().iter().enumerate() {
            if loaded_only && !wall_results.get(k).is_some_and(|r| r.fn_total > 0.0) {
                continue;
            }
            let plane = &contact.walls[w[0] as usize];
            let t = tris[w[1] as usize];
            self.add_wall(plane, t, x, inv_sqrt_mass);
        }
        let mut m = 0.0f64;
        for &n in &self.touched {
            if self.counted.get(n as usize).is_none_or(|c| *c) {
                m = m.max(self.rows[n as usize]);
            }
            self.rows[n as usize] = 0.0;
        }
        self.touched.clear();
        m
    }

    /// One couple (c, t) with its law: the edges of each triangle inside the other.
    fn add_couple(
        &mut self,
        law: &ContactLaw,
        tc: [u32; 3],
        tt: [u32; 3],
        x: &[V2],
        inv_sqrt_m: &[f64],
    ) {
        let xc = tc.map(|n| x[n as usize]);
        let xt = tt.map(|n| x[n as usize]);
        let (Some(pc), Some(pt)) = (TriPotential::new(xc), TriPotential::new(xt)) else {
            return;
        };
        for (xe, te, other, to) in [(&xc, &tc, &pt, &tt), (&xt, &tt, &pc, &tc)] {
            for e in 0..3 {
                let f = (e + 1) % 3;
                if let Some((gl, c, a)) = edge_terms(xe[e], xe[f], other) {
                    let nodes = [te[e], te[f], to[0], to[1], to[2]];
                    self.add_edge(law.penalty * gl, &nodes, &c, inv_sqrt_m);
                    if law.mu > 0.0 {
                        self.add_edge(law.kt, &nodes, &a, inv_sqrt_m);
                    }
                }
            }
        }
    }

    /// One wall against triangle `t`: the plane's segment inside T.
    fn add_wall(&mut self, plane: &RigidPlane, t: [u32; 3], x: &[V2], inv_sqrt_m: &[f64]) {
        let xt = t.map(|n| x[n as usize]);
        let Some(tp) = TriPotential::new(xt) else {
            return;
        };
        let Some((_, a, b)) = plane.load(&xt) else {
            return;
        };
        if let Some((gl, c, ca)) = edge_terms(a, b, &tp) {
            self.add_edge(plane.law.penalty * gl, &t, &c[2..], inv_sqrt_m);
            if plane.law.mu > 0.0 {
                self.add_edge(plane.law.kt, &t, &ca[2..], inv_sqrt_m);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit right triangles overlapping flat by d along their common leg (length 1):
    /// the contactor's leg inside the target and the target's leg inside the contactor, so
    /// each face node gets, from its one face edge, `kappa l (1/2)(1/2 + 1/2 + 1/2 + 1/2)/m`
    /// with `kappa = 3 p (1/H_c + 1/H_t)` = 6 p (H = 1 onto the leg).
    #[test]
    fn flat_overlap_of_two_legs_gives_kappa_l_over_m() {
        let d = 1e-6;
        // target below y = 0 (its top leg from (1, 0) to (0, 0)), contactor above y = -d
        let x = vec![
            [0.0, -1.0],
            [1.0, 0.0],
            [0.0, 0.0],
            [0.0, -d],
            [1.0, -d],
            [0.0, 1.0 - d],
        ];
        let tris = [[0u32, 1, 2], [3, 4, 5]];
        let p = 7.0;
        let law = ContactLaw::with_penalty(p);
        let mut b = ActiveBound::new();
        b.rows.resize(6, 0.0);
        b.add_couple(&law, tris[0], tris[1], &x, &[1.0; 6]);
        let m = b
            .touched
            .iter()
            .map(|n| b.rows[*n as usize])
            .fold(0.0, f64::max);
        // 6 p l / m = 42 for the face (l = 1 - d); the pieces of length ~d near the corners
        // (other sub-triangles, the short side edges) change it by O(d): to 1e-4
        assert!((m / (6.0 * p) - 1.0).abs() < 1e-4, "{m}");
    }
}
