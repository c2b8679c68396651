//! The joint-force pass over all joints and the end-of-step commit.
//!
//! One fused pass ([`accumulate_joint_forces`]) evaluates every intact joint at the given
//! positions with the committed history: its four nodal forces go to their slots in the
//! node-to-joint list (a buffer in the list's order, so the gather below reads it in order
//! instead of jumping between joints), and everything the commit needs (trial damage, mode
//! indicator and shear secant, the opening and sliding, the normal forces, the stored energy
//! and the dissipation) goes into the trial arrays of the caller's [`JointScratch`], one array
//! per field. The pass runs in parallel over fixed chunks of [`CHUNK`] joints; each chunk also
//! records whether one of its joints softened for the first time or may break. Then each node
//! adds its joint slots to its force, slot after slot in a fixed order (the node-slot list of
//! the [`JointSet`], increasing joint order). Where no node has more than two slots (every
//! exploded mesh) each node's slots sit side by side in the buffer and the gather reads it
//! straight through. A caller with its own pass over the node forces (the solver's element
//! pass) runs the joint pass first ([`joint_forces_ahead`]) and adds the joints' forces range by
//! range inside its pass ([`add_joint_forces`]): the same sums without a trip of their own
//! through the node array.
//!
//! The end-of-step [`commit_joints`] at the positions of the last pass (bitwise; the end of a
//! central-difference step) swaps the trial arrays with the committed ones (no copy, no
//! re-evaluation); at other positions it runs the pass first. The positions are compared
//! bit for bit with a copy the pass keeps; a caller that knows the commit is at the last
//! pass's positions (the solver, told by the time crate's FSAL schemes) turns that copy off
//! ([`JointScratch::set_position_check`]) and commits with [`commit_joints_at_last_pass`]. A
//! caller that knows, before a pass, that the commit at its positions follows with no other
//! pass in between (central difference, told by the time crate) calls
//! [`accumulate_joint_forces_committing`]: the pass then writes each joint's new history over
//! its committed one, field by field, the damage and mode indicators only where they changed,
//! and marks the joints that soften. Breaking and the list of newly softened joints then visit
//! only the flagged chunks, in joint order.
//!
//! Dissipation ([`crate::state`]): the trapezoidal work of the step on `(A sigma, o)` and
//! `(A tau, s)` less the change of stored energy, with the committed shear force computed
//! again as `A k_t s`.
//!
//! Results are bit-identical whatever the number of threads (each joint's values depend on
//! that joint only, the chunks are fixed, and the node sums run in a fixed order), and nothing
//! is allocated per step (except when an event is pushed to the caller's vector).

use std::sync::atomic::AtomicU64;
use std::sync::atomic::Ordering::Relaxed;

use rayon::prelude::*;

use crate::events::{FractureEvent, FractureMode};
use crate::joint::{JointEval, evaluate_into, step_dissipation};
use crate::lanes::{BlockIn, BlockOut, LANES, pre_peak_block};
use crate::material::SofteningConsts;
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
    /// The nodal forces of the last pass by node slot, node after node, each node's slots in
    /// the order of the set's node-slot list ([`JointSet::node_slots`], increasing joint
    /// order): the pass scatters each joint's four forces to their slots, and the per-node
    /// gather then reads this array in order.
    slot_forces: SlotBuf,
    /// Per slot `4 j + k` (node k of joint j), its place in `slot_forces`.
    slot_pos: Vec<u32>,
    /// With `pairs`, per joint: bit k set when node k's slot is the second of its node's two
    /// (the pass then reads this byte instead of the four places: the place is
    /// `2 node + bit`). Empty otherwise.
    ranks: Vec<u8>,
    /// True when no node has more than two slots (every node of a wholly exploded mesh lies
    /// on two edges of its triangle): node `i`'s slots are then `2 i` and `2 i + 1`, a place
    /// no joint fills holding -0.0 (`f + (-0.0) = f` for every `f`), and the gather needs no
    /// offsets and no inner loop. Otherwise the places follow the node-slot list.
    pairs: bool,
    /// Trial history of the last pass (the committed one after a commit swapped them).
    trial: Histories,
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
    /// Per joint: 1 when an in-place pass saw its damage become positive (cleared by the
    /// commit).
    marks: Vec<u8>,
    /// The generation of the state whose history an in-place pass advanced, until the commit.
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
        self.trial.resize(n);
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

    /// The nodal forces (P, Q, R, S) of joint `j` at the last pass of `set` (zero for a broken
    /// joint).
    pub fn joint_forces(&self, set: &JointSet, j: usize) -> [[f64; 2]; 4] {
        let pos = if self.slot_pos.len() == 4 * set.len() {
            &self.slot_pos[4 * j..4 * j + 4]
        } else {
            &[][..]
        };
        std::array::from_fn(|k| {
            pos.get(k)
                .map_or([0.0; 2], |&p| self.slot_forces.get(p as usize))
        })
    }

    /// Builds the slot places of `set` (once: a scratch serves one joint set) and sizes the
    /// slot buffer.
    fn fit_slots(&mut self, set: &JointSet) {
        if self.slot_pos.len() != set.node_slots.len() {
            let offsets = &set.node_offsets;
            self.pairs = !offsets.is_empty()
                && set.n_nodes < (u32::MAX / 2) as usize
                && offsets.windows(2).all(|w| w[1] - w[0] <= 2);
            self.slot_pos = vec![0; set.node_slots.len()];
            for (i, w) in offsets.windows(2).enumerate() {
                for p in w[0]..w[1] {
                    let slot = set.node_slots[p as usize] as usize;
                    self.slot_pos[slot] = if self.pairs {
                        (2 * i) as u32 + (p - w[0])
                    } else {
                        p
                    };
                }
            }
            self.ranks = if self.pairs {
                let bit = |q: &[u32], k: usize| ((q[k] & 1) as u8) << k;
                (self.slot_pos.chunks_exact(4))
                    .map(|q| bit(q, 0) | bit(q, 1) | bit(q, 2) | bit(q, 3))
                    .collect()
            } else {
                Vec::new()
            };
        }
        let n = if self.pairs {
            2 * set.n_nodes
        } else {
            set.node_slots.len()
        };
        self.slot_forces.fit(n);
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

/// The fused pass: forces and trial history of every joint at `x` into `scratch`. One branch
/// per pass: a set with initial offsets (prestressed joints) takes the offset variant.
fn trial_pass(set: &JointSet, state: &JointState, x: &[[f64; 2]], scratch: &mut JointScratch) {
    if set.initial_offsets.is_empty() {
        trial_pass_impl::<false>(set, state, x, scratch);
    } else {
        trial_pass_impl::<true>(set, state, x, scratch);
    }
}

/// [`trial_pass`]; with `OFF` each joint's law sees its initial offsets.
fn trial_pass_impl<const OFF: bool>(
    set: &JointSet,
    state: &JointState,
    x: &[[f64; 2]],
    scratch: &mut JointScratch,
) {
    let n = set.len();
    scratch.fit(n);
    scratch.fit_slots(set);
    let inp = PassIn::new(
        set,
        &state.intact,
        x,
        places(&scratch.slot_pos, &scratch.ranks),
        &scratch.slot_forces,
    );
    let old = &state.history;
    let arch = pulp::Arch::new();
    (out_chunks(&mut scratch.trial), scratch.flags.par_iter_mut())
        .into_par_iter()
        .with_min_len(min_chunks(n))
        .enumerate()
        .for_each(|(c, (new, flag))| {
            let j0 = c * CHUNK;
            let old = in_chunk(old, j0..j0 + new.damage.len());
            *flag = arch.dispatch(|| chunk_pass::<OFF, false>(&inp, j0, Some(old), new, &mut []));
        });
}

/// The histories `h` in chunks of [`CHUNK`] joints, to write.
fn out_chunks(h: &mut Histories) -> impl IndexedParallelIterator<Item = HistOut<'_>> {
    (
        h.damage.par_chunks_mut(CHUNK),
        h.shear_secant.par_chunks_mut(CHUNK),
        h.mode_mix.par_chunks_mut(CHUNK),
        h.local.par_chunks_mut(CHUNK),
        h.normal.par_chunks_mut(CHUNK),
        h.stored.par_chunks_mut(CHUNK),
        h.dissipated.par_chunks_mut(CHUNK),
    )
        .into_par_iter()
        .map(
            |(damage, shear_secant, mode_mix, local, normal, stored, dissipated)| HistOut {
                damage,
                shear_secant,
                mode_mix,
                local,
                normal,
                stored,
                dissipated,
            },
        )
}

/// The joints `r` of the histories `h`, to read.
fn in_chunk(h: &Histories, r: std::ops::Range<usize>) -> HistIn<'_> {
    HistIn {
        damage: &h.damage[r.clone()],
        shear_secant: &h.shear_secant[r.clone()],
        mode_mix: &h.mode_mix[r.clone()],
        local: &h.local[r.clone()],
        normal: &h.normal[r.clone()],
        stored: &h.stored[r.clone()],
        dissipated: &h.dissipated[r],
    }
}

/// The pass of [`accumulate_joint_forces_committing`]: every joint's new history written over
/// its committed one, the joints that soften marked in `scratch.marks`.
fn in_place_pass<const OFF: bool>(
    set: &JointSet,
    state: &mut JointState,
    x: &[[f64; 2]],
    scratch: &mut JointScratch,
) {
    let n = set.len();
    scratch.fit_slots(set);
    scratch.flags.resize(n.div_ceil(CHUNK), 0);
    scratch.marks.resize(n, 0);
    let inp = PassIn::new(
        set,
        &state.intact,
        x,
        places(&scratch.slot_pos, &scratch.ranks),
        &scratch.slot_forces,
    );
    let arch = pulp::Arch::new();
    (
        out_chunks(&mut state.history),
        scratch.marks.par_chunks_mut(CHUNK),
        scratch.flags.par_iter_mut(),
    )
        .into_par_iter()
        .with_min_len(min_chunks(n))
        .enumerate()
        .for_each(|(c, (new, marks, flag))| {
            *flag = arch.dispatch(|| chunk_pass::<OFF, true>(&inp, c * CHUNK, None, new, marks));
        });
}

/// What gives the pass the slot places: the places `pos`, or the rank bytes where there are
/// any ([`JointScratch::ranks`]).
fn places<'a>(pos: &'a [u32], ranks: &'a [u8]) -> (&'a [u32], &'a [u8]) {
    if ranks.is_empty() {
        (pos, ranks)
    } else {
        (&[], ranks)
    }
}

/// What a pass reads besides the histories, and where it puts the forces.
struct PassIn<'a> {
    set: &'a JointSet,
    intact: &'a [bool],
    x: &'a [[f64; 2]],
    /// The slot places (empty when `ranks` gives them).
    slot_pos: &'a [u32],
    ranks: &'a [u8],
    out: &'a SlotBuf,
}

impl<'a> PassIn<'a> {
    fn new(
        set: &'a JointSet,
        intact: &'a [bool],
        x: &'a [[f64; 2]],
        (slot_pos, ranks): (&'a [u32], &'a [u8]),
        out: &'a SlotBuf,
    ) -> Self {
        PassIn {
            set,
            intact,
            x,
            slot_pos,
            ranks,
            out,
        }
    }
}

/// One chunk of committed histories, field by field.
#[derive(Clone, Copy)]
struct HistIn<'a> {
    damage: &'a [[f64; 2]],
    shear_secant: &'a [[f64; 2]],
    mode_mix: &'a [[f64; 2]],
    local: &'a [[f64; 4]],
    normal: &'a [[f64; 2]],
    stored: &'a [f64],
    dissipated: &'a [f64],
}

impl HistIn<'static> {
    /// No history (an in-place pass reads the arrays it writes).
    const EMPTY: HistIn<'static> = HistIn {
        damage: &[],
        shear_secant: &[],
        mode_mix: &[],
        local: &[],
        normal: &[],
        stored: &[],
        dissipated: &[],
    };
}

/// One chunk of histories a pass writes, field by field.
struct HistOut<'a> {
    damage: &'a mut [[f64; 2]],
    shear_secant: &'a mut [[f64; 2]],
    mode_mix: &'a mut [[f64; 2]],
    local: &'a mut [[f64; 4]],
    normal: &'a mut [[f64; 2]],
    stored: &'a mut [f64],
    dissipated: &'a mut [f64],
}

impl HistOut<'_> {
    /// Entry `i` of `old` into entry `i`.
    #[inline(always)]
    fn copy(&mut self, i: usize, old: &HistIn<'_>) {
        self.damage[i] = old.damage[i];
        self.shear_secant[i] = old.shear_secant[i];
        self.mode_mix[i] = old.mode_mix[i];
        self.local[i] = old.local[i];
        self.normal[i] = old.normal[i];
        self.stored[i] = old.stored[i];
        self.dissipated[i] = old.dissipated[i];
    }

    /// The arrays as read-only slices.
    #[inline(always)]
    fn view(&self) -> HistIn<'_> {
        HistIn {
            damage: self.damage,
            shear_secant: self.shear_secant,
            mode_mix: self.mode_mix,
            local: self.local,
            normal: self.normal,
            stored: self.stored,
            dissipated: self.dissipated,
        }
    }
}

/// One chunk of a pass, joints `j0..j0 + h.len()`: each joint's forces to its slots and its new
/// history to `h`, from its committed history in `old` (or, `IN_PLACE`, in `h` itself, where
/// the new one replaces it, each field only where it changed, and a joint that softens gets a
/// mark in `marks`). With `OFF` the law sees the joints' initial offsets. Blocks of
/// [`LANES`] intact undamaged joints go through the vectorised [`pre_peak_block`] (the same
/// results); the other joints, and a block where a lane passes a peak, joint by joint.
/// Returns the chunk's flags.
#[inline(always)]
fn chunk_pass<const OFF: bool, const IN_PLACE: bool>(
    inp: &PassIn<'_>,
    j0: usize,
    old: Option<HistIn<'_>>,
    mut h: HistOut<'_>,
    marks: &mut [u8],
) -> u8 {
    let n = h.damage.len();
    let c = Chunk::new(inp, j0, n);
    // the committed history (in place: the output arrays themselves)
    let old = old.unwrap_or(HistIn::EMPTY);
    let mut fl = 0u8;
    let (mut b, mut o) = (BlockIn::default(), BlockOut::default());
    let mut b0 = 0;
    while b0 < n {
        let b1 = (b0 + LANES).min(n);
        if OFF || b1 - b0 < LANES || !block_pass::<IN_PLACE>(&c, b0, &old, &mut h, (&mut b, &mut o))
        {
            for i in b0..b1 {
                fl |= joint_pass::<OFF, IN_PLACE>(&c, i, &old, &mut h, marks);
            }
        }
        b0 = b1;
    }
    fl
}

/// What one chunk of a pass reads besides the histories: the set's arrays from the chunk's
/// first joint on.
struct Chunk<'a> {
    set: &'a JointSet,
    x: &'a [[f64; 2]],
    out: &'a SlotBuf,
    pos: &'a [u32],
    ranks: &'a [u8],
    intact: &'a [bool],
    nodes: &'a [[u32; 4]],
    ref_length: &'a [f64],
    softening: &'a [SofteningConsts],
    material: &'a [u32],
    offsets: &'a [[f64; 2]],
}

impl<'a> Chunk<'a> {
    #[inline(always)]
    fn new(inp: &PassIn<'a>, j0: usize, n: usize) -> Self {
        let (set, r) = (inp.set, j0..j0 + n);
        Chunk {
            set,
            x: inp.x,
            out: inp.out,
            pos: if inp.ranks.is_empty() {
                &inp.slot_pos[4 * j0..4 * (j0 + n)]
            } else {
                &[]
            },
            ranks: if inp.ranks.is_empty() {
                &[]
            } else {
                &inp.ranks[r.clone()]
            },
            intact: &inp.intact[r.clone()],
            nodes: &set.nodes[r.clone()],
            ref_length: &set.ref_length[r.clone()],
            softening: &set.softening[r.clone()],
            material: &set.material[r.clone()],
            offsets: if set.initial_offsets.is_empty() {
                &[]
            } else {
                &set.initial_offsets[r]
            },
        }
    }

    /// The slot places of joint `i`'s four nodes.
    #[inline(always)]
    fn slots(&self, i: usize) -> [u32; 4] {
        if let Some(&r) = self.ranks.get(i) {
            let n = &self.nodes[i];
            std::array::from_fn(|k| 2 * n[k] + u32::from((r >> k) & 1))
        } else {
            let p = &self.pos[4 * i..4 * i + 4];
            [p[0], p[1], p[2], p[3]]
        }
    }
}

/// The `LANES` entries of `v` from `b0` on.
#[inline(always)]
fn lanes<T>(v: &[T], b0: usize) -> &[T; LANES] {
    v[b0..b0 + LANES].try_into().expect("a whole block")
}

/// The `LANES` entries of `v` from `b0` on, to write.
#[inline(always)]
fn lanes_mut<T>(v: &mut [T], b0: usize) -> &mut [T; LANES] {
    (&mut v[b0..b0 + LANES]).try_into().expect("a whole block")
}

/// Joints `b0..b0 + LANES` of the chunk through [`pre_peak_block`], if every one is intact
/// and undamaged and stays before both peaks: then their forces and new history are written
/// (as [`joint_pass`] writes them) and the answer is true. Otherwise nothing is written.
/// `b` and `o` are the block's buffers (every lane of every field is written before it is
/// read).
#[inline(always)]
fn block_pass<const IN_PLACE: bool>(
    c: &Chunk<'_>,
    b0: usize,
    old: &HistIn<'_>,
    h: &mut HistOut<'_>,
    (b, o): (&mut BlockIn, &mut BlockOut),
) -> bool {
    let src = if IN_PLACE { h.view() } else { *old };
    let (intact, damage) = (lanes(c.intact, b0), lanes(src.damage, b0));
    if !(intact.iter().all(|&b| b) && damage.iter().all(|d| *d == [0.0; 2])) {
        return false;
    }
    let (nodes, ref_length, material) = (
        lanes(c.nodes, b0),
        lanes(c.ref_length, b0),
        lanes(c.material, b0),
    );
    let (secant, local, normal) = (
        lanes(src.shear_secant, b0),
        lanes(src.local, b0),
        lanes(src.normal, b0),
    );
    let (stored, dissipated) = (lanes(src.stored, b0), lanes(src.dissipated, b0));
    for l in 0..LANES {
        for (n, &nd) in nodes[l].iter().enumerate() {
            let xn = c.x[nd as usize];
            b.x[n][0][l] = xn[0];
            b.x[n][1][l] = xn[1];
        }
        b.h[l] = ref_length[l];
        let m = &c.set.materials[material[l] as usize];
        (b.ft[l], b.cohesion[l], b.tan_phi[l]) = (m.ft, m.cohesion, m.tan_phi);
        (b.p[l], b.p_t[l]) = (m.p, m.p_t);
        (b.secant[0][l], b.secant[1][l]) = (secant[l][0], secant[l][1]);
        for (q, u) in local[l].iter().enumerate() {
            b.local[q][l] = *u;
        }
        (b.normal[0][l], b.normal[1][l]) = (normal[l][0], normal[l][1]);
        (b.stored[l], b.dissipated[l]) = (stored[l], dissipated[l]);
    }
    if !pre_peak_block(b, c.set.thickness, o) {
        return false;
    }
    for l in 0..LANES {
        c.out.put(
            c.slots(b0 + l),
            std::array::from_fn(|n| [o.forces[n][0][l], o.forces[n][1][l]]),
        );
    }
    let secant_out = lanes_mut(h.shear_secant, b0);
    for l in 0..LANES {
        let k_b = [o.secant[0][l], o.secant[1][l]];
        if !IN_PLACE || k_b != [b.secant[0][l], b.secant[1][l]] {
            secant_out[l] = k_b;
        }
    }
    if !IN_PLACE {
        // an undamaged joint's damage and mode indicators stay 0
        *lanes_mut(h.damage, b0) = [[0.0; 2]; LANES];
        *lanes_mut(h.mode_mix, b0) = [[0.0; 2]; LANES];
    }
    let (local, normal) = (lanes_mut(h.local, b0), lanes_mut(h.normal, b0));
    for l in 0..LANES {
        local[l] = [o.local[0][l], o.local[1][l], o.local[2][l], o.local[3][l]];
        normal[l] = [o.normal[0][l], o.normal[1][l]];
    }
    *lanes_mut(h.stored, b0) = o.stored;
    *lanes_mut(h.dissipated, b0) = o.dissipated;
    true
}

/// Joint `i` of the chunk, on its own: its forces to its slots and its new history to `h`
/// (see [`chunk_pass`]). Returns its flags.
#[inline(always)]
fn joint_pass<const OFF: bool, const IN_PLACE: bool>(
    c: &Chunk<'_>,
    i: usize,
    old: &HistIn<'_>,
    h: &mut HistOut<'_>,
    marks: &mut [u8],
) -> u8 {
    let slots = c.slots(i);
    // the committed history (in place: the arrays about to be overwritten, read first)
    let src = if IN_PLACE { h.view() } else { *old };
    let (d_a, k_a) = (src.damage[i], src.shear_secant[i]);
    if !c.intact[i] {
        // a broken joint keeps its books (in place: untouched); no force
        c.out.put(slots, [[0.0; 2]; 4]);
        if !IN_PLACE {
            h.copy(i, old);
        }
        return 0;
    }
    // an undamaged joint's mode indicators are 0: not read
    let fresh = d_a == [0.0; 2];
    let mix_a = if fresh { [0.0; 2] } else { src.mode_mix[i] };
    let committed = (src.local[i], src.normal[i], k_a, src.stored[i]);
    let d_old = src.dissipated[i];
    let [np, nq, nr, ns] = c.nodes[i];
    let x = c.x;
    let xs = [
        x[np as usize],
        x[nq as usize],
        x[nr as usize],
        x[ns as usize],
    ];
    let mut e = JointEval::default();
    let mat = &c.set.materials[c.material[i] as usize];
    let th = c.set.thickness;
    let h_ref = c.ref_length[i];
    let stored = evaluate_into::<true, OFF>(
        mat,
        &mat.consts(h_ref),
        &c.softening[i],
        &xs,
        [d_a, mix_a, k_a],
        th,
        if OFF { c.offsets[i] } else { [0.0; 2] },
        e.out(),
    );
    let (d_b, mix_b, k_b, loc) = (e.damage, e.mode_mix, e.shear_secant, e.local);
    c.out.put(slots, e.forces);
    let u_b = [loc[2], loc[3], loc[6], loc[7]];
    let area = 0.5 * h_ref * th;
    h.dissipated[i] = d_old + step_dissipation(committed, &loc, stored, area);
    h.local[i] = u_b;
    h.normal[i] = [loc[0], loc[4]];
    h.stored[i] = stored;
    if !IN_PLACE || d_b != d_a {
        h.damage[i] = d_b;
    }
    if !IN_PLACE || k_b != k_a {
        h.shear_secant[i] = k_b;
    }
    if !IN_PLACE || mix_b != mix_a {
        h.mode_mix[i] = mix_b;
    }
    let mut fl = 0;
    if fresh && d_b != [0.0; 2] {
        fl |= SOFTENED;
        if IN_PLACE {
            marks[i] = 1;
        }
    }
    if d_b[0] >= 1.0 && d_b[1] >= 1.0 && breaks(&u_b, h_ref) {
        fl |= BREAKS;
    }
    fl
}

/// The nodal forces of a pass by node slot, written by the parallel pass: each joint writes
/// its own four slots (the slot positions are a permutation, so no two joints write the same
/// entry). The `f64` bits are held in relaxed atomics: plain loads and stores on the machine,
/// and safe to write from the pass's chunks.
#[derive(Debug, Default)]
struct SlotBuf(Vec<[AtomicU64; 2]>);

impl Clone for SlotBuf {
    fn clone(&self) -> Self {
        SlotBuf(
            self.0
                .iter()
                .map(|e| [0, 1].map(|d| AtomicU64::new(e[d].load(Relaxed))))
                .collect(),
        )
    }
}

impl SlotBuf {
    /// Sizes the buffer for `n` slots, each holding -0.0 until a joint writes it (the pages
    /// touched in parallel on the first sizing).
    fn fit(&mut self, n: usize) {
        if self.0.len() != n {
            let z = (-0.0f64).to_bits();
            self.0 = Vec::new();
            self.0.par_extend(
                (0..n)
                    .into_par_iter()
                    .map(|_| [AtomicU64::new(z), AtomicU64::new(z)]),
            );
        }
    }

    /// Writes a joint's four nodal forces to its slots.
    #[inline(always)]
    fn put(&self, slots: [u32; 4], f: [[f64; 2]; 4]) {
        for k in 0..4 {
            let e = &self.0[slots[k] as usize];
            e[0].store(f[k][0].to_bits(), Relaxed);
            e[1].store(f[k][1].to_bits(), Relaxed);
        }
    }

    /// The force in slot `p`.
    #[inline(always)]
    fn get(&self, p: usize) -> [f64; 2] {
        let e = &self.0[p];
        [
            f64::from_bits(e[0].load(Relaxed)),
            f64::from_bits(e[1].load(Relaxed)),
        ]
    }
}

/// Fully damaged (z(1) = 0: no tension, no shear) and open at both points: the joint carries
/// no force, so removing it changes no force and no energy, and the faces reach contact
/// without overlap. A fully damaged joint closed at a point keeps carrying that compression
/// (frictionless) until it opens, or until it has slid by a tenth of its length (its
/// kinematics no longer describe the faces well: contact takes over, with the energy jump the
/// solver measures). `local` is `[o_0, s_0, o_1, s_1]`, `h` the reference length.
#[inline]
fn breaks(local: &[f64; 4], h: f64) -> bool {
    let open = local[0] >= 0.0 && local[2] >= 0.0;
    let slid = local[1].abs().max(local[3].abs()) >= SLID * h;
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
    trial_evaluation(set, state, x, scratch);
    gather(set, x, scratch, f);
    scratch.valid = Some(state.generation);
}

/// The checks and the pass of [`accumulate_joint_forces`] and [`joint_forces_ahead`].
fn trial_evaluation(set: &JointSet, state: &JointState, x: &[[f64; 2]], s: &mut JointScratch) {
    check_sizes(set, state, x);
    assert!(
        s.in_place.is_none(),
        "a joint pass between an in-place pass and its commit"
    );
    trial_pass(set, state, x, s);
}

/// The checks and the pass of the committing variants.
fn in_place_evaluation(
    set: &JointSet,
    state: &mut JointState,
    x: &[[f64; 2]],
    s: &mut JointScratch,
) {
    check_sizes(set, state, x);
    assert!(
        s.in_place.is_none(),
        "a joint pass between an in-place pass and its commit"
    );
    if set.initial_offsets.is_empty() {
        in_place_pass::<false>(set, state, x, s);
    } else {
        in_place_pass::<true>(set, state, x, s);
    }
}

/// [`accumulate_joint_forces`] for the last force evaluation of a step that ends with
/// [`commit_joints_at_last_pass`] at these positions `x`, with no other joint pass in between
/// (the caller knows it: the time crate's central difference says so before its evaluation).
/// Each joint's new history is written over its committed one instead of into the scratch's
/// trial arrays, and the commit then only books the breaks and the newly softened joints: the
/// same forces, histories and events bit for bit, with one history array less to read and
/// write per step.
pub fn accumulate_joint_forces_committing(
    set: &JointSet,
    state: &mut JointState,
    x: &[[f64; 2]],
    scratch: &mut JointScratch,
    f: &mut [[f64; 2]],
) {
    assert_eq!(f.len(), set.n_nodes, "forces must have one entry per node");
    in_place_evaluation(set, state, x, scratch);
    gather(set, x, scratch, f);
    scratch.valid = None;
    scratch.in_place = Some(state.generation);
}

/// The per-node gather of the last pass's slot forces into `f`; the positions are kept for the
/// commit on the way, unless the caller turned the check off.
fn gather(set: &JointSet, x: &[[f64; 2]], scratch: &mut JointScratch, f: &mut [[f64; 2]]) {
    let sc = &*scratch;
    if scratch.skip_position_copy {
        f.par_chunks_mut(NODE_CHUNK)
            .with_min_len(min_chunks(set.len()))
            .enumerate()
            .for_each(|(c, fc)| gather_range(set, sc, c * NODE_CHUNK, fc));
    } else {
        let mut x_last = std::mem::take(&mut scratch.x_last);
        x_last.resize(x.len(), [0.0; 2]);
        let sc = &*scratch;
        f.par_chunks_mut(NODE_CHUNK)
            .zip(x_last.par_chunks_mut(NODE_CHUNK))
            .zip(x.par_chunks(NODE_CHUNK))
            .with_min_len(min_chunks(set.len()))
            .enumerate()
            .for_each(|(c, ((fc, xl), xc))| {
                xl.copy_from_slice(xc);
                gather_range(set, sc, c * NODE_CHUNK, fc);
            });
        scratch.x_last = x_last;
    }
}

/// Adds to `fc`, the forces of nodes `i0..i0 + fc.len()`, each node's slot forces in the order
/// of its (joint, slot) list (increasing joint order): `f_i += f_slot`, slot after slot.
#[inline(always)]
fn gather_range(set: &JointSet, scratch: &JointScratch, i0: usize, fc: &mut [[f64; 2]]) {
    let forces = &scratch.slot_forces;
    if scratch.pairs {
        for (i, fi) in (2 * i0..).step_by(2).zip(fc) {
            let (a, b) = (forces.get(i), forces.get(i + 1));
            fi[0] += a[0];
            fi[1] += a[1];
            fi[0] += b[0];
            fi[1] += b[1];
        }
    } else {
        let off = &set.node_offsets[i0..i0 + fc.len() + 1];
        for (fi, w) in fc.iter_mut().zip(off.windows(2)) {
            for p in w[0] as usize..w[1] as usize {
                let fe = forces.get(p);
                fi[0] += fe[0];
                fi[1] += fe[1];
            }
        }
    }
}

/// The joint pass of [`accumulate_joint_forces`] without its gather, for a caller that adds
/// the joints' forces node range by node range with [`add_joint_forces`], inside a pass of its
/// own over the node forces (the solver's element pass, while each range is in cache): the
/// same forces, trial history and commit, bit for bit, with one trip through the node array
/// less.
pub fn joint_forces_ahead(
    set: &JointSet,
    state: &JointState,
    x: &[[f64; 2]],
    scratch: &mut JointScratch,
) {
    trial_evaluation(set, state, x, scratch);
    keep_positions(set, x, scratch);
    scratch.valid = Some(state.generation);
}

/// [`joint_forces_ahead`] for the last force evaluation of a step, as
/// [`accumulate_joint_forces_committing`] is to [`accumulate_joint_forces`].
pub fn joint_forces_ahead_committing(
    set: &JointSet,
    state: &mut JointState,
    x: &[[f64; 2]],
    scratch: &mut JointScratch,
) {
    in_place_evaluation(set, state, x, scratch);
    keep_positions(set, x, scratch);
    scratch.valid = None;
    scratch.in_place = Some(state.generation);
}

/// Adds the forces of the last [`joint_forces_ahead`] (or its committing variant) on nodes
/// `i0..i0 + f.len()` to `f`, with the arithmetic of [`accumulate_joint_forces`]'s gather.
/// Callable from parallel tasks on disjoint ranges.
pub fn add_joint_forces(set: &JointSet, scratch: &JointScratch, i0: usize, f: &mut [[f64; 2]]) {
    assert!(
        i0 + f.len() <= set.n_nodes,
        "node range past the joint set's nodes"
    );
    gather_range(set, scratch, i0, f);
}

/// The positions of a pass kept for the commit, unless the caller turned the check off.
fn keep_positions(set: &JointSet, x: &[[f64; 2]], scratch: &mut JointScratch) {
    if !scratch.skip_position_copy {
        scratch.x_last.resize(x.len(), [0.0; 2]);
        scratch
            .x_last
            .par_chunks_mut(NODE_CHUNK)
            .zip(x.par_chunks(NODE_CHUNK))
            .with_min_len(min_chunks(set.len()))
            .for_each(|(xl, xc)| xl.copy_from_slice(xc));
    }
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
    let n = set.len();
    let in_place = scratch.in_place.take().is_some();
    if in_place {
        // the pass wrote the new history over the committed one
        assert!(
            at_last_pass,
            "an in-place joint pass must be committed at its positions"
        );
    } else {
        let reuse = at_last_pass && scratch.valid == Some(state.generation);
        if !reuse {
            trial_pass(set, state, x, scratch);
        }
        std::mem::swap(&mut state.history, &mut scratch.trial);
    }
    scratch.valid = None;
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
            let h = &state.history;
            // the arrays swapped: the scratch holds the history before the step (in place:
            // the pass marked the joints that softened)
            if fl & SOFTENED != 0 {
                let softened = if in_place {
                    std::mem::take(&mut scratch.marks[j]) != 0
                } else {
                    scratch.trial.damage[j] == [0.0; 2] && h.damage[j] != [0.0; 2]
                };
                if softened {
                    scratch.softened.push(j as u32);
                }
            }
            if fl & BREAKS != 0
                && h.damage[j][0] >= 1.0
                && h.damage[j][1] >= 1.0
                && breaks(&h.local[j], set.ref_length[j])
            {
                let stored = h.stored[j];
                let p = set.gather(j, x);
                let mix = h.joint_mode_mix(j);
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
                    energy_released: h.dissipated[j],
                    stored_at_break: stored,
                });
                state.record_break(j, time, stored);
                n_new += 1;
            }
        }
    }
    n_new
}
