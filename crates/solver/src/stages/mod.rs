//! The stages of the composition beyond the elements (contact, joints): attaching the ones a
//! problem needs to a [`SceneSystem`], their active frequency terms and their summed reports.
//! A scene without their sections gets none of them and pays nothing.

pub mod contact;
pub mod fluid;
pub mod fracture;
pub mod star_bonds;
pub mod system;

use std::path::Path;

use crate::error::SceneError;
use crate::problem::load::Problem;
use crate::problem::stable_step::FrequencyTerms;
use crate::stages::system::{Engaged, SceneSystem, StageReport};

/// The **active** frequency bound at positions `x` of a system whose stages are attached and
/// whose forces were last evaluated at `x`:
/// `omega^2 = omega_el^2 + omega_joints^2 + sum over the stages of their active term^2`
/// (the contact engaged in that state, `fdem_contact::active_bound`, in place of the a-priori
/// contact term that assumes every edge pressed flat; docs/contact.md section 12). `terms`:
/// the problem's frequency terms ([`Problem::frequency`]), whose element and joint terms
/// are taken as they are and whose contact term is not used.
pub fn omega_active(sys: &mut SceneSystem, x: &[[f64; 2]], terms: &FrequencyTerms) -> f64 {
    let stages = sys.contributions.iter_mut();
    terms.active(stages.filter_map(|c| c.active_frequency_bound(x, Engaged::LastEvaluation)))
}

/// [`omega_active`] with a look-ahead: the larger of the bound at `x` (the contact engaged at
/// the last force evaluation) and the bound of every detected couple at the extrapolated
/// positions `x + ahead v` (contact about to engage within `ahead` seconds at the current
/// velocities). `scratch` holds the extrapolated positions.
pub fn omega_active_ahead(
    sys: &mut SceneSystem,
    x: &[[f64; 2]],
    v: &[[f64; 2]],
    ahead: f64,
    terms: &FrequencyTerms,
    scratch: &mut Vec<[f64; 2]>,
) -> f64 {
    scratch.clear();
    scratch.extend(
        x.iter()
            .zip(v)
            .map(|(p, u)| [p[0] + ahead * u[0], p[1] + ahead * u[1]]),
    );
    terms.active(sys.contributions.iter_mut().filter_map(|c| {
        let now = c.active_frequency_bound(x, Engaged::LastEvaluation);
        let then = c.active_frequency_bound(scratch, Engaged::Elsewhere);
        now.into_iter().chain(then).reduce(f64::max)
    }))
}

/// The largest active contact bound over a run's end-of-step states [rad/s], from the run
/// summary's stage details (`contact.omega_active_max`); 0 without contact.
pub fn omega_contact_active_max(stages: &serde_json::Value) -> f64 {
    stages
        .get("contact")
        .and_then(|c| c.get("omega_active_max"))
        .and_then(|w| w.as_f64())
        .unwrap_or(0.0)
}

/// Attaches the stages a loaded scene needs to `sys` (time step `dt`, histories every `every`
/// steps into `out_dir`): joints first (from [`Problem::initial_joint_state`] when it is set,
/// else with the pre-existing cracks broken, [`crate::problem::cracks::initial_state`]), then contact
/// (which excludes the bonded pairs: intact joints and stars).
pub fn attach(
    l: &Problem,
    sys: &mut SceneSystem,
    dt: f64,
    out_dir: &Path,
    every: u64,
) -> Result<(), SceneError> {
    attach_to(l, sys, dt, Some(out_dir), every, false)
}

/// [`attach`], writing no files (`walls.csv`, `fractures.csv`) when `out_dir` is `None`:
/// the stages of `fdem check`'s timed sample of the run. `resume`: the stages continue the
/// files of a run resumed from a checkpoint (their state comes next, from
/// [`StageCheckpoint::restore`](crate::stages::system::StageCheckpoint::restore)).
pub fn attach_to(
    l: &Problem,
    sys: &mut SceneSystem,
    dt: f64,
    out_dir: Option<&Path>,
    every: u64,
    resume: bool,
) -> Result<(), SceneError> {
    let (scene, fracturing) = (&l.scene, &l.fracturing);
    let mut bonded = None;
    let initial = l.initial_joint_state.as_ref();
    crate::problem::joints::check_initial_state(initial, fracturing.n_joints(), &l.file)?;
    if let Some(set) = &fracturing.set {
        let initial = (initial.cloned())
            .or_else(|| crate::problem::cracks::initial_state(fracturing, &sys.model));
        let (mut stage, b) = crate::stages::fracture::FractureStage::new(
            set.clone(),
            &sys.model,
            out_dir,
            initial,
            resume,
        );
        stage.write_properties = scene.fracture.as_ref().is_some_and(|f| f.varied_joints());
        bonded = Some(b);
        sys.contributions.push(Box::new(stage));
    }
    if let Some(mut stage) =
        crate::stages::contact::ContactStage::new(scene, &sys.model, dt, out_dir, every, resume)
    {
        // the contact stage excludes the bonded pairs and takes those the joints release
        sys.events.released_taken = bonded.is_some();
        stage.bonded = bonded;
        stage.book_work = scene
            .histories
            .probes
            .iter()
            .any(|p| matches!(p, crate::input::scene::Probe::Energy));
        sys.contributions.push(Box::new(stage));
    }
    if let (Some(setup), Some(set)) = (&l.fluid, &fracturing.set) {
        // the joints broken at the start (cracks, a saved state) are channels
        let broken: Vec<bool> = match sys.contributions.iter().find_map(|c| c.joint_state()) {
            Some(s) => s.intact.iter().map(|i| !i).collect(),
            None => vec![false; set.len()],
        };
        let limit = l.scheme.stability_limit();
        let mut stage =
            crate::stages::fluid::FluidStage::new(setup, set, &broken, &sys.model, limit / dt);
        stage.set_scheme_limit(limit);
        sys.events.softened_taken = setup.wet_damaged;
        sys.contributions.push(Box::new(stage));
    }
    Ok(())
}

/// The first error a stage reports (e.g. too deep a penetration), if any.
pub fn first_error(sys: &SceneSystem) -> Option<String> {
    sys.contributions.iter().find_map(|c| c.error())
}

/// The stages' reports at positions `x`, summed, and their details by name.
pub fn reports(sys: &SceneSystem, x: &[[f64; 2]]) -> (StageReport, serde_json::Value) {
    let mut total = StageReport::default();
    let mut details = serde_json::Map::new();
    for (i, c) in sys.contributions.iter().enumerate() {
        let r = c.report(x);
        total.stored += r.stored;
        total.friction += r.friction;
        total.contact_damping += r.contact_damping;
        total.fracture += r.fracture;
        total.switch_loss += r.switch_loss;
        total.contact_residual += r.contact_residual;
        total.wall_work += r.wall_work;
        total.fluid_work += r.fluid_work;
        let mut d = r.details;
        if let (Some(obj), Some(t)) = (d.as_object_mut(), sys.contribution_times.get(i)) {
            // wall time of the stage's force passes and end-of-step hooks [s]
            obj.insert("wall_s".into(), serde_json::json!(t));
            // of which in the end-of-step hooks (commits, re-detections) [s]
            let e = sys.contribution_end_times.get(i).copied().unwrap_or(0.0);
            obj.insert("end_of_step_s".into(), serde_json::json!(e));
        }
        details.insert(c.name().to_string(), d);
    }
    (total, serde_json::Value::Object(details))
}

/// The stages' summed report at positions `x` (`None` without stages).
pub fn summed_report(sys: &SceneSystem, x: &[[f64; 2]]) -> Option<StageReport> {
    (!sys.contributions.is_empty()).then(|| reports(sys, x).0)
}
