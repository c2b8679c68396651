//! The joint (fracture) stage: the fracture crate's joints as a force term ([`ForceTerm`]), on
//! the joint set prepared at load ([`crate::problem::joints`]: the explode of the fracturing
//! regions of the scene's `"fracture"` section). Its other layers, each in its own file of
//! `stages/fracture/`: the reports, frames and `fractures.csv` (`output.rs`), the checkpoint
//! (`checkpoint.rs`), a distributed run's part (`distributed.rs`).
//!
//! Each force evaluation adds the forces of the intact joints (Munjiza's combined single and
//! smeared crack model, docs/fracture.md); the end-of-step hook commits damage
//! (`commit_joints`: damage never heals, energies booked, joints with both points at `D = 1`
//! break). The contact stage's bonded list (data this stage gives at attach,
//! [`FractureStage::new`]) holds the pairs of every intact joint and every pair
//! of triangles around an original (pre-explode) node whose star of joints is intact
//! ([`crate::stages::star_bonds`]): in an intact mesh no triangle is a contact couple of its edge or
//! vertex neighbours. A break removes its joint's pair; the first softening (damage > 0) or
//! break of a joint unbonds the vertex pairs of the stars of its two end nodes; the pairs that
//! leave the bonded set are appended to the step's [`StepEvents::released`] (no rebuild of the
//! list) with the step's breaks ([`StepEvents::fractures`]), and the contact stage, after this
//! one in stage order, hands them to the contact crate, which adds the close ones as couples
//! without a re-detection. (Releasing only at breaks let triangles slide along fully damaged, unbroken joints
//! into their vertex neighbours, and the overlaps entered contact at once when a star broke:
//! docs/fracture.md section 13.) Physics caveat: non-adjacent triangles of an intact star
//! could only overlap after their edge neighbours' joints are crushed by more than the joint
//! penalty allows (the joints carry the compression there; docs/fracture.md). Each break is a
//! row of `fractures.csv` (time, position, mode, energy released).
//!
//! A checkpoint (`StageCheckpoint::save`, section `fracture`) holds the joints' committed
//! state, the stars' flags, the released pairs the contact stage has not taken yet, the
//! release counters, the report with its events and the length of `fractures.csv`;
//! a stage attached afresh for the same scene continues from it bit for bit.
//!
//! Time step: `omega^2 += omega_j^2` ([`crate::problem::joints::omega_joints`]).

use std::path::Path;

use fdem_fracture::{
    JointScratch, JointSet, JointState, accumulate_joint_forces,
    accumulate_joint_forces_committing, add_joint_forces, commit_joints,
    commit_joints_at_last_pass, joint_forces_ahead, joint_forces_ahead_committing,
};
use serde::Serialize;

pub use crate::input::scene::fracture::{FractureSection, Region};
use crate::problem::model::Model;
use crate::stages::star_bonds::StarBonds;
use crate::stages::system::{AheadForces, ForceTerm, StepEvents};

#[cfg(test)]
mod ahead_tests;
mod checkpoint;
#[cfg(test)]
mod checkpoint_tests;
mod distributed;
mod output;

/// A word-wise FNV-1a hash of a list of pairs (a checkpoint's check of a rebuilt list).
fn pairs_hash(pairs: &[[u32; 2]]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for &w in pairs.as_flattened() {
        h = (h ^ u64::from(w)).wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The joint stage's count of joints and record of breaks (read by the tests:
/// [`FractureStage::fracture_report`]).
#[derive(Debug, Clone, Default, Serialize)]
pub struct FractureReport {
    /// Joints.
    pub joints: usize,
    /// Broken joints.
    pub broken: usize,
    /// Every fracture event so far: (time, x, y, mode, energy released).
    pub events: Vec<(f64, f64, f64, String, f64)>,
}

/// The joint stage (a [`crate::stages::system::Stage`]).
pub struct FractureStage {
    set: JointSet,
    state: JointState,
    scratch: JointScratch,
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
    /// The length and [`pairs_hash`] of the bonded list at set-up as built (a checkpoint
    /// checks that the resumed run rebuilt the same list).
    initial_pairs: (usize, u64),
    report: FractureReport,
    csv: Option<std::io::BufWriter<std::fs::File>>,
    /// `fractures.csv` was asked for (an output folder was given).
    csv_wanted: bool,
    /// True when the joint series carries each joint's strengths and fracture energies (a
    /// scene of several joint materials or drawn ones: `FractureSection::varied_joints`).
    pub(crate) write_properties: bool,
    /// The next force evaluation is the step's last, committed at its positions (set by
    /// [`ForceTerm::next_evaluation_ends_step`], cleared by that evaluation; never
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
    /// `initial` (one history per joint of `set`, see [`crate::problem::load::Problem::initial_joint_state`]);
    /// `fractures.csv` goes to `out_dir`. Returns with it the bonded pairs at set-up (intact
    /// joints and intact stars: the contact stage's exclusions, given to it at attach,
    /// [`crate::stages::contact::ContactStage::bonded`]); the pairs released later go to the
    /// step's [`StepEvents::released`].
    pub fn new(
        set: JointSet,
        model: &Model,
        out_dir: Option<&Path>,
        initial: Option<JointState>,
        resume: bool,
    ) -> (Self, Vec<[u32; 2]>) {
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
                let d = state.history.damage[j];
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
        let report = FractureReport {
            joints: set.len(),
            broken: state.n_broken,
            ..Default::default()
        };
        let csv = out_dir.and_then(|d| {
            let head = "time,x,y,mode,mode_mix,energy_released,joint";
            crate::output::open_csv(d, "fractures.csv", head, resume)
        });
        (
            Self {
                set,
                state,
                scratch,
                stars,
                bond_state,
                releases: 0,
                released_pairs: 0,
                release_s: 0.0,
                stars_scanned: adopted,
                initial_pairs,
                report,
                csv,
                csv_wanted: out_dir.is_some(),
                write_properties: false,
                ends_step: false,
                local: None,
                partial: false,
                softened: Vec::new(),
            },
            initial,
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
    /// The commit (trusting the last pass's positions when `at_last_pass`), the star
    /// releases and the events of an accepted step, into `events`.
    fn end_step(&mut self, t: f64, x: &[[f64; 2]], at_last_pass: bool, events: &mut StepEvents) {
        events.fractures.clear();
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
            &mut events.fractures,
        );
        self.softened.clear();
        self.softened
            .extend_from_slice(self.scratch.newly_softened());
        self.after_commit(events);
    }

    /// What follows a commit whose breaks are in `events.fractures` and whose newly softened
    /// joints are in `self.softened` (both in joint order, global ids), with `self.state`
    /// holding the breaks: the star releases (appended to `events.released`), the report and
    /// `fractures.csv` (`output.rs`).
    fn after_commit(&mut self, events: &mut StepEvents) {
        if events.softened_taken {
            events.softened.clear();
            events.softened.extend_from_slice(&self.softened);
        }
        // Stars stop bonding at the first softening of one of their joints (damage > 0 at
        // either point) or its break, and a break releases the joint's own pair. One scan of
        // every joint at the first step (a joint may start damaged or broken), then only the
        // joints the commit lists as newly softened or broken; the pairs that leave the
        // bonded set go to the contact stage.
        let t0 = std::time::Instant::now();
        let released = &mut events.released;
        let n_before = released.len();
        if self.stars_scanned {
            for &j in &self.softened {
                let j = j as usize;
                if self.bond_state[j] == 0 {
                    self.stars.release_stars(j, released);
                    self.bond_state[j] = 1;
                }
            }
            for e in &events.fractures {
                let j = e.joint.0 as usize;
                if self.bond_state[j] != 2 {
                    self.stars.break_joint(j, released);
                    self.bond_state[j] = 2;
                }
            }
        } else {
            for (j, st) in self.bond_state.iter_mut().enumerate() {
                // damaged after the commit (in a distributed run the histories here are
                // those before it, and the newly softened joints say the rest)
                let d = self.state.history.damage[j];
                if !self.state.intact[j] {
                    self.stars.break_joint(j, released);
                    *st = 2;
                } else if d[0] > 0.0
                    || d[1] > 0.0
                    || self.softened.binary_search(&(j as u32)).is_ok()
                {
                    self.stars.release_stars(j, released);
                    *st = 1;
                }
            }
            self.stars_scanned = true;
        }
        let n_released = released.len() - n_before;
        if !events.released_taken {
            // No contact stage takes them (a scene without contact): keep nothing.
            released.clear();
        }
        if n_released > 0 {
            self.releases += 1;
            self.released_pairs += n_released as u64;
            self.release_s += t0.elapsed().as_secs_f64();
        }
        self.record_breaks(&events.fractures);
    }
}

impl crate::stages::system::Stage for FractureStage {
    fn name(&self) -> &str {
        "fracture"
    }
}

impl AheadForces for FractureStage {
    fn add(&self, i0: usize, f: &mut [[f64; 2]]) {
        add_joint_forces(&self.set, &self.scratch, i0, f);
    }
}

impl ForceTerm for FractureStage {
    fn forces(
        &mut self,
        _t: f64,
        x: &[[f64; 2]],
        _v: &[[f64; 2]],
        f: &mut [[f64; 2]],
        _events: &mut StepEvents,
    ) {
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

    /// The joint pass ahead of the element forces (a whole run's), its per-node gather then
    /// inside the element pass.
    fn forces_ahead(
        &mut self,
        _t: f64,
        x: &[[f64; 2]],
        _v: &[[f64; 2]],
        _events: &mut StepEvents,
    ) -> Option<&dyn AheadForces> {
        if self.local.is_some() && self.partial {
            return None;
        }
        if std::mem::take(&mut self.ends_step) {
            joint_forces_ahead_committing(&self.set, &mut self.state, x, &mut self.scratch);
        } else {
            joint_forces_ahead(&self.set, &self.state, x, &mut self.scratch);
        }
        Some(self)
    }

    /// The commit (at the last pass's positions when `at_last`), and the pairs it releases
    /// and its breaks into `events` for the stages after this one.
    fn end_of_step(
        &mut self,
        t: f64,
        x: &[[f64; 2]],
        _v: &[[f64; 2]],
        at_last: bool,
        events: &mut StepEvents,
    ) {
        self.end_step(t, x, at_last, events);
    }

    /// The joints' forces depend on the positions and the committed history only.
    fn reads_velocities(&self) -> bool {
        false
    }
}
