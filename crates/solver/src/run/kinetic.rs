//! Kinetic damping of a relaxation ([`KineticDamping`], `integrator.relaxation: "kinetic"`):
//! the pseudo-dynamics runs undamped, and at each peak of its kinetic energy the velocities
//! are zeroed and the positions moved back to the peak.
//!
//! The peak: with the kinetic energies `E_0, E_1, E_2` at the ends of three consecutive
//! steps and `E_2 < E_1 >= E_0`, the parabola through them peaks at
//! `s = (E_0 - E_2) / (2 (E_0 - 2 E_1 + E_2))` steps after the middle one (`|s| <= 1/2`);
//! the free DOFs are put at `x_1 + s (x_2 - x_1)` (the velocity is near its largest and
//! about constant there, so the path is about straight) and their velocities zeroed. The
//! prescribed DOFs keep their motion.
//!
//! The energy a reset removes is booked as damping (`mass_damping` of the ledger): the
//! ledger's `initial + supplied - present - dissipated` after the reset less before it (the
//! kinetic energy zeroed, the change of the strain and stored energy and of the loads' work
//! over the move back), so that the reset leaves the books' error unchanged. The kinetic
//! energy is summed over the DOFs in their order (no reduction that depends on the threads).

use fdem_time::{Integrator, SecondOrderSystem, State};

use crate::checkpoint::pack::{Dec, DecodeError, Enc};
use crate::run::ledger::Books;
use crate::stages::summed_report;
use crate::stages::system::SceneSystem;

/// The kinetic damping of a relaxation run: the state it carries from step to step.
pub struct KineticDamping {
    /// The positions at the end of the last step (all DOFs).
    prev_x: Vec<f64>,
    /// The kinetic energies at the ends of the step before the last and of the last step.
    energies: [f64; 2],
    /// Resets so far.
    pub resets: u64,
    /// Energy removed by the resets so far [J].
    pub removed: f64,
}

impl KineticDamping {
    /// Kinetic damping for a run at `state` (its initial or resumed state).
    pub fn new(sys: &SceneSystem, state: &State) -> Self {
        Self {
            prev_x: state.x.clone(),
            energies: [0.0, kinetic_energy(sys, &state.v)],
            resets: 0,
            removed: 0.0,
        }
    }

    /// After the step that ended at `state` (its energy booked): a reset when the kinetic
    /// energy passed a peak. Returns whether it reset.
    pub fn after_step(
        &mut self,
        sys: &mut SceneSystem,
        state: &mut State,
        integrator: &mut dyn Integrator,
        ledger: &mut Books,
    ) -> bool {
        let e2 = kinetic_energy(sys, &state.v);
        let [e0, e1] = self.energies;
        if e2.partial_cmp(&e1) != Some(std::cmp::Ordering::Less) {
            self.energies = [e1, e2];
            self.prev_x.copy_from_slice(&state.x);
            return false;
        }
        let curvature = e0 - 2.0 * e1 + e2;
        let s = if curvature < 0.0 {
            (0.5 * (e0 - e2) / curvature).clamp(-0.5, 0.5)
        } else {
            0.0
        };
        let before = ledger
            .ledger(sys, state, summed_report(sys, state.x_nodes()).as_ref())
            .error;
        let constrained = &sys.model.constrained;
        for (d, (x, v)) in state.x.iter_mut().zip(state.v.iter_mut()).enumerate() {
            if !constrained[d] {
                let x1 = self.prev_x[d];
                *x = x1 + s * (*x - x1);
                *v = 0.0;
            }
        }
        // the force at the reset state (the residual and the books read it), and the move
        // committed as a step of the stages (their books of work see it; the state lies on
        // the path between two committed ones); the scheme's cached force is stale
        sys.evaluate(state.t, &state.x, &state.v);
        sys.end_of_step(state.t, &state.x, &state.v);
        sys.evaluated_at_end = true;
        integrator.invalidate();
        ledger.step(sys, state);
        let after = ledger
            .ledger(sys, state, summed_report(sys, state.x_nodes()).as_ref())
            .error;
        ledger.book_removed(after - before);
        self.removed += after - before;
        self.resets += 1;
        self.energies = [0.0, kinetic_energy(sys, &state.v)];
        self.prev_x.copy_from_slice(&state.x);
        true
    }

    /// Appends the state to a checkpoint.
    pub fn save(&self, e: &mut Enc) {
        e.put(&self.prev_x);
        e.put(&self.energies);
        e.put(&self.resets);
        e.put(&self.removed);
    }

    /// Takes up what [`KineticDamping::save`] wrote, for `n_dofs` DOFs.
    pub fn restore(&mut self, d: &mut Dec, n_dofs: usize) -> Result<(), DecodeError> {
        self.prev_x = d.vec_of_len(n_dofs, "kinetic damping positions")?;
        self.energies = d.get()?;
        self.resets = d.get()?;
        self.removed = d.get()?;
        Ok(())
    }
}

/// `1/2 sum v^2 / invm` over the DOFs of finite mass, in DOF order.
fn kinetic_energy(sys: &SceneSystem, v: &[f64]) -> f64 {
    let mut e = 0.0;
    for (vi, im) in v.iter().zip(sys.inv_mass()) {
        if *im > 0.0 {
            e += vi * vi / im;
        }
    }
    0.5 * e
}
