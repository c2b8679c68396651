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
use crate::model::Model;
use crate::scene::{BoundaryCondition, Scene, TimeStep};
use crate::summary::Summary;

pub use crate::model::LARGE_STRAIN;

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

/// One input's estimated strain on the body it acts on.
#[derive(Debug, Clone)]
pub struct InputStrain {
    /// JSON path of the input (e.g. `boundary_conditions[1]`).
    pub path: String,
    /// What it is, in words, with its magnitude.
    pub what: String,
    /// The strain estimate (dimensionless).
    pub strain: f64,
}

/// A body's scale for the estimates: smallest Young's modulus [Pa], largest density
/// [kg/m^3], smallest thickness [m], smaller and larger bounding-box sides [m].
#[derive(Debug, Clone, Copy)]
struct BodyScale {
    young: f64,
    density: f64,
    thickness: f64,
    h_small: f64,
    h_large: f64,
}

fn body_scales(model: &Model) -> Vec<BodyScale> {
    let nb = model.body_nodes.len();
    let mut s = vec![
        BodyScale {
            young: f64::INFINITY,
            density: 0.0,
            thickness: f64::INFINITY,
            h_small: 0.0,
            h_large: 0.0,
        };
        nb
    ];
    for (t, &b) in model.tri_body.iter().enumerate() {
        let Some(bs) = s.get_mut(b as usize) else {
            continue;
        };
        if let Some((m, _)) = model.materials.get(model.tri_material[t] as usize) {
            bs.young = bs.young.min(m.young);
            bs.density = bs.density.max(m.density);
        }
        bs.thickness = bs.thickness.min(model.tri_thickness[t]);
    }
    for (b, r) in model.body_nodes.iter().enumerate() {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &model.x0[r.start as usize..r.end as usize] {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
        s[b].h_large = w.max(h);
        s[b].h_small = if w.min(h) > 0.0 { w.min(h) } else { w.max(h) };
    }
    s
}

fn body_of_node(model: &Model, node: u32) -> usize {
    model
        .body_nodes
        .iter()
        .position(|r| r.contains(&node))
        .unwrap_or(0)
}

/// The name of body `b` for messages: `'name'` or `bodies[b]`.
fn body_name(scene: &Scene, b: usize) -> String {
    match scene.bodies.get(b).and_then(|x| x.name.as_deref()) {
        Some(n) => format!("'{}'", fdem_mesh::excerpt(n)),
        None => format!("bodies[{b}]"),
    }
}

/// The strain estimate of every load, velocity and gravity of the scene, largest first.
pub fn input_strains(scene: &Scene, model: &Model) -> Vec<InputStrain> {
    let scales = body_scales(model);
    let mut out = Vec::new();
    let scale = |b: usize| scales.get(b).copied();
    // Loads: one model load per load condition, in scene order.
    let mut loads = model.loads.iter();
    for (i, bc) in scene.boundary_conditions.iter().enumerate() {
        let (kind, group) = match bc {
            BoundaryCondition::Pressure(p) => ("pressure", &p.group),
            BoundaryCondition::Traction(p) => ("traction", &p.group),
            BoundaryCondition::PointLoad(p) => ("point load", &p.group),
            BoundaryCondition::Velocity(v) => {
                let peak = v
                    .history
                    .as_ref()
                    .map_or(1.0, |h| crate::time_history::History::new(h).max_abs());
                let speed = peak * v.x.unwrap_or(0.0).hypot(v.y.unwrap_or(0.0));
                let b = model
                    .groups
                    .iter()
                    .find(|(b, name, _)| {
                        *name == v.group
                            && v.body.as_ref().is_none_or(|want| {
                                scene.bodies.get(*b as usize).and_then(|x| x.name.as_ref())
                                    == Some(want)
                            })
                    })
                    .map_or(0, |(b, _, _)| *b as usize);
                if let Some(s) = scale(b) {
                    let c = (s.young / s.density).sqrt();
                    let what = format!(
                        "the prescribed velocity on '{}' ({speed:.3e} m/s, against the wave speed {c:.3e} m/s of body {})",
                        fdem_mesh::excerpt(&v.group),
                        body_name(scene, b)
                    );
                    // a velocity as written within range, made too large by the loading
                    // rate (which multiplied it): the rate is the input at fault
                    let rate = scene.loading.as_ref().map_or(1.0, |l| l.rate);
                    let (path, what) = if rate > 1.0 && speed / rate / c <= LARGE_STRAIN {
                        (
                            "loading.rate".to_string(),
                            format!("the loading rate {rate:.3e} makes {what}"),
                        )
                    } else {
                        (format!("boundary_conditions[{i}]"), what)
                    };
                    out.push(InputStrain {
                        path,
                        what,
                        strain: speed / c,
                    });
                }
                continue;
            }
            BoundaryCondition::Fixed(_) | BoundaryCondition::Displacement(_) => continue,
        };
        let Some(load) = loads.next() else { break };
        let total: f64 = {
            let mut per_node = std::collections::BTreeMap::<u32, [f64; 2]>::new();
            for &(d, f) in &load.forces {
                per_node.entry(d / 2).or_default()[(d % 2) as usize] += f;
            }
            let peak = load.history.as_ref().map_or(1.0, |h| h.max_abs());
            peak * per_node.values().map(|f| f[0].hypot(f[1])).sum::<f64>()
        };
        let b = load
            .forces
            .first()
            .map_or(0, |&(d, _)| body_of_node(model, d / 2));
        if let Some(s) = scale(b) {
            let stiff = s.young * s.thickness * s.h_small;
            out.push(InputStrain {
                path: format!("boundary_conditions[{i}]"),
                what: format!(
                    "the {kind} on '{}' ({total:.3e} N in total, against E t h = {stiff:.3e} N of body {})",
                    fdem_mesh::excerpt(group),
                    body_name(scene, b)
                ),
                strain: total / stiff,
            });
        }
    }
    for (b, body) in scene.bodies.iter().enumerate() {
        let speed = body.initial_velocity[0].hypot(body.initial_velocity[1]);
        if let (true, Some(s)) = (speed > 0.0, scale(b)) {
            let c = (s.young / s.density).sqrt();
            out.push(InputStrain {
                path: format!("bodies[{b}].initial_velocity"),
                what: format!(
                    "the initial velocity of body {} ({speed:.3e} m/s, against its wave speed {c:.3e} m/s)",
                    body_name(scene, b)
                ),
                strain: speed / c,
            });
        }
    }
    if let Some(g) = scene.gravity {
        let g = g[0].hypot(g[1]);
        for (b, s) in scales.iter().enumerate() {
            out.push(InputStrain {
                path: "gravity".into(),
                what: format!(
                    "gravity ({g:.3e} m/s^2 on body {}: rho g H / E)",
                    body_name(scene, b)
                ),
                strain: s.density * g * s.h_large / s.young,
            });
        }
    }
    out.retain(|s| !s.strain.is_nan());
    out.sort_by(|a, b| b.strain.total_cmp(&a.strain));
    out
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
    let damp = match scene.integrator.relaxation_method(&scene.damping) {
        crate::scene::RelaxationMethod::Viscous => format!(
            "damp near critically (`damping.mass_proportional`, now {alpha:e} 1/s: about twice the lowest natural frequency), or remove it for kinetic damping (`integrator.relaxation`: \"kinetic\", the default)"
        ),
        crate::scene::RelaxationMethod::Kinetic => "kinetic damping (the default) needs about (omega_max / omega_1) ln(1/tol) / 4 steps, omega_1 the lowest natural frequency: a finer mesh or a slender body needs more".into(),
        crate::scene::RelaxationMethod::Adaptive => "try kinetic damping (`integrator.relaxation`: \"kinetic\", the default), which needed half the steps of adaptive damping on the cantilever".into(),
        crate::scene::RelaxationMethod::ConjugateGradient => "the conjugate-gradient relaxation took 4 800 iterations on a 25 920-triangle cantilever, more under loads that rotate the body far (finite strain); where damage grows during the relaxation its energy is not a potential: try kinetic damping (`integrator.relaxation`: \"kinetic\", the default)".into(),
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
