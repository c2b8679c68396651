//! The contact model the solver drives: detection with refresh, the parallel force pass with
//! deterministic scatter, friction history with an end-of-step commit, walls and energies.
//!
//! Per step the solver calls, in order:
//! 1. [`Contact::update_detection`] (redetects only when a node or a plane has moved `b/2`
//!    since the last detection, or the bonded list was set / topology changed); pairs that
//!    stop being bonded are released by [`Contact::release_pairs`], which adds the couples
//!    among them that the last detection would have listed, without a re-detection;
//! 2. [`Contact::compute_forces`] any number of times (trial stages included): it reads the
//!    committed friction history and writes only trial values;
//! 3. [`Contact::add_forces`] (or [`Contact::add_family`]) to scatter into the node forces;
//! 4. [`Contact::commit`] once at the end of the step (the time crate's end-of-step hook).
//!
//! The force pass evaluates every couple in parallel (rayon) into a per-couple buffer and
//! scatters serially in couple order, so the result is bit-identical for any thread count;
//! once the buffers have grown to the largest couple count, a step allocates nothing.
//!
//! Layout for speed: the vertices and vertex box of every triangle that is in a couple or a
//! plane candidate are gathered once per pass into a table (`tri_x`, `tri_box`), so a couple
//! reads two contiguous records instead of six scattered nodes, and is rejected on its boxes
//! before any other work. One byte per couple
//! (`flags`) says whether its result slot holds a force; only couples that overlap write
//! their slot, and the statistics and the scatter read only flagged slots. A couple that was
//! not flagged before and stays without force touches nothing but its flag (its trial
//! friction is then already zero).

use rayon::prelude::*;

use crate::bounding::BoundingCircles;
use crate::broad_parry::ParryBroadPhase;
use crate::couple::{CoupleForce, WallForce, couple_force_from_loads, loads_empty, wall_force};
use crate::exclusions::Exclusions;
use crate::friction::stored_energy;
use crate::geom::{V2, add, dot, norm, sub};
use crate::laws::{BroadPhase, ContactLaws, ContactSettings};
use crate::narrow::separated;
use crate::nbs::Nbs;
use crate::potential_tri_tri::{pair_energy, pair_loads};
use crate::walls::RigidPlane;

mod part;
mod snapshot;
pub use part::{COUPLE_SHARE, LEAD, LOCAL, TALLY, Tally, WALL_SHARE, react};
pub use snapshot::ContactSnapshot;

/// The exact refresh test on one chunk: some node moved `|x - x_det|^2 >= h2`, or is NaN.
fn moved_exact(xa: &[V2], xb: &[V2], h2: f64) -> bool {
    xa.iter().zip(xb).fold(false, |moved, (a, b)| {
        let d = sub(*a, *b);
        let d2 = d[0] * d[0] + d[1] * d[1];
        moved | (d2 >= h2) | d2.is_nan()
    })
}

/// Errors found at the contact check point.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ContactError {
    /// A contact went deeper than the allowed fraction of the altitude.
    #[error(
        "contact between {what} reached phi = {phi:.3} (penetration {pct:.0}% of the altitude H/3 at which the \
         potential force stops growing), above the limit {limit:.3}: the time step is too large for the impact \
         speed or the contact penalty is too low; reduce dt or raise the penalty"
    )]
    TooDeep {
        /// Which couple, in words (triangle ids or plane id).
        what: String,
        /// Largest phi reached.
        phi: f64,
        /// phi as a percentage of the limit depth H/3.
        pct: f64,
        /// The limit from the settings.
        limit: f64,
    },
    /// Triangles in contact were degenerate, inverted or had non-finite positions.
    #[error(
        "{count} contact couples involve degenerate, inverted or non-finite triangles (first: triangles {first:?}); \
         they carry no contact force: check the element check point for inverted elements or NaN"
    )]
    InvalidTriangles {
        /// Number of such couples.
        count: usize,
        /// The first such couple.
        first: [u32; 2],
    },
}

/// Summary of the last force pass.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactStats {
    /// Triangle couples evaluated.
    pub n_couples: usize,
    /// Triangle couples with a non-zero normal force.
    pub n_active: usize,
    /// Plane-triangle couples with a non-zero normal force.
    pub n_wall_active: usize,
    /// Edges slipping.
    pub n_slipping: usize,
    /// Largest phi on a contacting edge (0..1; `phi = 3 d/H`).
    pub max_phi: f64,
    /// The couple with the largest phi: triangles `[i, j]`, or `[u32::MAX, tri]` for a plane.
    pub max_phi_couple: [u32; 2],
    /// The sum over the couples and plane pairs with a non-zero normal force of each one's
    /// largest phi (its mean over them: this over `n_active + n_wall_active`).
    pub sum_phi_loaded: f64,
    /// Couples skipped because a triangle was degenerate, inverted or not finite.
    pub n_invalid: usize,
    /// First such couple.
    pub first_invalid: [u32; 2],
    /// Slip dissipation of this (trial) step \[J/m\]; booked by [`Contact::commit`].
    pub trial_dissipation: f64,
}

impl ContactStats {
    /// The check point: an error if a contact reached `phi > max_phi` or a couple was invalid.
    pub fn check(&self, max_phi: f64) -> Result<(), ContactError> {
        if self.n_invalid > 0 {
            return Err(ContactError::InvalidTriangles {
                count: self.n_invalid,
                first: self.first_invalid,
            });
        }
        if self.max_phi > max_phi {
            let [a, b] = self.max_phi_couple;
            let what = if a == u32::MAX {
                format!("a rigid plane and triangle {b}")
            } else {
                format!("triangles {a} and {b}")
            };
            return Err(ContactError::TooDeep {
                what,
                phi: self.max_phi,
                pct: 100.0 * self.max_phi,
                limit: max_phi,
            });
        }
        Ok(())
    }
}

/// Energies of the contact state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactEnergy {
    /// Potential `sum p int (phi_c + phi_t) dA` over couples and planes \[J/m\].
    pub potential: f64,
    /// Stored tangential spring energy `sum Ft^2/(2 k_t)` (committed) \[J/m\].
    pub friction_stored: f64,
    /// Slip dissipation committed since the start \[J/m\].
    pub friction_dissipated: f64,
}

/// Force family, for separate work bookkeeping.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// Normal potential force.
    Normal,
    /// Coulomb friction.
    Friction,
    /// Contact damping.
    Damping,
}

/// The contact model: settings, laws, planes, and the state and scratch it owns.
pub struct Contact {
    /// Detection settings.
    pub settings: ContactSettings,
    /// Laws per pair of materials.
    pub laws: ContactLaws,
    /// Rigid planes and platens (move a platen by changing its `point` and `velocity`).
    pub walls: Vec<RigidPlane>,
    excl: Exclusions,
    circles: BoundingCircles,
    nbs: Nbs,
    parry: ParryBroadPhase,
    x_det: Vec<V2>,
    /// `x_det` rounded to single precision: the refresh check's filter (see
    /// [`Contact::update_detection`]).
    x_det32: Vec<[f32; 2]>,
    /// The filter's bound: a node with `|x - x_det32|^2 < det32_clear` has certainly moved
    /// less than `b/2` (negative: the filter clears nothing).
    det32_clear: f64,
    wall_det: Vec<V2>,
    n_tris_det: usize,
    buffer: f64,
    stale: bool,
    n_detections: u64,
    couples: Vec<[u32; 2]>,
    ft: Vec<[f64; 6]>,
    ft_trial: Vec<[f64; 6]>,
    results: Vec<CoupleForce>,
    /// Per couple: 1 when its `results` slot may hold a force (or an invalid report).
    flags: Vec<u8>,
    /// Per triangle, this pass: vertices and vertex box `[xmin, xmax, ymin, ymax]` (gathered
    /// only for the triangles `tri_used` marks).
    tri_x: Vec<[V2; 3]>,
    tri_box: Vec<[f64; 4]>,
    /// Per triangle: bit 0 when it is in a couple or a plane candidate, bit 1 when in one
    /// this rank evaluates (set at each detection, and by releases; both bits outside a
    /// distributed run).
    tri_used: Vec<u8>,
    wall_pairs: Vec<[u32; 2]>,
    wall_ft: Vec<f64>,
    wall_ft_trial: Vec<f64>,
    wall_results: Vec<WallForce>,
    scratch_couples: Vec<[u32; 2]>,
    scratch_ft: Vec<[f64; 6]>,
    scratch_wall_ft: Vec<f64>,
    /// Per candidate of a detection: kept by the narrow filter.
    keep: Vec<u8>,
    /// Couples added by the last [`Contact::release_pairs`], sorted.
    added: Vec<[u32; 2]>,
    n_released_couples: u64,
    friction_dissipated: f64,
    stats: ContactStats,
    /// Per triangle in one rank's part of a distributed run: [`LOCAL`] when the rank evaluates
    /// the couples and plane pairs of the triangle, [`LEAD`] when it also counts them in the
    /// statistics and books ([`part`]). Empty: the whole model.
    part: Vec<u8>,
    /// The part set aside while [`Contact::set_whole`] evaluates every couple.
    held_part: Vec<u8>,
}

impl Contact {
    /// A contact model with no planes and no bonded pairs.
    pub fn new(settings: ContactSettings, laws: ContactLaws) -> Self {
        Contact {
            settings,
            laws,
            walls: Vec::new(),
            excl: Exclusions::new(),
            circles: BoundingCircles::default(),
            nbs: Nbs::new(),
            parry: ParryBroadPhase::new(),
            x_det: Vec::new(),
            x_det32: Vec::new(),
            det32_clear: -1.0,
            wall_det: Vec::new(),
            n_tris_det: 0,
            buffer: settings.buffer,
            stale: true,
            n_detections: 0,
            couples: Vec::new(),
            ft: Vec::new(),
            ft_trial: Vec::new(),
            results: Vec::new(),
            flags: Vec::new(),
            tri_x: Vec::new(),
            tri_box: Vec::new(),
            tri_used: Vec::new(),
            wall_pairs: Vec::new(),
            wall_ft: Vec::new(),
            wall_ft_trial: Vec::new(),
            wall_results: Vec::new(),
            scratch_couples: Vec::new(),
            scratch_ft: Vec::new(),
            scratch_wall_ft: Vec::new(),
            keep: Vec::new(),
            added: Vec::new(),
            n_released_couples: 0,
            friction_dissipated: 0.0,
            stats: ContactStats::default(),
            part: Vec::new(),
            held_part: Vec::new(),
        }
    }

    /// Sets the bonded pairs (intact joints): they are never contact couples. The next
    /// [`Self::update_detection`] redetects. When joints break, [`Self::release_pairs`] is the
    /// cheap way to thin the list (no re-detection).
    pub fn set_bonded(&mut self, n_tris: usize, pairs: &[[u32; 2]]) {
        self.excl.set_bonded(n_tris, pairs);
        self.stale = true;
    }

    /// Releases bonded pairs (broken joints, stars that stopped bonding): from now on they
    /// are not excluded. Without a new detection: while the last detection is current (not
    /// stale, same triangle count), a released pair becomes a couple at once exactly when
    /// that detection would have listed it with the new exclusions (its criterion at the
    /// detection positions: bounding circles within the buffer `b`,
    /// `|c_i - c_j| <= r_i + r_j + b`, no shared node, and with the narrow filter no edge line
    /// separating the triangles by more than `b`); it starts with no friction history. The
    /// other released pairs were more than `b` apart at the detection, so they cannot touch
    /// before the refresh criterion triggers the next detection, which lists them when they
    /// have come close. When the detection is not current, the next
    /// [`Self::update_detection`] redetects anyway.
    ///
    /// The couple list stays sorted (merged from the back, in place: `O(couples + released)`,
    /// no allocation once the buffers are large enough). Pairs in any orientation; pairs that
    /// were not bonded, repeated, or naming a triangle `>= tris.len()` are harmless. Returns
    /// the number of couples added ([`Self::added_couples`] lists them).
    pub fn release_pairs(&mut self, pairs: &[[u32; 2]], tris: &[[u32; 3]]) -> usize {
        let n = tris.len();
        if !self.stale && n == self.n_tris_det && self.circles.len() != n {
            // Restored from a snapshot: the circles of the last detection, from its positions.
            self.circles.update(&self.x_det, tris);
        }
        let current = !self.stale && n == self.n_tris_det && self.circles.len() == n;
        self.added.clear();
        for p in pairs {
            let (i, j) = (p[0].min(p[1]), p[0].max(p[1]));
            if (j as usize) >= n || i == j || !self.excl.unbond(i, j) {
                continue;
            }
            if current && self.detection_keeps(i, j, tris) {
                self.added.push([i, j]);
            }
        }
        if self.added.is_empty() {
            return 0;
        }
        // Each pair was bonded, hence not a couple; unbond succeeded once per pair, so the
        // list holds no repeats. Sorted, it merges into the sorted couples.
        self.added.sort_unstable();
        self.merge_added();
        self.n_released_couples += self.added.len() as u64;
        self.added.len()
    }

    /// The couple criterion of the last detection, at its positions: bounding circles within
    /// the buffer, not excluded, and (with the narrow filter) not separated by more than `b`.
    fn detection_keeps(&self, i: u32, j: u32, tris: &[[u32; 3]]) -> bool {
        let b = self.buffer;
        let v = |t: u32| tris[t as usize].map(|n| self.x_det[n as usize]);
        self.circles.near(i as usize, j as usize, b)
            && !self.excl.excluded(tris, i, j)
            && !(self.settings.narrow && separated(&v(i), &v(j), b))
    }

    /// Merges the sorted `added` couples (none of them present) into the sorted couple list
    /// from the back, moving each couple's committed and trial friction and its flag; a moved
    /// couple's result slot moves only when its flag says it may hold a force, otherwise only
    /// its `active` is cleared (so `couple_results` stays truthful). New couples: no friction,
    /// flag set, not active until the next force pass.
    fn merge_added(&mut self) {
        let (n_old, k) = (self.couples.len(), self.added.len());
        let n = n_old + k;
        self.results.resize(n_old, CoupleForce::default());
        self.flags.resize(n_old, 1);
        self.couples.resize(n, [0, 0]);
        self.ft.resize(n, [0.0; 6]);
        self.ft_trial.resize(n, [0.0; 6]);
        self.flags.resize(n, 1);
        self.results.resize(n, CoupleForce::default());
        for c in &self.added {
            self.tri_used[c[0] as usize] = 3;
            self.tri_used[c[1] as usize] = 3;
        }
        let (mut i, mut a, mut w) = (n_old, k, n);
        while a > 0 {
            w -= 1;
            if i > 0 && self.couples[i - 1] > self.added[a - 1] {
                i -= 1;
                self.couples[w] = self.couples[i];
                self.ft[w] = self.ft[i];
                self.ft_trial[w] = self.ft_trial[i];
                self.flags[w] = self.flags[i];
                if self.flags[i] != 0 {
                    self.results[w] = self.results[i];
                } else {
                    self.results[w].active = false;
                }
            } else {
                a -= 1;
                self.couples[w] = self.added[a];
                self.ft[w] = [0.0; 6];
                self.ft_trial[w] = [0.0; 6];
                self.flags[w] = 1;
                self.results[w].active = false;
            }
        }
    }

    /// The couples added by the last [`Self::release_pairs`] call, sorted.
    pub fn added_couples(&self) -> &[[u32; 2]] {
        &self.added
    }

    /// Number of couples added by [`Self::release_pairs`] so far (without a detection).
    pub fn n_released_couples(&self) -> u64 {
        self.n_released_couples
    }

    /// Number of bonded pairs still excluded.
    pub fn n_bonded(&self) -> usize {
        self.excl.len()
    }

    /// Forces a new detection at the next [`Self::update_detection`].
    pub fn invalidate(&mut self) {
        self.stale = true;
    }

    /// The buffer in use \[m\] (fixed at the first detection when the setting is 0).
    pub fn buffer(&self) -> f64 {
        self.buffer
    }

    /// Number of detections done so far.
    pub fn n_detections(&self) -> u64 {
        self.n_detections
    }

    /// The current triangle couples `(i < j)`, sorted.
    pub fn couples(&self) -> &[[u32; 2]] {
        &self.couples
    }

    /// Per-couple results of the last force pass, aligned with [`Self::couples`]; entries with
    /// `active == false` carry no force and their other fields are stale.
    pub fn couple_results(&self) -> &[CoupleForce] {
        &self.results
    }

    /// Per couple, aligned with [`Self::couples`]: 0 when the last force pass found no force
    /// (the result slot is stale), 1 when the slot holds a result (a force or an invalid
    /// report). One byte a couple: a cheap filter before reading [`Self::couple_results`].
    pub fn couple_flags(&self) -> &[u8] {
        &self.flags
    }

    /// The current plane-triangle candidates `[plane, tri]`, sorted.
    pub fn wall_pairs(&self) -> &[[u32; 2]] {
        &self.wall_pairs
    }

    /// Per-candidate results of the last force pass, aligned with [`Self::wall_pairs`].
    pub fn wall_results(&self) -> &[WallForce] {
        &self.wall_results
    }

    /// Statistics of the last force pass.
    pub fn stats(&self) -> &ContactStats {
        &self.stats
    }

    /// Redetects if needed (rigorous criterion, module docs); returns true if it did.
    ///
    /// The criterion is exact: a node moved `|x - x_det| >= b/2` since the last detection
    /// (in double precision, NaN counting as moved), or a plane moved `b/2` along its normal.
    /// To read less memory per step, each chunk of 8 192 nodes is first compared with a
    /// single-precision copy of the detection positions: where every node of the chunk is
    /// closer to its copy than `b/2` minus the copy's rounding bound (`det32_clear`), no node
    /// of the chunk can have moved `b/2`, and the chunk is done; only the other chunks are
    /// compared with the double-precision positions. The answer is always the exact test's
    /// (7.2 MB read instead of 9.6 MB for 600 000 nodes while nothing is near the bound).
    pub fn update_detection(&mut self, x: &[V2], tris: &[[u32; 3]]) -> bool {
        let mut need = self.stale
            || x.len() != self.x_det.len()
            || x.len() != self.x_det32.len()
            || tris.len() != self.n_tris_det
            || self.walls.len() != self.wall_det.len();
        if !need {
            let half = 0.5 * self.buffer;
            let h2 = half * half;
            let clear = self.det32_clear;
            // Branch-free per chunk (vectorises), chunks in parallel; NaN counts as moved
            // (and never passes the filter: `NaN < clear` is false).
            need = x
                .par_chunks(8192)
                .zip(self.x_det32.par_chunks(8192))
                .zip(self.x_det.par_chunks(8192))
                .any(|((xa, xf), xb)| {
                    let cleared = xa.iter().zip(xf).fold(true, |ok, (a, f)| {
                        let d = [a[0] - f64::from(f[0]), a[1] - f64::from(f[1])];
                        ok & (d[0] * d[0] + d[1] * d[1] < clear)
                    });
                    !cleared && moved_exact(xa, xb, h2)
                })
                || self.walls.iter().zip(&self.wall_det).any(|(w, p0)| {
                    let s = dot(sub(w.point, *p0), w.normal).abs();
                    s >= half || s.is_nan()
                });
        }
        if need {
            self.detect(x, tris);
        }
        need
    }

    /// Detects couples now, keeping the friction history of couples found again.
    pub fn detect(&mut self, x: &[V2], tris: &[[u32; 3]]) {
        self.circles.update(x, tris);
        if self.buffer <= 0.0 || self.buffer.is_nan() {
            let (s, n) = self
                .circles
                .r
                .iter()
                .filter(|r| r.is_finite())
                .fold((0.0, 0usize), |(s, n), r| (s + r, n + 1));
            self.buffer = if n > 0 { 0.2 * s / n as f64 } else { 0.0 };
        }
        let b = self.buffer;
        let mut found = std::mem::take(&mut self.scratch_couples);
        match self.settings.broad_phase {
            BroadPhase::Nbs => {
                self.nbs
                    .find_couples(&self.circles, b, tris, &self.excl, &mut found)
            }
            BroadPhase::ParryBvh => {
                self.parry
                    .find_couples(&self.circles, b, tris, &self.excl, &mut found)
            }
        }
        if self.settings.narrow {
            // Narrow filter (crate::narrow), per candidate in parallel, then a serial retain.
            self.keep.clear();
            self.keep.resize(found.len(), 0);
            self.keep
                .par_iter_mut()
                .zip(found.par_iter())
                .with_min_len(1024)
                .for_each(|(k, c)| {
                    let v = |t: u32| tris[t as usize].map(|n| x[n as usize]);
                    *k = !separated(&v(c[0]), &v(c[1]), b) as u8;
                });
            let mut keep = self.keep.iter();
            found.retain(|_| keep.next().is_some_and(|k| *k != 0));
        }
        // Carry the committed friction of couples found again (both lists sorted).
        self.scratch_ft.clear();
        let mut k = 0;
        for c in &found {
            while k < self.couples.len() && self.couples[k] < *c {
                k += 1;
            }
            let old = if k < self.couples.len() && self.couples[k] == *c {
                self.ft[k]
            } else {
                [0.0; 6]
            };
            self.scratch_ft.push(old);
        }
        std::mem::swap(&mut self.couples, &mut found);
        std::mem::swap(&mut self.ft, &mut self.scratch_ft);
        self.scratch_couples = found;
        self.ft_trial.clear();
        self.ft_trial.extend_from_slice(&self.ft);
        // Every slot is stale for the new list: the next pass rewrites each one.
        self.flags.clear();
        self.flags.resize(self.couples.len(), 1);

        // Plane candidates: bounding circle within the buffer of the plane.
        let mut found = std::mem::take(&mut self.scratch_couples);
        found.clear();
        for (w, plane) in self.walls.iter().enumerate() {
            for e in 0..self.circles.len() {
                let r = self.circles.r[e];
                if r.is_finite() && plane.signed_distance(self.circles.c[e]) < r + b {
                    found.push([w as u32, e as u32]);
                }
            }
        }
        self.scratch_wall_ft.clear();
        let mut k = 0;
        for c in &found {
            while k < self.wall_pairs.len() && self.wall_pairs[k] < *c {
                k += 1;
            }
            let old = if k < self.wall_pairs.len() && self.wall_pairs[k] == *c {
                self.wall_ft[k]
            } else {
                0.0
            };
            self.scratch_wall_ft.push(old);
        }
        std::mem::swap(&mut self.wall_pairs, &mut found);
        std::mem::swap(&mut self.wall_ft, &mut self.scratch_wall_ft);
        self.scratch_couples = found;
        self.wall_ft_trial.clear();
        self.wall_ft_trial.extend_from_slice(&self.wall_ft);

        // The triangles the force pass reads.
        self.tri_used.clear();
        self.tri_used.resize(tris.len(), 0);
        for c in &self.couples {
            let m = 1 | (self.couple_local(c) as u8) << 1;
            self.tri_used[c[0] as usize] |= m;
            self.tri_used[c[1] as usize] |= m;
        }
        for c in &self.wall_pairs {
            self.tri_used[c[1] as usize] |= 1 | (self.tri_local(c[1]) as u8) << 1;
        }

        self.x_det.clear();
        self.x_det.extend_from_slice(x);
        self.set_det32();
        self.wall_det.clear();
        self.wall_det.extend(self.walls.iter().map(|w| w.point));
        self.n_tris_det = tris.len();
        self.stale = false;
        self.n_detections += 1;
    }

    /// The single-precision copy of the detection positions and the filter's bound:
    /// `(b/2 (1 - 1e-9) - e)^2` with `e = 2^-23 max |x_det| + 2^-140` bounding the copy's rounding
    /// error per node (at most `2^-24 |x|` per coordinate, so `|x_det32 - x_det| <= 2^-24
    /// sqrt 2 max |x|`); the relative `1e-9` covers the rounding of the double-precision
    /// differences and squares (about `2^-52` each). Non-finite positions, or an `e` not
    /// below the margin, switch the filter off (bound -1: only the exact test decides).
    fn set_det32(&mut self) {
        self.x_det32.resize(self.x_det.len(), [0.0; 2]);
        // Per node, in parallel; the largest coordinate and the finiteness are exact
        // reductions (any order gives the same value).
        let (finite, amax) = self
            .x_det32
            .par_iter_mut()
            .zip(self.x_det.par_iter())
            .with_min_len(8192)
            .fold(
                || (true, 0.0f64),
                |(ok, m), (f, p)| {
                    *f = [p[0] as f32, p[1] as f32];
                    (
                        ok & p[0].is_finite() & p[1].is_finite(),
                        m.max(p[0].abs()).max(p[1].abs()),
                    )
                },
            )
            .reduce(|| (true, 0.0f64), |a, b| (a.0 & b.0, a.1.max(b.1)));
        // plus 2^-140 for coordinates below f32's normal range (spacing 2^-149 there)
        let e = amax * 2f64.powi(-23) + 2f64.powi(-140);
        let r = 0.5 * self.buffer * (1.0 - 1e-9) - e;
        self.det32_clear = if finite && r > 0.0 && r.is_finite() {
            r * r
        } else {
            -1.0
        };
    }

    /// Evaluates all contact forces (trial: the committed friction history is only read).
    /// `material[i]` is triangle i's material (empty slice: all 0); `v` may be empty (zero
    /// velocities) when no law has friction or damping; `dt` is the step used for the friction
    /// increment. Call [`Self::update_detection`] first (it redetects when the node or
    /// triangle count changed).
    pub fn compute_forces(
        &mut self,
        x: &[V2],
        v: &[V2],
        tris: &[[u32; 3]],
        material: &[u32],
        dt: f64,
    ) -> ContactStats {
        self.gather_triangles(x, tris);
        self.couple_pass(v, tris, material, dt);
        self.plane_pass(v, tris, dt);
        // Serial, fixed-order reduction of the statistics (in a distributed run, of the
        // couples and plane pairs this rank leads).
        let s = ContactStats::tally(self.couples.len(), self.tallies());
        self.stats = s;
        s
    }

    /// The vertices and box of every triangle in a couple or plane candidate, once per pass
    /// (of the triangles this pass reads, module `part`).
    fn gather_triangles(&mut self, x: &[V2], tris: &[[u32; 3]]) {
        self.tri_x.resize(tris.len(), [[0.0; 2]; 3]);
        self.tri_box.resize(tris.len(), [0.0; 4]);
        self.tri_used.resize(tris.len(), 3);
        // the marks of the triangles this pass reads (module `part`)
        let need = if self.part.is_empty() { 1 } else { 2 };
        self.tri_x
            .par_iter_mut()
            .zip(self.tri_box.par_iter_mut())
            .zip(tris.par_iter().zip(self.tri_used.par_iter()))
            .with_min_len(4096)
            .for_each(|((tx, tb), (t, used))| {
                if *used & need == 0 {
                    return;
                }
                *tx = t.map(|n| x[n as usize]);
                *tb = [
                    tx[0][0].min(tx[1][0]).min(tx[2][0]),
                    tx[0][0].max(tx[1][0]).max(tx[2][0]),
                    tx[0][1].min(tx[1][1]).min(tx[2][1]),
                    tx[0][1].max(tx[1][1]).max(tx[2][1]),
                ];
            });
    }

    /// The force of every couple, into `results` (trial friction into `ft_trial`); see
    /// [`Self::compute_forces`].
    fn couple_pass(&mut self, v: &[V2], tris: &[[u32; 3]], material: &[u32], dt: f64) {
        let laws = &self.laws;
        let mat = |i: u32| material.get(i as usize).copied().unwrap_or(0);
        let vel = |n: u32| v.get(n as usize).copied().unwrap_or([0.0; 2]);
        let (tri_x, tri_box) = (&self.tri_x, &self.tri_box);
        let part = &self.part;
        let local = |t: u32| part.get(t as usize).is_none_or(|r| r & LOCAL != 0);
        let nc = self.couples.len();
        self.results.resize(nc, CoupleForce::default());
        self.flags.resize(nc, 1);
        self.results
            .par_iter_mut()
            .zip(self.flags.par_iter_mut())
            .zip(self.ft_trial.par_iter_mut())
            .zip(self.couples.par_iter().zip(self.ft.par_iter()))
            .with_min_len(512)
            .for_each(|(((res, flag), ftt), (c, ft_old))| {
                let (i, j) = (c[0] as usize, c[1] as usize);
                if !local(c[0]) && !local(c[1]) {
                    // another rank's couple (a distributed run): no force here
                    *flag = 0;
                    return;
                }
                let law = laws.get(mat(c[0]), mat(c[1]));
                let (bi, bj) = (&tri_box[i], &tri_box[j]);
                let apart = bi[1] < bj[0] || bj[1] < bi[0] || bi[3] < bj[2] || bj[3] < bi[2];
                let loads = if !law.enabled || law.penalty <= 0.0 || apart {
                    None
                } else {
                    match pair_loads(&tri_x[i], &tri_x[j]) {
                        Some(l) if loads_empty(&l) => None,
                        Some(l) => Some(Some(l)),
                        None => Some(None), // invalid triangle
                    }
                };
                let Some(loads) = loads else {
                    // No force. Only a slot that may hold one is cleared; otherwise the slot
                    // and the trial friction (then already 0) are left alone.
                    if *flag != 0 {
                        *flag = 0;
                        res.active = false;
                        *ftt = [0.0; 6];
                    }
                    return;
                };
                *flag = 1;
                let Some(loads) = loads else {
                    *res = CoupleForce {
                        active: true,
                        invalid: true,
                        ..Default::default()
                    };
                    *ftt = [0.0; 6];
                    return;
                };
                let vs = if law.mu > 0.0 || law.damping > 0.0 {
                    let (ti, tj) = (&tris[i], &tris[j]);
                    [ti[0], ti[1], ti[2], tj[0], tj[1], tj[2]].map(vel)
                } else {
                    [[0.0; 2]; 6]
                };
                couple_force_from_loads(res, &tri_x[i], &tri_x[j], &loads, &vs, ft_old, dt, law);
                *ftt = res.ft;
            });
    }

    /// The force of every plane pair, into `wall_results` (trial friction into
    /// `wall_ft_trial`); see [`Self::compute_forces`].
    fn plane_pass(&mut self, v: &[V2], tris: &[[u32; 3]], dt: f64) {
        let vel = |n: u32| v.get(n as usize).copied().unwrap_or([0.0; 2]);
        let tri_x = &self.tri_x;
        let part = &self.part;
        let local = |t: u32| part.get(t as usize).is_none_or(|r| r & LOCAL != 0);
        let walls = &self.walls;
        self.wall_results
            .resize(self.wall_pairs.len(), WallForce::default());
        self.wall_results
            .par_iter_mut()
            .zip(self.wall_ft_trial.par_iter_mut())
            .zip(self.wall_pairs.par_iter().zip(self.wall_ft.par_iter()))
            .with_min_len(512)
            .for_each(|((res, ftt), (c, ft_old))| {
                // A plane removed since the last detection acts no more.
                let Some(plane) = walls.get(c[0] as usize) else {
                    *res = WallForce::default();
                    *ftt = 0.0;
                    return;
                };
                let t = &tris[c[1] as usize];
                // (another rank's plane pair in a distributed run: no force here)
                if !plane.law.enabled || plane.law.penalty <= 0.0 || !local(c[1]) {
                    *res = WallForce::default();
                    *ftt = 0.0;
                    return;
                }
                let xs = tri_x[c[1] as usize];
                let vs = t.map(vel);
                *res = wall_force(plane, &xs, &vs, *ft_old, dt);
                *ftt = res.ft;
            });
    }

    /// Adds all contact forces (normal + friction + damping) of the last pass to `f`, in
    /// couple order (deterministic).
    pub fn add_forces(&self, tris: &[[u32; 3]], f: &mut [V2]) {
        self.scatter(
            tris,
            f,
            |r| r.total,
            |r| std::array::from_fn(|k| add(add(r.normal[k], r.friction[k]), r.damping[k])),
        );
    }

    /// Adds one family of forces of the last pass to `f` (for separate work bookkeeping).
    pub fn add_family(&self, family: Family, tris: &[[u32; 3]], f: &mut [V2]) {
        match family {
            Family::Normal => self.scatter(tris, f, |r| r.normal, |r| r.normal),
            Family::Friction => self.scatter(tris, f, |r| r.friction, |r| r.friction),
            Family::Damping => self.scatter(tris, f, |r| r.damping, |r| r.damping),
        }
    }

    /// The couples of the last pass in contact with a load (active, normal force not 0), in
    /// couple order, each with the six nodes of its two triangles.
    fn loaded_couples<'a>(
        &'a self,
        tris: &'a [[u32; 3]],
    ) -> impl Iterator<Item = (&'a CoupleForce, [u32; 6])> + 'a {
        self.results
            .iter()
            .zip(&self.couples)
            .zip(&self.flags)
            .filter(|((r, _), f)| **f != 0 && r.active && r.fn_total != 0.0)
            .map(|((r, c), _)| {
                let (ti, tj) = (&tris[c[0] as usize], &tris[c[1] as usize]);
                (r, [ti[0], ti[1], ti[2], tj[0], tj[1], tj[2]])
            })
    }

    /// Adds to `f`, in couple order then plane-pair order, the nodal forces that `couple`
    /// picks from each couple in contact and `wall` from each plane pair.
    fn scatter(
        &self,
        tris: &[[u32; 3]],
        f: &mut [V2],
        couple: impl Fn(&CoupleForce) -> [V2; 6],
        wall: impl Fn(&WallForce) -> [V2; 3],
    ) {
        for (r, nodes) in self.loaded_couples(tris) {
            let g = couple(r);
            for k in 0..6 {
                let n = nodes[k] as usize;
                f[n] = add(f[n], g[k]);
            }
        }
        for (r, c) in self.wall_results.iter().zip(&self.wall_pairs) {
            let t = &tris[c[1] as usize];
            let g = wall(r);
            for k in 0..3 {
                let n = t[k] as usize;
                f[n] = add(f[n], g[k]);
            }
        }
    }

    /// Total force of the last pass on each plane (all families) \[N/m\], into `out`
    /// (length = number of planes): the reaction to what the plane does to the triangles.
    pub fn wall_reactions(&self, out: &mut [V2]) {
        out.iter_mut().for_each(|o| *o = [0.0; 2]);
        self.wall_forces(|_, plane, g| react(out, plane, &g));
    }

    /// Power dissipated by the contact damping of the last pass at node velocities `v` \[W/m\]:
    /// minus the power of the damping forces on the nodes and on the planes,
    /// `-sum_k f_d,k . (v_k - v_plane)` (`v_plane` 0 for triangle couples). A dashpot only
    /// removes energy, so it is `>= 0` up to the lag between the velocities the pass used and
    /// `v`. 0 at once, reading nothing, when no law (pair or plane) has damping.
    pub fn damping_power(&self, tris: &[[u32; 3]], v: &[V2]) -> f64 {
        let mut p = 0.0;
        self.damping_terms(tris, v, |_, terms| {
            for d in terms {
                p -= d;
            }
        });
        p
    }

    /// End-of-step hook: the trial tangential forces of the last pass become the committed
    /// history, and the pass's slip dissipation is booked.
    pub fn commit(&mut self) {
        self.ft.copy_from_slice(&self.ft_trial);
        self.wall_ft.copy_from_slice(&self.wall_ft_trial);
        self.friction_dissipated += self.stats.trial_dissipation;
    }

    /// Energies of the current state: the contact potential at positions `x` (parallel,
    /// summed in couple order), the committed tangential spring energy and the dissipation.
    pub fn energy(&self, x: &[V2], tris: &[[u32; 3]], material: &[u32]) -> ContactEnergy {
        let mat = |i: u32| material.get(i as usize).copied().unwrap_or(0);
        let mut potential = self.potential_of(&self.couples, x, tris, material);
        for c in &self.wall_pairs {
            let Some(plane) = self.walls.get(c[0] as usize) else {
                continue;
            };
            if plane.law.enabled {
                potential += plane.energy(&tris[c[1] as usize].map(|n| x[n as usize]));
            }
        }
        let mut friction_stored = 0.0;
        for (c, ft) in self.couples.iter().zip(&self.ft) {
            let kt = self.laws.get(mat(c[0]), mat(c[1])).kt;
            friction_stored += ft.iter().map(|f| stored_energy(*f, kt)).sum::<f64>();
        }
        for (c, ft) in self.wall_pairs.iter().zip(&self.wall_ft) {
            if let Some(w) = self.walls.get(c[0] as usize) {
                friction_stored += stored_energy(*ft, w.law.kt);
            }
        }
        ContactEnergy {
            potential,
            friction_stored,
            friction_dissipated: self.friction_dissipated,
        }
    }

    /// Contact potential `sum p int (phi_c + phi_t) dA` of the given triangle couples at
    /// positions `x` \[J/m\] (parallel, summed in list order: the same sum for any thread
    /// count), e.g. of [`Self::added_couples`]. `material` as in [`Self::compute_forces`].
    /// Below 512 couples it runs serially and allocates nothing; above, one `Vec<f64>` of
    /// per-couple values keeps the sum in list order.
    pub fn potential_of(
        &self,
        couples: &[[u32; 2]],
        x: &[V2],
        tris: &[[u32; 3]],
        material: &[u32],
    ) -> f64 {
        let pot = |c: &[u32; 2]| self.pair_potential(c, x, tris, material);
        if couples.len() < 512 {
            return couples.iter().map(pot).sum();
        }
        let per: Vec<f64> = couples.par_iter().with_min_len(512).map(pot).collect();
        per.iter().sum()
    }

    /// Contact potential of one triangle couple at positions `x` \[J/m\] (0 when its law
    /// is off): a term of [`Self::potential_of`].
    pub fn pair_potential(
        &self,
        c: &[u32; 2],
        x: &[V2],
        tris: &[[u32; 3]],
        material: &[u32],
    ) -> f64 {
        let mat = |i: u32| material.get(i as usize).copied().unwrap_or(0);
        let law = self.laws.get(mat(c[0]), mat(c[1]));
        if !law.enabled {
            return 0.0;
        }
        let (ti, tj) = (&tris[c[0] as usize], &tris[c[1] as usize]);
        let xc = ti.map(|n| x[n as usize]);
        let xt = tj.map(|n| x[n as usize]);
        pair_energy(&xc, &xt, law.penalty)
    }

    /// Largest node displacement since the last detection \[m\] (for diagnostics).
    pub fn max_displacement_since_detection(&self, x: &[V2]) -> f64 {
        x.iter()
            .zip(&self.x_det)
            .map(|(a, b)| norm(sub(*a, *b)))
            .fold(0.0, f64::max)
    }
}
