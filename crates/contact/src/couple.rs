//! Evaluation of one couple (triangle-triangle or plane-triangle): normal potential force,
//! Coulomb friction and optional damping, as per-node forces kept apart by family so that the
//! caller can book the work of each (contact, friction, damping) separately.

use crate::friction::{coulomb_update, edge_relative_velocity};
use crate::geom::{V2, add, dot, scale};
use crate::laws::ContactLaw;
use crate::potential_tri_tri::{PairLoads, edge_frame, lump_edge_force, pair_loads};
use crate::walls::RigidPlane;

/// Forces of one triangle-triangle couple on its 6 nodes (0..3 = first, 3..6 = second
/// triangle), by family, and the trial friction state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CoupleForce {
    /// False when the couple carries no force; the other fields are then stale (not rewritten,
    /// to save memory traffic) and must be ignored.
    pub active: bool,
    /// Normal (potential) forces \[N/m\].
    pub normal: [V2; 6],
    /// Friction forces \[N/m\].
    pub friction: [V2; 6],
    /// Damping forces \[N/m\].
    pub damping: [V2; 6],
    /// Sum of the three families, `normal + friction + damping` \[N/m\] (what the scatter
    /// reads).
    pub total: [V2; 6],
    /// Trial tangential force per couple edge (0..3 edges of the first, 3..6 of the second).
    pub ft: [f64; 6],
    /// Trial slip dissipation of this step \[J/m\].
    pub dissipation: f64,
    /// Total normal load `sum p Q` over the 6 edges \[N/m\].
    pub fn_total: f64,
    /// Largest `phi` on a contacting edge (0..1).
    pub phi_max: f64,
    /// Number of edges slipping.
    pub slipping: u8,
    /// True if a triangle of the couple was degenerate, inverted or not finite (no force).
    pub invalid: bool,
}

/// Evaluates a couple with positions `x`, velocities `v` of its 6 nodes, committed
/// tangential forces `ft_old`, step `dt` (friction increment) and the pair's `law`.
#[inline]
pub fn couple_force(
    x: &[V2; 6],
    v: &[V2; 6],
    ft_old: &[f64; 6],
    dt: f64,
    law: &ContactLaw,
) -> CoupleForce {
    let mut out = CoupleForce::default();
    couple_force_into(&mut out, x, v, ft_old, dt, law);
    out
}

/// [`couple_force`] writing into `out` in place (no copy of the result).
#[inline]
pub fn couple_force_into(
    out: &mut CoupleForce,
    x: &[V2; 6],
    v: &[V2; 6],
    ft_old: &[f64; 6],
    dt: f64,
    law: &ContactLaw,
) {
    let xc = [x[0], x[1], x[2]];
    let xt = [x[3], x[4], x[5]];
    match pair_loads(&xc, &xt) {
        Some(loads) => couple_force_from_loads(out, &xc, &xt, &loads, v, ft_old, dt, law),
        None => {
            *out = CoupleForce {
                active: true,
                invalid: true,
                ..Default::default()
            }
        }
    }
}

/// True when no edge of the couple carries a load (the triangles do not overlap).
#[inline(always)]
pub(crate) fn loads_empty(loads: &PairLoads) -> bool {
    loads.edges.iter().all(|l| l.q <= 0.0)
}

/// The forces of a couple from its edge loads ([`pair_loads`]): normal, friction and
/// damping per edge, lumped onto the 6 nodes; written whole into `out`.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn couple_force_from_loads(
    out: &mut CoupleForce,
    xc: &[V2; 3],
    xt: &[V2; 3],
    loads: &PairLoads,
    v: &[V2; 6],
    ft_old: &[f64; 6],
    dt: f64,
    law: &ContactLaw,
) {
    *out = CoupleForce {
        active: true,
        ..Default::default()
    };
    let p = law.penalty;
    for e in 0..6 {
        let ld = &loads.edges[e];
        out.phi_max = out.phi_max.max(ld.phi_max);
        if ld.q <= 0.0 {
            continue; // ft stays 0: reset on separation.
        }
        let (a, b) = if e < 3 {
            (xc[e], xc[(e + 1) % 3])
        } else {
            (xt[e - 3], xt[(e - 2) % 3])
        };
        let (n, s) = edge_frame(a, b);
        let fn_ = p * ld.q;
        out.fn_total += fn_;
        lump_edge_force(&mut out.normal, e, ld, scale(n, -fn_));
        if law.mu > 0.0 || law.damping > 0.0 {
            let vr = edge_relative_velocity(v, e, ld);
            // Positive v_n: E's edge moves deeper into T. Bounded by the edge's normal force
            // both ways: never tensile in total, and no ploughing by edges that slide along a
            // surface they barely touch.
            let fd = if law.damping > 0.0 {
                let fd = (law.damping * ld.len_in * dot(vr, n)).clamp(-fn_, fn_);
                lump_edge_force(&mut out.damping, e, ld, scale(n, -fd));
                fd
            } else {
                0.0
            };
            if law.mu > 0.0 {
                // Coulomb bounds the tangential force by the whole normal force of the edge,
                // potential plus damping (docs/contact.md section 3).
                let up = coulomb_update(ft_old[e], fn_ + fd, dot(vr, s), dt, law.mu, law.kt);
                out.ft[e] = up.ft;
                out.dissipation += up.dissipation;
                out.slipping += up.slipping as u8;
                lump_edge_force(&mut out.friction, e, ld, scale(s, up.ft));
            }
        }
    }
    for k in 0..6 {
        out.total[k] = add(add(out.normal[k], out.friction[k]), out.damping[k]);
    }
}

/// Forces of one plane-triangle couple on the triangle's 3 nodes, by family.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WallForce {
    /// Normal forces \[N/m\].
    pub normal: [V2; 3],
    /// Friction forces \[N/m\].
    pub friction: [V2; 3],
    /// Damping forces \[N/m\].
    pub damping: [V2; 3],
    /// Trial tangential force (along `rot(normal)`, acting on the plane).
    pub ft: f64,
    /// Trial slip dissipation \[J/m\].
    pub dissipation: f64,
    /// Normal load `p Q` \[N/m\].
    pub fn_total: f64,
    /// Largest `phi` on the plane's segment inside the triangle.
    pub phi_max: f64,
    /// True when slipping.
    pub slipping: bool,
}

/// Evaluates a plane against triangle `xt` with velocities `vt`.
#[inline]
pub fn wall_force(
    plane: &RigidPlane,
    xt: &[V2; 3],
    vt: &[V2; 3],
    ft_old: f64,
    dt: f64,
) -> WallForce {
    let mut out = WallForce::default();
    let Some((ld, _, _)) = plane.load(xt) else {
        return out;
    };
    let law = &plane.law;
    let n = plane.normal;
    let s = [-n[1], n[0]];
    let fn_ = law.penalty * ld.q;
    out.fn_total = fn_;
    out.phi_max = ld.phi_max;
    // The plane (body E) gets g; node k of the triangle gets -lam_k g.
    let apply = |f: &mut [V2; 3], g: V2| {
        for k in 0..3 {
            f[k] = add(f[k], scale(g, -ld.lam[k]));
        }
    };
    apply(&mut out.normal, scale(n, -fn_));
    if law.mu > 0.0 || law.damping > 0.0 {
        let mut vr = plane.velocity;
        for k in 0..3 {
            vr = add(vr, scale(vt[k], -ld.lam[k]));
        }
        let fd = if law.damping > 0.0 {
            let fd = (law.damping * ld.len_in * dot(vr, n)).clamp(-fn_, fn_);
            apply(&mut out.damping, scale(n, -fd));
            fd
        } else {
            0.0
        };
        if law.mu > 0.0 {
            // Bounded by the whole normal force, potential plus damping (as for triangles).
            let up = coulomb_update(ft_old, fn_ + fd, dot(vr, s), dt, law.mu, law.kt);
            out.ft = up.ft;
            out.dissipation = up.dissipation;
            out.slipping = up.slipping;
            apply(&mut out.friction, scale(s, up.ft));
        }
    }
    out
}
