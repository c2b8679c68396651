//! The state of a [`Contact`] that carries from one step to the next, as plain data: what a
//! checkpoint writes so that a model built afresh for the same mesh, laws and planes, once
//! [`Contact::restore`]d, continues bit for bit.
//!
//! Saved: the couple list in its order (sorted; the scatter sums in that order), the committed
//! friction history of couples and plane pairs, the detection state (positions, plane points
//! and triangle count at the last detection, buffer, stale flag, counters), the bonded pairs
//! still excluded (releases thin them during a run), the planes' positions and velocities,
//! the last force pass's results that the scatter, reactions, statistics, energies and the
//! active bound read (only the slots whose flag says they hold a force), the statistics and
//! the dissipation booked.
//!
//! Rebuilt on restore, bit for bit, from what is saved: the single-precision copy of the
//! detection positions and its bound (`set_det32`, from `x_det` and the buffer), the per-triangle
//! marks of the force pass (from the couples and plane pairs), the trial friction (between
//! steps, after [`Contact::commit`], it equals the committed one), the result slots without a
//! force (inactive), and the bounding circles of the last detection (recomputed from `x_det`
//! the first time [`Contact::release_pairs`] needs them).
//!
//! Not saved, scratch rewritten before it is read: the broad phases' grids and trees (NBS and
//! parry rebuild them at each detection and sort the couples they find, so their content never
//! carries over), the gathered triangle vertices and boxes of the force pass, the narrow
//! filter's marks, the merge buffers and the couples added by the last release.

use super::Contact;
use super::ContactStats;
use crate::bounding::BoundingCircles;
use crate::couple::{CoupleForce, WallForce};
use crate::exclusions::Exclusions;
use crate::geom::V2;

/// The state of a [`Contact`] between two steps ([`Contact::snapshot`], [`Contact::restore`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContactSnapshot {
    /// Per plane: its point and velocity \[m, m/s\] (a platen's motion; the normal and law
    /// come from the set-up).
    pub walls: Vec<[V2; 2]>,
    /// Bonded pairs still excluded: the number of live partners per triangle (empty when no
    /// list was set) ...
    pub bonded_lens: Vec<u32>,
    /// ... and the partners, row after row (each pair in both of its rows).
    pub bonded: Vec<u32>,
    /// Node positions at the last detection \[m\] (empty before the first).
    pub x_det: Vec<V2>,
    /// Plane points at the last detection \[m\].
    pub wall_det: Vec<V2>,
    /// Number of triangles at the last detection.
    pub n_tris_det: usize,
    /// The buffer in use \[m\].
    pub buffer: f64,
    /// The next [`Contact::update_detection`] redetects whatever the motion.
    pub stale: bool,
    /// Detections done.
    pub n_detections: u64,
    /// Triangle couples `(i < j)`, sorted (the order of the scatter's sums).
    pub couples: Vec<[u32; 2]>,
    /// Committed tangential forces per couple edge, only for the couples where one of the six
    /// is not `+0.0`: (couple index, forces), by increasing index \[N/m\].
    pub friction: Vec<(u32, [f64; 6])>,
    /// The couples whose result slot holds the last force pass's result (a force or an
    /// invalid report), by increasing index ...
    pub flagged: Vec<u32>,
    /// ... and those results, aligned with `flagged`.
    pub results: Vec<CoupleForce>,
    /// Plane-triangle candidates `[plane, tri]`, sorted.
    pub wall_pairs: Vec<[u32; 2]>,
    /// Committed tangential force per plane pair \[N/m\].
    pub wall_ft: Vec<f64>,
    /// The last force pass's result per plane pair.
    pub wall_results: Vec<WallForce>,
    /// Couples added by releases without a detection, so far.
    pub n_released_couples: u64,
    /// Slip dissipation committed so far \[J/m\].
    pub friction_dissipated: f64,
    /// Statistics of the last force pass.
    pub stats: ContactStats,
}

/// Strictly increasing, every value below `n`.
fn increasing_below<T: Copy + PartialOrd>(
    v: impl Iterator<Item = T>,
    below: impl Fn(T) -> bool,
) -> bool {
    let mut prev: Option<T> = None;
    for x in v {
        if !below(x) || prev.is_some_and(|p| p >= x) {
            return false;
        }
        prev = Some(x);
    }
    true
}

impl Contact {
    /// The state that carries over to the next step (module docs), taken between steps
    /// (after [`Contact::commit`]). Costs one copy of that state; nothing per step.
    pub fn snapshot(&self) -> ContactSnapshot {
        let (bonded_lens, bonded) = self.excl.rows();
        let flagged: Vec<u32> = (0..self.flags.len() as u32)
            .filter(|&k| self.flags[k as usize] != 0)
            .collect();
        let results = flagged
            .iter()
            .map(|&k| self.results.get(k as usize).copied().unwrap_or_default())
            .collect();
        let friction = self
            .ft
            .iter()
            .enumerate()
            .filter(|(_, f)| f.iter().any(|v| v.to_bits() != 0))
            .map(|(k, f)| (k as u32, *f))
            .collect();
        let wall_results = (0..self.wall_pairs.len())
            .map(|k| self.wall_results.get(k).copied().unwrap_or_default())
            .collect();
        ContactSnapshot {
            walls: self.walls.iter().map(|w| [w.point, w.velocity]).collect(),
            bonded_lens,
            bonded,
            x_det: self.x_det.clone(),
            wall_det: self.wall_det.clone(),
            n_tris_det: self.n_tris_det,
            buffer: self.buffer,
            stale: self.stale,
            n_detections: self.n_detections,
            couples: self.couples.clone(),
            friction,
            flagged,
            results,
            wall_pairs: self.wall_pairs.clone(),
            wall_ft: self.wall_ft.clone(),
            wall_results,
            n_released_couples: self.n_released_couples,
            friction_dissipated: self.friction_dissipated,
            stats: self.stats,
        }
    }

    /// Restores a [`Self::snapshot`] into a model built afresh with the same settings, laws
    /// and planes, which then continues bit for bit. An error, leaving the model as it was,
    /// when the snapshot does not fit together or not this model's planes: couples not
    /// sorted or naming a triangle beyond the detection's count, indices beyond the couple
    /// list, lengths that differ. The caller checks `x_det` (empty or one per node) and
    /// `n_tris_det` (0 or its triangle count) against its mesh.
    pub fn restore(&mut self, s: ContactSnapshot) -> Result<(), String> {
        let nw = self.walls.len();
        if s.walls.len() != nw {
            return Err(format!("{} planes where the model has {nw}", s.walls.len()));
        }
        let excl = Exclusions::from_rows(&s.bonded_lens, &s.bonded)?;
        let nt = s.n_tris_det;
        if nt > 0 && s.n_detections == 0 {
            return Err(format!("{nt} triangles at a detection before any"));
        }
        if nt > u32::MAX as usize + 1 {
            return Err(format!("{nt} triangles at the last detection"));
        }
        if !increasing_below(s.couples.iter().copied(), |c| {
            c[0] < c[1] && (c[1] as usize) < nt
        }) {
            return Err(format!(
                "the {} couples are not sorted pairs (i < j) of the {nt} triangles",
                s.couples.len()
            ));
        }
        let nc = s.couples.len();
        if !increasing_below(s.friction.iter().map(|f| f.0), |k| (k as usize) < nc) {
            return Err(format!(
                "friction history of couples not in increasing order among the {nc}"
            ));
        }
        if !increasing_below(s.flagged.iter().copied(), |k| (k as usize) < nc)
            || s.results.len() != s.flagged.len()
        {
            return Err(format!(
                "{} results for {} couples with a result, not in increasing order among the {nc}",
                s.results.len(),
                s.flagged.len()
            ));
        }
        let np = s.wall_pairs.len();
        if !increasing_below(s.wall_pairs.iter().copied(), |w| {
            (w[0] as usize) < nw && (w[1] as usize) < nt
        }) || s.wall_ft.len() != np
            || s.wall_results.len() != np
        {
            return Err(format!(
                "{np} plane pairs (sorted, of {nw} planes and {nt} triangles expected) with {} \
                 friction values and {} results",
                s.wall_ft.len(),
                s.wall_results.len()
            ));
        }
        for (w, [point, velocity]) in self.walls.iter_mut().zip(&s.walls) {
            w.point = *point;
            w.velocity = *velocity;
        }
        self.excl = excl;
        self.circles = BoundingCircles::default();
        self.buffer = s.buffer;
        self.x_det = s.x_det;
        if s.n_detections > 0 {
            self.set_det32();
        } else {
            self.x_det32.clear();
            self.det32_clear = -1.0;
        }
        self.wall_det = s.wall_det;
        self.n_tris_det = nt;
        self.stale = s.stale;
        self.n_detections = s.n_detections;
        self.ft = vec![[0.0; 6]; nc];
        for (k, f) in &s.friction {
            self.ft[*k as usize] = *f;
        }
        self.ft_trial = self.ft.clone();
        self.results = vec![CoupleForce::default(); nc];
        self.flags = vec![0; nc];
        for (k, r) in s.flagged.iter().zip(s.results) {
            self.results[*k as usize] = r;
            self.flags[*k as usize] = 1;
        }
        self.tri_used = vec![0; nt];
        for c in &s.couples {
            self.tri_used[c[0] as usize] = 3;
            self.tri_used[c[1] as usize] = 3;
        }
        for w in &s.wall_pairs {
            self.tri_used[w[1] as usize] = 3;
        }
        self.couples = s.couples;
        self.wall_pairs = s.wall_pairs;
        self.wall_ft_trial = s.wall_ft.clone();
        self.wall_ft = s.wall_ft;
        self.wall_results = s.wall_results;
        self.tri_x.clear();
        self.tri_box.clear();
        self.added.clear();
        self.n_released_couples = s.n_released_couples;
        self.friction_dissipated = s.friction_dissipated;
        self.stats = s.stats;
        Ok(())
    }
}
