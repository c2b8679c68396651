//! The accuracy section of a run (`summary.json`'s `accuracy`, and a block at the end of the
//! console): the indicators the problem decided before the run
//! ([`crate::problem::accuracy`]), with what the run measured: the time step against the
//! active bound, the energy ledger's closure, the quasi-static indicator and the loading
//! speed, the contact's deepest penetration, and a static solve's largest strain.

use serde_json::json;

use crate::input::scene::Analysis;
use crate::problem::indicator::{Accuracy, Good, Indicator};
use crate::problem::load::Problem;
use crate::problem::stable_step::stable_step;
use crate::run::summary::Summary;

/// The largest relative closure error of the energy ledger without a warning.
pub const ENERGY_ERROR_MAX: f64 = 1e-2;

/// The largest contact overlap over the altitude of the triangle without a warning: a penalty
/// `p_c` gives overlaps of order `sigma h / p_c`, and at 5 % of the element the contact zone's
/// compliance is that of a fifth of an element more (docs/accuracy.md).
pub const PENETRATION_MAX: f64 = 0.05;

/// The largest strain of a static solve without a warning: the solve is linear (small
/// strain), so above 1 % its stresses and displacements drift from the finite-strain answer.
pub const STATIC_STRAIN_MAX: f64 = 1e-2;

/// The accuracy section of the finished run of `l` with the summary `s` (its stages, ledger
/// and quasi-static indicator filled in); `strain`: a static solve's largest strain.
pub fn assess(l: &Problem, s: &Summary, strain: Option<f64>) -> Accuracy {
    let mut out = l.accuracy.clone();
    if l.scene.analysis == Analysis::Static {
        out.extend(strain.map(static_strain));
        return Accuracy::new(out);
    }
    let wc = crate::stages::omega_contact_active_max(&s.stages);
    let active = (wc > 0.0).then(|| stable_step(l.scheme, l.frequency.active([wc]), l.z_high));
    out.push(time_step(l, active));
    out.push(energy_error(s));
    if let Some(q) = quasi_static(l, s) {
        out.push(q);
    }
    if let Some(p) = penetration(s) {
        out.push(p);
    }
    Accuracy::new(out)
}

/// The ledger's closure over the energy in play.
fn energy_error(s: &Summary) -> Indicator {
    let e = &s.energy;
    let rel = e.relative_error().abs();
    let mut ind = Indicator {
        name: "energy_error".into(),
        subject: "run".into(),
        measure: "|ledger error| / energy in play".into(),
        value: rel,
        threshold: ENERGY_ERROR_MAX,
        good: Good::AtMost,
        meaning: "the energy the books do not account for: the integration error (and the \
                  residuals of the laws not booked apart)"
            .into(),
        warning: None,
        details: json!({"error": e.error, "in_play": e.in_play}),
    };
    if !ind.passes() {
        ind.warning = Some(format!(
            "the energy ledger misses {:.2} % of the energy in play: lower \
             integrator.safety or take a smaller time step, and check contact and joint \
             penalties for stiff spikes",
            100.0 * rel
        ));
    }
    ind
}

/// The quasi-static indicator of a loaded specimen (a `loading` or `mass_scaling` section,
/// moving walls or prescribed velocities): the kinetic over the stored energy while loading.
fn quasi_static(l: &Problem, s: &Summary) -> Option<Indicator> {
    let q = s.quasi_static.as_ref()?;
    // moving walls or prescribed velocities load it (as the loading-speed indicator says)
    let (speed, _) = crate::problem::strains::fastest_loading(&l.scene, &l.model);
    let specimen = l.scene.loading.is_some() || l.scene.mass_scaling.is_some() || speed > 0.0;
    if !specimen {
        return None;
    }
    let limit = q
        .limit
        .unwrap_or(crate::input::scene::mass_scaling::KINETIC_RATIO_LIMIT);
    let mut ind = Indicator {
        name: "quasi_static".into(),
        subject: "run".into(),
        measure: "kinetic / stored energy while loading (before the peak)".into(),
        value: q.kinetic_ratio_max,
        threshold: limit,
        good: Good::AtMost,
        meaning: "inertia in a test meant to be quasi-static: above the limit the peak load \
                  is raised by the loading rate"
            .into(),
        warning: None,
        details: json!({
            "peak_time": q.peak_time,
            "kinetic_ratio_max_all": q.kinetic_ratio_max_all,
            "mass_scaling_factor": s.mass_scaling_factor,
        }),
    };
    if !ind.passes() {
        ind.warning = Some(format!(
            "the run is not quasi-static: the kinetic energy reached {:.3} of the stored \
             energy while loading; load more slowly (loading.rate, wall velocities) or lower \
             the mass_scaling factor",
            q.kinetic_ratio_max
        ));
    }
    Some(ind)
}

/// The deepest contact overlap of the run over the altitude of its triangle.
fn penetration(s: &Summary) -> Option<Indicator> {
    let c = s.stages.get("contact")?;
    let d = c.get("max_depth_over_altitude")?.as_f64()?;
    let mean = c
        .get("mean_depth_over_altitude")
        .and_then(|m| m.as_f64())
        .unwrap_or(0.0);
    let mut ind = Indicator {
        name: "contact_penetration".into(),
        subject: "contact".into(),
        measure: format!(
            "the deepest overlap / the altitude of its triangle (mean over the loaded \
             contacts {mean:.2e})"
        ),
        value: d,
        threshold: PENETRATION_MAX,
        good: Good::AtMost,
        meaning: "the penalty's overlap: deep overlaps make contact soft and the bodies sink \
                  into each other"
            .into(),
        warning: None,
        details: json!({"max_depth_over_altitude": d, "mean_depth_over_altitude": mean}),
    };
    if !ind.passes() {
        ind.warning = Some(format!(
            "contact overlapped {:.1} % of an element: raise the contact penalty (contact \
             law `penalty`, about 10 E or more) so that overlaps stay below {:.0} %",
            100.0 * d,
            100.0 * PENETRATION_MAX
        ));
    }
    Some(ind)
}

/// The largest strain of a static solve.
fn static_strain(strain: f64) -> Indicator {
    let mut ind = Indicator {
        name: "static_strain".into(),
        subject: "run".into(),
        measure: "the largest principal strain of the static solve (absolute)".into(),
        value: strain,
        threshold: STATIC_STRAIN_MAX,
        good: Good::AtMost,
        meaning: "a static solve is linear: it holds for small strains only".into(),
        warning: None,
        details: json!({"largest_strain": strain}),
    };
    if !ind.passes() {
        ind.warning = Some(format!(
            "the static solve reached a strain of {strain:.3e}, outside the small-strain \
             range of a linear solve: check the units of the moduli and loads (Pa, N/m), or \
             run a dynamic relaxation (analysis \"relaxation\"), which is at finite strain"
        ));
    }
    ind
}

/// The largest principal strain (absolute) of the displacements `u` (two per node) on the
/// triangles of `elements`, small strain ([`crate::run::static_solve::small_strain`]).
pub fn largest_strain(elements: &fdem_mesh::Elements, u: &[f64]) -> f64 {
    elements
        .tris
        .iter()
        .map(|td| {
            let [exx, eyy, gxy] = crate::run::static_solve::small_strain(td, u);
            let m = 0.5 * (exx + eyy);
            let r = (0.25 * (exx - eyy).powi(2) + 0.25 * gxy * gxy).sqrt();
            (m + r).abs().max((m - r).abs())
        })
        .fold(0.0, f64::max)
}

/// The time-step indicator: the step used over the scheme's stable step a priori
/// (`l.dt / l.dt_limit`); with `active_limit`, the stable step of the largest active bound
/// the run met (contact engaged as it was, not every edge pressed flat), as a detail. The
/// joints' term in both is that of every joint intact: softening lowers a joint's secant
/// stiffness and a broken joint has none, so the intact term is the largest the joints reach
/// in any state of the run, their active bound as well as their a-priori one.
pub fn time_step(l: &Problem, active_limit: Option<f64>) -> Indicator {
    let ratio = l.dt / l.dt_limit;
    let mut details = json!({
        "scheme": l.scheme.name(),
        "time_step": l.dt,
        "stable_step": l.dt_limit,
        "omega_max": l.omega_max(),
        "omega_terms": {
            "elements": l.frequency.elements,
            "contact": l.frequency.contact,
            "joints_intact": l.frequency.joints,
        },
    });
    if let Some(h) = active_limit {
        details["active_stable_step"] = json!(h);
        details["step_over_active_stable_step"] = json!(l.dt / h);
    }
    let mut ind = Indicator {
        name: "time_step".into(),
        subject: "integrator".into(),
        measure: "the step over the stable step of every stage (a priori)".into(),
        value: ratio,
        threshold: 1.0,
        good: Good::AtMost,
        meaning: "above 1 the explicit scheme is unstable; the a-priori bound assumes every \
                  edge in contact, so the margin to the active bound is larger"
            .into(),
        warning: None,
        details,
    };
    if !ind.passes() {
        ind.warning = Some(format!(
            "the step {:.4e} s is {ratio:.3} times the stable step {:.4e} s: set \
             integrator.time_step to \"auto\" or below the stable step",
            l.dt, l.dt_limit
        ));
    }
    ind
}

/// What `fdem check` reports before a run: the problem's indicators
/// ([`crate::problem::accuracy`]) and, for a dynamic or relaxation analysis, the time step's.
pub fn before_run(l: &Problem) -> Vec<Indicator> {
    let mut out = l.accuracy.clone();
    if l.scene.analysis != crate::input::scene::Analysis::Static {
        out.push(time_step(l, None));
    }
    out
}

/// `fdem check`'s accuracy block: a header with the number of warnings, then one line per
/// indicator of `predicted` ([`before_run`]).
pub fn check_block(predicted: &[Indicator]) -> String {
    let warnings = predicted.iter().filter(|i| !i.passes()).count();
    format!(
        "accuracy before the run: {warnings} warning{} (a run reports these again with what it measures){}",
        if warnings == 1 { "" } else { "s" },
        crate::problem::indicator::describe(predicted)
    )
}
