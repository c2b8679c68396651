//! The stable step of a scene, in one place: the terms of the frequency bound (elements,
//! contact, joints: [`FrequencyTerms`]), their combination a priori ([`FrequencyTerms::omega_max`])
//! and in a state ([`FrequencyTerms::active`], with the stages' active terms in place of the
//! a-priori contact term), the damping ratio of the highest mode ([`high_mode_damping`]) and
//! the stable step of a scheme ([`stable_step`]):
//!
//! `h_limit = (h omega)_scheme / omega_max * (sqrt(1 + z^2) - z)`
//!
//! with `omega_max^2 = omega_el^2 + omega_contact^2 + omega_joints^2`
//! (docs/time-integration.md, "The stable step of a scene"). Loading ([`crate::problem::load`]),
//! `fdem check`, the run, the study and the adaptive step all take their step from here;
//! [`crate::problem::limits`] checks it.

use fdem_fracture::JointSet;
use fdem_mesh::{Elements, TriId};
use fdem_time::SchemeKind;

use crate::input::scene::Scene;
use crate::problem::model::Model;

/// Relative tolerance of [`step_count`]: `duration / h` within `1e-12` of a whole number is
/// that number.
pub const STEP_TOLERANCE: f64 = 1e-12;

/// The terms of the a-priori frequency bound of a scene [rad/s]:
/// `omega_max^2 = elements^2 + contact^2 + joints^2` (docs/time-integration.md, "The stable
/// step of a scene"). Each term is 0 when the scene lacks it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrequencyTerms {
    /// The largest element frequency bound at the reference positions.
    pub elements: f64,
    /// The contact term: every edge pressed flat with the contact penalty.
    pub contact: f64,
    /// The joints' term, over every joint intact.
    pub joints: f64,
}

impl FrequencyTerms {
    /// The terms of `model` with `elements` (at the reference positions) and the joint set
    /// `joints` (`None` without joints).
    pub fn of(
        scene: &Scene,
        model: &Model,
        elements: &Elements,
        joints: Option<&JointSet>,
    ) -> Self {
        FrequencyTerms {
            elements: elements.max_frequency_bound(&model.x0),
            contact: crate::problem::contact_laws::omega_contact(scene, model),
            joints: joints.map_or(0.0, |set| crate::problem::joints::omega_joints(set, model)),
        }
    }

    /// The bound in a state: `sqrt(elements^2 + joints^2 + sum of active^2)`, each `active`
    /// term a stage's bound for the contact engaged in that state (`fdem_contact::active_bound`,
    /// docs/contact.md section 12) in place of the a-priori contact term.
    pub fn active(&self, active: impl IntoIterator<Item = f64>) -> f64 {
        let mut w2 = self.elements * self.elements + self.joints * self.joints;
        for w in active {
            w2 += w * w;
        }
        w2.sqrt()
    }

    /// `sqrt(elements^2 + contact^2 + joints^2)`.
    pub fn omega_max(&self) -> f64 {
        let (e, c, j) = (self.elements, self.contact, self.joints);
        (e * e + c * c + j * j).sqrt()
    }
}

/// The damping ratio of the highest mode: the largest element viscosity ratio at the highest
/// frequency plus the mass-proportional damping's `alpha / (2 omega_max)`.
pub fn high_mode_damping(scene: &Scene, model: &Model, elements: &Elements, omega_max: f64) -> f64 {
    let z_visc = (0..elements.len())
        .map(|t| elements.high_mode_damping(TriId(t as u32), &model.x0))
        .fold(0.0, f64::max);
    z_visc + scene.damping.mass_proportional / (2.0 * omega_max)
}

/// The number of steps of about `h` that span `duration`: `duration / h` when it is a whole
/// number within a relative [`STEP_TOLERANCE`] (so `2e-5 / 1e-8 = 2000.0000000000002` is
/// 2000 steps, not 2001), else rounded up; at least 1. The step used is then
/// `duration / steps`, within `1e-12` of `h` relative when `duration / h` is whole (so a
/// fixed step given at the stable limit may exceed it by that much, far inside the margins of
/// the limit, an upper bound of the frequencies). Returned
/// as a float: it may be huge or infinite, which [`crate::problem::limits::time_steps`] refuses.
pub fn step_count(duration: f64, h: f64) -> f64 {
    let r = duration / h;
    if !r.is_finite() {
        return r;
    }
    let k = r.round();
    let n = if k >= 1.0 && (r - k).abs() <= STEP_TOLERANCE * r {
        k
    } else {
        r.ceil()
    };
    n.max(1.0)
}

/// The stable step of `scheme` for highest frequency `omega` and its damping ratio `z`:
/// `(h omega)_scheme / omega * (sqrt(1 + z^2) - z)`.
pub fn stable_step(scheme: SchemeKind, omega: f64, z: f64) -> f64 {
    scheme.stability_limit() / omega * ((1.0 + z * z).sqrt() - z)
}
