//! One four-node joint: kinematics, the traction law at its two nodal integration points,
//! nodal forces and stored energy. Pure functions of the node positions and the committed
//! history; nothing here changes state.
//!
//! Kinematics (edge P->Q of T1 against edge R->S of T2, P = S and Q = R in the reference):
//!
//! ```text
//! M0 = (x_P + x_S)/2,  M1 = (x_Q + x_R)/2,  l = |M1 - M0|,  tt = (M1 - M0)/l,  nn = (tt_y, -tt_x)
//! w0 = x_S - x_P,  w1 = x_R - x_Q,  o_k = w_k . nn,  s_k = w_k . tt     (k = 0 at P/S, 1 at Q/R)
//! ```
//!
//! Law at each point, with `<v> = max(0, v)`, `o_p = 2 h ft/p`, `o_c` and `s_p`, `s_c` from
//! [`crate::material`], and the damage committed at the last step end `D_old`:
//!
//! ```text
//! o < 0:  sigma = (p/h) o                       (compression is carried by the joint, always)
//! fs = c + <-sigma> tan(phi),  s_p = 2 h fs/p_t,  s_c - s_p = <G_II - (2/3) fs s_p>/(I_z fs)
//! D = min(1, max(D_old, sqrt(<o - o_p>^2/(o_c - o_p)^2 + <|s| - s_p>^2/(s_c - s_p)^2)))
//! D = 0:  sigma = ft (2x - x^2) (x = o/o_p, o >= 0),   tau = fs (2y - y^2) sign(s) (y = |s|/s_p)
//! D > 0:  sigma = ft z(D) o/o_D (o >= 0),  tau_law = fs z(D) s/s_D,
//!         o_D = o_p + D (o_c - o_p),  s_D = s_p + D (s_c - s_p)
//! shear:  k_t = min(k_t_old, tau_law/|s|),  tau = k_t s     (secant history, never stiffens)
//! ```
//!
//! Stored energy per unit area: at `D = 0`, `ft o_p (x^2 - x^3/3)` (or `(p/h) o^2/2` for
//! `o < 0`); at `D > 0`, `sigma o/2` (secant unloading); plus `k_t s^2/2`. The shear secant
//! history is what keeps the joint from creating energy: `fs` depends on `sigma`, so
//! `tau_law(s, sigma)` has no potential (docs/fracture.md section 3).
//!
//! Nodal forces: each point carries the reference area `A = h t/2` (so that the forces are
//! exactly `-d(A psi)/dx` for a frozen history). The forces are the virtual-work
//! conjugates of the point's opening and sliding, `f_a = -A (sigma d o/d x_a + tau d s/d x_a)`,
//! including the turn of the joint frame (`d tt = nn (nn . d(M1-M0))/l`, `d nn = -tt (...)/l`):
//!
//! ```text
//! f_P += A q_0,  f_S -= A q_0,  f_Q += A q_1,  f_R -= A q_1,    q_k = sigma_k nn + tau_k tt
//! c = A sum_k (tau_k o_k - sigma_k s_k)/l:   f_P, f_S += (c/2) nn,   f_Q, f_R -= (c/2) nn
//! ```
//!
//! The first line is the form in the literature; the frame terms are of relative size `|w|/l`
//! and make `sum f = 0` and `sum x x f = 0` hold exactly, whatever the tractions, because `o`
//! and `s` are invariant under rigid motions. The nodal power then equals
//! `sum_k A (sigma_k do_k/dt + tau_k ds_k/dt)`, which the energy accounting integrates.

use crate::material::{JointConsts, JointMaterial, SofteningConsts};
use crate::softening::{Z_INTEGRAL, pre_peak, pre_peak_energy, z};

/// Geometry of a joint in its current position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointKinematics {
    /// Current length `l = |M1 - M0|` (m).
    pub l: f64,
    /// Unit tangent from M0 to M1.
    pub tt: [f64; 2],
    /// Unit normal, pointing from T1 to T2.
    pub nn: [f64; 2],
    /// Opening at the two points (P/S, Q/R) (m); positive when open.
    pub o: [f64; 2],
    /// Sliding at the two points (m).
    pub s: [f64; 2],
}

/// Node positions of one joint in the order P, Q, R, S.
pub type JointNodes = [[f64; 2]; 4];

/// Below this fraction of the reference length a joint is treated as degenerate: its frame
/// falls back to a fixed direction, so forces stay finite.
const DEGENERATE: f64 = 1e-9;

/// Kinematics of a joint at positions `x` (P, Q, R, S), reference length `h`.
#[inline]
pub fn kinematics(x: &JointNodes, h: f64) -> JointKinematics {
    let [xp, xq, xr, xs] = *x;
    let d = [
        0.5 * (xq[0] + xr[0] - xp[0] - xs[0]),
        0.5 * (xq[1] + xr[1] - xp[1] - xs[1]),
    ];
    let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let tt = if l > DEGENERATE * h {
        [d[0] / l, d[1] / l]
    } else {
        [1.0, 0.0]
    };
    let nn = [tt[1], -tt[0]];
    let w0 = [xs[0] - xp[0], xs[1] - xp[1]];
    let w1 = [xr[0] - xq[0], xr[1] - xq[1]];
    JointKinematics {
        l,
        tt,
        nn,
        o: [dot(w0, nn), dot(w1, nn)],
        s: [dot(w0, tt), dot(w1, tt)],
    }
}

#[inline]
fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// The law's result at one integration point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointTraction {
    /// Normal stress (Pa), tension-positive.
    pub sigma: f64,
    /// Shear stress (Pa), along `tt`.
    pub tau: f64,
    /// Damage after this evaluation (never below the committed damage).
    pub damage: f64,
    /// Mode indicator `(2/pi) atan2(d_II, d_I)` of the damage increment: 0 pure mode I,
    /// 1 pure mode II. The committed value is returned when the damage does not grow.
    pub mode_mix: f64,
    /// Secant shear stiffness `k_t = tau/s` after this evaluation (Pa/m): the smaller of the
    /// committed one and the law's; never increases.
    pub shear_secant: f64,
    /// Stored (recoverable) energy per unit area (J/m^2).
    pub stored: f64,
}

/// The traction law at one point: opening `o`, sliding `s`, the joint's constants `k`
/// (reference length, stiffness, peak opening, softening width), committed damage, mode
/// indicator and secant shear stiffness (`f64::INFINITY` before the first commit).
#[inline]
pub fn point_traction(
    mat: &JointMaterial,
    k: &JointConsts,
    soft: &SofteningConsts,
    o: f64,
    s: f64,
    damage_old: f64,
    mix_old: f64,
    shear_secant_old: f64,
) -> PointTraction {
    law::<true>(mat, k, soft, o, s, damage_old, mix_old, shear_secant_old)
}

/// The law; with `FULL = false` the mode indicator is not computed. An undamaged point
/// that stays before both peaks takes [`pre_peak_lane`] (the same operations, without the
/// softening quantities and without branches); every other point the general [`law_any`].
#[inline(always)]
fn law<const FULL: bool>(
    mat: &JointMaterial,
    k: &JointConsts,
    soft: &SofteningConsts,
    o: f64,
    s: f64,
    damage_old: f64,
    mix_old: f64,
    shear_secant_old: f64,
) -> PointTraction {
    if damage_old == 0.0 {
        let (pt, before_peaks) = pre_peak_lane(mat, k, o, s, mix_old, shear_secant_old);
        if before_peaks {
            return pt;
        }
    }
    law_any::<FULL>(mat, k, soft, o, s, damage_old, mix_old, shear_secant_old)
}

/// The law at an undamaged point, and whether it stays undamaged: false when the opening
/// passes `o_p` or the slip passes `s_p` (where [`law_any`] computes the damage). Where it
/// says true, its result is bit for bit that of [`law_any`]: with `D = 0` the damage terms
/// vanish exactly (`<o - o_p> = 0`, `<|s| - s_p> = 0`), so only the pre-peak curves remain.
/// Without branches (every quantity computed, the cases chosen by selects), so that a loop
/// over joints vectorises.
#[inline(always)]
pub(crate) fn pre_peak_lane(
    mat: &JointMaterial,
    k: &JointConsts,
    o: f64,
    s: f64,
    mix_old: f64,
    shear_secant_old: f64,
) -> (PointTraction, bool) {
    let abs_s = s.abs();
    let compr = o < 0.0;
    let sigma_compr = k.kn * o;
    let fs = if compr {
        mat.shear_strength(sigma_compr)
    } else {
        mat.cohesion
    };
    let s_p = if compr { k.slip_per_fs * fs } else { k.s_p0 };
    let before_peaks = !(o > k.o_p || abs_s > s_p);
    let inv_s_p = if compr { 1.0 / s_p } else { k.inv_s_p0 };
    let x = o * k.inv_o_p;
    let (sigma, psi_n) = if compr {
        (sigma_compr, 0.5 * sigma_compr * o)
    } else {
        (mat.ft * pre_peak(x), mat.ft * k.o_p * pre_peak_energy(x))
    };
    let k_law = fs * (2.0 - abs_s * inv_s_p) * inv_s_p;
    let shear_secant = k_law.min(shear_secant_old);
    let tau = shear_secant * s;
    let pt = PointTraction {
        sigma,
        tau,
        damage: 0.0,
        mode_mix: mix_old,
        shear_secant,
        stored: psi_n + 0.5 * tau * s,
    };
    (pt, before_peaks)
}

/// The general law (any damage, any branch). Kept out of line: in a force pass most points
/// take [`pre_peak_lane`], and the hot loop stays small.
#[inline(never)]
fn law_any<const FULL: bool>(
    mat: &JointMaterial,
    k: &JointConsts,
    soft: &SofteningConsts,
    o: f64,
    s: f64,
    damage_old: f64,
    mix_old: f64,
    shear_secant_old: f64,
) -> PointTraction {
    let abs_s = s.abs();
    let (sigma_compr, fs, s_p, inv_s_p, s_soft, d_ii) = if o < 0.0 {
        let sigma_compr = k.kn * o;
        let fs = mat.shear_strength(sigma_compr);
        let s_p = k.slip_per_fs * fs;
        // s_c - s_p = <G_II - (2/3) fs s_p>/(I_z fs)
        let s_soft = (mat.g_ii - 2.0 / 3.0 * fs * s_p).max(0.0) / (Z_INTEGRAL * fs);
        let d_ii = if s_soft > 0.0 {
            (abs_s - s_p).max(0.0) / s_soft
        } else if abs_s > s_p {
            1.0
        } else {
            0.0
        };
        (sigma_compr, fs, s_p, 1.0 / s_p, s_soft, d_ii)
    } else {
        // no compression: fs = c and the slip constants are the joint's precomputed ones
        let d_ii = (abs_s - k.s_p0).max(0.0) * soft.inv_s_soft0;
        (0.0, mat.cohesion, k.s_p0, k.inv_s_p0, soft.s_soft0, d_ii)
    };
    let d_i = (o - k.o_p).max(0.0) * soft.inv_o_soft;
    let d_kin = if d_ii == 0.0 {
        d_i
    } else {
        (d_i * d_i + d_ii * d_ii).sqrt()
    };
    let damage = d_kin.max(damage_old).min(1.0);
    let mode_mix = if FULL && d_kin > damage_old {
        std::f64::consts::FRAC_2_PI * d_ii.atan2(d_i)
    } else {
        mix_old
    };
    // Shear: the law's secant stiffness tau_law/|s| (2 fs/s_p at s = 0), capped by the
    // committed secant so that a rise of fs with compression never stiffens the joint again
    // (that would create energy: fs depends on sigma, so tau_law(s, sigma) has no potential).
    let (sigma, psi_n, zd) = if damage == 0.0 {
        if o < 0.0 {
            (sigma_compr, 0.5 * sigma_compr * o, 1.0)
        } else {
            let x = o * k.inv_o_p;
            (
                mat.ft * pre_peak(x),
                mat.ft * k.o_p * pre_peak_energy(x),
                1.0,
            )
        }
    } else {
        let zd = z(damage);
        let sigma = if o < 0.0 {
            sigma_compr
        } else {
            mat.ft * zd * o / (k.o_p + damage * soft.o_soft)
        };
        (sigma, 0.5 * sigma * o, zd)
    };
    let k_law = if damage == 0.0 {
        fs * (2.0 - abs_s * inv_s_p) * inv_s_p
    } else {
        fs * zd / (s_p + damage * s_soft)
    };
    let shear_secant = k_law.min(shear_secant_old);
    let tau = shear_secant * s;
    PointTraction {
        sigma,
        tau,
        damage,
        mode_mix,
        shear_secant,
        stored: psi_n + 0.5 * tau * s,
    }
}

/// Everything one evaluation of a joint produces.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointEval {
    /// Forces on the nodes P, Q, R, S (N).
    pub forces: [[f64; 2]; 4],
    /// Trial damage at the two points.
    pub damage: [f64; 2],
    /// Trial mode indicator at the two points.
    pub mode_mix: [f64; 2],
    /// Trial secant shear stiffness at the two points (Pa/m).
    pub shear_secant: [f64; 2],
    /// Per point k: `[A sigma, A tau, o, s]` at `4k..4k+4` (the energy accounting's work
    /// conjugates; `A = h t/2`).
    pub local: [f64; 8],
    /// Stored energy of the joint (J).
    pub stored: f64,
}

impl JointEval {
    /// Where [`evaluate_into`] writes: the fields of `self` (all but the stored energy, which
    /// it returns).
    #[inline(always)]
    pub(crate) fn out(&mut self) -> EvalOut<'_> {
        EvalOut {
            forces: &mut self.forces,
            damage: &mut self.damage,
            mode_mix: &mut self.mode_mix,
            shear_secant: &mut self.shear_secant,
            local: &mut self.local,
        }
    }
}

/// The committed history of one joint that a force evaluation reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointHistory {
    /// Damage at the two points.
    pub damage: [f64; 2],
    /// Mode indicator at the two points.
    pub mode_mix: [f64; 2],
    /// Secant shear stiffness at the two points (Pa/m); `f64::INFINITY` for a fresh joint.
    pub shear_secant: [f64; 2],
}

impl PointHistory {
    /// The history of a fresh joint: no damage, no shear softening yet.
    pub const FRESH: PointHistory = PointHistory {
        damage: [0.0; 2],
        mode_mix: [0.0; 2],
        shear_secant: [f64::INFINITY; 2],
    };
}

/// Evaluates one joint at positions `x` (P, Q, R, S): tractions, nodal forces, trial damage
/// and stored energy. `hist` is the committed history, `t` the thickness.
#[inline]
pub fn evaluate(
    mat: &JointMaterial,
    consts: &JointConsts,
    soft: &SofteningConsts,
    x: &JointNodes,
    hist: &PointHistory,
    t: f64,
) -> JointEval {
    evaluate_impl::<true>(
        mat,
        consts,
        soft,
        x,
        hist.damage,
        hist.mode_mix,
        hist.shear_secant,
        t,
    )
}

/// The nodal forces (P, Q, R, S) only, as [`evaluate`] computes them (bit for bit).
#[inline]
pub fn evaluate_forces(
    mat: &JointMaterial,
    consts: &JointConsts,
    soft: &SofteningConsts,
    x: &JointNodes,
    damage_old: [f64; 2],
    shear_secant_old: [f64; 2],
    t: f64,
) -> [[f64; 2]; 4] {
    evaluate_impl::<false>(
        mat,
        consts,
        soft,
        x,
        damage_old,
        [0.0; 2],
        shear_secant_old,
        t,
    )
    .forces
}

#[inline(always)]
pub(crate) fn evaluate_impl<const FULL: bool>(
    mat: &JointMaterial,
    consts: &JointConsts,
    soft: &SofteningConsts,
    x: &JointNodes,
    damage_old: [f64; 2],
    mix_old: [f64; 2],
    shear_secant_old: [f64; 2],
    t: f64,
) -> JointEval {
    let mut out = JointEval::default();
    out.stored = evaluate_into::<FULL, false>(
        mat,
        consts,
        soft,
        x,
        [damage_old, mix_old, shear_secant_old],
        t,
        [0.0; 2],
        out.out(),
    );
    out
}

/// [`evaluate`] of a prestressed joint: the law at the opening `o + o0` and the sliding
/// `s + s0` with `off = [o0, s0]` ([`crate::JointSet::set_initial_tractions`]); the frame
/// terms of the forces keep the kinematic `o`, `s` (the offsets are constants of the joint's
/// frame). The local work conjugates hold `o + o0`, `s + s0`.
#[inline]
pub fn evaluate_offset(
    mat: &JointMaterial,
    consts: &JointConsts,
    soft: &SofteningConsts,
    x: &JointNodes,
    hist: &PointHistory,
    t: f64,
    off: [f64; 2],
) -> JointEval {
    let mut out = JointEval::default();
    out.stored = evaluate_into::<true, true>(
        mat,
        consts,
        soft,
        x,
        [hist.damage, hist.mode_mix, hist.shear_secant],
        t,
        off,
        out.out(),
    );
    out
}

/// Where [`evaluate_into`] writes a joint's results (the fields of [`JointEval`]).
pub(crate) struct EvalOut<'a> {
    pub(crate) forces: &'a mut [[f64; 2]; 4],
    pub(crate) damage: &'a mut [f64; 2],
    pub(crate) mode_mix: &'a mut [f64; 2],
    pub(crate) shear_secant: &'a mut [f64; 2],
    pub(crate) local: &'a mut [f64; 8],
}

/// One joint's evaluation written in place (no [`JointEval`] in between); `old` is the
/// committed damage, mode indicator and shear secant per point. With `OFF`, the law sees the
/// opening and sliding shifted by `off = [o0, s0]` (a prestressed joint; without `OFF` the
/// offsets are not read). Returns the stored energy.
#[inline(always)]
pub(crate) fn evaluate_into<const FULL: bool, const OFF: bool>(
    mat: &JointMaterial,
    consts: &JointConsts,
    soft: &SofteningConsts,
    x: &JointNodes,
    old: [[f64; 2]; 3],
    t: f64,
    off: [f64; 2],
    out: EvalOut<'_>,
) -> f64 {
    let [damage_old, mix_old, shear_secant_old] = old;
    evaluate_with::<OFF>(consts.h, x, t, off, out, |i, o, s| {
        law::<FULL>(
            mat,
            consts,
            soft,
            o,
            s,
            damage_old[i],
            mix_old[i],
            shear_secant_old[i],
        )
    })
}

/// The evaluation of a joint of reference length `h` whose point `i` (0 or 1) at opening `o`
/// and sliding `s` has the traction `law(i, o, s)`: the kinematics, the forces and the work
/// conjugates into `out`; returns the stored energy. [`evaluate_into`] with the joint's law;
/// the vectorised pass of undamaged joints with [`pre_peak_lane`].
#[inline(always)]
pub(crate) fn evaluate_with<const OFF: bool>(
    h: f64,
    x: &JointNodes,
    t: f64,
    off: [f64; 2],
    out: EvalOut<'_>,
    mut law: impl FnMut(usize, f64, f64) -> PointTraction,
) -> f64 {
    let k = kinematics(x, h);
    // Reference area: the forces are then exactly -d(A psi)/dx for a frozen history.
    let area = 0.5 * h * t;
    let mut stored = 0.0;
    let mut frame = 0.0;
    let mut q = [[0.0; 2]; 2];
    let mut local = [0.0; 8];
    for i in 0..2 {
        let (o, sl) = if OFF {
            (k.o[i] + off[0], k.s[i] + off[1])
        } else {
            (k.o[i], k.s[i])
        };
        let pt = law(i, o, sl);
        out.damage[i] = pt.damage;
        out.mode_mix[i] = pt.mode_mix;
        out.shear_secant[i] = pt.shear_secant;
        stored += area * pt.stored;
        let (a_sigma, a_tau) = (area * pt.sigma, area * pt.tau);
        local[4 * i] = a_sigma;
        local[4 * i + 1] = a_tau;
        local[4 * i + 2] = o;
        local[4 * i + 3] = sl;
        q[i] = [
            a_sigma * k.nn[0] + a_tau * k.tt[0],
            a_sigma * k.nn[1] + a_tau * k.tt[1],
        ];
        frame += a_tau * k.o[i] - a_sigma * k.s[i];
    }
    *out.local = local;
    let c = 0.5 * frame / k.l.max(DEGENERATE * h);
    let cn = [c * k.nn[0], c * k.nn[1]];
    // P = 0, Q = 1, R = 2, S = 3
    *out.forces = [
        [q[0][0] + cn[0], q[0][1] + cn[1]],
        [q[1][0] - cn[0], q[1][1] - cn[1]],
        [-q[1][0] - cn[0], -q[1][1] - cn[1]],
        [-q[0][0] + cn[0], -q[0][1] + cn[1]],
    ];
    stored
}

/// A joint's dissipation in a step: the step's work by the trapezoidal rule on `(A sigma, o)`
/// and `(A tau, s)`, less the change of stored energy. `committed` is the committed opening
/// and sliding, `A sigma`, shear secants and stored energy (`A tau = A k_t s` is computed
/// again: the same bits as the law's); `new` is the evaluation's `[A sigma, A tau, o, s]` per
/// point, `stored` its stored energy, `area` the points' area `A`.
#[inline(always)]
pub(crate) fn step_dissipation(
    committed: ([f64; 4], [f64; 2], [f64; 2], f64),
    new: &[f64; 8],
    stored: f64,
    area: f64,
) -> f64 {
    let (u_a, normal_a, k_a, stored_a) = committed;
    let mut dw = 0.0;
    for p in 0..2 {
        let (o_a, s_a) = (u_a[2 * p], u_a[2 * p + 1]);
        let tau_a = area * (k_a[p] * s_a);
        let q = 4 * p;
        dw += 0.5 * (normal_a[p] + new[q]) * (new[q + 2] - o_a)
            + 0.5 * (tau_a + new[q + 1]) * (new[q + 3] - s_a);
    }
    dw - (stored - stored_a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::JointMaterialInput;

    fn mat() -> JointMaterial {
        JointMaterialInput {
            tensile_strength: 5e6,
            cohesion: 8e6,
            friction_angle_deg: 35.0,
            fracture_energy_i: 50.0,
            fracture_energy_ii: 200.0,
            penalty_normal: 3e11,
            penalty_tangential: 2e11,
        }
        .validate(0)
        .unwrap()
    }

    /// A rotated, translated and deformed joint of reference length 0.02 m.
    fn config(scale: f64) -> JointNodes {
        let (c, s) = (0.6f64.cos(), 0.6f64.sin());
        let local = [
            [0.0, 0.0],
            [0.02, 0.0],
            [0.02 + 0.3e-6 * scale, -1.1e-6 * scale],
            [-0.7e-6 * scale, -0.4e-6 * scale],
        ];
        local.map(|p| [1.5 + c * p[0] - s * p[1], -2.0 + s * p[0] + c * p[1]])
    }

    #[test]
    fn nodal_forces_are_the_work_conjugates_of_opening_and_sliding() {
        // With sigma, tau frozen, f_a = -A (sigma grad o + tau grad s); compare against central
        // differences of o and s (relative error O(eps^2) ~ 1e-8 of |f|).
        let m = mat();
        let h = 0.02;
        let x = config(3.0);
        let e = evaluate(
            &m,
            &m.consts(h),
            &m.softening_consts(h),
            &x,
            &PointHistory {
                damage: [0.2, 0.3],
                ..PointHistory::FRESH
            },
            1.0,
        );
        let area = 0.5 * h;
        let fmax = e
            .forces
            .iter()
            .flatten()
            .fold(0.0f64, |a, v| a.max(v.abs()));
        for a in 0..4 {
            for d in 0..2 {
                let eps = 1e-9;
                let mut xp = x;
                xp[a][d] += eps;
                let mut xm = x;
                xm[a][d] -= eps;
                let (kp, km) = (kinematics(&xp, h), kinematics(&xm, h));
                let mut f = 0.0;
                for i in 0..2 {
                    let sigma = e.local[4 * i] / area;
                    let tau = e.local[4 * i + 1] / area;
                    let dodx = (kp.o[i] - km.o[i]) / (2.0 * eps);
                    let dsdx = (kp.s[i] - km.s[i]) / (2.0 * eps);
                    f -= area * (sigma * dodx + tau * dsdx);
                }
                assert!(
                    (f - e.forces[a][d]).abs() < 1e-6 * fmax,
                    "node {a} dof {d}: {f} vs {}",
                    e.forces[a][d]
                );
            }
        }
    }

    #[test]
    fn pre_peak_fast_path_is_the_general_law_bit_for_bit() {
        // undamaged points over openings and slips on both sides of the peaks (tension and
        // compression, s_p growing with compression), fresh and softened shear secants: where
        // the fast path answers, every field equals the general law's bit for bit
        let m = mat();
        let (k, soft) = (m.consts(0.02), m.softening_consts(0.02));
        let bits = |p: &PointTraction| {
            [
                p.sigma,
                p.tau,
                p.damage,
                p.mode_mix,
                p.shear_secant,
                p.stored,
            ]
            .map(f64::to_bits)
        };
        let (mut taken, mut declined) = (0, 0);
        let mut r = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            r ^= r << 13;
            r ^= r >> 7;
            r ^= r << 17;
            (r >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for n in 0..20_000 {
            let o = 3.0 * k.o_p * rnd();
            let s = 3.0 * k.s_p0 * rnd();
            let secant = if n % 2 == 0 {
                f64::INFINITY
            } else {
                (1.0 + rnd()) * m.cohesion / k.s_p0
            };
            let mix = 0.5 * (1.0 + rnd());
            match pre_peak_lane(&m, &k, o, s, mix, secant) {
                (fast, true) => {
                    taken += 1;
                    let any = law_any::<true>(&m, &k, &soft, o, s, 0.0, mix, secant);
                    assert_eq!(bits(&fast), bits(&any), "o = {o:e}, s = {s:e}");
                }
                (_, false) => declined += 1,
            }
        }
        // both cases occur (the fast path is not vacuous, the general law is reached)
        assert!(
            taken > 2_000 && declined > 2_000,
            "{taken} taken, {declined} declined"
        );
    }

    /// A fresh joint of length 0.02 m and unit thickness evaluated at `x`.
    fn fresh(m: &JointMaterial, x: &JointNodes) -> JointEval {
        let h = 0.02;
        evaluate(
            m,
            &m.consts(h),
            &m.softening_consts(h),
            x,
            &PointHistory::FRESH,
            1.0,
        )
    }

    #[test]
    fn rigid_motion_of_the_reference_joint_gives_no_force() {
        let m = mat();
        let x = config(0.0);
        let e = fresh(&m, &x);
        let fmax = e
            .forces
            .iter()
            .flatten()
            .fold(0.0f64, |a, v| a.max(v.abs()));
        // Openings are round-off (1e-16 m) times p/h: forces below 1e-12 * ft * l.
        assert!(fmax < 1e-12 * 5e6 * 0.02, "{fmax}");
    }

    #[test]
    fn degenerate_joint_stays_finite() {
        let m = mat();
        let x = [[0.0, 0.0]; 4];
        let e = fresh(&m, &x);
        assert!(e.forces.iter().flatten().all(|v| v.is_finite()));
        assert!(e.stored.is_finite());
    }
}
