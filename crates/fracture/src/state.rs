//! Joint history and energy books: changed only by [`crate::commit_joints`] at the end of a
//! step, never by force evaluations (trial stages of multi-stage schemes leave it alone).
//!
//! Structure of arrays: one array per field, indexed by joint. A force pass reads the
//! committed arrays and writes the trial values of every field into the same arrays of its
//! [`crate::JointScratch`]; the commit swaps the two sets (no copy).

use crate::joint::{PointHistory, evaluate};
use crate::set::JointSet;

/// Committed history and energy of one joint: a copy of its entries in the arrays of a
/// [`JointState`] ([`JointState::history`]).
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
    pub last: [f64; 8],
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

/// The per-joint arrays that a step changes: the committed ones in [`JointState`], the trial
/// ones of the last pass in [`crate::JointScratch`].
#[derive(Debug, Clone, Default)]
pub(crate) struct Histories {
    pub(crate) damage: Vec<[f64; 2]>,
    pub(crate) shear_secant: Vec<[f64; 2]>,
    pub(crate) mode_mix: Vec<[f64; 2]>,
    pub(crate) last: Vec<[f64; 8]>,
    pub(crate) work: Vec<f64>,
    pub(crate) stored: Vec<f64>,
    pub(crate) dissipated: Vec<f64>,
}

impl Histories {
    /// Arrays of `n` joints (zero, secant infinite).
    pub(crate) fn new(n: usize) -> Self {
        Histories {
            damage: vec![[0.0; 2]; n],
            shear_secant: vec![[f64::INFINITY; 2]; n],
            mode_mix: vec![[0.0; 2]; n],
            last: vec![[0.0; 8]; n],
            work: vec![0.0; n],
            stored: vec![0.0; n],
            dissipated: vec![0.0; n],
        }
    }

    /// Number of joints.
    pub(crate) fn len(&self) -> usize {
        self.damage.len()
    }
}

/// The history of every joint of a [`JointSet`], one array per field.
#[derive(Debug, Clone)]
pub struct JointState {
    /// Damage at the two points (P/S, Q/R) of each joint, in `[0, 1]`, never decreasing.
    pub damage: Vec<[f64; 2]>,
    /// Secant shear stiffness `tau/s` at the two points of each joint (Pa/m), never increasing
    /// (read by every force pass, like the damage).
    pub shear_secant: Vec<[f64; 2]>,
    /// Mode indicator at the two points of each joint (0 pure mode I, 1 pure mode II).
    pub mode_mix: Vec<[f64; 2]>,
    /// Work done on each joint since the start (J), trapezoidal rule over committed steps on
    /// the conjugate pairs (A sigma, o) and (A tau, s).
    pub work: Vec<f64>,
    /// Energy stored in each joint now (J); 0 once broken.
    pub stored: Vec<f64>,
    /// Energy dissipated by each joint so far (J): `work - (stored - stored at the start)`
    /// until the break.
    pub dissipated: Vec<f64>,
    /// `[A sigma, A tau, o, s]` per point of each joint at the last commit (zero once broken).
    pub last: Vec<[f64; 8]>,
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
        let mut h = Histories::new(n);
        let mut stored_initial = 0.0;
        for j in 0..n {
            let m = &set.materials[set.material[j] as usize];
            let e = evaluate(
                m,
                &set.consts[j],
                &set.gather(j, x),
                &PointHistory::FRESH,
                set.thickness,
            );
            stored_initial += e.stored;
            h.damage[j] = e.damage;
            h.shear_secant[j] = e.shear_secant;
            h.mode_mix[j] = e.mode_mix;
            h.stored[j] = e.stored;
            h.last[j] = e.local;
        }
        let mut state = JointState {
            damage: Vec::new(),
            shear_secant: Vec::new(),
            mode_mix: Vec::new(),
            work: Vec::new(),
            stored: Vec::new(),
            dissipated: Vec::new(),
            last: Vec::new(),
            intact: vec![true; n],
            broken_at: vec![None; n],
            stored_initial,
            released_at_break: 0.0,
            n_broken: 0,
            generation: 0,
        };
        state.swap_histories(&mut h);
        state
    }

    /// Exchanges the arrays that a step changes with `h` (the commit of a trial).
    pub(crate) fn swap_histories(&mut self, h: &mut Histories) {
        std::mem::swap(&mut self.damage, &mut h.damage);
        std::mem::swap(&mut self.shear_secant, &mut h.shear_secant);
        std::mem::swap(&mut self.mode_mix, &mut h.mode_mix);
        std::mem::swap(&mut self.last, &mut h.last);
        std::mem::swap(&mut self.work, &mut h.work);
        std::mem::swap(&mut self.stored, &mut h.stored);
        std::mem::swap(&mut self.dissipated, &mut h.dissipated);
    }

    /// Number of joints.
    pub fn len(&self) -> usize {
        self.damage.len()
    }

    /// True when there are no joints.
    pub fn is_empty(&self) -> bool {
        self.damage.is_empty()
    }

    /// The committed history of joint `j` that a force evaluation reads.
    #[inline]
    pub fn point_history(&self, j: usize) -> PointHistory {
        PointHistory {
            damage: self.damage[j],
            mode_mix: self.mode_mix[j],
            shear_secant: self.shear_secant[j],
        }
    }

    /// The committed history and energy books of joint `j`, gathered from the arrays.
    pub fn history(&self, j: usize) -> JointHistory {
        JointHistory {
            mode_mix: self.mode_mix[j],
            broken_at: self.broken_at[j],
            work: self.work[j],
            stored: self.stored[j],
            dissipated: self.dissipated[j],
            last: self.last[j],
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
        for j in 0..self.len() {
            e.work += self.work[j];
            e.stored += self.stored[j];
            e.dissipated += self.dissipated[j];
        }
        e
    }
}
