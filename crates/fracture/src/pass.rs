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
//! re-evaluation); at other positions it runs the pass first. The positions are compared
//! bit for bit with a copy the pass keeps; a caller that knows the commit is at the last
//! pass's positions (the solver, told by the time crate's FSAL schemes) turns that copy off
//! ([`JointScratch::set_position_check`]) and commits with [`commit_joints_at_last_pass`]. Breaking and the list of newly
//! softened joints then visit only the flagged chunks, in joint order.
//!
//! Results are bit-identical whatever the number of threads (each joint's values depend on
//! that joint only, the chunks are fixed, and the node sums run in a fixed order), and nothing
//! is allocated per step (except when an event is pushed to the caller's vector).

use rayon::prelude::*;

use crate::events::{FractureEvent, FractureMode};
use crate::joint::{EvalOut, evaluate_into};
use crate::set::{JointId, JointSet};
use crate::state::{JointHistory, JointState};

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
    trial: Vec<JointHistory>,
    /// Per chunk of joints: [`SOFTENED`] | [`BREAKS`].
    flags: Vec<u8>,
    /// Positions of the last pass (not kept after [`JointScratch::set_position_check`]
    /// turned the check off).
    x_last: Vec<[f64; 2]>,
    /// True when the pass keeps no copy of its positions.
    skip_position_copy: bool,
    /// The generation of the state whose trial `trial` holds at `x_last`, until a commit.
    valid: Option<u64>,
    /// Joints whose damage became positive at the last commit.
    softened: Vec<u32>,
    /// Per joint, [`SOFTENED`] when the last in-place pass softened it for the first time.
    softened_bits: Vec<u8>,
    /// The generation of the state that the last in-place pass advanced, until its commit.
    in_place: Option<u64>,
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
        if self.trial.is_empty() && self.forces.is_empty() {
            // first sizing: filled in parallel (the pages are touched by both threads)
            self.trial
                .par_extend(rayon::iter::repeat_n(JointHistory::FRESH, n));
            self.forces
                .par_extend(rayon::iter::repeat_n([[0.0; 2]; 4], n));
        }
        self.trial.resize(n, JointHistory::FRESH);
        self.forces.resize(n, [[0.0; 2]; 4]);
        self.flags.resize(n.div_ceil(CHUNK), 0);
        if self.softened.capacity() == 0 {
            self.softened.reserve(256);
        }
    }

    /// With `false`, the force pass keeps no copy of its positions (4.8 MB a pass for 3 x
    /// 10^5 nodes) and [`commit_joints`] re-evaluates every joint: for callers that commit
    /// with [`commit_joints_at_last_pass`] whenever the last pass was at the commit's
    /// positions. Default `true`.
    pub fn set_position_check(&mut self, on: bool) {
        self.skip_position_copy = !on;
        if !on {
            self.x_last = Vec::new();
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
    (
        scratch.forces.par_chunks_mut(CHUNK),
        scratch.trial.par_chunks_mut(CHUNK),
        scratch.flags.par_iter_mut(),
    )
        .into_par_iter()
        .with_min_len(min_chunks(n))
        .enumerate()
        .for_each(|(c, (f, h, flag))| {
            let j0 = c * CHUNK;
            // the committed history and the joint data of this chunk, cut to its length
            let n = f.len().min(h.len());
            let r = j0..j0 + n;
            let (old, intact) = (&state.history[r.clone()], &state.intact[r.clone()]);
            let (nodes, consts, material) = (
                &set.nodes[r.clone()],
                &set.consts[r.clone()],
                &set.material[r],
            );
            let mut fl = 0u8;
            for i in 0..n {
                let ho = &old[i];
                if !intact[i] {
                    // a broken joint keeps its books; no force
                    f[i] = [[0.0; 2]; 4];
                    h[i] = *ho;
                    continue;
                }
                fl |= joint_step(
                    set,
                    &consts[i],
                    material[i],
                    nodes[i],
                    x,
                    ho,
                    &mut f[i],
                    &mut h[i],
                );
            }
            *flag = fl;
        });
}

/// One intact joint's evaluation at `x` from the committed history `ho`: its forces into `f`,
/// its new history (trial damage, books advanced by the trapezoidal rule) into `hn`. Returns
/// the chunk flags it raises ([`SOFTENED`], [`BREAKS`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn joint_step(
    set: &JointSet,
    consts: &crate::material::JointConsts,
    material: u32,
    nodes: [u32; 4],
    x: &[[f64; 2]],
    ho: &JointHistory,
    f: &mut [[f64; 2]; 4],
    hn: &mut JointHistory,
) -> u8 {
    let [np, nq, nr, ns] = nodes;
    let xs = [
        x[np as usize],
        x[nq as usize],
        x[nr as usize],
        x[ns as usize],
    ];
    let stored = evaluate_into::<true>(
        &set.materials[material as usize],
        consts,
        &xs,
        [ho.damage, ho.mode_mix, ho.shear_secant],
        set.thickness,
        EvalOut {
            forces: f,
            damage: &mut hn.damage,
            mode_mix: &mut hn.mode_mix,
            shear_secant: &mut hn.shear_secant,
            local: &mut hn.last,
        },
    );
    // work of the step, trapezoidal rule on (A sigma, o) and (A tau, s)
    let (a, b) = (&ho.last, &hn.last);
    let mut dw = 0.0;
    for p in 0..2 {
        let q = 4 * p;
        dw += 0.5 * (a[q] + b[q]) * (b[q + 2] - a[q + 2])
            + 0.5 * (a[q + 1] + b[q + 1]) * (b[q + 3] - a[q + 3]);
    }
    hn.work = ho.work + dw;
    hn.dissipated = ho.dissipated + (dw - (stored - ho.stored));
    hn.stored = stored;
    let mut fl = 0;
    if ho.damage == [0.0; 2] && hn.damage != [0.0; 2] {
        fl |= SOFTENED;
    }
    if hn.damage[0] >= 1.0 && hn.damage[1] >= 1.0 && breaks(&hn.last, consts.h) {
        fl |= BREAKS;
    }
    fl
}

/// The fused pass writing the new history into `state` itself (the commit to follow is
/// [`commit_joints_in_place`]): same values as [`trial_pass`] bit for bit, without the trial
/// array (136 bytes of memory traffic less per joint: no write-allocate of a second array).
/// Per joint, `scratch.softened_bits` records a first softening (the commit no longer has the
/// old damage to compare with).
fn in_place_pass(
    set: &JointSet,
    state: &mut JointState,
    x: &[[f64; 2]],
    scratch: &mut JointScratch,
) {
    let n = set.len();
    scratch.fit(n);
    scratch.softened_bits.resize(n, 0);
    let intact = &state.intact;
    (
        scratch.forces.par_chunks_mut(CHUNK),
        state.history.par_chunks_mut(CHUNK),
        scratch.softened_bits.par_chunks_mut(CHUNK),
        scratch.flags.par_iter_mut(),
    )
        .into_par_iter()
        .with_min_len(min_chunks(n))
        .enumerate()
        .for_each(|(c, (f, h, soft, flag))| {
            let j0 = c * CHUNK;
            let n = f.len().min(h.len());
            let r = j0..j0 + n;
            let (intact, nodes, consts, material) = (
                &intact[r.clone()],
                &set.nodes[r.clone()],
                &set.consts[r.clone()],
                &set.material[r],
            );
            let mut fl = 0u8;
            for i in 0..n {
                if !intact[i] {
                    f[i] = [[0.0; 2]; 4];
                    soft[i] = 0;
                    continue;
                }
                let ho = h[i];
                let b = joint_step(
                    set,
                    &consts[i],
                    material[i],
                    nodes[i],
                    x,
                    &ho,
                    &mut f[i],
                    &mut h[i],
                );
                soft[i] = b & SOFTENED;
                fl |= b;
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
    gather_forces(set, scratch, x, f, true);
    scratch.valid = Some(state.generation);
}

/// Adds the joints' forces of the last pass to the node forces `f`: per node over its
/// (joint, slot) list in joint order (parallel and deterministic); the positions are kept
/// for the commit on the way, unless the caller turned the check off (or the pass was in
/// place).
fn gather_forces(
    set: &JointSet,
    scratch: &mut JointScratch,
    x: &[[f64; 2]],
    f: &mut [[f64; 2]],
    keep_positions: bool,
) {
    // slot 4 j + k of the flat list is node k of joint j
    let forces = scratch.forces.as_flattened();
    let (offsets, slots) = (&set.node_offsets, &set.node_slots);
    let gather = |c: usize, fc: &mut [[f64; 2]]| {
        let i0 = c * NODE_CHUNK;
        let off = &offsets[i0..i0 + fc.len() + 1];
        for (fi, w) in fc.iter_mut().zip(off.windows(2)) {
            for &js in &slots[w[0] as usize..w[1] as usize] {
                let fe = forces[js as usize];
                fi[0] += fe[0];
                fi[1] += fe[1];
            }
        }
    };
    if scratch.skip_position_copy || !keep_positions {
        f.par_chunks_mut(NODE_CHUNK)
            .with_min_len(min_chunks(set.len()))
            .enumerate()
            .for_each(|(c, fc)| gather(c, fc));
    } else {
        scratch.x_last.resize(x.len(), [0.0; 2]);
        f.par_chunks_mut(NODE_CHUNK)
            .zip(scratch.x_last.par_chunks_mut(NODE_CHUNK))
            .zip(x.par_chunks(NODE_CHUNK))
            .with_min_len(min_chunks(set.len()))
            .enumerate()
            .for_each(|(c, ((fc, xl), xc))| {
                xl.copy_from_slice(xc);
                gather(c, fc);
            });
    }
}

/// [`accumulate_joint_forces`] for an evaluation that the caller commits next, at these
/// positions, with [`commit_joints_in_place`] (the last force evaluation of a central
/// difference step): the new history goes into `state` itself instead of a trial array, 136
/// bytes of memory traffic less per joint, the same values bit for bit. Between this pass and
/// its commit `state` holds the step's new history (damage, books) but not yet its breaks.
/// Any other force evaluation before that commit must not happen (it would read the new
/// history as the committed one).
pub fn accumulate_joint_forces_in_place(
    set: &JointSet,
    state: &mut JointState,
    x: &[[f64; 2]],
    scratch: &mut JointScratch,
    f: &mut [[f64; 2]],
) {
    assert_eq!(f.len(), set.n_nodes, "forces must have one entry per node");
    check_sizes(set, state, x);
    in_place_pass(set, state, x, scratch);
    gather_forces(set, scratch, x, f, false);
    scratch.valid = None;
    scratch.in_place = Some(state.generation);
}

/// The commit of an [`accumulate_joint_forces_in_place`] pass at the same positions `x`:
/// breaks, events and the newly softened joints as [`commit_joints`] gives them. Without such
/// a pass since the last commit it is [`commit_joints_at_last_pass`].
pub fn commit_joints_in_place(
    set: &JointSet,
    state: &mut JointState,
    x: &[[f64; 2]],
    time: f64,
    scratch: &mut JointScratch,
    events: &mut Vec<FractureEvent>,
) -> usize {
    check_sizes(set, state, x);
    if scratch.in_place != Some(state.generation) {
        return commit(set, state, x, time, scratch, events, true);
    }
    scratch.in_place = None;
    scratch.valid = None;
    state.generation += 1;
    let bits = std::mem::take(&mut scratch.softened_bits);
    let n = finish_commit(set, state, x, time, scratch, events, |j, _| bits[j] != 0);
    scratch.softened_bits = bits;
    n
}

/// True when `a` and `b` hold the same positions (`==` on every coordinate).
fn same_positions(a: &[[f64; 2]], b: &[[f64; 2]], par: bool) -> bool {
    // no early exit inside a chunk: the loop vectorises
    let same = |p: &[[f64; 2]], q: &[[f64; 2]]| {
        p.iter()
            .zip(q)
            .fold(true, |acc, (u, v)| acc & (u[0] == v[0]) & (u[1] == v[1]))
    };
    a.len() == b.len()
        && if par {
            a.par_chunks(NODE_CHUNK)
                .zip(b.par_chunks(NODE_CHUNK))
                .all(|(p, q)| same(p, q))
        } else {
            same(a, b)
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
    let same =
        !scratch.skip_position_copy && same_positions(&scratch.x_last, x, set.len() >= PAR_MIN);
    commit(set, state, x, time, scratch, events, same)
}

/// [`commit_joints`] for a caller that knows that `x` are the positions of the last
/// [`accumulate_joint_forces`] call, bit for bit (the end of a step of a scheme whose last
/// force evaluation is at the final state): the trial history of that pass is committed
/// without comparing the positions (it is still re-evaluated when the state was committed
/// since that pass). Same results as [`commit_joints`].
pub fn commit_joints_at_last_pass(
    set: &JointSet,
    state: &mut JointState,
    x: &[[f64; 2]],
    time: f64,
    scratch: &mut JointScratch,
    events: &mut Vec<FractureEvent>,
) -> usize {
    check_sizes(set, state, x);
    commit(set, state, x, time, scratch, events, true)
}

/// The commit; `at_last_pass`: the last pass was at `x`.
fn commit(
    set: &JointSet,
    state: &mut JointState,
    x: &[[f64; 2]],
    time: f64,
    scratch: &mut JointScratch,
    events: &mut Vec<FractureEvent>,
    at_last_pass: bool,
) -> usize {
    let reuse = at_last_pass && scratch.valid == Some(state.generation);
    scratch.valid = None;
    if !reuse {
        trial_pass(set, state, x, scratch);
    }
    scratch.in_place = None;
    std::mem::swap(&mut state.history, &mut scratch.trial);
    state.generation += 1;
    // the arrays swapped: the scratch holds the history before the step
    let old = std::mem::take(&mut scratch.trial);
    let n = finish_commit(set, state, x, time, scratch, events, |j, h| {
        old[j].damage == [0.0; 2] && h.damage != [0.0; 2]
    });
    scratch.trial = old;
    n
}

/// The rest of a commit once `state.history` holds the step's new history: visits the
/// flagged chunks in joint order, lists the joints `softened(j, new history)` says softened
/// for the first time, breaks the fully damaged open or slid ones (events in joint order). Returns the
/// number of new breaks.
fn finish_commit(
    set: &JointSet,
    state: &mut JointState,
    x: &[[f64; 2]],
    time: f64,
    scratch: &mut JointScratch,
    events: &mut Vec<FractureEvent>,
    softened: impl Fn(usize, &JointHistory) -> bool,
) -> usize {
    let n = set.len();
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
            let h = &mut state.history[j];
            if fl & SOFTENED != 0 && softened(j, h) {
                scratch.softened.push(j as u32);
            }
            if fl & BREAKS != 0
                && h.damage[0] >= 1.0
                && h.damage[1] >= 1.0
                && breaks(&h.last, set.consts[j].h)
            {
                state.intact[j] = false;
                state.broken_at[j] = Some(time);
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
    }
    n_new
}
