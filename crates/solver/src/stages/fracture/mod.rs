//! The joint (fracture) stage: the fracture crate's joints as a [`ForceContribution`], on the
//! joint set prepared at load ([`crate::problem::joints`]: the explode of the fracturing
//! regions of the scene's `"fracture"` section).
//!
//! Each force evaluation adds the forces of the intact joints (Munjiza's combined single and
//! smeared crack model, docs/fracture.md); the end-of-step hook commits damage
//! (`commit_joints`: damage never heals, energies booked, joints with both points at `D = 1`
//! break). The contact stage's bonded list (passed as data through
//! [`crate::stages::contact::BondedPairs`]) holds the pairs of every intact joint and every pair
//! of triangles around an original (pre-explode) node whose star of joints is intact
//! ([`crate::stages::star_bonds`]): in an intact mesh no triangle is a contact couple of its edge or
//! vertex neighbours. A break removes its joint's pair; the first softening (damage > 0) or
//! break of a joint unbonds the vertex pairs of the stars of its two end nodes; the pairs that
//! leave the bonded set are appended to `BondedPairs::released` (no rebuild of the list), and
//! the contact stage hands them to the contact crate, which adds the close ones as couples
//! without a re-detection. (Releasing only at breaks let triangles slide along fully damaged, unbroken joints
//! into their vertex neighbours, and the overlaps entered contact at once when a star broke:
//! docs/fracture.md section 13.) Physics caveat: non-adjacent triangles of an intact star
//! could only overlap after their edge neighbours' joints are crushed by more than the joint
//! penalty allows (the joints carry the compression there; docs/fracture.md). Each break is a
//! row of `fractures.csv` (time, position, mode, energy released).
//!
//! A checkpoint (`ForceContribution::save`, section `fracture`) holds the joints' committed
//! state, the stars' flags, the released pairs the contact stage has not taken yet, the
//! release counters, the shared report with its events and the length of `fractures.csv`;
//! a stage attached afresh for the same scene continues from it bit for bit.
//!
//! Time step: `omega^2 += omega_j^2` ([`crate::problem::joints::omega_joints`]).

use std::io::Write;
use std::path::Path;
use std::sync::{Arc, Mutex};

use fdem_fracture::{
    FractureEvent, JointHistory, JointScratch, JointSet, JointState, JointStateSnapshot,
    accumulate_joint_forces, accumulate_joint_forces_committing, commit_joints,
    commit_joints_at_last_pass,
};
use serde::Serialize;

use crate::checkpoint::pack::PackSlice;
use crate::checkpoint::{Dec, DecodeError, Enc, Pack};
pub use crate::input::scene::fracture::{FractureSection, Region};
use crate::problem::model::Model;
use crate::stages::contact::BondedPairs;
use crate::stages::star_bonds::StarBonds;
use crate::stages::system::{ForceContribution, StageReport};

#[cfg(test)]
mod checkpoint_tests;
mod distributed;

/// A word-wise FNV-1a hash of a list of pairs (a checkpoint's check of a rebuilt list).
fn pairs_hash(pairs: &[[u32; 2]]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for &w in pairs.as_flattened() {
        h = (h ^ u64::from(w)).wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

impl Pack for JointHistory {
    fn pack(&self, e: &mut Enc) {
        e.put(&self.damage);
        e.put(&self.shear_secant);
        e.put(&self.mode_mix);
        e.put(&self.last);
        e.put(&self.work);
        e.put(&self.stored);
        e.put(&self.dissipated);
    }

    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        fn arr<const N: usize>(d: &mut Dec) -> Result<[f64; N], DecodeError> {
            let mut a = [0.0; N];
            for v in &mut a {
                *v = d.get()?;
            }
            Ok(a)
        }
        Ok(JointHistory {
            damage: arr(d)?,
            shear_secant: arr(d)?,
            mode_mix: arr(d)?,
            last: arr(d)?,
            work: d.get()?,
            stored: d.get()?,
            dissipated: d.get()?,
        })
    }
}

/// A fracture stage's checkpoint as read, checked against the scene but not yet taken over.
struct Saved {
    state: JointState,
    bond_state: Vec<u8>,
    star_intact: Vec<bool>,
    joint_released: Vec<bool>,
    n_bonded: usize,
    releases: u64,
    released_pairs: u64,
    release_s: f64,
    stars_scanned: bool,
    initial_pairs: (usize, u64),
    released: Vec<[u32; 2]>,
    report: FractureReport,
    csv_len: Option<u64>,
}

/// What the joint stage shares with the driver and the tests.
#[derive(Debug, Clone, Default, Serialize)]
pub struct FractureReport {
    /// Joints.
    pub joints: usize,
    /// Broken joints.
    pub broken: usize,
    /// Every fracture event so far: (time, x, y, mode, energy released).
    pub events: Vec<(f64, f64, f64, String, f64)>,
}

/// The joint stage (a [`ForceContribution`]).
pub struct FractureStage {
    set: JointSet,
    state: JointState,
    scratch: JointScratch,
    events: Vec<FractureEvent>,
    stars: StarBonds,
    /// Per joint: 0 nothing released, 1 its stars released (it softened), 2 its stars and
    /// its own pair released (it broke).
    bond_state: Vec<u8>,
    /// Steps that released pairs, pairs released, and the wall time of the releases [s]
    /// (reported in the details).
    releases: u64,
    released_pairs: u64,
    release_s: f64,
    /// True once the first end-of-step hook has scanned every joint for damage.
    stars_scanned: bool,
    bonded: Arc<Mutex<BondedPairs>>,
    /// The length and [`pairs_hash`] of `BondedPairs::initial` as built (a checkpoint checks
    /// that the resumed run rebuilt the same list).
    initial_pairs: (usize, u64),
    report: Arc<Mutex<FractureReport>>,
    csv: Option<std::io::BufWriter<std::fs::File>>,
    /// `fractures.csv` was asked for (an output folder was given).
    csv_wanted: bool,
    /// True when the joint series carries each joint's strengths and fracture energies (a
    /// scene of several joint materials or drawn ones: `FractureSection::varied_joints`).
    pub(crate) write_properties: bool,
    /// The next force evaluation is the step's last, committed at its positions (set by
    /// [`ForceContribution::next_evaluation_ends_step`], cleared by that evaluation; never
    /// set between steps, so not in checkpoints).
    ends_step: bool,
    /// In a distributed run: this rank's joints ([`distributed::LocalJoints`]).
    local: Option<distributed::LocalJoints>,
    /// The force passes evaluate `local` (the run's steps of a distributed run).
    partial: bool,
    /// The joints newly softened at the last commit (global ids, increasing).
    softened: Vec<u32>,
}

impl FractureStage {
    /// The stage over `set` at the reference positions of `model`, or from the saved state
    /// `initial` (one history per joint of `set`, see [`FractureSection::initial_state`]);
    /// `fractures.csv` goes to `out_dir`. Returns the bonded pairs for the contact stage and
    /// the shared report.
    pub fn new(
        set: JointSet,
        model: &Model,
        out_dir: Option<&Path>,
        initial: Option<JointState>,
        resume: bool,
    ) -> (Self, Arc<Mutex<BondedPairs>>, Arc<Mutex<FractureReport>>) {
        let adopted = initial.is_some();
        let n_joints = set.len();
        let mut bond_state = vec![0; n_joints];
        let mut pairs = Vec::new();
        // A fresh start: the star bonds (partly serial) are built while the joints' state
        // and scratch (parallel) are, each from the set alone (the same values either way).
        let (fresh_stars, (state, mut scratch)) = rayon::join(
            || {
                (!adopted).then(|| {
                    StarBonds::with_pairs(&set.nodes, &set.triangles, model.n_nodes(), &mut pairs)
                })
            },
            || {
                let state = initial.unwrap_or_else(|| JointState::new(&set, &model.x0));
                (state, JointScratch::new(set.len()))
            },
        );
        assert_eq!(state.intact.len(), set.len(), "one saved history per joint");
        // the time crate says when the commit is at the last pass's positions
        scratch.set_position_check(false);
        let mut initial = pairs;
        let stars = if let Some(stars) = fresh_stars {
            stars
        } else {
            // A saved state: its broken joints' pairs and its softened joints' stars leave the
            // bonded set before the first force evaluation (the scan of the first end-of-step
            // hook, done here), so the contact stage's first detection finds them.
            let mut stars = StarBonds::new(&set.nodes, &set.triangles, model.n_nodes());
            let mut dropped = Vec::new();
            for (j, st) in bond_state.iter_mut().enumerate() {
                let d = state.history[j].damage;
                if !state.intact[j] {
                    stars.break_joint(j, &mut dropped);
                    *st = 2;
                } else if d[0] > 0.0 || d[1] > 0.0 {
                    stars.release_stars(j, &mut dropped);
                    *st = 1;
                }
            }
            stars.pairs(&mut initial);
            stars
        };
        let initial_pairs = (initial.len(), pairs_hash(&initial));
        let bonded = Arc::new(Mutex::new(BondedPairs {
            initial,
            released: Vec::new(),
        }));
        let report = Arc::new(Mutex::new(FractureReport {
            joints: set.len(),
            broken: state.n_broken,
            ..Default::default()
        }));
        let csv = out_dir.and_then(|d| {
            let head = "time,x,y,mode,mode_mix,energy_released,joint";
            crate::output::open_csv(d, "fractures.csv", head, resume)
        });
        (
            Self {
                set,
                state,
                scratch,
                events: Vec::new(),
                stars,
                bond_state,
                releases: 0,
                released_pairs: 0,
                release_s: 0.0,
                stars_scanned: adopted,
                bonded: bonded.clone(),
                initial_pairs,
                report: report.clone(),
                csv,
                csv_wanted: out_dir.is_some(),
                write_properties: false,
                ends_step: false,
                local: None,
                partial: false,
                softened: Vec::new(),
            },
            bonded,
            report,
        )
    }

    /// Joint `j`'s damage (mean of its points), broken flag and time of failure.
    pub fn joint_fields(&self) -> (Vec<f64>, Vec<bool>, Vec<f64>) {
        let d = (0..self.set.len())
            .map(|j| self.state.joint_damage(j))
            .collect();
        let b = self.state.intact.iter().map(|i| !i).collect();
        let t = self
            .state
            .broken_at
            .iter()
            .map(|b| b.unwrap_or(-1.0))
            .collect();
        (d, b, t)
    }
}

impl FractureStage {
    /// Reads the section body [`ForceContribution::save`] wrote, checking its sizes against
    /// the scene's joints and stars and its flags against each other.
    fn read_saved(&self, d: &mut Dec) -> Result<Saved, DecodeError> {
        let n = self.set.len();
        let nj: usize = d.get()?;
        if nj != n {
            return Err(d.error(format!("{nj} joints where the scene has {n}")));
        }
        let snapshot = JointStateSnapshot {
            history: d.vec_of_len(n, "joint histories")?,
            intact: d.vec_of_len(n, "joint intact flags")?,
            broken_at: d.vec_of_len(n, "joint times of failure")?,
            stored_initial: d.get()?,
            released_at_break: d.get()?,
            n_broken: d.get()?,
            generation: d.get()?,
        };
        let state = JointState::from_snapshot(&self.set, snapshot).map_err(|e| d.error(e))?;
        let bond_state: Vec<u8> = d.vec_of_len(n, "joint bond states")?;
        let star_intact = d.vec_of_len(self.stars.n_stars(), "star flags")?;
        let joint_released: Vec<bool> = d.vec_of_len(n, "joint pair flags")?;
        let n_bonded = d.get()?;
        let (releases, released_pairs, release_s, stars_scanned) =
            (d.get()?, d.get()?, d.get()?, d.get()?);
        // what the end-of-step hooks give: 2 once broken (its pair released), else 1 once
        // damaged (after the first scan), else 0
        for j in 0..n {
            let (b, released, intact) = (bond_state[j], joint_released[j], state.intact[j]);
            let damaged = state.history[j].damage != [0.0; 2];
            let want = match (released, stars_scanned && damaged) {
                (true, _) => 2,
                (false, true) => 1,
                (false, false) => 0,
            };
            if b != want || (!intact && !released) {
                return Err(d.error(format!(
                    "joint {j}: bond state {b}, pair released {released}, intact {intact}, \
                     damaged {damaged}"
                )));
            }
        }
        let initial_pairs = d.get()?;
        let released = d.get()?;
        let (joints, broken, n_events): (usize, usize, usize) = (d.get()?, d.get()?, d.get()?);
        if joints != n || broken != state.n_broken {
            return Err(d.error(format!(
                "the report has {joints} joints and {broken} broken, the state {n} and {}",
                state.n_broken
            )));
        }
        if n_events > d.remaining() {
            return Err(d.error(format!("{n_events} events in {} bytes", d.remaining())));
        }
        let mut events = Vec::with_capacity(n_events);
        for _ in 0..n_events {
            events.push((d.get()?, d.get()?, d.get()?, d.get()?, d.get()?));
        }
        Ok(Saved {
            state,
            bond_state,
            star_intact,
            joint_released,
            n_bonded,
            releases,
            released_pairs,
            release_s,
            stars_scanned,
            initial_pairs,
            released,
            report: FractureReport {
                joints,
                broken,
                events,
            },
            csv_len: d.get()?,
        })
    }

    /// The commit (trusting the last pass's positions when `at_last_pass`), the star
    /// releases and the events of an accepted step.
    fn end_step(&mut self, t: f64, x: &[[f64; 2]], at_last_pass: bool) {
        self.events.clear();
        let commit = if at_last_pass {
            commit_joints_at_last_pass
        } else {
            commit_joints
        };
        commit(
            &self.set,
            &mut self.state,
            x,
            t,
            &mut self.scratch,
            &mut self.events,
        );
        self.softened.clear();
        self.softened
            .extend_from_slice(self.scratch.newly_softened());
        self.after_commit();
    }

    /// What follows a commit whose breaks are in `self.events` and whose newly softened
    /// joints are in `self.softened` (both in joint order, global ids), with `self.state`
    /// holding the breaks: the star releases, the report and `fractures.csv`.
    fn after_commit(&mut self) {
        // Stars stop bonding at the first softening of one of their joints (damage > 0 at
        // either point) or its break, and a break releases the joint's own pair. One scan of
        // every joint at the first step (a joint may start damaged or broken), then only the
        // joints the commit lists as newly softened or broken; the pairs that leave the
        // bonded set go to the contact stage.
        let t0 = std::time::Instant::now();
        let mut b = self.bonded.lock().unwrap_or_else(|e| e.into_inner());
        let n_before = b.released.len();
        if self.stars_scanned {
            for &j in &self.softened {
                let j = j as usize;
                if self.bond_state[j] == 0 {
                    self.stars.release_stars(j, &mut b.released);
                    self.bond_state[j] = 1;
                }
            }
            for e in &self.events {
                let j = e.joint.0 as usize;
                if self.bond_state[j] != 2 {
                    self.stars.break_joint(j, &mut b.released);
                    self.bond_state[j] = 2;
                }
            }
        } else {
            for (j, st) in self.bond_state.iter_mut().enumerate() {
                // damaged after the commit (in a distributed run the histories here are
                // those before it, and the newly softened joints say the rest)
                let d = self.state.history[j].damage;
                if !self.state.intact[j] {
                    self.stars.break_joint(j, &mut b.released);
                    *st = 2;
                } else if d[0] > 0.0
                    || d[1] > 0.0
                    || self.softened.binary_search(&(j as u32)).is_ok()
                {
                    self.stars.release_stars(j, &mut b.released);
                    *st = 1;
                }
            }
            self.stars_scanned = true;
        }
        let n_released = b.released.len() - n_before;
        if Arc::strong_count(&self.bonded) == 1 {
            // No contact stage takes them (a scene without contact): keep nothing.
            b.released.clear();
        }
        drop(b);
        if n_released > 0 {
            self.releases += 1;
            self.released_pairs += n_released as u64;
            self.release_s += t0.elapsed().as_secs_f64();
        }
        if self.events.is_empty() {
            return;
        }
        let mut r = self.report.lock().unwrap_or_else(|e| e.into_inner());
        r.broken = self.state.n_broken;
        for e in &self.events {
            r.events.push((
                e.time,
                e.position[0],
                e.position[1],
                e.mode.as_str().to_string(),
                e.energy_released,
            ));
            if let Some(w) = &mut self.csv {
                let _ = writeln!(
                    w,
                    "{:.9e},{:.9e},{:.9e},{},{:.4},{:.9e},{}",
                    e.time,
                    e.position[0],
                    e.position[1],
                    e.mode.as_str(),
                    e.mode_mix,
                    e.energy_released,
                    e.joint.0
                );
            }
        }
    }
}

impl ForceContribution for FractureStage {
    /// Section `fracture`: the joints' committed state, the star bonds' flags, the release
    /// counters and timer, the bonded pairs not yet taken by the contact stage, the shared
    /// report and the length of `fractures.csv` (flushed). Not saved: the joint set and the
    /// star topology (rebuilt from the scene by the attach; the list of bonded pairs at
    /// set-up is checked by its length and hash), and the scratch: `JointScratch` holds
    /// nothing a later step reads after a commit (its trial history, forces and chunk flags
    /// are rewritten by the next force pass, its list of newly softened joints by the next
    /// commit, it keeps no positions, and a commit marks its trial stale), nor does
    /// `events` (cleared at each commit).
    fn save(&mut self, e: &mut Enc) -> std::io::Result<()> {
        let csv_len = match &mut self.csv {
            Some(w) => Some(crate::output::csv_length(w)?),
            None => None,
        };
        let bonded = self.bonded.lock().unwrap_or_else(|e| e.into_inner());
        let report = self.report.lock().unwrap_or_else(|e| e.into_inner());
        let (n, s) = (self.set.len(), &self.state);
        // the section's size, to grow the buffer once: 136 bytes of history and 4 flags per
        // joint, a flag per star, 8 bytes per time of failure, released pair and event field
        let events = report.events.len();
        let size = 140 * n + self.stars.n_stars() + 8 * (s.n_broken + bonded.released.len());
        e.buf.reserve(size + 48 * events + 256);
        e.section("fracture", |e| {
            e.put(&n);
            e.put(&s.history);
            e.put(&s.intact);
            e.put(&s.broken_at);
            e.put(&s.stored_initial);
            e.put(&s.released_at_break);
            e.put(&s.n_broken);
            e.put(&s.generation());
            e.put(&self.bond_state);
            let (stars, joints, n_bonded) = self.stars.bond_flags();
            stars.pack_slice(e);
            joints.pack_slice(e);
            e.put(&n_bonded);
            e.put(&self.releases);
            e.put(&self.released_pairs);
            e.put(&self.release_s);
            e.put(&self.stars_scanned);
            e.put(&self.initial_pairs);
            e.put(&bonded.released);
            e.put(&report.joints);
            e.put(&report.broken);
            e.put(&report.events.len());
            for (t, x, y, mode, energy) in &report.events {
                e.put(t);
                e.put(x);
                e.put(y);
                e.text(mode);
                e.put(energy);
            }
            e.put(&csv_len);
        });
        Ok(())
    }

    /// Reads what [`FractureStage::save`] wrote, checks it against the scene (joint and star
    /// counts, the bonded list at set-up, flags that agree with each other), then cuts
    /// `fractures.csv` back to its length at the checkpoint (shorter is an error) and takes
    /// the state over. Every check of the checkpoint's content comes before any change; after
    /// an error (a short or missing file included) the stage is not to be used.
    fn restore(&mut self, d: &mut Dec) -> Result<(), DecodeError> {
        let saved = d.section("fracture", |d| self.read_saved(d))?;
        let err = |m: String| DecodeError(format!("section `fracture`: {m}"));
        if saved.initial_pairs != self.initial_pairs {
            return Err(err(format!(
                "the scene's bonded pairs at set-up ({} pairs) are not the checkpoint's ({} \
                 pairs, or another list): it was written for another scene",
                self.initial_pairs.0, saved.initial_pairs.0
            )));
        }
        self.stars
            .set_bond_flags(saved.star_intact, saved.joint_released, saved.n_bonded)
            .map_err(err)?;
        match (&mut self.csv, saved.csv_len) {
            (Some(w), Some(len)) => crate::output::truncate_csv(w, len)
                .map_err(|m| err(format!("fractures.csv {m}")))?,
            (None, None) => {}
            (None, Some(_)) if !self.csv_wanted => {}
            (None, Some(_)) => {
                return Err(err(
                    "fractures.csv of the run being resumed cannot be opened".into(),
                ));
            }
            (Some(_), None) => {
                return Err(err("the checkpoint's run wrote no fractures.csv".into()));
            }
        }
        self.state = saved.state;
        self.bond_state = saved.bond_state;
        self.releases = saved.releases;
        self.released_pairs = saved.released_pairs;
        self.release_s = saved.release_s;
        self.stars_scanned = saved.stars_scanned;
        self.bonded
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .released = saved.released;
        *self.report.lock().unwrap_or_else(|e| e.into_inner()) = saved.report;
        Ok(())
    }

    fn name(&self) -> &str {
        "fracture"
    }

    fn add_forces(&mut self, _t: f64, x: &[[f64; 2]], _v: &[[f64; 2]], f: &mut [[f64; 2]]) {
        if let Some(l) = self.local.as_mut().filter(|_| self.partial) {
            if std::mem::take(&mut self.ends_step) {
                accumulate_joint_forces_committing(&l.set, &mut l.state, x, &mut l.scratch, f);
            } else {
                accumulate_joint_forces(&l.set, &l.state, x, &mut l.scratch, f);
            }
            return;
        }
        if std::mem::take(&mut self.ends_step) {
            // the step's commit follows at these positions: the new histories go straight
            // into the state (no trial copy to write and swap)
            accumulate_joint_forces_committing(&self.set, &mut self.state, x, &mut self.scratch, f);
        } else {
            accumulate_joint_forces(&self.set, &self.state, x, &mut self.scratch, f);
        }
    }

    fn next_evaluation_ends_step(&mut self) {
        self.ends_step = true;
    }

    /// An intact joint costs [`crate::distributed::balance::JOINT`], to its first triangle.
    fn add_costs(&self, tri_cost: &mut [f64]) {
        for (t, intact) in self.set.triangles.iter().zip(&self.state.intact) {
            if *intact {
                tri_cost[t[0] as usize] += crate::distributed::balance::JOINT;
            }
        }
    }

    /// Takes this rank's joints: those with a node of its own.
    fn distribute(&mut self, layout: &crate::distributed::Layout) {
        let mut l = distributed::LocalJoints::new(&self.set, &self.state, layout);
        // the time crate says when the commit is at the last pass's positions
        l.scratch.set_position_check(false);
        self.local = Some(l);
    }

    fn set_partial(&mut self, on: bool) {
        self.partial = on;
    }

    fn end_of_step_distributed(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        at_last: bool,
        comm: &mut dyn crate::distributed::Comm,
    ) {
        let Some(l) = &mut self.local else {
            return self.end_step(t, x, at_last);
        };
        let _ = v;
        l.commit_and_share(
            t,
            x,
            at_last,
            comm,
            &mut self.state,
            &mut self.softened,
            &mut self.events,
        );
        self.after_commit();
    }

    /// The nodes of this rank's joints from their owners (the joints read no velocities).
    fn exchange_distributed(
        &mut self,
        _t: f64,
        x: &mut [[f64; 2]],
        v: &mut [[f64; 2]],
        _before_forces: bool,
        comm: &mut dyn crate::distributed::Comm,
    ) {
        if let Some(l) = &mut self.local {
            l.ghosts.exchange(comm, x, v, false);
        }
    }

    fn share(&mut self, comm: &mut dyn crate::distributed::Comm) {
        if let Some(l) = &mut self.local {
            l.share_histories(comm, &mut self.state);
        }
    }

    /// The joints' forces depend on the positions and the committed history only.
    fn reads_velocities(&self) -> bool {
        false
    }

    fn end_of_step(&mut self, t: f64, x: &[[f64; 2]], _v: &[[f64; 2]]) {
        self.end_step(t, x, false);
    }

    fn end_of_step_at_last_evaluation(&mut self, t: f64, x: &[[f64; 2]], _v: &[[f64; 2]]) {
        self.end_step(t, x, true);
    }

    /// Hands the joints to the writer (the `joints_NNNN.vtu` series, `crate::output::joints`).
    fn frame_fields(&self, x: &[[f64; 2]], frame: &mut crate::output::FrameData) {
        let mut joints = crate::output::JointFrame::new(&self.set, &self.state, x);
        if self.write_properties {
            joints.properties = Some(crate::output::JointProperties::new(&self.set));
        }
        frame.joints = Some(joints);
    }

    fn report(&self, _x: &[[f64; 2]]) -> StageReport {
        let e = self.state.energy();
        StageReport {
            stored: e.stored - e.stored_initial,
            fracture: e.dissipated,
            switch_loss: e.released_at_break,
            details: serde_json::json!({
                "joints": self.set.len(),
                "broken": self.state.n_broken,
                "bonded_pairs": self.stars.n_bonded(),
                "bonded_releases": self.releases,
                "released_pairs": self.released_pairs,
                "bonded_release_s": self.release_s,
                "stored": e.stored,
                "dissipated": e.dissipated,
                "released_at_break": e.released_at_break,
                "work": e.work,
                // in a distributed run: the joints this rank evaluates
                "rank_joints": self.local.as_ref().map(|l| l.ids.len()),
            }),
            ..StageReport::default()
        }
    }

    fn joint_state(&self) -> Option<&JointState> {
        Some(&self.state)
    }

    fn joint_links(&self) -> Option<crate::output::recovery::Links<'_>> {
        Some(crate::output::recovery::Links {
            nodes: &self.set.nodes,
            intact: &self.state.intact,
        })
    }

    fn files(&self, files: &mut Vec<String>) {
        if self.csv.is_some() {
            files.push("fractures.csv".into());
        }
    }

    fn finish(&mut self) {
        if let Some(w) = &mut self.csv {
            let _ = w.flush();
        }
    }
}
