//! Joint history and energy books: changed only by [`crate::commit_joints`] at the end of a
//! step, never by force evaluations (trial stages of multi-stage schemes leave it alone).
//!
//! One [`JointHistory`] per joint holds everything a step changes (136 bytes). A force pass
//! reads the committed array and writes the trial history of every joint into the same array
//! of its [`crate::JointScratch`]; the commit swaps the two arrays (no copy). One array rather
//! than one per field: the pass then streams through few arrays, and keeps their pointers in
//! registers.

use rayon::prelude::*;

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
                let (k, xs) = (&set.consts[j], set.gather(j, x));
                let e = if set.initial_offsets.is_empty() {
                    evaluate(m, k, &xs, &PointHistory::FRESH, set.thickness)
                } else {
                    let off = set.initial_offsets[j];
                    evaluate_offset(m, k, &xs, &PointHistory::FRESH, set.thickness, off)
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
