//! Joint history and energy books: changed only by [`crate::commit_joints`] at the end of a
//! step, never by force evaluations (trial stages of multi-stage schemes leave it alone).
//!
//! One [`JointHistory`] per joint holds everything a step changes (136 bytes). A force pass
//! reads the committed array and writes the trial history of every joint into the same array
//! of its [`crate::JointScratch`]; the commit swaps the two arrays (no copy). One array rather
//! than one per field: the pass then streams through few arrays, and keeps their pointers in
//! registers.

use rayon::prelude::*;

use crate::error::FractureError;
use crate::joint::{PointHistory, evaluate, evaluate_offset};
use crate::set::JointSet;

/// Committed history and energy books of one joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointHistory {
    /// Damage at the two points (P/S, Q/R), in `[0, 1]`, never decreasing.
    pub damage: [f64; 2],
    /// Secant shear stiffness `tau/s` at the two points (Pa/m), never increasing;
    /// `f64::INFINITY` for a fresh joint.
    pub shear_secant: [f64; 2],
    /// Mode indicator at the two points (0 pure mode I, 1 pure mode II).
    pub mode_mix: [f64; 2],
    /// `[A sigma, A tau, o, s]` per point at the last commit (zero once broken).
    pub last: [f64; 8],
    /// Work done on the joint since the start (J), trapezoidal rule over committed steps on
    /// the conjugate pairs (A sigma, o) and (A tau, s).
    pub work: f64,
    /// Energy stored in the joint now (J); 0 once broken.
    pub stored: f64,
    /// Energy dissipated so far (J): `work - (stored - stored at the start)` until the break.
    pub dissipated: f64,
}

impl JointHistory {
    /// The history of a fresh joint (no damage, no shear softening, empty books).
    pub const FRESH: JointHistory = JointHistory {
        damage: [0.0; 2],
        shear_secant: [f64::INFINITY; 2],
        mode_mix: [0.0; 2],
        last: [0.0; 8],
        work: 0.0,
        stored: 0.0,
        dissipated: 0.0,
    };

    /// Mode indicator of the joint: the mean of its two points.
    pub fn mode_mix(&self) -> f64 {
        0.5 * (self.mode_mix[0] + self.mode_mix[1])
    }
}

/// Totals over all joints (J).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointEnergy {
    /// Work done on the joints since the start.
    pub work: f64,
    /// Energy stored in intact joints now.
    pub stored: f64,
    /// Energy stored at the start.
    pub stored_initial: f64,
    /// Energy dissipated by fracture.
    pub dissipated: f64,
    /// Energy still stored in joints when they broke (handed over with the break).
    pub released_at_break: f64,
}

/// A [`JointState`] as plain data, for checkpoints: its public fields and its
/// [`JointState::generation`]; [`JointState::from_snapshot`] checks it against the joint set
/// and gives the state back.
#[derive(Debug, Clone, PartialEq)]
pub struct JointStateSnapshot {
    /// [`JointState::history`].
    pub history: Vec<JointHistory>,
    /// [`JointState::intact`].
    pub intact: Vec<bool>,
    /// [`JointState::broken_at`].
    pub broken_at: Vec<Option<f64>>,
    /// [`JointState::stored_initial`].
    pub stored_initial: f64,
    /// [`JointState::released_at_break`].
    pub released_at_break: f64,
    /// [`JointState::n_broken`].
    pub n_broken: usize,
    /// [`JointState::generation`].
    pub generation: u64,
}

/// The history of every joint of a [`JointSet`].
#[derive(Debug, Clone)]
pub struct JointState {
    /// Damage, shear secant, mode indicator, work conjugates and energy books per joint.
    pub history: Vec<JointHistory>,
    /// False once a joint has broken.
    pub intact: Vec<bool>,
    /// Time of failure of each joint, if broken.
    pub broken_at: Vec<Option<f64>>,
    /// Stored energy at the start (J).
    pub stored_initial: f64,
    /// Sum of the energies stored in joints at their breaks (J).
    pub released_at_break: f64,
    /// Number of broken joints.
    pub n_broken: usize,
    /// Number of commits so far: a pass's trial values are those of this history only.
    pub(crate) generation: u64,
}

impl JointState {
    /// Fresh history (no damage) at the initial positions `x`.
    pub fn new(set: &JointSet, x: &[[f64; 2]]) -> Self {
        assert_eq!(
            x.len(),
            set.n_nodes,
            "positions must have one entry per node"
        );
        let n = set.len();
        // every joint in parallel, then the stored energy summed in joint order
        let history: Vec<JointHistory> = (0..n)
            .into_par_iter()
            .with_min_len(1024)
            .map(|j| {
                let m = &set.materials[set.material[j] as usize];
                let (k, soft, xs) = (&set.consts[j], &set.softening[j], set.gather(j, x));
                let e = if set.initial_offsets.is_empty() {
                    evaluate(m, k, soft, &xs, &PointHistory::FRESH, set.thickness)
                } else {
                    let off = set.initial_offsets[j];
                    evaluate_offset(m, k, soft, &xs, &PointHistory::FRESH, set.thickness, off)
                };
                JointHistory {
                    damage: e.damage,
                    shear_secant: e.shear_secant,
                    mode_mix: e.mode_mix,
                    last: e.local,
                    work: 0.0,
                    stored: e.stored,
                    dissipated: 0.0,
                }
            })
            .collect();
        let mut stored_initial = 0.0;
        for h in &history {
            stored_initial += h.stored;
        }
        JointState {
            history,
            intact: vec![true; n],
            broken_at: vec![None; n],
            stored_initial,
            released_at_break: 0.0,
            n_broken: 0,
            generation: 0,
        }
    }

    /// Number of commits so far (saved with the state: [`JointStateSnapshot::generation`]).
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The state a [`JointStateSnapshot`] saved (from the public fields of a state and its
    /// [`JointState::generation`]), for `set`: every array must have one entry per joint of
    /// `set`, an intact joint has no time of failure, `n_broken` counts the broken joints and
    /// every damage lies in `[0, 1]`. Continues bit for bit where the saved
    /// state left off.
    pub fn from_snapshot(set: &JointSet, s: JointStateSnapshot) -> Result<Self, FractureError> {
        let n = set.len();
        for (what, got) in [
            ("history", s.history.len()),
            ("intact", s.intact.len()),
            ("broken_at", s.broken_at.len()),
        ] {
            if got != n {
                return Err(FractureError::LengthMismatch {
                    what,
                    got,
                    expected: n,
                });
            }
        }
        let bad = |m: String| Err(FractureError::InvalidState(m));
        // a broken joint may have no time of failure (broken before the run)
        if let Some(j) = (0..n).find(|&j| s.intact[j] && s.broken_at[j].is_some()) {
            return bad(format!("joint {j} is intact but has a time of failure"));
        }
        let broken = s.intact.iter().filter(|i| !**i).count();
        if broken != s.n_broken {
            return bad(format!(
                "{} broken joints counted, {broken} flagged",
                s.n_broken
            ));
        }
        if let Some(j) = s
            .history
            .iter()
            .position(|h| !h.damage.iter().all(|d| (0.0..=1.0).contains(d)))
        {
            return bad(format!(
                "joint {j} has damage {:?} outside [0, 1]",
                s.history[j].damage
            ));
        }
        Ok(JointState {
            history: s.history,
            intact: s.intact,
            broken_at: s.broken_at,
            stored_initial: s.stored_initial,
            released_at_break: s.released_at_break,
            n_broken: s.n_broken,
            generation: s.generation,
        })
    }

    /// Number of joints.
    pub fn len(&self) -> usize {
        self.history.len()
    }

    /// True when there are no joints.
    pub fn is_empty(&self) -> bool {
        self.history.is_empty()
    }

    /// The committed history of joint `j` that a force evaluation reads.
    #[inline]
    pub fn point_history(&self, j: usize) -> PointHistory {
        let h = &self.history[j];
        PointHistory {
            damage: h.damage,
            mode_mix: h.mode_mix,
            shear_secant: h.shear_secant,
        }
    }

    /// Damage of joint `j`: the mean of its two points; the joint breaks when it reaches 1.
    pub fn joint_damage(&self, j: usize) -> f64 {
        let d = self.history[j].damage;
        0.5 * (d[0] + d[1])
    }

    /// The state of the joints `keep` (increasing ids, as [`crate::JointSet::subset`]): their
    /// histories, intact flags and break times, generation 0; the totals (initial stored
    /// energy, energy released at breaks, broken count) are those of `self`.
    pub fn subset(&self, keep: &[u32]) -> JointState {
        JointState {
            history: keep.iter().map(|&j| self.history[j as usize]).collect(),
            intact: keep.iter().map(|&j| self.intact[j as usize]).collect(),
            broken_at: keep.iter().map(|&j| self.broken_at[j as usize]).collect(),
            stored_initial: self.stored_initial,
            released_at_break: self.released_at_break,
            n_broken: self.n_broken,
            generation: 0,
        }
    }

    /// Totals over all joints, summed in joint order.
    pub fn energy(&self) -> JointEnergy {
        let mut e = JointEnergy {
            stored_initial: self.stored_initial,
            released_at_break: self.released_at_break,
            ..Default::default()
        };
        for h in &self.history {
            e.work += h.work;
            e.stored += h.stored;
            e.dissipated += h.dissipated;
        }
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::JointMaterialInput;
    use crate::set::Joint;

    /// Two joints of length 1 cm, fresh at their reference positions.
    fn two() -> (JointSet, JointState) {
        let m = JointMaterialInput {
            tensile_strength: 5e6,
            cohesion: 10e6,
            friction_angle_deg: 30.0,
            fracture_energy_i: 50.0,
            fracture_energy_ii: 250.0,
            penalty_normal: 3e12,
            penalty_tangential: 3e12,
        };
        let j = |k: u32| Joint {
            nodes: [4 * k, 4 * k + 1, 4 * k + 2, 4 * k + 3],
            triangles: [2 * k, 2 * k + 1],
            ref_length: 0.01,
            material: 0,
        };
        let x = [[0.0, 0.0], [0.01, 0.0], [0.01, 0.0], [0.0, 0.0]].repeat(2);
        let set = JointSet::new(&[j(0), j(1)], &[m], 8, 1.0).unwrap();
        let state = JointState::new(&set, &x);
        (set, state)
    }

    fn snapshot(s: &JointState) -> JointStateSnapshot {
        JointStateSnapshot {
            history: s.history.clone(),
            intact: s.intact.clone(),
            broken_at: s.broken_at.clone(),
            stored_initial: s.stored_initial,
            released_at_break: s.released_at_break,
            n_broken: s.n_broken,
            generation: s.generation(),
        }
    }

    /// A snapshot gives the state back field for field (the commit count included); one of
    /// another length, an intact joint with a time of failure, a wrong count or a damage outside [0, 1] is refused
    /// with a message naming it.
    #[test]
    fn a_snapshot_restores_the_state_and_a_damaged_one_is_refused() {
        let (set, mut state) = two();
        state.history[1].damage = [0.25, 1.0];
        state.intact[1] = false;
        state.broken_at[1] = Some(2e-6);
        state.n_broken = 1;
        state.generation = 17;
        let back = JointState::from_snapshot(&set, snapshot(&state)).unwrap();
        assert_eq!(back.history, state.history);
        assert_eq!(back.intact, state.intact);
        assert_eq!(back.broken_at, state.broken_at);
        assert_eq!(back.n_broken, 1);
        assert_eq!(back.generation(), 17);
        let err = |edit: &dyn Fn(&mut JointStateSnapshot)| {
            let mut s = snapshot(&state);
            edit(&mut s);
            JointState::from_snapshot(&set, s).unwrap_err().to_string()
        };
        assert!(err(&|s| s.history.truncate(1)).contains("`history` has 1 entries"));
        assert!(err(&|s| s.intact.push(true)).contains("`intact` has 3"));
        assert!(err(&|s| s.broken_at[0] = Some(0.0)).contains("joint 0 is intact"));
        // a joint broken before the run has no time of failure
        let mut pre = snapshot(&state);
        pre.broken_at[1] = None;
        assert!(JointState::from_snapshot(&set, pre).is_ok());
        assert!(err(&|s| s.n_broken = 2).contains("2 broken joints counted, 1 flagged"));
        assert!(err(&|s| s.history[0].damage[1] = f64::NAN).contains("outside [0, 1]"));
        assert!(err(&|s| s.history[0].damage[0] = -1e-300).contains("joint 0 has damage"));
    }
}
