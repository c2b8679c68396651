//! The active prediction (scenes with contact).
//!
//! The a-priori contact term of `omega_max` assumes every edge of every triangle pressed flat
//! along its whole length, which a collision of curved bodies or a fracture whose crack faces
//! never re-close does not reach. The study first runs the scene once with central difference
//! at half its a-priori step and records at the end of every step the bound of the contact
//! engaged in that state (`fdem_contact::active_bound`); the active bound is
//! `sqrt(omega_el^2 + omega_joints^2 + omega_c,active^2)` with the largest engaged term over
//! that run, and the active predicted step `h_active = r h_pred`, `r = omega_max /
//! omega_active`. The listed fractions stay fractions of `h_pred` (the step a run takes by
//! default), but once they are all stable the ladder goes on in units of the active
//! prediction ([`super::ladder`]), and each scheme's limit is reported against both
//! predictions (`observed_over_active_*`).

use std::path::Path;

use anyhow::{Context, Result};
use fdem_solver::driver::{self, RunOptions};
use fdem_time::SchemeKind;
use serde::Serialize;

/// The active prediction ([`active_bound_run`]).
#[derive(Clone, Debug, Serialize)]
pub(super) struct Active {
    /// The a-priori frequency bound of the scene (elements, contact as if pressed flat
    /// everywhere, joints) [rad/s].
    pub(super) omega_a_priori: f64,
    /// The active bound: `sqrt(omega_el^2 + omega_joints^2 + omega_c,active^2)`, the contact
    /// term the largest over the bound run's states [rad/s].
    pub(super) omega_active: f64,
    /// That largest active contact term [rad/s] and when [s].
    pub(super) omega_contact_active: f64,
    pub(super) omega_contact_active_time: f64,
    /// `h_active / h_pred = omega_a_priori / omega_active`.
    pub(super) ratio: f64,
}

/// The active prediction: the scene (as studied) run once with central difference at half its
/// a-priori predicted step, recording at the end of every step the bound of the contact
/// engaged in that state (`fdem_contact::active_bound`, the contact stage's
/// `omega_active_max`). The active bound is the largest over the run's states combined with
/// the elements' and the joints' terms; `None` without contact (the a-priori bound is then
/// the active one).
pub(super) fn active_bound_run(scene: &Path, out: &Path) -> Result<Option<Active>> {
    let mut l = driver::load(scene)?;
    if !l.scene.contact.as_ref().is_some_and(|c| c.enabled) {
        return Ok(None);
    }
    let k = SchemeKind::CentralDifference;
    l.scheme = k;
    l.dt_limit = driver::stable_step(k, l.omega_max(), l.z_high);
    l.scene.integrator.scheme = k.name().into();
    l.scene.output.frames = 0;
    if let Some(c) = &mut l.scene.contact {
        // every state: a sampled maximum misses brief peaks (16 % on the pressed blocks
        // sampled every 10 steps)
        c.active_bound_every = 1;
    }
    let duration = l.scene.duration.unwrap_or(0.0);
    (l.n_steps, l.dt) = driver::step_count(duration, 0.5 * l.dt_limit);
    std::fs::create_dir_all(out)?;
    let options = RunOptions {
        out_dir: out.to_path_buf(),
        raw: false,
        ..Default::default()
    };
    let o = driver::run_outcome(&mut l, &options, &mut |_| {})
        .with_context(|| format!("the active-bound run of {}", scene.display()))?;
    let wc = fdem_solver::stages::omega_contact_active_max(&o.summary.stages);
    let tc = o
        .summary
        .stages
        .pointer("/contact/omega_active_max_time")
        .and_then(|v| v.as_f64())
        .unwrap_or(0.0);
    let omega_active = l.frequency.active([wc]);
    Ok(Some(Active {
        omega_a_priori: l.omega_max(),
        omega_active,
        omega_contact_active: wc,
        omega_contact_active_time: tc,
        ratio: l.omega_max() / omega_active,
    }))
}
