//! Joint history and energy books: changed only by [`crate::commit_joints`] at the end of a
//! step, never by force evaluations (trial stages of multi-stage schemes leave it alone).
//!
//! The history is held field by field ([`Histories`]): a force pass reads the damage, the
//! shear secants, the committed openings and slidings, normal forces `A sigma`, stored and
//! dissipated energy of every joint, and the mode indicators of the damaged ones only; it
//! writes the openings, slidings, normal forces and energies of every joint, and the damage,
//! secants and mode indicators only where they change. An undamaged joint whose secants stay
//! moves 160 bytes of history per step.
//!
//! Energy books: each step a joint's dissipated energy grows by the work of the step (the
//! trapezoidal rule on the conjugate pairs `(A sigma, o)` and `(A tau, s)`) less the change of
//! its stored energy. The shear force at the start of the step is computed again as
//! `A k_t s` from the committed secant and sliding (the law's own operations: the same bits),
//! so it is not kept. The work done on the joints is `stored - stored at the start +
//! dissipated + stored at the breaks`, joint by joint ([`JointState::work`]) and in total
//! ([`JointState::energy`]).

use rayon::prelude::*;

use crate::error::FractureError;
use crate::joint::{PointHistory, evaluate, evaluate_offset};
use crate::set::{JointSet, pick};

/// The committed history of every joint, one array per field (joint order).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Histories {
    /// Damage at the two points (P/S, Q/R), in `[0, 1]`, never decreasing.
    pub damage: Vec<[f64; 2]>,
    /// Secant shear stiffness `tau/s` at the two points (Pa/m), never increasing.
    pub shear_secant: Vec<[f64; 2]>,
    /// Mode indicator at the two points (0 pure mode I, 1 pure mode II); 0 while undamaged.
    pub mode_mix: Vec<[f64; 2]>,
    /// `[o, s]` of the two points at the last commit, `[o_0, s_0, o_1, s_1]` (m), with the
    /// initial offsets of a prestressed joint included; zero once broken.
    pub local: Vec<[f64; 4]>,
    /// `A sigma` of the two points at the last commit (N); zero once broken.
    pub normal: Vec<[f64; 2]>,
    /// Energy stored in the joint at the last commit (J); zero once broken.
    pub stored: Vec<f64>,
    /// Energy dissipated so far (J).
    pub dissipated: Vec<f64>,
}

impl Histories {
    /// Number of joints.
    pub fn len(&self) -> usize {
        self.damage.len()
    }

    /// True when there are no joints.
    pub fn is_empty(&self) -> bool {
        self.damage.is_empty()
    }

    /// The histories of the joints `keep`, in that order.
    pub fn subset(&self, keep: &[u32]) -> Histories {
        Histories {
            damage: pick(&self.damage, keep),
            shear_secant: pick(&self.shear_secant, keep),
            mode_mix: pick(&self.mode_mix, keep),
            local: pick(&self.local, keep),
            normal: pick(&self.normal, keep),
            stored: pick(&self.stored, keep),
            dissipated: pick(&self.dissipated, keep),
        }
    }

    /// Sizes every array for `n` joints, new entries fresh.
    pub(crate) fn resize(&mut self, n: usize) {
        self.damage.resize(n, [0.0; 2]);
        self.shear_secant.resize(n, [f64::INFINITY; 2]);
        self.mode_mix.resize(n, [0.0; 2]);
        self.local.resize(n, [0.0; 4]);
        self.normal.resize(n, [0.0; 2]);
        self.stored.resize(n, 0.0);
        self.dissipated.resize(n, 0.0);
    }

    /// What a force evaluation of joint `j` reads.
    #[inline]
    pub fn point_history(&self, j: usize) -> PointHistory {
        PointHistory {
            damage: self.damage[j],
            mode_mix: self.mode_mix[j],
            shear_secant: self.shear_secant[j],
        }
    }

    /// Mode indicator of joint `j`: the mean of its two points.
    pub fn joint_mode_mix(&self, j: usize) -> f64 {
        0.5 * (self.mode_mix[j][0] + self.mode_mix[j][1])
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

/// Each joint's energy books (J), in joint order: for output.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JointBooks {
    /// [`JointState::stored`].
    pub stored: Vec<f64>,
    /// [`JointState::work`].
    pub work: Vec<f64>,
    /// [`Histories::dissipated`].
    pub dissipated: Vec<f64>,
}

/// A [`JointState`] as plain data, for checkpoints: its public fields and its
/// [`JointState::generation`]; [`JointState::from_snapshot`] checks it against the joint set
/// and gives the state back.
#[derive(Debug, Clone, PartialEq)]
pub struct JointStateSnapshot {
    /// [`JointState::history`].
    pub history: Histories,
    /// [`JointState::stored_at_start`].
    pub stored_at_start: Vec<f64>,
    /// [`JointState::stored_at_break`].
    pub stored_at_break: Vec<f64>,
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
    /// Damage, shear secant, mode indicator, committed opening and sliding, and dissipated
    /// energy per joint.
    pub history: Histories,
    /// Energy stored in each joint at the start (J).
    pub stored_at_start: Vec<f64>,
    /// Energy stored in each joint when it broke (J); 0 while intact.
    pub stored_at_break: Vec<f64>,
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
        let evals: Vec<_> = (0..n)
            .into_par_iter()
            .with_min_len(1024)
            .map(|j| {
                let m = &set.materials[set.material[j] as usize];
                let (k, soft, xs) = (&set.consts(j), &set.softening[j], set.gather(j, x));
                if set.initial_offsets.is_empty() {
                    evaluate(m, k, soft, &xs, &PointHistory::FRESH, set.thickness)
                } else {
                    let off = set.initial_offsets[j];
                    evaluate_offset(m, k, soft, &xs, &PointHistory::FRESH, set.thickness, off)
                }
            })
            .collect();
        let mut history = Histories::default();
        let mut stored_at_start = Vec::with_capacity(n);
        let mut stored_initial = 0.0;
        for e in &evals {
            history.damage.push(e.damage);
            history.shear_secant.push(e.shear_secant);
            history.mode_mix.push(e.mode_mix);
            history
                .local
                .push([e.local[2], e.local[3], e.local[6], e.local[7]]);
            history.normal.push([e.local[0], e.local[4]]);
            history.stored.push(e.stored);
            history.dissipated.push(0.0);
            stored_at_start.push(e.stored);
            stored_initial += e.stored;
        }
        JointState {
            history,
            stored_at_start,
            stored_at_break: vec![0.0; n],
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

    /// The state as plain data (for a checkpoint).
    pub fn snapshot(&self) -> JointStateSnapshot {
        JointStateSnapshot {
            history: self.history.clone(),
            stored_at_start: self.stored_at_start.clone(),
            stored_at_break: self.stored_at_break.clone(),
            intact: self.intact.clone(),
            broken_at: self.broken_at.clone(),
            stored_initial: self.stored_initial,
            released_at_break: self.released_at_break,
            n_broken: self.n_broken,
            generation: self.generation,
        }
    }

    /// The state a [`JointStateSnapshot`] saved (from the public fields of a state and its
    /// [`JointState::generation`]), for `set`: every array must have one entry per joint of
    /// `set`, an intact joint has no time of failure, `n_broken` counts the broken joints and
    /// every damage lies in `[0, 1]`. Continues bit for bit where the saved
    /// state left off.
    pub fn from_snapshot(set: &JointSet, s: JointStateSnapshot) -> Result<Self, FractureError> {
        let n = set.len();
        let h = &s.history;
        for (what, got) in [
            ("damage", h.damage.len()),
            ("shear_secant", h.shear_secant.len()),
            ("mode_mix", h.mode_mix.len()),
            ("local", h.local.len()),
            ("normal", h.normal.len()),
            ("stored", h.stored.len()),
            ("dissipated", h.dissipated.len()),
            ("stored_at_start", s.stored_at_start.len()),
            ("stored_at_break", s.stored_at_break.len()),
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
        if let Some(j) = h
            .damage
            .iter()
            .position(|d| !d.iter().all(|d| (0.0..=1.0).contains(d)))
        {
            return bad(format!(
                "joint {j} has damage {:?} outside [0, 1]",
                h.damage[j]
            ));
        }
        Ok(JointState {
            history: s.history,
            stored_at_start: s.stored_at_start,
            stored_at_break: s.stored_at_break,
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
        self.intact.len()
    }

    /// True when there are no joints.
    pub fn is_empty(&self) -> bool {
        self.intact.is_empty()
    }

    /// The committed history of joint `j` that a force evaluation reads.
    #[inline]
    pub fn point_history(&self, j: usize) -> PointHistory {
        self.history.point_history(j)
    }

    /// Damage of joint `j`: the mean of its two points; the joint breaks when it reaches 1.
    pub fn joint_damage(&self, j: usize) -> f64 {
        let d = self.history.damage[j];
        0.5 * (d[0] + d[1])
    }

    /// Energy stored in joint `j` now (J); 0 once broken.
    pub fn stored(&self, j: usize) -> f64 {
        self.history.stored[j]
    }

    /// Work done on joint `j` since the start (J): stored energy now (at its break, once
    /// broken) less that at the start, plus the energy it dissipated.
    pub fn work(&self, j: usize) -> f64 {
        let now = if self.intact[j] {
            self.history.stored[j]
        } else {
            self.stored_at_break[j]
        };
        now - self.stored_at_start[j] + self.history.dissipated[j]
    }

    /// Books the break of joint `j` at `time`, with the energy `stored` it held then: no longer
    /// intact, the energy handed over to the totals, its opening, sliding, normal forces and
    /// stored energy zeroed (its damage, secants, mode indicators and dissipation stay).
    pub fn record_break(&mut self, j: usize, time: f64, stored: f64) {
        self.intact[j] = false;
        self.broken_at[j] = Some(time);
        self.released_at_break += stored;
        self.stored_at_break[j] = stored;
        self.n_broken += 1;
        let h = &mut self.history;
        h.local[j] = [0.0; 4];
        h.normal[j] = [0.0; 2];
        h.stored[j] = 0.0;
    }

    /// Every joint's energy books.
    pub fn books(&self) -> JointBooks {
        JointBooks {
            stored: self.history.stored.clone(),
            work: (0..self.len()).map(|j| self.work(j)).collect(),
            dissipated: self.history.dissipated.clone(),
        }
    }

    /// The state of the joints `keep` (increasing ids, as [`crate::JointSet::subset`]): their
    /// histories, intact flags and break times, generation 0; the totals (initial stored
    /// energy, energy released at breaks, broken count) are those of `self`.
    pub fn subset(&self, keep: &[u32]) -> JointState {
        JointState {
            history: self.history.subset(keep),
            stored_at_start: pick(&self.stored_at_start, keep),
            stored_at_break: pick(&self.stored_at_break, keep),
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
        let stored = self.history.stored.iter().fold(0.0, |a, b| a + b);
        let dissipated = self.history.dissipated.iter().fold(0.0, |a, b| a + b);
        JointEnergy {
            work: stored - self.stored_initial + dissipated + self.released_at_break,
            stored,
            stored_initial: self.stored_initial,
            dissipated,
            released_at_break: self.released_at_break,
        }
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
        s.snapshot()
    }

    /// A snapshot gives the state back field for field (the commit count included); one of
    /// another length, an intact joint with a time of failure, a wrong count or a damage outside [0, 1] is refused
    /// with a message naming it.
    #[test]
    fn a_snapshot_restores_the_state_and_a_damaged_one_is_refused() {
        let (set, mut state) = two();
        state.history.damage[1] = [0.25, 1.0];
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
        assert!(err(&|s| s.history.damage.truncate(1)).contains("`damage` has 1 entries"));
        assert!(err(&|s| s.history.local.truncate(1)).contains("`local` has 1 entries"));
        assert!(err(&|s| s.stored_at_break.push(0.0)).contains("`stored_at_break` has 3"));
        assert!(err(&|s| s.intact.push(true)).contains("`intact` has 3"));
        assert!(err(&|s| s.broken_at[0] = Some(0.0)).contains("joint 0 is intact"));
        // a joint broken before the run has no time of failure
        let mut pre = snapshot(&state);
        pre.broken_at[1] = None;
        assert!(JointState::from_snapshot(&set, pre).is_ok());
        assert!(err(&|s| s.n_broken = 2).contains("2 broken joints counted, 1 flagged"));
        assert!(err(&|s| s.history.damage[0][1] = f64::NAN).contains("outside [0, 1]"));
        assert!(err(&|s| s.history.damage[0][0] = -1e-300).contains("joint 0 has damage"));
    }
}
