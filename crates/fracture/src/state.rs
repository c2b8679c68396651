//! Joint history and energy books: changed only by [`crate::commit_joints`] at the end of a
//! step, never by force evaluations (trial stages of multi-stage schemes leave it alone).

use crate::joint::{PointHistory, evaluate};
use crate::set::JointSet;

/// Committed history and energy of one joint (the damage, read by every force pass, is kept
/// apart in [`JointState::damage`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointHistory {
    /// Mode indicator at the two points (0 pure mode I, 1 pure mode II).
    pub mode_mix: [f64; 2],
    /// Time of failure, if broken.
    pub broken_at: Option<f64>,
    /// Work done on the joint since the start (J), trapezoidal rule over committed steps on
    /// the conjugate pairs (A sigma, o) and (A tau, s).
    pub work: f64,
    /// Energy stored in the joint now (J); 0 once broken.
    pub stored: f64,
    /// Energy dissipated so far (J): `work - (stored - stored at the start)` until the break.
    pub dissipated: f64,
    /// `[A sigma, A tau, o, s]` per point at the last commit.
    pub(crate) last: [f64; 8],
}

impl JointHistory {
    /// Mode indicator of the joint: the mean of its two points.
    pub fn mode_mix(&self) -> f64 {
        0.5 * (self.mode_mix[0] + self.mode_mix[1])
    }

    /// True once broken.
    pub fn is_broken(&self) -> bool {
        self.broken_at.is_some()
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
    /// Damage at the two points (P/S, Q/R) of each joint, in `[0, 1]`, never decreasing.
    pub damage: Vec<[f64; 2]>,
    /// Secant shear stiffness `tau/s` at the two points of each joint (Pa/m), never increasing
    /// (read by every force pass, like the damage).
    pub shear_secant: Vec<[f64; 2]>,
    /// False once a joint has broken.
    pub intact: Vec<bool>,
    /// Mode, failure time and energy books, one entry per joint.
    pub history: Vec<JointHistory>,
    /// Stored energy at the start (J).
    pub stored_initial: f64,
    /// Sum of the energies stored in joints at their breaks (J).
    pub released_at_break: f64,
    /// Number of broken joints.
    pub n_broken: usize,
}

impl JointState {
    /// Fresh history (no damage) at the initial positions `x`.
    pub fn new(set: &JointSet, x: &[[f64; 2]]) -> Self {
        assert_eq!(
            x.len(),
            set.n_nodes,
            "positions must have one entry per node"
        );
        let mut stored_initial = 0.0;
        let mut damage = Vec::with_capacity(set.len());
        let mut shear_secant = Vec::with_capacity(set.len());
        let history = (0..set.len())
            .map(|j| {
                let m = &set.materials[set.material[j] as usize];
                let e = evaluate(
                    m,
                    &set.consts[j],
                    &set.gather(j, x),
                    &PointHistory::FRESH,
                    set.thickness,
                );
                stored_initial += e.stored;
                damage.push(e.damage);
                shear_secant.push(e.shear_secant);
                JointHistory {
                    mode_mix: e.mode_mix,
                    broken_at: None,
                    work: 0.0,
                    stored: e.stored,
                    dissipated: 0.0,
                    last: e.local,
                }
            })
            .collect();
        JointState {
            damage,
            shear_secant,
            intact: vec![true; set.len()],
            history,
            stored_initial,
            released_at_break: 0.0,
            n_broken: 0,
        }
    }

    /// The committed history of joint `j` that a force evaluation reads.
    #[inline]
    pub fn point_history(&self, j: usize) -> PointHistory {
        PointHistory {
            damage: self.damage[j],
            mode_mix: self.history[j].mode_mix,
            shear_secant: self.shear_secant[j],
        }
    }

    /// Damage of joint `j`: the mean of its two points; the joint breaks when it reaches 1.
    pub fn joint_damage(&self, j: usize) -> f64 {
        0.5 * (self.damage[j][0] + self.damage[j][1])
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
