//! Rigid planes (walls, floors) and prescribed-motion platens acting on triangles.
//!
//! A plane is the boundary of a rigid half-space: the solid lies behind the line through
//! `point` with outward unit normal `normal` (pointing into the free side). It is treated with
//! the same potential idea as a triangle pair, the rigid solid being a target of infinite
//! altitude (`phi_wall = 0`, `1/H_wall = 0`). With T the overlapping triangle:
//!
//! ```text
//! f_T = p * int_{T behind plane} grad phi_T dA = p * int_{plane ∩ T} phi_T ds * n
//! W   = p * int_{T behind plane} phi_T dA
//! ```
//!
//! (Gauss's theorem: `phi_T = 0` on T's edges). The plane's segment inside T is an "edge" of
//! the rigid body with outward normal `n` and tangent `rot(n)`, processed with
//! [`edge_load`]; T's node k gets `lam_k(x_P) p Q n`, the plane the opposite. The flat-overlap
//! traction is `3 p d / H_T`. Friction and damping are those of a triangle edge with the
//! plane's velocity as the edge velocity (Coulomb, tangential penalty `k_t`, one history
//! value per (plane, triangle)).
//!
//! A platen is a plane whose `point` the caller moves (prescribed velocity `velocity`, or a
//! rigid body integrated by the caller from [`crate::Contact::wall_reactions`]).
//!
//! Limits: as for triangles, a triangle whose centroid passes behind the plane (`phi` reaching 1)
//! gets a force that decreases with depth and can pass through; `phi_max` in the stats
//! reports how deep contacts are.

use crate::geom::{Poly, V2, add, centroid, dot, norm, rot, scale, sub};
use crate::laws::ContactLaw;
use crate::potential_tri_tri::{EdgeLoad, TriPotential, edge_load};

/// A rigid plane (wall, floor) or platen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidPlane {
    /// A point of the plane [m]; move it to prescribe a platen's motion.
    pub point: V2,
    /// Outward unit normal, pointing from the solid into the free side.
    pub normal: V2,
    /// Velocity of the plane [m/s] (used by friction and damping).
    pub velocity: V2,
    /// Contact law between the plane and every triangle.
    pub law: ContactLaw,
}

impl RigidPlane {
    /// A fixed plane through `point` with outward normal `normal` (normalised here;
    /// a zero normal gives a plane that touches nothing).
    pub fn new(point: V2, normal: V2, law: ContactLaw) -> Self {
        let l = norm(normal);
        let normal = if l > 0.0 && l.is_finite() {
            scale(normal, 1.0 / l)
        } else {
            [0.0, 0.0]
        };
        RigidPlane {
            point,
            normal,
            velocity: [0.0, 0.0],
            law,
        }
    }

    /// Signed distance of `x` from the plane (positive on the free side).
    #[inline(always)]
    pub fn signed_distance(&self, x: V2) -> f64 {
        dot(sub(x, self.point), self.normal)
    }

    /// The plane's segment inside triangle `xt` as an edge `A -> B` of the rigid body, with
    /// its load against `phi_T`; `None` if the triangle is degenerate or the plane misses it.
    pub fn load(&self, xt: &[V2; 3]) -> Option<(EdgeLoad, V2, V2)> {
        let t = TriPotential::new(*xt)?;
        let c = centroid(xt);
        let r = norm(sub(xt[0], c))
            .max(norm(sub(xt[1], c)))
            .max(norm(sub(xt[2], c)));
        let dc = self.signed_distance(c);
        if dc >= r || dc.is_nan() || r.is_nan() || self.normal == [0.0, 0.0] {
            return None;
        }
        let q = sub(c, scale(self.normal, dc));
        let e = rot(self.normal);
        let rr = 2.0 * r;
        let a = sub(q, scale(e, rr));
        let b = add(q, scale(e, rr));
        let ld = edge_load(a, b, &t);
        if ld.q > 0.0 { Some((ld, a, b)) } else { None }
    }

    /// Normal force of the plane on the 3 nodes of `xt` [N/m].
    pub fn normal_force(&self, xt: &[V2; 3]) -> [V2; 3] {
        let mut f = [[0.0; 2]; 3];
        if let Some((ld, _, _)) = self.load(xt) {
            let g = scale(self.normal, self.law.penalty * ld.q);
            for k in 0..3 {
                f[k] = scale(g, ld.lam[k]);
            }
        }
        f
    }

    /// Energy `p * int_{T behind plane} phi_T dA` [J/m] (exact: linear pieces).
    pub fn energy(&self, xt: &[V2; 3]) -> f64 {
        let Some(t) = TriPotential::new(*xt) else {
            return 0.0;
        };
        if self.normal == [0.0, 0.0] {
            return 0.0;
        }
        let c = centroid(xt);
        let mut w = 0.0;
        for k in 0..3 {
            let sub_t = Poly::tri([c, xt[(k + 1) % 3], xt[(k + 2) % 3]]);
            let behind = sub_t.clip_halfplane(self.point, scale(self.normal, -1.0));
            let (area, cen) = behind.area_centroid();
            if area > 0.0 {
                w += area * t.phi(cen);
            }
        }
        self.law.penalty * w
    }
}
