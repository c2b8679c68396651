//! The narrow filter of detection: a candidate couple (bounding circles within the buffer
//! `b`) is kept only when no edge line of either triangle has all three vertices of the other
//! triangle more than `b` beyond it (a separating axis with a margin).
//!
//! For an edge `A -> B` of triangle `P` with third vertex `C`, the signed distance of a point
//! `v` beyond the edge line, on the side away from `C`, is
//! `s(v) = -sign(cross(B - A, C - A)) cross(B - A, v - A) / |B - A|`; the couple is dropped
//! when `min_{v in Q} s(v) > b` for some edge of `P` or of `Q`. Then every point of `Q` is
//! more than `b` from the half-plane that holds `P`, so the triangles are more than `b` apart.
//! That keeps the refresh criterion rigorous: until some node has moved `b/2` (the next
//! detection), every point of a triangle, a convex combination of its nodes, has moved less
//! than `b/2`, so a dropped couple cannot touch before it is tested again. Two triangles
//! overlap exactly when no edge line separates them (separating axis theorem for convex
//! polygons), so with `b = 0` the test is exact; with `b > 0` it may keep a couple whose
//! closest features are two vertices slightly more than `b` apart (conservative).
//!
//! In an exploded mesh whose vertex neighbours are bonded (the solver's intact stars), the
//! bounding-circle candidates are mostly triangles two rings apart: their circles overlap,
//! the triangles are a good fraction of an altitude apart, and this filter drops them before
//! the force pass sees them (docs/contact.md section 6).

use crate::geom::{V2, cross, norm, sub};

/// True when an edge line of `p` or of `q` has all three vertices of the other triangle more
/// than `b` beyond it (then the triangles are more than `b` apart). Either orientation;
/// degenerate edges and non-finite coordinates never separate.
#[inline]
pub fn separated(p: &[V2; 3], q: &[V2; 3], b: f64) -> bool {
    beyond_an_edge(p, q, b) || beyond_an_edge(q, p, b)
}

/// True when an edge line of `p` has all of `q` more than `b` beyond it.
#[inline(always)]
fn beyond_an_edge(p: &[V2; 3], q: &[V2; 3], b: f64) -> bool {
    (0..3).any(|k| {
        let a = p[k];
        let e = sub(p[(k + 1) % 3], a);
        let inside = cross(e, sub(p[(k + 2) % 3], a));
        // Outward sign: away from the third vertex.
        let s = if inside > 0.0 {
            -1.0
        } else if inside < 0.0 {
            1.0
        } else {
            return false;
        };
        let margin = b * norm(e);
        q.iter().all(|v| s * cross(e, sub(*v, a)) > margin)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shift(t: &[V2; 3], d: V2) -> [V2; 3] {
        t.map(|p| [p[0] + d[0], p[1] + d[1]])
    }

    #[test]
    fn separation_margin_is_the_gap_along_an_edge_normal() {
        // Unit right triangle and a copy moved right by 1 + g: the gap across the vertical
        // line x = 1 (the copy's left edge) is g, so separated iff g > b; either orientation.
        let p = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        for g in [0.05, 0.2, 0.5] {
            let q = shift(&p, [1.0 + g, 0.0]);
            let q_cw = [q[0], q[2], q[1]];
            for b in [0.0, 0.1, 0.3] {
                assert_eq!(separated(&p, &q, b), g > b, "g {g} b {b}");
                assert_eq!(separated(&q_cw, &p, b), g > b, "g {g} b {b} (cw)");
            }
        }
    }

    #[test]
    fn overlapping_or_crossing_triangles_are_never_separated() {
        // Overlap, a star of David (edges cross, no vertex inside the other), a shared
        // vertex, and a degenerate (flat) triangle inside the other.
        let p = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(!separated(&p, &shift(&p, [0.2, 0.2]), 0.0));
        let up = [[0.0, 0.0], [2.0, 0.0], [1.0, 1.8]];
        let down = [[0.0, 1.2], [1.0, -0.6], [2.0, 1.2]];
        assert!(!separated(&up, &down, 0.0));
        assert!(!separated(&p, &[[1.0, 0.0], [2.0, 0.0], [2.0, 1.0]], 0.0));
        let flat = [[0.1, 0.1], [0.2, 0.2], [0.3, 0.3]];
        assert!(!separated(&p, &flat, 0.0) && !separated(&flat, &p, 0.0));
        // A flat triangle far away is still separated by the edges of the other.
        assert!(separated(&p, &shift(&flat, [5.0, 5.0]), 1.0));
        // Brute force on random pairs: separated at b = 0 only when no vertex of one is in
        // the other and no edges cross (a coarse sampling of both triangles stays apart).
        let mut s = 1u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 * 3.0
        };
        let (mut n_sep, mut n_touch) = (0, 0);
        for _ in 0..2000 {
            let p = [[rnd(), rnd()], [rnd(), rnd()], [rnd(), rnd()]];
            let q = [[rnd(), rnd()], [rnd(), rnd()], [rnd(), rnd()]];
            let inside = |t: &[V2; 3], v: V2| {
                let c = (0..3).map(|k| cross(sub(t[(k + 1) % 3], t[k]), sub(v, t[k])));
                let c: Vec<f64> = c.collect();
                c.iter().all(|x| *x >= 0.0) || c.iter().all(|x| *x <= 0.0)
            };
            // Sample points of p (a 20 x 20 barycentric grid) inside q.
            let mut meet = false;
            for i in 0..=20 {
                for j in 0..=20 - i {
                    let (a, b) = (i as f64 / 20.0, j as f64 / 20.0);
                    let v = [
                        p[0][0] + a * (p[1][0] - p[0][0]) + b * (p[2][0] - p[0][0]),
                        p[0][1] + a * (p[1][1] - p[0][1]) + b * (p[2][1] - p[0][1]),
                    ];
                    meet |= inside(&q, v);
                }
            }
            if separated(&p, &q, 0.0) {
                assert!(!meet, "separated triangles share a point: {p:?} {q:?}");
                n_sep += 1;
            } else {
                n_touch += 1;
            }
        }
        assert!(n_sep > 200 && n_touch > 200, "{n_sep} {n_touch}");
    }
}
