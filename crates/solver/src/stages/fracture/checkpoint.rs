//! The fracture stage in a checkpoint ([`StageCheckpoint`]): section `fracture` (module docs of
//! [`crate::stages::fracture`]).

use fdem_fracture::{Histories, JointState, JointStateSnapshot};

use super::{FractureReport, FractureStage};
use crate::checkpoint::pack::PackSlice;
use crate::checkpoint::{Dec, DecodeError, Enc, Pack};
use crate::stages::system::{StageCheckpoint, StepEvents};

/// The joints' histories, field by field.
impl Pack for Histories {
    fn pack(&self, e: &mut Enc) {
        e.put(&self.damage);
        e.put(&self.shear_secant);
        e.put(&self.mode_mix);
        e.put(&self.local);
        e.put(&self.normal);
        e.put(&self.stored);
        e.put(&self.dissipated);
    }

    fn unpack(d: &mut Dec) -> Result<Self, DecodeError> {
        Ok(Histories {
            damage: d.get()?,
            shear_secant: d.get()?,
            mode_mix: d.get()?,
            local: d.get()?,
            normal: d.get()?,
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

impl FractureStage {
    /// Reads the section body [`StageCheckpoint::save`] wrote, checking its sizes against
    /// the scene's joints and stars and its flags against each other.
    fn read_saved(&self, d: &mut Dec) -> Result<Saved, DecodeError> {
        let n = self.set.len();
        let nj: usize = d.get()?;
        if nj != n {
            return Err(d.error(format!("{nj} joints where the scene has {n}")));
        }
        let snapshot = JointStateSnapshot {
            // the lengths are checked against the joint set by `from_snapshot`
            history: d.get()?,
            stored_at_start: d.vec_of_len(n, "joints' stored energies at the start")?,
            stored_at_break: d.vec_of_len(n, "joints' stored energies at their breaks")?,
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
            let damaged = state.history.damage[j] != [0.0; 2];
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
}

impl StageCheckpoint for FractureStage {
    /// Section `fracture`: the joints' committed state, the star bonds' flags, the release
    /// counters and timer, the bonded pairs not yet taken by the contact stage, the shared
    /// report and the length of `fractures.csv` (flushed). Not saved: the joint set and the
    /// star topology (rebuilt from the scene by the attach; the list of bonded pairs at
    /// set-up is checked by its length and hash), and the scratch: `JointScratch` holds
    /// nothing a later step reads after a commit (its trial history, forces and chunk flags
    /// are rewritten by the next force pass, its list of newly softened joints by the next
    /// commit, it keeps no positions, and a commit marks its trial stale), nor does
    /// `events` (cleared at each commit).
    fn save(&mut self, e: &mut Enc, events: &StepEvents) -> std::io::Result<()> {
        let csv_len = match &mut self.csv {
            Some(w) => Some(crate::output::csv_length(w)?),
            None => None,
        };
        let report = &self.report;
        let (n, s) = (self.set.len(), &self.state);
        // the section's size, to grow the buffer once: 112 bytes of history, 16 of stored
        // energies and 4 flags per joint, a flag per star, 8 bytes per time of failure,
        // released pair and event field
        let n_events = report.events.len();
        let size = 132 * n + self.stars.n_stars() + 8 * (s.n_broken + events.released.len());
        e.buf.reserve(size + 48 * n_events + 256);
        e.section("fracture", |e| {
            e.put(&n);
            e.put(&s.history);
            e.put(&s.stored_at_start);
            e.put(&s.stored_at_break);
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
            e.put(&events.released);
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

    /// Reads what [`StageCheckpoint::save`] wrote, checks it against the scene (joint and star
    /// counts, the bonded list at set-up, flags that agree with each other), then cuts
    /// `fractures.csv` back to its length at the checkpoint (shorter is an error) and takes
    /// the state over. Every check of the checkpoint's content comes before any change; after
    /// an error (a short or missing file included) the stage is not to be used.
    fn restore(&mut self, d: &mut Dec, events: &mut StepEvents) -> Result<(), DecodeError> {
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
        events.released = saved.released;
        self.report = saved.report;
        Ok(())
    }

    fn joint_state(&self) -> Option<&JointState> {
        Some(&self.state)
    }
}
