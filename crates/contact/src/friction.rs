//! Coulomb friction with a tangential penalty, per (couple, edge) (Munjiza 2004 ch. 2;
//! Mahabadi et al. 2012 for the stick/slip form).
//!
//! For an edge `A -> B` of body E with normal load `Fn = p Q` at `x(sbar)` in target T:
//!
//! ```text
//! s_E = (B - A)/l,   v_t = ((1 - sbar) v_A + sbar v_B - sum_k lam_k v_k) . s_E
//! Ft* = Ft_old - k_t v_t dt
//! |Ft*| > mu N:   Ft = mu N sign(Ft*)    (slip; dissipation += Ft (Ft* - Ft)/k_t)
//! otherwise       Ft = Ft*               (stick)
//! ```
//!
//! `N = Fn + f_d` is the edge's whole normal force, potential plus contact damping (the
//! caller passes it as `fn_`): only that sum is fixed by the normal balance, and with the
//! potential part alone a chattering sliding contact gets the wrong mean friction
//! (docs/contact.md section 3).
//!
//! `Ft s_E` is applied with the same consistent weights as the normal force. `Ft_old` is the
//! committed value of the end of the previous step: force evaluations (including the trial
//! stages of multi-stage integrators) read it and never write it; only the end-of-step commit
//! does. An edge with no overlap has `Fn = 0`, so its `Ft` returns to 0 (the history is reset
//! when a couple separates). `k_t` is in Pa (N/m per unit thickness, per m of displacement).

use crate::geom::{V2, add, scale, sub};
use crate::potential_tri_tri::{EdgeLoad, edge_nodes};

/// The outcome of one return-mapping update.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrictionUpdate {
    /// The new tangential force \[N/m\], along the edge's unit tangent.
    pub ft: f64,
    /// Energy dissipated by slip in this update, `Ft (Ft* - Ft)/k_t` \[J/m\].
    pub dissipation: f64,
    /// True when the edge slips (`|Ft*| > mu N`).
    pub slipping: bool,
}

/// Coulomb return mapping: trial `Ft* = ft_old - kt v_t dt`, then the cap `mu fn_` (`fn_`: the
/// edge's whole normal force N).
#[inline]
pub fn coulomb_update(
    ft_old: f64,
    fn_: f64,
    v_t: f64,
    dt: f64,
    mu: f64,
    kt: f64,
) -> FrictionUpdate {
    let trial = ft_old - kt * v_t * dt;
    let cap = mu * fn_.max(0.0);
    if trial.abs() > cap {
        let ft = cap.copysign(trial);
        let dissipation = if kt > 0.0 {
            ft * (trial - ft) / kt
        } else {
            0.0
        };
        FrictionUpdate {
            ft,
            dissipation,
            slipping: true,
        }
    } else {
        FrictionUpdate {
            ft: trial,
            dissipation: 0.0,
            slipping: false,
        }
    }
}

/// Velocity of E's edge point at `x(sbar)` relative to T's material point there, for couple
/// edge `e` with node velocities `v` (0..3 = c, 3..6 = t).
#[inline]
pub fn edge_relative_velocity(v: &[V2; 6], e: usize, load: &EdgeLoad) -> V2 {
    let (a, b, tn) = edge_nodes(e);
    let mut r = add(scale(v[a], 1.0 - load.sbar), scale(v[b], load.sbar));
    for k in 0..3 {
        r = sub(r, scale(v[tn[k]], load.lam[k]));
    }
    r
}

/// Stored energy of the tangential springs, `sum Ft^2/(2 k_t)` \[J/m\].
#[inline]
pub fn stored_energy(ft: f64, kt: f64) -> f64 {
    if kt > 0.0 { ft * ft / (2.0 * kt) } else { 0.0 }
}
