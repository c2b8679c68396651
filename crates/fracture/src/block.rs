//! The force pass's kernel for [`LANES`] joints at once: the joints of a block evaluated side
//! by side in lane arrays (`[f64; LANES]`), so that the compiler emits packed instructions
//! (two lanes per SSE2 instruction, four with AVX2).
//!
//! It covers the common case only: an intact joint, undamaged at both points, whose points
//! both stay before their peaks ([`crate::joint`]'s pre-peak fast path, `o <= o_p` and
//! `|s| <= s_p`). Both branches of the law (compression `o < 0` and tension) are computed for
//! every lane and one is selected, with the same IEEE operations in the same order as the
//! scalar code: kinematics, the pre-peak law at both points, forces, stored energy and the
//! books advanced by the trapezoidal rule
//!
//! ```text
//! dW = sum_k [ (A sigma_k + A sigma_k_old)/2 (o_k - o_k_old) + (A tau_k + A tau_k_old)/2 (s_k - s_k_old) ]
//! work += dW,  dissipated += dW - (stored - stored_old)
//! ```
//!
//! so each result is bit for bit the scalar pass's (no fused multiply-add: Rust never
//! contracts `a * b + c`). A lane outside the fast path (broken, damaged, past a peak) is
//! left to the scalar code, which the caller runs for it.

use crate::joint::DEGENERATE;
use crate::material::{JointConsts, JointMaterial};
use crate::state::JointHistory;

/// Joints per block.
pub(crate) const LANES: usize = 4;

/// One block's inputs: joint data, committed histories and intact flags of [`LANES`]
/// consecutive joints.
pub(crate) struct BlockIn<'a> {
    pub(crate) nodes: &'a [[u32; 4]; LANES],
    pub(crate) consts: &'a [JointConsts; LANES],
    pub(crate) material: &'a [u32; LANES],
    pub(crate) old: &'a [JointHistory; LANES],
    pub(crate) intact: &'a [bool; LANES],
}

/// Evaluates a block of joints at positions `x` (thickness `t`). For each lane in the fast
/// path it writes the forces and the trial history (what the scalar pass writes) and sets the
/// lane's entry of the returned mask; the other lanes' outputs are not touched.
#[inline(always)]
pub(crate) fn pre_peak_block(
    materials: &[JointMaterial],
    x: &[[f64; 2]],
    t: f64,
    b: BlockIn<'_>,
    f: &mut [[[f64; 2]; 4]; LANES],
    h: &mut [JointHistory; LANES],
) -> [bool; LANES] {
    // a block with a broken or damaged joint goes to the scalar code whole (it is rare in a
    // loaded specimen; in a softening one such blocks would pay for both kernels)
    if !(0..LANES).all(|l| b.intact[l] && b.old[l].damage == [0.0; 2]) {
        return [false; LANES];
    }
    // gather into lane arrays (the loads are scalar: the nodes are anywhere)
    let mut xc = [[0.0; LANES]; 8];
    let (mut hh, mut kn, mut o_p, mut inv_o_p) =
        ([0.0; LANES], [0.0; LANES], [0.0; LANES], [0.0; LANES]);
    let (mut slip_per_fs, mut s_p0, mut inv_s_p0) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
    let (mut ft, mut coh, mut tan_phi) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
    let mut sec_old = [[0.0; LANES]; 2];
    let mut last = [[0.0; LANES]; 8];
    let (mut work_old, mut stored_old, mut diss_old) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
    for l in 0..LANES {
        for (k, &nd) in b.nodes[l].iter().enumerate() {
            let p = x[nd as usize];
            xc[2 * k][l] = p[0];
            xc[2 * k + 1][l] = p[1];
        }
        let c = &b.consts[l];
        (hh[l], kn[l], o_p[l], inv_o_p[l]) = (c.h, c.kn, c.o_p, c.inv_o_p);
        (slip_per_fs[l], s_p0[l], inv_s_p0[l]) = (c.slip_per_fs, c.s_p0, c.inv_s_p0);
        let m = &materials[b.material[l] as usize];
        (ft[l], coh[l], tan_phi[l]) = (m.ft, m.cohesion, m.tan_phi);
        let o = &b.old[l];
        for p in 0..2 {
            sec_old[p][l] = o.shear_secant[p];
        }
        for q in 0..8 {
            last[q][l] = o.last[q];
        }
        (work_old[l], stored_old[l], diss_old[l]) = (o.work, o.stored, o.dissipated);
    }
    // the evaluation on lane arrays, in the scalar code's order
    let xc = xc.map(F);
    let (hh, kn, o_p, inv_o_p) = (F(hh), F(kn), F(o_p), F(inv_o_p));
    let (slip_per_fs, s_p0, inv_s_p0) = (F(slip_per_fs), F(s_p0), F(inv_s_p0));
    let (ft, coh, tan_phi) = (F(ft), F(coh), F(tan_phi));
    let half = F::splat(0.5);
    let zero = F::splat(0.0);
    // kinematics (joint::kinematics)
    let d = [
        half * (xc[2] + xc[4] - xc[0] - xc[6]),
        half * (xc[3] + xc[5] - xc[1] - xc[7]),
    ];
    let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let small = F::splat(DEGENERATE) * hh;
    let regular = len.gt(small);
    let tt = [
        F::select(regular, d[0] / len, F::splat(1.0)),
        F::select(regular, d[1] / len, zero),
    ];
    let nn = [tt[1], -tt[0]];
    let w = [
        [xc[6] - xc[0], xc[7] - xc[1]],
        [xc[4] - xc[2], xc[5] - xc[3]],
    ];
    let area = half * hh * F::splat(t);
    let mut st = zero;
    let mut frame = zero;
    let mut q = [[zero; 2]; 2];
    let mut ok = M([true; LANES]);
    let mut sec = [zero; 2];
    let mut loc = [zero; 8];
    for i in 0..2 {
        let o = w[i][0] * nn[0] + w[i][1] * nn[1];
        let s = w[i][0] * tt[0] + w[i][1] * tt[1];
        // the pre-peak law (joint::pre_peak_point), both branches, one selected
        let abs_s = s.abs();
        let compr = o.lt(zero);
        let sigma_compr = kn * o;
        let fs = F::select(compr, coh + (-sigma_compr).max(zero) * tan_phi, coh);
        let s_p = F::select(compr, slip_per_fs * fs, s_p0);
        ok = ok.and(o.gt(o_p).or(abs_s.gt(s_p)).not());
        let inv_s_p = F::select(compr, F::splat(1.0) / s_p, inv_s_p0);
        let xo = o * inv_o_p;
        // pre_peak(x) = x (2 - x), pre_peak_energy(x) = x x (1 - x/3)
        let sigma_t = ft * (xo * (F::splat(2.0) - xo));
        let psi_t = ft * o_p * (xo * xo * (F::splat(1.0) - xo / F::splat(3.0)));
        let sigma = F::select(compr, sigma_compr, sigma_t);
        let psi_n = F::select(compr, half * sigma_compr * o, psi_t);
        let k_law = fs * (F::splat(2.0) - abs_s * inv_s_p) * inv_s_p;
        let shear_secant = k_law.min(F(sec_old[i]));
        let tau = shear_secant * s;
        let pt_stored = psi_n + half * tau * s;
        // joint::evaluate_into
        sec[i] = shear_secant;
        st = st + area * pt_stored;
        let (a_sigma, a_tau) = (area * sigma, area * tau);
        loc[4 * i] = a_sigma;
        loc[4 * i + 1] = a_tau;
        loc[4 * i + 2] = o;
        loc[4 * i + 3] = s;
        q[i] = [
            a_sigma * nn[0] + a_tau * tt[0],
            a_sigma * nn[1] + a_tau * tt[1],
        ];
        frame = frame + (a_tau * o - a_sigma * s);
    }
    let c = half * frame / len.max(small);
    let cn = [c * nn[0], c * nn[1]];
    let fo = [
        q[0][0] + cn[0],
        q[0][1] + cn[1],
        q[1][0] - cn[0],
        q[1][1] - cn[1],
        -q[1][0] - cn[0],
        -q[1][1] - cn[1],
        -q[0][0] + cn[0],
        -q[0][1] + cn[1],
    ];
    // the books (pass::trial_pass)
    let mut dw = zero;
    for p in 0..2 {
        let r = 4 * p;
        let (a, b) = (&last[r..r + 4], &loc[r..r + 4]);
        let (a, b) = (
            [F(a[0]), F(a[1]), F(a[2]), F(a[3])],
            [b[0], b[1], b[2], b[3]],
        );
        dw = dw + (half * (a[0] + b[0]) * (b[2] - a[2]) + half * (a[1] + b[1]) * (b[3] - a[3]));
    }
    let work = F(work_old) + dw;
    let diss = F(diss_old) + (dw - (st - F(stored_old)));
    let stored = st;
    let fast = ok.0;
    // write the fast lanes
    for l in 0..LANES {
        if !fast[l] {
            continue;
        }
        for k in 0..4 {
            f[l][k] = [fo[2 * k].0[l], fo[2 * k + 1].0[l]];
        }
        let hn = &mut h[l];
        hn.damage = [0.0; 2];
        hn.mode_mix = b.old[l].mode_mix;
        hn.shear_secant = [sec[0].0[l], sec[1].0[l]];
        for k in 0..8 {
            hn.last[k] = loc[k].0[l];
        }
        hn.work = work.0[l];
        hn.stored = stored.0[l];
        hn.dissipated = diss.0[l];
    }
    fast
}

/// [`LANES`] values, one per joint of a block. Each operation is the scalar one lane by lane
/// (so bit for bit the scalar result); the compiler packs the lanes.
#[derive(Clone, Copy)]
struct F([f64; LANES]);

/// A lane mask.
#[derive(Clone, Copy)]
struct M([bool; LANES]);

impl F {
    #[inline(always)]
    fn splat(v: f64) -> F {
        F([v; LANES])
    }
    #[inline(always)]
    fn map(self, g: impl Fn(f64) -> f64) -> F {
        F(self.0.map(g))
    }
    #[inline(always)]
    fn zip(self, o: F, g: impl Fn(f64, f64) -> f64) -> F {
        let mut r = [0.0; LANES];
        for l in 0..LANES {
            r[l] = g(self.0[l], o.0[l]);
        }
        F(r)
    }
    #[inline(always)]
    fn cmp(self, o: F, g: impl Fn(f64, f64) -> bool) -> M {
        let mut r = [false; LANES];
        for l in 0..LANES {
            r[l] = g(self.0[l], o.0[l]);
        }
        M(r)
    }
    #[inline(always)]
    fn sqrt(self) -> F {
        self.map(f64::sqrt)
    }
    #[inline(always)]
    fn abs(self) -> F {
        self.map(f64::abs)
    }
    #[inline(always)]
    fn max(self, o: F) -> F {
        self.zip(o, f64::max)
    }
    #[inline(always)]
    fn min(self, o: F) -> F {
        self.zip(o, f64::min)
    }
    #[inline(always)]
    fn lt(self, o: F) -> M {
        self.cmp(o, |a, b| a < b)
    }
    #[inline(always)]
    fn gt(self, o: F) -> M {
        self.cmp(o, |a, b| a > b)
    }
    /// `a` where `m`, else `b`.
    #[inline(always)]
    fn select(m: M, a: F, b: F) -> F {
        let mut r = [0.0; LANES];
        for l in 0..LANES {
            r[l] = if m.0[l] { a.0[l] } else { b.0[l] };
        }
        F(r)
    }
}

impl M {
    #[inline(always)]
    fn and(self, o: M) -> M {
        let mut r = [false; LANES];
        for l in 0..LANES {
            r[l] = self.0[l] & o.0[l];
        }
        M(r)
    }
    #[inline(always)]
    fn or(self, o: M) -> M {
        let mut r = [false; LANES];
        for l in 0..LANES {
            r[l] = self.0[l] | o.0[l];
        }
        M(r)
    }
    #[inline(always)]
    fn not(self) -> M {
        M(self.0.map(|v| !v))
    }
}

macro_rules! binop {
    ($tr:ident, $f:ident, $op:tt) => {
        impl std::ops::$tr for F {
            type Output = F;
            #[inline(always)]
            fn $f(self, o: F) -> F {
                self.zip(o, |a, b| a $op b)
            }
        }
    };
}
binop!(Add, add, +);
binop!(Sub, sub, -);
binop!(Mul, mul, *);
binop!(Div, div, /);

impl std::ops::Neg for F {
    type Output = F;
    #[inline(always)]
    fn neg(self) -> F {
        self.map(|a| -a)
    }
}
