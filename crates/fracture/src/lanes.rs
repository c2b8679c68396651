//! The joint pass over blocks of [`LANES`] intact, undamaged joints at once.
//!
//! Most joints of a specimen are intact and undamaged, and stay before both peaks of the law
//! in a step. For a block of them the pass gathers the inputs lane by lane (structure of
//! arrays: node positions, constants, strengths, committed history), then runs the very
//! operations of the scalar pass ([`crate::joint::evaluate_with`] with the branch-free
//! [`crate::joint::pre_peak_lane`], and the step's dissipation) for every lane in one loop.
//! That loop has no branch (the law's cases are selects), so the compiler turns it into
//! vector instructions; the caller runs it under `pulp`'s run-time dispatch, which compiles it
//! for the widest instruction set the processor has (AVX2 on x86-64, NEON on ARM) without
//! `unsafe` in this crate.
//!
//! Each lane computes exactly what the scalar pass computes for its joint, in the same order,
//! with IEEE operations that vector units round alike (no fused multiply-add: Rust does not
//! contract), so the results are bit for bit those of the scalar pass. A block where a lane
//! leaves the pre-peak branch (its opening or slip passes a peak) reports it, and the caller
//! evaluates that block joint by joint instead.

use crate::joint::{JointEval, evaluate_with, pre_peak_lane, step_dissipation};
use crate::material::JointMaterial;

/// Joints per block: two AVX2 vectors of `f64`, one AVX-512 vector.
pub(crate) const LANES: usize = 8;

/// One value per lane.
pub(crate) type Lanes = [f64; LANES];

/// What a block of joints reads, lane by lane.
#[derive(Default)]
pub(crate) struct BlockIn {
    /// Node positions: `x[node][axis][lane]`, nodes P, Q, R, S.
    pub(crate) x: [[Lanes; 2]; 4],
    /// The reference length `h`.
    pub(crate) h: Lanes,
    /// The material's tensile strength, cohesion, `tan(phi)` and penalties `p`, `p_t`.
    pub(crate) ft: Lanes,
    pub(crate) cohesion: Lanes,
    pub(crate) tan_phi: Lanes,
    pub(crate) p: Lanes,
    pub(crate) p_t: Lanes,
    /// The committed history: shear secants, `[o, s]` per point, `A sigma` per point, stored
    /// and dissipated energy.
    pub(crate) secant: [Lanes; 2],
    pub(crate) local: [Lanes; 4],
    pub(crate) normal: [Lanes; 2],
    pub(crate) stored: Lanes,
    pub(crate) dissipated: Lanes,
}

impl BlockIn {
    /// The node positions P, Q, R, S of lane `l`.
    #[inline(always)]
    fn nodes(&self, l: usize) -> [[f64; 2]; 4] {
        std::array::from_fn(|n| [self.x[n][0][l], self.x[n][1][l]])
    }
}

/// What a block of joints produces, lane by lane.
#[derive(Default)]
pub(crate) struct BlockOut {
    /// Nodal forces: `forces[node][axis][lane]`.
    pub(crate) forces: [[Lanes; 2]; 4],
    /// The new history (the damage and mode indicators stay 0).
    pub(crate) secant: [Lanes; 2],
    pub(crate) local: [Lanes; 4],
    pub(crate) normal: [Lanes; 2],
    pub(crate) stored: Lanes,
    pub(crate) dissipated: Lanes,
}

/// Evaluates a block of intact, undamaged joints of thickness `th` into `out`. True when
/// every point of every lane stayed before both peaks: only then is `out` the law's result
/// (the caller otherwise evaluates the block joint by joint, and `out` is discarded).
#[inline(always)]
pub(crate) fn pre_peak_block(b: &BlockIn, th: f64, out: &mut BlockOut) -> bool {
    let mut all = true;
    for l in 0..LANES {
        let xs = b.nodes(l);
        // the fracture energies do not enter the pre-peak law
        let mat = JointMaterial {
            ft: b.ft[l],
            cohesion: b.cohesion[l],
            tan_phi: b.tan_phi[l],
            g_i: 0.0,
            g_ii: 0.0,
            p: b.p[l],
            p_t: b.p_t[l],
        };
        // the joint's constants, derived here as the scalar pass derives them
        let k = mat.consts(b.h[l]);
        let secant_old = [b.secant[0][l], b.secant[1][l]];
        let mut e = JointEval::default();
        let mut before_peaks = true;
        let stored = evaluate_with::<false>(k.h, &xs, th, [0.0; 2], e.out(), |i, o, s| {
            let (pt, ok) = pre_peak_lane(&mat, &k, o, s, 0.0, secant_old[i]);
            before_peaks &= ok;
            pt
        });
        let loc = e.local;
        all &= before_peaks;
        let u_a = [b.local[0][l], b.local[1][l], b.local[2][l], b.local[3][l]];
        let committed = (
            u_a,
            [b.normal[0][l], b.normal[1][l]],
            secant_old,
            b.stored[l],
        );
        let area = 0.5 * k.h * th;
        out.dissipated[l] = b.dissipated[l] + step_dissipation(committed, &loc, stored, area);
        for (n, f) in e.forces.iter().enumerate() {
            out.forces[n][0][l] = f[0];
            out.forces[n][1][l] = f[1];
        }
        for (p, kp) in e.shear_secant.iter().enumerate() {
            out.secant[p][l] = *kp;
        }
        for (c, u) in [loc[2], loc[3], loc[6], loc[7]].iter().enumerate() {
            out.local[c][l] = *u;
        }
        out.normal[0][l] = loc[0];
        out.normal[1][l] = loc[4];
        out.stored[l] = stored;
    }
    all
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::joint::evaluate_into;
    use crate::material::{JointConsts, JointMaterialInput};

    /// A reproducible number in [-1, 1) (SplitMix64 of a counter).
    fn r(state: &mut u64) -> f64 {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        2.0 * (z >> 11) as f64 / (1u64 << 53) as f64 - 1.0
    }

    /// The material of lane `l`: strengths and penalties differ from lane to lane (as the
    /// joints of a heterogeneous specimen).
    fn material(l: usize) -> JointMaterial {
        let f = 1.0 + 0.1 * l as f64;
        JointMaterialInput {
            tensile_strength: 5e6 * f,
            cohesion: 8e6 / f,
            friction_angle_deg: 35.0,
            fracture_energy_i: 50.0,
            fracture_energy_ii: 200.0,
            penalty_normal: 3e11 * f,
            penalty_tangential: 2e11 / f,
        }
        .validate(0)
        .unwrap()
    }

    /// A block of joints of lengths about 1 mm, turned and moved at random, opened (or
    /// closed) and slid by up to `reach` times the peak opening and slip; committed histories
    /// at random, half of the secants still infinite.
    fn block(seed: u64, reach: f64) -> (BlockIn, [JointConsts; LANES]) {
        let mut s = seed;
        let mut b = BlockIn::default();
        let mut ks = [material(0).consts(1.0); LANES];
        for l in 0..LANES {
            let m = material(l);
            let h = 1e-3 * (1.0 + 0.5 * r(&mut s));
            let k = m.consts(h);
            ks[l] = k;
            let (a, c) = (3.0 * r(&mut s), [r(&mut s), r(&mut s)]);
            let (tt, nn) = ([a.cos(), a.sin()], [a.sin(), -a.cos()]);
            // opening and sliding of the two points, within reach of the peaks
            let w: [[f64; 2]; 2] = std::array::from_fn(|_| {
                let (o, sl) = (reach * k.o_p * r(&mut s), reach * k.s_p0 * r(&mut s));
                [o * nn[0] + sl * tt[0], o * nn[1] + sl * tt[1]]
            });
            let p = c;
            let q = [c[0] + h * tt[0], c[1] + h * tt[1]];
            let xs = [
                p,
                q,
                [q[0] + w[1][0], q[1] + w[1][1]],
                [p[0] + w[0][0], p[1] + w[0][1]],
            ];
            for (n, xn) in xs.iter().enumerate() {
                b.x[n][0][l] = xn[0];
                b.x[n][1][l] = xn[1];
            }
            b.h[l] = h;
            (b.ft[l], b.cohesion[l], b.tan_phi[l]) = (m.ft, m.cohesion, m.tan_phi);
            (b.p[l], b.p_t[l]) = (m.p, m.p_t);
            for p in 0..2 {
                b.secant[p][l] = if l % 2 == 0 {
                    f64::INFINITY
                } else {
                    1e14 * (1.5 + r(&mut s))
                };
                b.normal[p][l] = 1e3 * r(&mut s);
            }
            for q in 0..4 {
                b.local[q][l] = 1e-6 * r(&mut s);
            }
            (b.stored[l], b.dissipated[l]) = (1e-3 * (1.0 + r(&mut s)), 1e-4 * (1.0 + r(&mut s)));
        }
        (b, ks)
    }

    /// Thickness of the test joints.
    const TH: f64 = 0.01;

    /// [`block`], and the block evaluated as the pass runs it (compiled for the processor's
    /// vectors): its result and whether every lane stayed before the peaks.
    fn run_block(seed: u64, reach: f64) -> (BlockIn, [JointConsts; LANES], BlockOut, bool) {
        let (b, ks) = block(seed, reach);
        let mut o = BlockOut::default();
        let ok = pulp::Arch::new().dispatch(|| pre_peak_block(&b, TH, &mut o));
        (b, ks, o, ok)
    }

    #[test]
    fn a_block_is_the_scalar_pass_bit_for_bit() {
        let (th, blocks) = (TH, 200);
        for seed in 0..blocks {
            // the reference joint by joint, without the vectors
            let (b, ks, o, ok) = run_block(seed, 0.95);
            assert!(ok, "seed {seed}: a lane passed a peak");
            for (l, k) in ks.iter().enumerate() {
                let xs = b.nodes(l);
                let m = material(l);
                let soft = m.softening_consts(k.h);
                let secant = [b.secant[0][l], b.secant[1][l]];
                let mut e = JointEval::default();
                let stored = evaluate_into::<true, false>(
                    &m,
                    k,
                    &soft,
                    &xs,
                    [[0.0; 2], [0.0; 2], secant],
                    th,
                    [0.0; 2],
                    e.out(),
                );
                let (f, d, mix, kb, loc) =
                    (e.forces, e.damage, e.mode_mix, e.shear_secant, e.local);
                assert_eq!(
                    (d, mix),
                    ([0.0; 2], [0.0; 2]),
                    "seed {seed} lane {l}: damaged"
                );
                let committed = (
                    [b.local[0][l], b.local[1][l], b.local[2][l], b.local[3][l]],
                    [b.normal[0][l], b.normal[1][l]],
                    secant,
                    b.stored[l],
                );
                let area = 0.5 * k.h * th;
                let diss = b.dissipated[l] + step_dissipation(committed, &loc, stored, area);
                let lane = |a: [[Lanes; 2]; 4]| -> Vec<u64> {
                    a.iter()
                        .flat_map(|n| [n[0][l].to_bits(), n[1][l].to_bits()])
                        .collect()
                };
                let bits = |v: &[f64]| -> Vec<u64> { v.iter().map(|x| x.to_bits()).collect() };
                let scalar: Vec<u64> = f.iter().flat_map(|v| bits(v)).collect();
                assert_eq!(lane(o.forces), scalar, "seed {seed} lane {l}: forces");
                let got = [
                    o.secant[0][l],
                    o.secant[1][l],
                    o.local[0][l],
                    o.local[1][l],
                    o.local[2][l],
                    o.local[3][l],
                    o.normal[0][l],
                    o.normal[1][l],
                    o.stored[l],
                    o.dissipated[l],
                ];
                let want = [
                    kb[0], kb[1], loc[2], loc[3], loc[6], loc[7], loc[0], loc[4], stored, diss,
                ];
                assert_eq!(bits(&got), bits(&want), "seed {seed} lane {l}: history");
                assert!(o.forces[0][0][l] != 0.0 || o.forces[0][1][l] != 0.0);
            }
        }
        fdem_figures::record_part(
            146,
            1,
            format!(
                "{} joints before their peaks: identical",
                blocks as usize * LANES
            ),
        );
    }

    #[test]
    fn a_lane_past_a_peak_sends_the_block_to_the_scalar_pass() {
        let mut past = 0;
        for seed in 0..200 {
            // openings and slips up to 1.03 times the peaks: some blocks have a lane past one
            let (b, ks, _, ok) = run_block(seed, 1.03);
            // the scalar law's own verdict, point by point
            let beyond = (0..LANES).any(|l| {
                let xs = b.nodes(l);
                let kin = crate::joint::kinematics(&xs, ks[l].h);
                (0..2).any(|p| {
                    let (_, before) =
                        pre_peak_lane(&material(l), &ks[l], kin.o[p], kin.s[p], 0.0, f64::INFINITY);
                    !before
                })
            });
            assert_eq!(ok, !beyond, "seed {seed}");
            past += usize::from(beyond);
        }
        assert!(
            (20..180).contains(&past),
            "{past} blocks with a lane past a peak: both verdicts must occur"
        );
        fdem_figures::record_part(
            146,
            2,
            format!(
                "{past} of 200 blocks with a lane past a peak, each reported, the others taken"
            ),
        );
    }
}
