//! The distributed potential contact force between two triangles (Munjiza & Andrews 2000).
//!
//! Each triangle carries the potential `phi(x) = 3 min(lam_0, lam_1, lam_2)` (barycentric
//! coordinates `lam_k`): 1 at the centroid, 0 on the edges, linear in each of the three
//! sub-triangles (centroid + edge k), where `grad phi = 3 grad lam_k`. The force on the
//! contactor `c` from the target `t` with penalty `p` (per unit thickness) is
//!
//! ```text
//! f_c = p * int_{c ∩ t} (grad phi_c - grad phi_t) dA
//!     = -p * int_{edges of c inside t} phi_t n_c ds  +  p * int_{edges of t inside c} phi_c n_t ds
//! ```
//!
//! (Gauss's theorem; `n` is each triangle's own outward edge normal). The couple is processed
//! both ways round: the edges of `c` against `phi_t`, then the edges of `t` against `phi_c`.
//! One edge `A -> B` of body E against triangle T ([`edge_load`]):
//!
//! 1. clip `x(s) = A + s (B - A)` to T (all `lam_k(x(s)) >= 0`), giving `[s0, s1]`;
//! 2. split at the points where the smallest `lam_k` changes (the crossings with T's
//!    centroid-to-vertex segments), so `phi_T` is linear on each piece `[sa, sb]`;
//! 3. each piece carries `q = l (sb - sa)(phi_a + phi_b)/2` (the integral of `phi_T` along it)
//!    with its resultant at `sbar = sa + (sb - sa)(phi_a + 2 phi_b)/(3 (phi_a + phi_b))`;
//!    the pieces of one edge all push along `-n_E`, so they add to one resultant
//!    `F = -p Q n_E`, `Q = sum q`, at `sbar = sum(q sbar)/Q`.
//! 4. consistent lumping: `(1 - sbar) F` to A, `sbar F` to B, `-lam_k(x(sbar)) F` to node k
//!    of T. Both bodies get opposite forces through the same point, so linear and angular
//!    momentum are conserved to round-off.
//!
//! The pair energy `W = p * int_{c ∩ t} (phi_c + phi_t) dA` ([`pair_energy`]) is an exact
//! potential of the force for rigid relative motion. It is computed by clipping each of the
//! 3 x 3 pairs of sub-triangles (where both potentials are linear) and summing
//! `area * (phi_c + phi_t)(area centroid)`; the same decomposition gives an independent
//! area-integral force ([`pair_force_area`]) used by the tests.
//!
//! For edges overlapping flat to a depth `d` along a length `L`:
//! `W = (3/2) p L d^2 (1/H_c + 1/H_t)` and the traction is `3 p d (1/H_c + 1/H_t)`
//! (`H` the altitudes onto the contacting edges).

use crate::geom::{Poly, V2, add, centroid, cross, finite, norm, rot, scale, sub};

/// A triangle's potential, precomputed: its vertices (CCW) and `1/(2A)`.
#[derive(Clone, Copy, Debug)]
pub struct TriPotential {
    /// Vertices, counter-clockwise.
    pub x: [V2; 3],
    inv2a: f64,
}

impl TriPotential {
    /// The potential of a CCW triangle; `None` if the area is not positive and finite
    /// (inverted, degenerate or non-finite triangles carry no potential).
    #[inline]
    pub fn new(x: [V2; 3]) -> Option<Self> {
        let a2 = cross(sub(x[1], x[0]), sub(x[2], x[0]));
        let inv2a = 1.0 / a2;
        if a2 > 0.0 && inv2a.is_finite() && finite(x[0]) && finite(x[1]) && finite(x[2]) {
            Some(TriPotential { x, inv2a })
        } else {
            None
        }
    }

    /// Barycentric coordinates `lam_k = A_k / A` of point `p`.
    #[inline(always)]
    pub fn barycentric(&self, p: V2) -> [f64; 3] {
        let x = &self.x;
        [
            cross(sub(x[2], x[1]), sub(p, x[1])) * self.inv2a,
            cross(sub(x[0], x[2]), sub(p, x[2])) * self.inv2a,
            cross(sub(x[1], x[0]), sub(p, x[0])) * self.inv2a,
        ]
    }

    /// The potential `phi(p) = 3 min(lam_k)`, clamped at 0 outside the triangle.
    #[inline]
    pub fn phi(&self, p: V2) -> f64 {
        let l = self.barycentric(p);
        (3.0 * l[0].min(l[1]).min(l[2])).max(0.0)
    }

    /// Gradient `3 grad lam_k = 3 rot(x_(k+2) - x_(k+1)) / (2A)` of `phi` in sub-triangle `k`.
    #[inline]
    pub fn grad_phi(&self, k: usize) -> V2 {
        scale(
            rot(sub(self.x[(k + 2) % 3], self.x[(k + 1) % 3])),
            3.0 * self.inv2a,
        )
    }
}

/// The load of one edge `A -> B` of body E inside triangle T, without the penalty.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EdgeLoad {
    /// `Q = int phi_T ds` over the part of the edge inside T \[m\]; the normal force is `p Q`.
    pub q: f64,
    /// Parameter of the resultant point `x(sbar) = A + sbar (B - A)`.
    pub sbar: f64,
    /// Barycentric coordinates of the resultant point in T.
    pub lam: [f64; 3],
    /// Length of the edge inside T \[m\].
    pub len_in: f64,
    /// Largest `phi_T` on the edge (0..1; 1 means the edge reached T's centroid).
    pub phi_max: f64,
}

/// Closed-form integral of `phi_T` along the edge `A -> B` (steps 1-3 of the module docs).
/// Returns a zero load (`q = 0`) when the edge misses T or has zero length.
#[inline]
pub fn edge_load(a: V2, b: V2, t: &TriPotential) -> EdgeLoad {
    edge_load_bary(norm(sub(b, a)), t.barycentric(a), t.barycentric(b))
}

/// [`edge_load`] from the edge length `l` and the barycentric coordinates in T of its ends
/// (shared by the two edges meeting at a vertex).
#[inline]
pub fn edge_load_bary(l: f64, la: [f64; 3], lb: [f64; 3]) -> EdgeLoad {
    edge_load_with(|| l, la, lb)
}

/// [`edge_load_bary`] with the edge length computed only when the edge meets T (most edges
/// of the candidate couples do not: their square root is saved).
#[inline(always)]
fn edge_load_with(len: impl FnOnce() -> f64, la: [f64; 3], lb: [f64; 3]) -> EdgeLoad {
    let mut out = EdgeLoad::default();
    let dl = [lb[0] - la[0], lb[1] - la[1], lb[2] - la[2]];
    // 1. Clip to T.
    let (mut s0, mut s1) = (0.0f64, 1.0f64);
    for k in 0..3 {
        if dl[k] > 0.0 {
            s0 = s0.max(-la[k] / dl[k]);
        } else if dl[k] < 0.0 {
            s1 = s1.min(-la[k] / dl[k]);
        } else if la[k] < 0.0 {
            return out;
        }
    }
    if s1 <= s0 || s1.is_nan() || s0.is_nan() {
        return out;
    }
    let l = len();
    if l.is_nan() || l <= 0.0 {
        return out;
    }
    // 2. Break points: where two lam are equal and smallest.
    let mut sb = [0.0f64; 5];
    let mut n = 0;
    sb[n] = s0;
    n += 1;
    for (i, j, k) in [(0, 1, 2), (1, 2, 0), (2, 0, 1)] {
        let den = dl[i] - dl[j];
        if den != 0.0 {
            let s = (la[j] - la[i]) / den;
            if s > s0 && s < s1 {
                let li = la[i] + s * dl[i];
                let lk = la[k] + s * dl[k];
                if lk >= li {
                    // Insertion keeps the break points sorted.
                    let mut m = n;
                    while m > 1 && sb[m - 1] > s {
                        sb[m] = sb[m - 1];
                        m -= 1;
                    }
                    sb[m] = s;
                    n += 1;
                }
            }
        }
    }
    sb[n] = s1;
    n += 1;
    let phi_at = |s: f64| -> f64 {
        let m = (la[0] + s * dl[0])
            .min(la[1] + s * dl[1])
            .min(la[2] + s * dl[2]);
        (3.0 * m).max(0.0)
    };
    // 3. Linear pieces.
    let mut q = 0.0;
    let mut qs = 0.0;
    let mut phi_max = 0.0f64;
    let mut phi_a = phi_at(sb[0]);
    for m in 1..n {
        let (sa, sbb) = (sb[m - 1], sb[m]);
        let phi_b = phi_at(sbb);
        phi_max = phi_max.max(phi_a).max(phi_b);
        let w = phi_a + phi_b;
        if w > 0.0 && sbb > sa {
            let qi = l * (sbb - sa) * w * 0.5;
            let si = sa + (sbb - sa) * (phi_a + 2.0 * phi_b) / (3.0 * w);
            q += qi;
            qs += qi * si;
        }
        phi_a = phi_b;
    }
    out.len_in = l * (s1 - s0);
    out.phi_max = phi_max;
    if q > 0.0 {
        let sbar = (qs / q).clamp(s0, s1);
        out.q = q;
        out.sbar = sbar;
        out.lam = [
            la[0] + sbar * dl[0],
            la[1] + sbar * dl[1],
            la[2] + sbar * dl[2],
        ];
    }
    out
}

/// The 6 edge loads of a couple: `edges[0..3]` are the edges of `c` (edge e runs from vertex
/// e to e+1) against `phi_t`; `edges[3..6]` are the edges of `t` against `phi_c`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairLoads {
    /// Edge loads, see the type docs.
    pub edges: [EdgeLoad; 6],
}

/// Local node indices (0..3 = c, 3..6 = t) of edge `e` of a couple: `(A, B, T's three nodes)`.
#[inline(always)]
pub const fn edge_nodes(e: usize) -> (usize, usize, [usize; 3]) {
    if e < 3 {
        (e, (e + 1) % 3, [3, 4, 5])
    } else {
        (e, 3 + (e - 3 + 1) % 3, [0, 1, 2])
    }
}

/// Edge loads of the couple (c, t) both ways round; `None` if either triangle is degenerate,
/// inverted or not finite.
#[inline]
pub fn pair_loads(xc: &[V2; 3], xt: &[V2; 3]) -> Option<PairLoads> {
    let pc = TriPotential::new(*xc)?;
    let pt = TriPotential::new(*xt)?;
    let mut out = PairLoads::default();
    // Barycentric coordinates of each vertex in the other triangle, computed once.
    // Separating axis: all vertices of one triangle outside one edge of the other -> no
    // overlap (tested on c's vertices before the other half is computed).
    let outside =
        |l: &[[f64; 3]; 3]| (0..3).any(|k| l[0][k] < 0.0 && l[1][k] < 0.0 && l[2][k] < 0.0);
    let lt = xc.map(|p| pt.barycentric(p));
    if outside(&lt) {
        return Some(out);
    }
    let lc = xt.map(|p| pc.barycentric(p));
    if outside(&lc) {
        return Some(out);
    }
    for e in 0..3 {
        let f = (e + 1) % 3;
        out.edges[e] = edge_load_with(|| norm(sub(xc[f], xc[e])), lt[e], lt[f]);
        out.edges[3 + e] = edge_load_with(|| norm(sub(xt[f], xt[e])), lc[e], lc[f]);
    }
    Some(out)
}

/// Outward unit normal and unit tangent of a CCW edge `A -> B`: `n = (e_y, -e_x)/|e|`.
#[inline(always)]
pub fn edge_frame(a: V2, b: V2) -> (V2, V2) {
    let e = sub(b, a);
    let l = norm(e);
    let s = [e[0] / l, e[1] / l];
    ([s[1], -s[0]], s)
}

/// Adds the edge force `g` (acting on body E at `x(sbar)`) to the 6 couple nodes with the
/// consistent weights: `(1 - sbar) g` to A, `sbar g` to B, `-lam_k g` to T's node k.
#[inline(always)]
pub fn lump_edge_force(f: &mut [V2; 6], e: usize, load: &EdgeLoad, g: V2) {
    let (a, b, tn) = edge_nodes(e);
    f[a] = add(f[a], scale(g, 1.0 - load.sbar));
    f[b] = add(f[b], scale(g, load.sbar));
    for k in 0..3 {
        f[tn[k]] = sub(f[tn[k]], scale(g, load.lam[k]));
    }
}

/// Normal (potential) contact forces of a couple on its 6 nodes (0..3 = c, 3..6 = t) for
/// penalty `p` \[Pa\], per unit thickness \[N/m\]. Zero for degenerate triangles.
pub fn pair_normal_force(xc: &[V2; 3], xt: &[V2; 3], p: f64) -> [V2; 6] {
    let mut f = [[0.0; 2]; 6];
    if let Some(loads) = pair_loads(xc, xt) {
        add_normal_forces(&mut f, xc, xt, &loads, p);
    }
    f
}

/// Adds the normal forces of precomputed `loads` to `f`.
#[inline]
pub fn add_normal_forces(f: &mut [V2; 6], xc: &[V2; 3], xt: &[V2; 3], loads: &PairLoads, p: f64) {
    for e in 0..6 {
        let ld = &loads.edges[e];
        if ld.q > 0.0 {
            let (a, b) = if e < 3 {
                (xc[e], xc[(e + 1) % 3])
            } else {
                (xt[e - 3], xt[(e - 2) % 3])
            };
            let (n, _) = edge_frame(a, b);
            lump_edge_force(f, e, ld, scale(n, -p * ld.q));
        }
    }
}

/// Sub-triangle `k` (centroid, vertex k+1, vertex k+2) of a CCW triangle, where `phi = 3 lam_k`.
#[inline]
fn sub_triangle(x: &[V2; 3], k: usize) -> [V2; 3] {
    [centroid(x), x[(k + 1) % 3], x[(k + 2) % 3]]
}

/// Visits the 3 x 3 convex pieces of the overlap where both potentials are linear, with
/// (area, area centroid, sub-triangle of c, sub-triangle of t).
fn for_each_overlap_piece(xc: &[V2; 3], xt: &[V2; 3], mut f: impl FnMut(f64, V2, usize, usize)) {
    let whole = Poly::tri(*xc).clip_tri(xt);
    if whole.n < 3 {
        return;
    }
    for kc in 0..3 {
        let sc = whole.clip_tri(&sub_triangle(xc, kc));
        if sc.n < 3 {
            continue;
        }
        for kt in 0..3 {
            let piece = sc.clip_tri(&sub_triangle(xt, kt));
            let (area, cen) = piece.area_centroid();
            if area > 0.0 {
                f(area, cen, kc, kt);
            }
        }
    }
}

/// Pair energy `W = p * int_{c ∩ t} (phi_c + phi_t) dA` \[J/m\], exact (piecewise-linear
/// integrand on 3 x 3 clipped convex pieces). Zero for degenerate triangles.
pub fn pair_energy(xc: &[V2; 3], xt: &[V2; 3], p: f64) -> f64 {
    let (Some(pc), Some(pt)) = (TriPotential::new(*xc), TriPotential::new(*xt)) else {
        return 0.0;
    };
    let mut w = 0.0;
    for_each_overlap_piece(xc, xt, |area, cen, _, _| {
        w += area * (pc.phi(cen) + pt.phi(cen));
    });
    p * w
}

/// Reference force on `c`, `p * int_{c ∩ t} (grad phi_c - grad phi_t) dA`, by the area
/// decomposition (independent of the edge integral; used for verification).
pub fn pair_force_area(xc: &[V2; 3], xt: &[V2; 3], p: f64) -> V2 {
    let (Some(pc), Some(pt)) = (TriPotential::new(*xc), TriPotential::new(*xt)) else {
        return [0.0; 2];
    };
    let mut f = [0.0; 2];
    for_each_overlap_piece(xc, xt, |area, _, kc, kt| {
        let g = sub(pc.grad_phi(kc), pt.grad_phi(kt));
        f = add(f, scale(g, p * area));
    });
    f
}

/// The overlap area of two triangles (Sutherland-Hodgman clipping).
pub fn overlap_area(xc: &[V2; 3], xt: &[V2; 3]) -> f64 {
    Poly::tri(*xc).clip_tri(xt).area_centroid().0
}
