//! The joint-force pass over all joints and the end-of-step commit.
//!
//! Both evaluate every intact joint in parallel (rayon) into a per-joint buffer owned by the
//! caller ([`JointScratch`]), then work through the buffer serially in joint order: forces are
//! scattered into the node array, history and events are updated. Results are bit-identical
//! whatever the number of threads, and nothing is allocated per step (except when an event is
//! pushed to the caller's vector).

use rayon::prelude::*;

use crate::events::{FractureEvent, FractureMode};
use crate::joint::{JointEval, evaluate};
use crate::set::{JointId, JointSet};
use crate::state::{JointHistory, JointState};

/// A fully damaged joint closed in compression breaks once it has slid by this fraction of its
/// reference length.
pub const SLID: f64 = 0.1;

/// Joints per rayon task: below this, splitting costs more than it gains.
const MIN_CHUNK: usize = 512;

/// Below this many joints the passes run on the calling thread: waking rayon's workers
/// several times per step costs more than the work (and much more on a loaded machine).
const PAR_MIN: usize = 8 * MIN_CHUNK;

/// Per-joint scratch of the pass, owned by the stepping code.
#[derive(Debug, Clone, Default)]
pub struct JointScratch {
    forces: Vec<[[f64; 2]; 4]>,
    evals: Vec<JointEval>,
    /// Positions of the last force pass, whose full evaluations `evals` holds (valid while
    /// `evals_valid`: no commit since).
    x_last: Vec<[f64; 2]>,
    evals_valid: bool,
}

/// Runs `f(j, &mut out[j])` over all entries, in parallel for large sets.
fn for_each_joint<T: Send>(out: &mut [T], f: impl Fn(usize, &mut T) + Sync + Send) {
    if out.len() >= PAR_MIN {
        out.par_iter_mut()
            .with_min_len(MIN_CHUNK)
            .enumerate()
            .for_each(|(j, o)| f(j, o));
    } else {
        out.iter_mut().enumerate().for_each(|(j, o)| f(j, o));
    }
}

impl JointScratch {
    /// Scratch for `n_joints` joints.
    pub fn new(n_joints: usize) -> Self {
        JointScratch {
            forces: vec![[[0.0; 2]; 4]; n_joints],
            evals: vec![JointEval::default(); n_joints],
            x_last: Vec::new(),
            evals_valid: false,
        }
    }

    /// The full evaluations of the last force pass or commit (zero for broken joints).
    pub fn evals(&self) -> &[JointEval] {
        &self.evals
    }

    /// The nodal forces (P, Q, R, S) of the last force pass (zero for broken joints).
    pub fn forces(&self) -> &[[[f64; 2]; 4]] {
        &self.forces
    }
}

#[inline]
fn eval_joint(set: &JointSet, state: &JointState, x: &[[f64; 2]], j: usize) -> JointEval {
    if !state.intact[j] {
        return JointEval::default();
    }
    evaluate(
        &set.materials[set.material[j] as usize],
        &set.consts[j],
        &set.gather(j, x),
        &state.point_history(j),
        set.thickness,
    )
}

fn check_sizes(set: &JointSet, state: &JointState, x: &[[f64; 2]]) {
    assert_eq!(
        x.len(),
        set.n_nodes,
        "positions must have one entry per node"
    );
    assert_eq!(
        state.damage.len(),
        set.len(),
        "state belongs to another joint set"
    );
}

/// Adds the forces of every intact joint at positions `x` to `f` (one entry per node). Reads
/// the committed history only: call it at every force evaluation, trial stages included.
pub fn accumulate_joint_forces(
    set: &JointSet,
    state: &JointState,
    x: &[[f64; 2]],
    scratch: &mut JointScratch,
    f: &mut [[f64; 2]],
) {
    assert_eq!(f.len(), set.n_nodes, "forces must have one entry per node");
    check_sizes(set, state, x);
    scratch.forces.resize(set.len(), [[0.0; 2]; 4]);
    scratch.evals.resize(set.len(), JointEval::default());
    // Full evaluations (forces, trial damage, work conjugates, stored energy): the commit at
    // the same positions (the end of a central-difference step) reuses them.
    for_each_joint(&mut scratch.evals, |j, out| {
        *out = eval_joint(set, state, x, j)
    });
    let evals = &scratch.evals;
    for_each_joint(&mut scratch.forces, |j, out| *out = evals[j].forces);
    scratch.x_last.clear();
    scratch.x_last.extend_from_slice(x);
    scratch.evals_valid = true;
    // gather per node over its (joint, slot) list in joint order: parallel and deterministic
    let forces = &scratch.forces;
    let (offsets, slots) = (&set.node_offsets, &set.node_slots);
    let gather = |i: usize, fi: &mut [f64; 2]| {
        for &js in &slots[offsets[i] as usize..offsets[i + 1] as usize] {
            let fe = forces[(js >> 2) as usize][(js & 3) as usize];
            fi[0] += fe[0];
            fi[1] += fe[1];
        }
    };
    if set.len() >= PAR_MIN {
        f.par_iter_mut()
            .with_min_len(4 * MIN_CHUNK)
            .enumerate()
            .for_each(|(i, fi)| gather(i, fi));
    } else {
        f.iter_mut().enumerate().for_each(|(i, fi)| gather(i, fi));
    }
}

/// End-of-step commit at the step's final positions `x` and time `time`: damage grows to its
/// trial value (it never heals), the work done in the step is added with the trapezoidal rule,
/// stored and dissipated energy are updated, and joints whose two points reached `D = 1`
/// break. One [`FractureEvent`] per new break is pushed to `events`, in joint order. Returns
/// the number of joints that broke.
pub fn commit_joints(
    set: &JointSet,
    state: &mut JointState,
    x: &[[f64; 2]],
    time: f64,
    scratch: &mut JointScratch,
    events: &mut Vec<FractureEvent>,
) -> usize {
    check_sizes(set, state, x);
    scratch.evals.resize(set.len(), JointEval::default());
    // reuse the last force pass's evaluations when it was at these positions (bitwise) with
    // this history; otherwise evaluate
    let reuse = scratch.evals_valid && scratch.x_last.as_slice() == x;
    scratch.evals_valid = false;
    if !reuse {
        let st: &JointState = state;
        for_each_joint(&mut scratch.evals, |j, out| {
            *out = eval_joint(set, st, x, j)
        });
    }
    let update =
        |h: &mut JointHistory, d: &mut [f64; 2], k: &mut [f64; 2], e: &JointEval, intact: bool| {
            if !intact {
                return;
            }
            let mut dw = 0.0;
            for k in 0..2 {
                let (a, b) = (&h.last[4 * k..4 * k + 4], &e.local[4 * k..4 * k + 4]);
                dw += 0.5 * (a[0] + b[0]) * (b[2] - a[2]) + 0.5 * (a[1] + b[1]) * (b[3] - a[3]);
            }
            h.work += dw;
            h.dissipated += dw - (e.stored - h.stored);
            h.stored = e.stored;
            *d = e.damage;
            *k = e.shear_secant;
            h.mode_mix = e.mode_mix;
            h.last = e.local;
        };
    if set.len() >= PAR_MIN {
        state
            .history
            .par_iter_mut()
            .with_min_len(MIN_CHUNK)
            .zip(state.damage.par_iter_mut())
            .zip(state.shear_secant.par_iter_mut())
            .zip(scratch.evals.par_iter())
            .zip(state.intact.par_iter())
            .for_each(|((((h, d), k), e), &i)| update(h, d, k, e, i));
    } else {
        state
            .history
            .iter_mut()
            .zip(state.damage.iter_mut())
            .zip(state.shear_secant.iter_mut())
            .zip(scratch.evals.iter())
            .zip(state.intact.iter())
            .for_each(|((((h, d), k), e), &i)| update(h, d, k, e, i));
    }
    let mut n_new = 0;
    for (j, h) in state.history.iter_mut().enumerate() {
        let d = state.damage[j];
        // Fully damaged (z(1) = 0: no tension, no shear) and open at both points: the
        // joint carries no force, so removing it changes no force and no energy, and the
        // faces reach contact without overlap. A fully damaged joint closed at a point keeps
        // carrying that compression (frictionless) until it opens, or until it has slid by
        // a tenth of its length (its kinematics no longer describe the faces well: contact
        // takes over, with the energy jump the solver measures).
        let open = h.last[2] >= 0.0 && h.last[6] >= 0.0;
        let slid = h.last[3].abs().max(h.last[7].abs()) >= SLID * set.consts[j].h;
        if state.intact[j] && d[0] >= 1.0 && d[1] >= 1.0 && (open || slid) {
            state.intact[j] = false;
            h.broken_at = Some(time);
            let p = set.gather(j, x);
            let mix = h.mode_mix();
            events.push(FractureEvent {
                joint: JointId(j as u32),
                triangles: set.triangles[j],
                time,
                position: [
                    0.25 * (p[0][0] + p[1][0] + p[2][0] + p[3][0]),
                    0.25 * (p[0][1] + p[1][1] + p[2][1] + p[3][1]),
                ],
                mode: FractureMode::from_mix(mix),
                mode_mix: mix,
                energy_released: h.dissipated,
                stored_at_break: h.stored,
            });
            state.released_at_break += h.stored;
            h.stored = 0.0;
            h.last = [0.0; 8];
            state.n_broken += 1;
            n_new += 1;
        }
    }
    n_new
}
