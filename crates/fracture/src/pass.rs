//! The joint-force pass over all joints and the end-of-step commit.
//!
//! One fused pass ([`accumulate_joint_forces`]) evaluates every intact joint at the given
//! positions with the committed history: its four nodal forces go into a per-joint buffer,
//! and everything the commit needs (trial damage, mode indicator and shear secant, the work
//! conjugates `[A sigma, A tau, o, s]`, the stored energy, and the work and dissipation books
//! advanced by the trapezoidal rule) goes into the trial arrays of the caller's
//! [`JointScratch`], one array per field. The pass runs in parallel over fixed chunks of
//! [`CHUNK`] joints; each chunk also records whether one of its joints softened for the
//! first time or may break. Then each node sums its joint slots in a fixed order (CSR list of
//! the [`JointSet`]) and adds the sum to the node force.
//!
//! The end-of-step [`commit_joints`] at the positions of the last pass (bitwise; the end of a
//! central-difference step) swaps the trial arrays with the committed ones (no copy, no
//! re-evaluation); at other positions it runs the pass first. Breaking and the list of newly
//! softened joints then visit only the flagged chunks, in joint order.
//!
//! Results are bit-identical whatever the number of threads (each joint's values depend on
//! that joint only, the chunks are fixed, and the node sums run in a fixed order), and nothing
//! is allocated per step (except when an event is pushed to the caller's vector).

use rayon::prelude::*;

use crate::events::{FractureEvent, FractureMode};
use crate::joint::evaluate_impl;
use crate::set::{JointId, JointSet};
use crate::state::{Histories, JointState};

/// A fully damaged joint closed in compression breaks once it has slid by this fraction of its
/// reference length.
pub const SLID: f64 = 0.1;

/// Joints per chunk: the unit of a rayon task and of the per-chunk flags. Fixed, so that the
/// chunks (and the results) do not depend on the number of threads.
pub const CHUNK: usize = 1024;

/// Below this many joints the passes run on the calling thread: waking rayon's workers
/// several times per step costs more than the work (and much more on a loaded machine).
const PAR_MIN: usize = 4 * CHUNK;

/// Nodes per rayon task in the gather.
const NODE_CHUNK: usize = 4 * CHUNK;

/// Chunk flag: a joint of the chunk got its first damage.
const SOFTENED: u8 = 1;
/// Chunk flag: a joint of the chunk is fully damaged at both points and open or slid.
const BREAKS: u8 = 2;

/// Per-joint scratch of the pass, owned by the stepping code.
#[derive(Debug, Clone, Default)]
pub struct JointScratch {
    forces: Vec<[[f64; 2]; 4]>,
    /// Trial history of the last pass (the committed one after a commit swapped them).
    trial: Histories,
    /// Per chunk of joints: [`SOFTENED`] | [`BREAKS`].
    flags: Vec<u8>,
    /// Positions of the last pass.
    x_last: Vec<[f64; 2]>,
    /// The generation of the state whose trial `trial` holds at `x_last`, until a commit.
    valid: Option<u64>,
    /// Joints whose damage became positive at the last commit.
    softened: Vec<u32>,
}

/// Minimum number of chunks per rayon task: everything on the calling thread for small sets.
fn min_chunks(n_joints: usize) -> usize {
    if n_joints >= PAR_MIN { 1 } else { usize::MAX }
}

impl JointScratch {
    /// Scratch for `n_joints` joints.
    pub fn new(n_joints: usize) -> Self {
        let mut s = JointScratch::default();
        s.fit(n_joints);
        s
    }

    /// Sizes the buffers for `n` joints (no-op when they already are).
    fn fit(&mut self, n: usize) {
        if self.trial.len() != n {
            self.trial = Histories::new(n);
        }
        self.forces.resize(n, [[0.0; 2]; 4]);
        self.flags.resize(n.div_ceil(CHUNK), 0);
        if self.softened.capacity() == 0 {
            self.softened.reserve(256);
        }
    }

    /// The nodal forces (P, Q, R, S) of the last pass (zero for broken joints).
    pub fn forces(&self) -> &[[[f64; 2]; 4]] {
        &self.forces
    }

    /// The joints whose damage became positive (at either point, from zero at both) at the
    /// last commit, in increasing order.
    pub fn newly_softened(&self) -> &[u32] {
        &self.softened
    }
}

fn check_sizes(set: &JointSet, state: &JointState, x: &[[f64; 2]]) {
    assert_eq!(
        x.len(),
        set.n_nodes,
        "positions must have one entry per node"
    );
    assert_eq!(state.len(), set.len(), "state belongs to another joint set");
}

/// The fused pass: forces and trial history of every joint at `x` into `scratch`.
fn trial_pass(set: &JointSet, state: &JointState, x: &[[f64; 2]], scratch: &mut JointScratch) {
    let n = set.len();
    scratch.fit(n);
    let th = set.thickness;
    let t = &mut scratch.trial;
    (
        scratch.forces.par_chunks_mut(CHUNK),
        t.damage.par_chunks_mut(CHUNK),
        t.shear_secant.par_chunks_mut(CHUNK),
        t.mode_mix.par_chunks_mut(CHUNK),
        t.last.par_chunks_mut(CHUNK),
        t.work.par_chunks_mut(CHUNK),
        t.stored.par_chunks_mut(CHUNK),
        t.dissipated.par_chunks_mut(CHUNK),
        scratch.flags.par_iter_mut(),
    )
        .into_par_iter()
        .with_min_len(min_chunks(n))
        .enumerate()
        .for_each(|(c, (f, d, k, m, l, w, s, di, flag))| {
            let j0 = c * CHUNK;
            let mut fl = 0u8;
            for i in 0..f.len() {
                let j = j0 + i;
                let (d_old, last_old) = (state.damage[j], &state.last[j]);
                if !state.intact[j] {
                    // a broken joint keeps its books; no force
                    f[i] = [[0.0; 2]; 4];
                    d[i] = d_old;
                    k[i] = state.shear_secant[j];
                    m[i] = state.mode_mix[j];
                    l[i] = *last_old;
                    w[i] = state.work[j];
                    s[i] = state.stored[j];
                    di[i] = state.dissipated[j];
                    continue;
                }
                let consts = &set.consts[j];
                let e = evaluate_impl::<true>(
                    &set.materials[set.material[j] as usize],
                    consts,
                    &set.gather(j, x),
                    d_old,
                    state.mode_mix[j],
                    state.shear_secant[j],
                    th,
                );
                // work of the step, trapezoidal rule on (A sigma, o) and (A tau, s)
                let (a, b) = (last_old, &e.local);
                let mut dw = 0.0;
                for p in 0..2 {
                    let q = 4 * p;
                    dw += 0.5 * (a[q] + b[q]) * (b[q + 2] - a[q + 2])
                        + 0.5 * (a[q + 1] + b[q + 1]) * (b[q + 3] - a[q + 3]);
                }
                w[i] = state.work[j] + dw;
                di[i] = state.dissipated[j] + (dw - (e.stored - state.stored[j]));
                s[i] = e.stored;
                d[i] = e.damage;
                k[i] = e.shear_secant;
                m[i] = e.mode_mix;
                l[i] = e.local;
                f[i] = e.forces;
                if d_old == [0.0; 2] && e.damage != [0.0; 2] {
                    fl |= SOFTENED;
                }
                if e.damage[0] >= 1.0 && e.damage[1] >= 1.0 && breaks(b, consts.h) {
                    fl |= BREAKS;
                }
            }
            *flag = fl;
        });
}

/// Fully damaged (z(1) = 0: no tension, no shear) and open at both points: the joint carries
/// no force, so removing it changes no force and no energy, and the faces reach contact
/// without overlap. A fully damaged joint closed at a point keeps carrying that compression
/// (frictionless) until it opens, or until it has slid by a tenth of its length (its
/// kinematics no longer describe the faces well: contact takes over, with the energy jump the
/// solver measures). `local` is `[A sigma, A tau, o, s]` per point, `h` the reference length.
#[inline]
fn breaks(local: &[f64; 8], h: f64) -> bool {
    let open = local[2] >= 0.0 && local[6] >= 0.0;
    let slid = local[3].abs().max(local[7].abs()) >= SLID * h;
    open || slid
}

/// Adds the forces of every intact joint at positions `x` to `f` (one entry per node). Reads
/// the committed history only (the trial history goes to `scratch`): call it at every force
/// evaluation, trial stages included.
pub fn accumulate_joint_forces(
    set: &JointSet,
    state: &JointState,
    x: &[[f64; 2]],
    scratch: &mut JointScratch,
    f: &mut [[f64; 2]],
) {
    assert_eq!(f.len(), set.n_nodes, "forces must have one entry per node");
    check_sizes(set, state, x);
    trial_pass(set, state, x, scratch);
    scratch.x_last.resize(x.len(), [0.0; 2]);
    // gather per node over its (joint, slot) list in joint order (parallel and
    // deterministic); the positions are kept for the commit on the way
    let forces = &scratch.forces;
    let (offsets, slots) = (&set.node_offsets, &set.node_slots);
    f.par_chunks_mut(NODE_CHUNK)
        .zip(scratch.x_last.par_chunks_mut(NODE_CHUNK))
        .zip(x.par_chunks(NODE_CHUNK))
        .with_min_len(min_chunks(set.len()))
        .enumerate()
        .for_each(|(c, ((fc, xl), xc))| {
            xl.copy_from_slice(xc);
            let i0 = c * NODE_CHUNK;
            for (k, fi) in fc.iter_mut().enumerate() {
                let i = i0 + k;
                for &js in &slots[offsets[i] as usize..offsets[i + 1] as usize] {
                    let fe = forces[(js >> 2) as usize][(js & 3) as usize];
                    fi[0] += fe[0];
                    fi[1] += fe[1];
                }
            }
        });
    scratch.valid = Some(state.generation);
}

/// True when `a` and `b` hold the same positions (`==` on every coordinate).
fn same_positions(a: &[[f64; 2]], b: &[[f64; 2]], par: bool) -> bool {
    a.len() == b.len()
        && if par {
            a.par_chunks(NODE_CHUNK)
                .zip(b.par_chunks(NODE_CHUNK))
                .all(|(p, q)| p == q)
        } else {
            a == b
        }
}

/// End-of-step commit at the step's final positions `x` and time `time`: damage grows to its
/// trial value (it never heals), the work done in the step is added with the trapezoidal rule,
/// stored and dissipated energy are updated, and joints whose two points reached `D = 1`
/// break. One [`FractureEvent`] per new break is pushed to `events`, in joint order; the
/// joints softened for the first time are listed in [`JointScratch::newly_softened`]. Returns
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
    // reuse the last pass's trial when it was at these positions with this history;
    // otherwise evaluate
    let n = set.len();
    let reuse =
        scratch.valid == Some(state.generation) && same_positions(&scratch.x_last, x, n >= PAR_MIN);
    scratch.valid = None;
    if !reuse {
        trial_pass(set, state, x, scratch);
    }
    state.swap_histories(&mut scratch.trial);
    state.generation += 1;
    scratch.softened.clear();
    let mut n_new = 0;
    for (c, &fl) in scratch.flags.iter().enumerate() {
        if fl == 0 {
            continue;
        }
        for j in c * CHUNK..((c + 1) * CHUNK).min(n) {
            if !state.intact[j] {
                continue;
            }
            let d = state.damage[j];
            // the arrays swapped: the scratch holds the damage before the step
            if fl & SOFTENED != 0 && scratch.trial.damage[j] == [0.0; 2] && d != [0.0; 2] {
                scratch.softened.push(j as u32);
            }
            if fl & BREAKS != 0
                && d[0] >= 1.0
                && d[1] >= 1.0
                && breaks(&state.last[j], set.consts[j].h)
            {
                state.intact[j] = false;
                state.broken_at[j] = Some(time);
                let p = set.gather(j, x);
                let mix = 0.5 * (state.mode_mix[j][0] + state.mode_mix[j][1]);
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
                    energy_released: state.dissipated[j],
                    stored_at_break: state.stored[j],
                });
                state.released_at_break += state.stored[j];
                state.stored[j] = 0.0;
                state.last[j] = [0.0; 8];
                state.n_broken += 1;
                n_new += 1;
            }
        }
    }
    n_new
}
