//! Why a run did not reach its goal, said in the terms of the scene: the cause of an
//! instability and its fix, and the fix for a relaxation that did not converge.
//!
//! An instability is found by the run's stability checks (every 100 steps: non-finite values,
//! energy growth, a stage's error such as too deep a contact). What was found does not say
//! why, and the fixes differ. The cause is taken, in this order, as:
//!
//! 1. **An input far too large for the material.** The estimate of the strain each input
//!    imposes on the body it acts on: a load of total nodal magnitude `F` (N) on a body of
//!    smallest Young's modulus `E`, thickness `t` and smaller bounding-box side `h` strains it by
//!    about `F / (E t h)`; a velocity `v` (initial or prescribed) by `v / c` with the bar wave
//!    speed `c = sqrt(E / rho)`; gravity by `rho |g| H / E` (`H` the larger side). An estimate
//!    above [`LARGE_STRAIN`] is beyond what the constant-strain triangles represent: the fix is
//!    the input's magnitude or units, and a shorter step does not help. A prescribed velocity
//!    in range as written, made too large by `loading.rate` (which multiplies it), is laid at
//!    the rate.
//! 2. **Energy growth** (the mechanical energy above the energy supplied, and growing): the
//!    scheme is past its stable step on this scene; the fix is the step.
//! 3. **A triangle turned inside out** (signed area of opposite sign to the reference one,
//!    looked for by [`InversionWatch`] at each check) at a check whose energy check passed:
//!    a deformation within the energy the inputs supplied but too large for the mesh; the fix
//!    names the largest input.
//! 4. Otherwise (non-finite values with none of the above, or a stage's error): the step, or
//!    the stage's own fix, with the largest input named.
//!
//! Any inversion seen is reported too (which triangle, which body, where, when).

use std::fmt::Write as _;

use crate::error::RunError;
use crate::input::scene::{Scene, TimeStep};
use crate::problem::model::Model;
use crate::problem::strains::{InputStrain, body_name, input_strains};
use crate::run::summary::Summary;

pub use crate::problem::model::LARGE_STRAIN;

/// The first triangle seen turned inside out.
#[derive(Debug, Clone, Copy)]
pub struct Inversion {
    /// Step of the check that saw it.
    pub step: u64,
    /// Simulated time [s].
    pub time: f64,
    /// Triangle index (the model's numbering, as in the output frames).
    pub tri: usize,
    /// Its centroid in the reference configuration [m].
    pub at: [f64; 2],
}

/// Watches for triangles turned inside out; costs one pass over the triangles per call, no
/// allocation.
#[derive(Debug, Default)]
pub struct InversionWatch {
    /// The first inversion seen, if any.
    pub first: Option<Inversion>,
}

fn signed_area(x: &[[f64; 2]], t: &[u32; 3]) -> f64 {
    let (a, b, c) = (x[t[0] as usize], x[t[1] as usize], x[t[2] as usize]);
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
}

impl InversionWatch {
    /// Records the first triangle whose signed area at `x` has the opposite sign of its
    /// reference area (non-finite positions are not an inversion: the caller reports them).
    pub fn scan(&mut self, model: &Model, x: &[[f64; 2]], step: u64, time: f64) {
        if self.first.is_some() || x.len() != model.x0.len() {
            return;
        }
        for (i, t) in model.triangles.iter().enumerate() {
            let a = signed_area(x, t);
            let a0 = signed_area(&model.x0, t);
            if a * a0 < 0.0 {
                let c = |k: usize| {
                    (model.x0[t[0] as usize][k]
                        + model.x0[t[1] as usize][k]
                        + model.x0[t[2] as usize][k])
                        / 3.0
                };
                self.first = Some(Inversion {
                    step,
                    time,
                    tri: i,
                    at: [c(0), c(1)],
                });
                return;
            }
        }
    }
}

/// What the run's checks found.
#[derive(Debug, Clone)]
pub enum Found {
    /// Non-finite positions or velocities.
    NonFinite,
    /// Energy growth (the guard's message, with the step and its predicted limit).
    EnergyGrowth(String),
    /// A stage's error (e.g. too deep a contact).
    Stage(String),
    /// Non-finite values in an output frame.
    Frame,
}

/// The `Unstable` error for what the run's checks found at `step` (time `t`): what was found, the
/// cause in the scene's terms and the fix for that cause (module docs).
pub fn unstable(
    scene: &Scene,
    model: &Model,
    watch: &InversionWatch,
    step: u64,
    time: f64,
    found: Found,
) -> RunError {
    let inputs = input_strains(scene, model);
    let largest = inputs.first();
    let mut m = match &found {
        Found::NonFinite => "non-finite positions or velocities".to_string(),
        Found::EnergyGrowth(s) | Found::Stage(s) => s.clone(),
        Found::Frame => {
            "non-finite positions, velocities, forces or stresses in an output frame (not written)"
                .to_string()
        }
    };
    if let Some(inv) = &watch.first {
        let b = model.tri_body.get(inv.tri).copied().unwrap_or(0) as usize;
        let _ = write!(
            m,
            "\n  seen: triangle {} of body {} (near ({:.4e}, {:.4e}) m) turned inside out (negative area) by step {} (t = {:.4e} s)",
            inv.tri,
            body_name(scene, b),
            inv.at[0],
            inv.at[1],
            inv.step,
            inv.time
        );
    }
    let input_fix = |l: &InputStrain| {
        if l.path == "loading.rate" {
            return "lower `loading.rate`: it multiplies every prescribed velocity and wall velocity; a shorter step does not help".to_string();
        }
        format!(
            "check the magnitude and units of `{}` (N for point loads, Pa for pressures and tractions, m/s for velocities) against the material (young in Pa, density in kg/m^3); a shorter step does not help",
            l.path
        )
    };
    let step_fix = || {
        format!(
            "lower the time step: `integrator.safety` (now {}){}",
            scene.integrator.safety,
            match scene.integrator.time_step {
                TimeStep::Fixed(h) =>
                    format!(", or the fixed `integrator.time_step` (now {h:e} s), or use \"auto\""),
                _ => String::new(),
            }
        )
    };
    let largest_text = |l: &InputStrain| {
        format!(
            "`{}`: {}, a strain of about {:.2e}",
            l.path, l.what, l.strain
        )
    };
    let fix = if let Some(l) = largest.filter(|l| l.strain > LARGE_STRAIN) {
        let _ = write!(
            m,
            "\n  cause: `{}` is far too large for the material: {}, a strain of about {:.2e} (the triangles represent strains well below 1)",
            l.path, l.what, l.strain
        );
        input_fix(l)
    } else {
        match &found {
            Found::EnergyGrowth(_) => step_fix(),
            _ if watch.first.is_some() => {
                // seen at a check that the energy check passed: a deformation within the
                // energy supplied, too large for the mesh
                let _ = write!(
                    m,
                    "\n  cause: a deformation larger than the triangles can represent, within the energy the loads supplied{}",
                    largest.map_or(String::new(), |l| format!(
                        "; the largest input is {}",
                        largest_text(l)
                    ))
                );
                match largest {
                    Some(l) => format!(
                        "lower `{}` or the other loads and velocities, stiffen the material, or refine the mesh where the triangle turned; a shorter step does not help",
                        l.path
                    ),
                    None => "lower the loads or velocities, or stiffen the material".into(),
                }
            }
            Found::Stage(_) => "lower the loads or velocities that drive the bodies together, or stiffen the contact (`contact.penalty_factor`)".into(),
            Found::NonFinite | Found::Frame => format!(
                "{}; check the materials (young, density) and the loads{}",
                step_fix(),
                largest.map_or(String::new(), |l| format!(
                    " (largest: {})",
                    largest_text(l)
                ))
            ),
        }
    };
    let _ = write!(m, "\n  fix: {fix}");
    RunError::Unstable {
        step,
        time,
        message: m,
    }
}

/// The `NotConverged` error of a relaxation whose summary says `converged: false`; `None`
/// for any other run.
pub fn not_converged(scene: &Scene, summary: &Summary) -> Option<RunError> {
    if summary.converged != Some(false) {
        return None;
    }
    let alpha = scene.damping.mass_proportional;
    let duration = scene.duration.unwrap_or(0.0);
    let tol = scene.integrator.relaxation_tolerance;
    let damp = match scene.relaxation_choice().0 {
        crate::input::scene::RelaxationMethod::Viscous => format!(
            "damp near critically (`damping.mass_proportional`, now {alpha:e} 1/s: about twice the lowest natural frequency), or remove it for kinetic damping (`integrator.relaxation`: \"kinetic\")"
        ),
        crate::input::scene::RelaxationMethod::Kinetic => "kinetic damping needs about (omega_max / omega_1) ln(1/tol) / 4 steps, omega_1 the lowest natural frequency: a finer mesh or a slender body needs more".into(),
        crate::input::scene::RelaxationMethod::Adaptive => "try kinetic damping (`integrator.relaxation`: \"kinetic\"), which needed half the steps of adaptive damping on the cantilever".into(),
        crate::input::scene::RelaxationMethod::ConjugateGradient => "the conjugate-gradient relaxation took 4 800 iterations on a 25 920-triangle cantilever, more under loads that rotate the body far (finite strain); where damage grows during the relaxation its energy is not a potential: try kinetic damping (`integrator.relaxation`: \"kinetic\")".into(),
    };
    Some(RunError::NotConverged {
        residual: summary.relative_residual.unwrap_or(f64::NAN),
        tolerance: tol,
        steps: summary.steps,
        time: summary.simulated_time,
        fix: format!(
            "run longer (`duration`, now {duration:e} s), or loosen `integrator.relaxation_tolerance` (now {tol:e}); {damp}; the output written is the state at the end of the duration"
        ),
    })
}
