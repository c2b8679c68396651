//! The derived quantities a run depends on, checked in one place before anything is written:
//! the frequency bound, the stable step, the time step, the number of steps, the frames and
//! the history rows. Each failure is a [`SceneError::Invalid`] that names the input
//! responsible (its JSON path) and the fix.
//!
//! - The highest frequency bound must be finite: an infinite bound is a stable step of 0.
//! - The stable step and the step used must be at least [`MIN_TIME_STEP`].
//! - The number of steps ([`step_count`](crate::problem::stable_step::step_count)) must be at most [`MAX_STEPS`].
//! - The step used must be at least [`MIN_TIME_STEP`] (a duration shorter than that is
//!   refused at `duration`, or at `loading.rate` when the rate shortened it).
//! - A mass scaling may not lengthen the step to the whole duration (one step), nor make a
//!   mass overflow ([`check_mass_factor`]): refused at the field that gives the factor.
//! - A fixed-step run writes at most one frame per step: `output.frames` <= steps (refused at
//!   the mass scaling or the loading rate when without it there would be steps enough).
//! - The history rows (`histories.csv`, held in memory until written, and `walls.csv`) must
//!   stay below [`MAX_HISTORY_BYTES`].
//!
//! When the step is too small, the message names the input responsible ([`step_driver`]):
//! damping that shrinks the stable step a thousandfold; else a material with a wave speed
//! `sqrt(E / rho)` above 1e5 m/s (its density or Young's modulus, whichever is farther from a
//! usual solid's); else the largest term of the frequency bound: the elements (the material
//! or the mesh of the triangle with the highest bound), the contact (the law with the largest
//! penalty) or the joints (their penalty).

use std::path::Path;

use fdem_mesh::{Elements, TriId};
use fdem_time::SchemeKind;

use crate::error::SceneError;
use crate::input::scene::{Analysis, Probe, Scene, TimeStep};
use crate::problem::model::Model;
use crate::problem::stable_step::{FrequencyTerms, stable_step, step_count};

/// The most steps a run may take: `1e10`. Far above any useful run (fdem steps about 1.5e7
/// triangles per second, so 1e10 steps of even a 100-triangle mesh take 18 hours), and it
/// keeps the step at least `1e-10` of the duration, so the time `t + h` advances at every step
/// with six digits to spare in a 64-bit float and the step count is an exact integer.
pub const MAX_STEPS: f64 = 1e10;

/// The smallest time step a run may use: `1e-18` s. The stable step of a 1 nm element of
/// diamond is about 5e-14 s; a continuum model of a solid never needs a step below an
/// attosecond, and below it `h^2` heads for the underflow range.
pub const MIN_TIME_STEP: f64 = 1e-18;

/// The most bytes of history rows a run may write: 2 GiB (`histories.csv` is held in memory
/// until it is written; `walls.csv` goes to disk as it runs). A row value takes about 25 bytes.
pub const MAX_HISTORY_BYTES: f64 = 2.0 * 1024.0 * 1024.0 * 1024.0;

/// The energy terms of a history row with the `energy` probe (the run's energy ledger,
/// `crate::run::ledger::Energies::columns`).
pub const ENERGY_COLUMNS: usize = 24;

/// What [`time_steps`] needs.
pub struct StepInputs<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The scene file, for messages.
    pub file: &'a Path,
    /// The model.
    pub model: &'a Model,
    /// The elements.
    pub elements: &'a Elements,
    /// The scheme.
    pub scheme: SchemeKind,
    /// The highest frequency bound [rad/s].
    pub omega_max: f64,
    /// The terms of the a-priori frequency bound (elements, contact, joints), for naming the
    /// one that sets the step.
    pub frequency: FrequencyTerms,
    /// The damping ratio of the highest mode.
    pub z_high: f64,
    /// A fixed `time_step` above the stable limit: lowered to it (`true`) or refused.
    pub lower_fixed_step: bool,
}

/// The steps of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Steps {
    /// The stable limit of the scheme [s].
    pub dt_limit: f64,
    /// The step used [s] (0 for static).
    pub dt: f64,
    /// The number of steps (0 for static).
    pub n_steps: u64,
}

/// The stable limit, the step and the number of steps of a scene, every one checked (module
/// docs).
pub fn time_steps(inp: &StepInputs) -> Result<Steps, SceneError> {
    let scene = inp.scene;
    let bad = |path: &str, message: String, fix: String| SceneError::Invalid {
        file: inp.file.to_path_buf(),
        path: path.to_string(),
        message,
        fix,
    };
    let dt_limit = stable_step(inp.scheme, inp.omega_max, inp.z_high);
    if scene.analysis == Analysis::Static {
        return Ok(Steps {
            dt_limit,
            dt: 0.0,
            n_steps: 0,
        });
    }
    if !(inp.omega_max.is_finite()
        && inp.omega_max > 0.0
        && dt_limit.is_finite()
        && dt_limit >= MIN_TIME_STEP)
    {
        let d = step_driver(inp);
        // (the damping factor in its cancellation-free form, for the message)
        let z = inp.z_high;
        let dt_limit = inp.scheme.stability_limit() / inp.omega_max / ((1.0 + z * z).sqrt() + z);
        return Err(bad(
            &d.path,
            format!(
                "the stable time step is {dt_limit:.3e} s, not a step a run can take (at least \
                 {MIN_TIME_STEP:e} s; highest frequency bound {:.3e} rad/s): {}",
                inp.omega_max, d.what
            ),
            d.fix,
        ));
    }
    let duration = scene.duration.unwrap_or(0.0);
    let fixed = match scene.integrator.time_step {
        TimeStep::Fixed(h) => Some(h),
        TimeStep::Auto | TimeStep::Adaptive => None,
    };
    let h = match fixed {
        None => scene.integrator.safety * dt_limit,
        Some(h) if h > dt_limit && inp.lower_fixed_step => dt_limit,
        Some(h) if h > dt_limit => {
            return Err(bad(
                "integrator.time_step",
                format!(
                    "time step {h:e} s is above the stability limit {dt_limit:e} s of {} on this mesh",
                    inp.scheme
                ),
                format!(
                    "use \"auto\" or a step below {:.3e} s (e.g. {:.3e} s)",
                    dt_limit,
                    0.5 * dt_limit
                ),
            ));
        }
        Some(h) => h,
    };
    if h.is_nan() || h < MIN_TIME_STEP {
        let (path, fix) = if fixed.is_some() {
            (
                "integrator.time_step",
                format!(
                    "use \"auto\" or a step between {MIN_TIME_STEP:e} s and the stable limit {dt_limit:.3e} s"
                ),
            )
        } else {
            (
                "integrator.safety",
                "use a safety factor between 0.5 and 0.9".to_string(),
            )
        };
        return Err(bad(
            path,
            format!(
                "the time step {h:.3e} s is below the smallest step {MIN_TIME_STEP:e} s a run may use"
            ),
            fix,
        ));
    }
    let n = step_count(duration, h);
    if n.is_nan() || n > MAX_STEPS {
        return Err(too_many_steps(inp, fixed.is_some(), h, n));
    }
    let n_steps = n as u64;
    let dt = duration / n;
    check_scaled_steps(inp, h, n, dt)?;
    check_frames(inp, n, n_steps)?;
    check_history_rows(inp, n_steps)?;
    Ok(Steps {
        dt_limit,
        dt,
        n_steps,
    })
}

/// A fixed-step run of `n_steps` steps (`n` as a float) writes at most one frame per step:
/// refused at the mass scaling or the loading rate when without it there would be steps
/// enough, else at `output.frames`.
fn check_frames(inp: &StepInputs, n: f64, n_steps: u64) -> Result<(), SceneError> {
    let scene = inp.scene;
    let adaptive = scene.integrator.time_step == TimeStep::Adaptive;
    let frames = scene.output.frames;
    if !adaptive && frames as u64 > n_steps {
        // the input that cut the steps below the frames: the mass scaling or the loading
        // rate when without it there would be enough steps, else the frames themselves
        let (path, why, fix) = match slow_run_driver(inp) {
            Some((path, gain, what)) if frames as f64 <= n * gain => (
                path.clone(),
                format!(" ({what} cuts the steps {gain:.3e}-fold)"),
                format!("lower {path}, or ask for at most {n_steps} frame(s)"),
            ),
            _ => (
                "output.frames".to_string(),
                String::new(),
                format!("ask for at most {n_steps} frame(s), or use a smaller time step"),
            ),
        };
        return Err(invalid(
            inp,
            &path,
            format!(
                "{frames} frames over a run of {n_steps} step(s){why}: a frame is written at the \
                 end of a step, at most one per step"
            ),
            fix,
        ));
    }
    Ok(())
}

/// A mass scaling factor `f` (given at `path`, or derived from it) on `model`: the scaled
/// masses and densities must be finite numbers, else the error names `path`, not the density
/// of a body.
pub fn check_mass_factor(f: f64, path: &str, model: &Model, file: &Path) -> Result<(), SceneError> {
    let m_max = model.mass.iter().fold(0.0f64, |a, m| a.max(*m));
    let rho_max = model
        .materials
        .iter()
        .fold(0.0f64, |a, (m, _)| a.max(m.density));
    let factor = (0..model.triangles.len())
        .map(|e| model.density_factor(e))
        .fold(1.0f64, f64::max);
    if (f * m_max).is_finite() && (f * rho_max * factor).is_finite() {
        return Ok(());
    }
    Err(SceneError::invalid(
        file,
        path,
        format!(
            "a mass scaling factor {f:.3e} makes the masses (largest {m_max:.3e} kg, density \
             {rho_max:.3e} kg/m^3) larger than any finite number"
        ),
        "give a mass scaling that lengthens the step a few times to some hundred times (the factor is the square of that)",
    ))
}

/// The mass scaling or the loading rate of a scene, when it has one that cuts the number of
/// steps: (its JSON path, the factor by which it cuts them, what it is in words).
fn slow_run_driver(inp: &StepInputs) -> Option<(String, f64, String)> {
    let scene = inp.scene;
    if let Some((f, _)) = &inp.model.mass_scaling
        && *f > 1.0
    {
        let path = match scene.mass_scaling.as_ref().and_then(|m| m.target_step) {
            Some(_) => "mass_scaling.target_step",
            None => "mass_scaling.factor",
        };
        return Some((
            path.into(),
            f.sqrt(),
            format!("the mass scaling factor {f:.3e} (from `{path}`)"),
        ));
    }
    let r = scene.loading.as_ref().map_or(1.0, |l| l.rate);
    (r > 1.0).then(|| {
        (
            "loading.rate".into(),
            r,
            format!("the loading rate {r:.3e}"),
        )
    })
}

/// The steps of a slow run (`mass_scaling`, `loading.rate`), whose inputs lengthen the step
/// or shorten the duration: a mass scaling that lengthens the step to the whole duration (a
/// run of one step, nothing of its dynamics resolved) is refused at the mass scaling; a step
/// used `dt` below [`MIN_TIME_STEP`] (the duration shorter than it) at the loading rate that
/// shortened the duration, else at the duration.
fn check_scaled_steps(inp: &StepInputs, h: f64, n: f64, dt: f64) -> Result<(), SceneError> {
    let scene = inp.scene;
    let duration = scene.duration.unwrap_or(0.0);
    if let Some((f, _)) = &inp.model.mass_scaling
        && *f > 1.0
        && n <= 1.0
    {
        let (path, fix) = match scene.mass_scaling.as_ref().and_then(|m| m.target_step) {
            Some(_) => (
                "mass_scaling.target_step",
                format!(
                    "give a target step well below the duration, e.g. {:.3e} s (1000 steps)",
                    1e-3 * duration
                ),
            ),
            None => (
                "mass_scaling.factor",
                format!(
                    "lower the factor (the step grows as its square root): {:.3e} gives 1000 steps",
                    (f * (1e-3 * duration / h).powi(2)).max(1.0)
                ),
            ),
        };
        return Err(invalid(
            inp,
            path,
            format!(
                "the mass scaling factor {f:.3e} lengthens the time step to {h:.3e} s, at least \
                 the duration {duration:.3e} s: the run would be a single step, nothing of its \
                 dynamics resolved"
            ),
            fix,
        ));
    }
    if dt >= MIN_TIME_STEP {
        return Ok(());
    }
    let r = scene.loading.as_ref().map_or(1.0, |l| l.rate);
    let (path, fix) = if r > 1.0 {
        (
            "loading.rate",
            format!(
                "lower the rate: it divides the duration as written, {:.3e} s; at most {:.3e}",
                duration * r,
                duration * r / MIN_TIME_STEP
            ),
        )
    } else {
        (
            "duration",
            format!("give a duration of at least {MIN_TIME_STEP:e} s"),
        )
    };
    Err(invalid(
        inp,
        path,
        format!(
            "the duration {duration:.3e} s is shorter than the smallest step {MIN_TIME_STEP:e} s \
             a run may use"
        ),
        fix,
    ))
}

/// The error of a run of `n` steps of `h` (more than [`MAX_STEPS`]): names the duration, or the
/// input far outside the usual range that sets the step.
fn too_many_steps(inp: &StepInputs, fixed: bool, h: f64, n: f64) -> SceneError {
    let duration = inp.scene.duration.unwrap_or(0.0);
    // The duration, unless the step comes from an input far outside the usual range
    // (then that input).
    let (path, origin, fix) = if fixed {
        (
            "duration".to_string(),
            "integrator.time_step".to_string(),
            "or a larger integrator.time_step".to_string(),
        )
    } else {
        let d = step_driver(inp);
        let origin = format!("{}: {}", d.path, d.what);
        if d.unusual {
            (d.path, origin, format!("or {}", d.fix))
        } else {
            ("duration".to_string(), origin, format!("or {}", d.fix))
        }
    };
    invalid(
        inp,
        &path,
        format!(
            "a duration of {duration:.4e} s at a time step of {h:.4e} s (set by {origin}) is \
             {n:.3e} steps, more than the {MAX_STEPS:e} a run may take"
        ),
        format!(
            "shorten the duration to at most {:.3e} s, {fix}",
            MAX_STEPS * h
        ),
    )
}

/// The history rows of a run of `n_steps` steps (`histories.csv`, `walls.csv`) must stay below
/// [`MAX_HISTORY_BYTES`].
fn check_history_rows(inp: &StepInputs, n_steps: u64) -> Result<(), SceneError> {
    let scene = inp.scene;
    let every = scene
        .histories
        .every
        .map_or((n_steps / 1000).max(1), |e| e as u64);
    let columns: usize = scene
        .histories
        .probes
        .iter()
        .map(|p| match p {
            Probe::Energy => ENERGY_COLUMNS,
            Probe::Fluid => crate::problem::fluid::COLUMNS.len(),
            _ => 2,
        })
        .sum::<usize>()
        + scene
            .contact
            .as_ref()
            .map_or(0, |c| if c.enabled { 4 * c.walls.len() } else { 0 });
    let rows = (n_steps / every + 2) as f64;
    let bytes = rows * (columns + 1) as f64 * 25.0;
    if columns > 0 && bytes > MAX_HISTORY_BYTES {
        let need = (rows * (columns + 1) as f64 * 25.0 * every as f64 / MAX_HISTORY_BYTES).ceil();
        return Err(invalid(
            inp,
            "histories.every",
            format!(
                "a history row every {every} steps over {n_steps} steps is {rows:.3e} rows of \
                 {} values, {:.3e} bytes: more than the {:.0} GiB a run may write",
                columns + 1,
                bytes,
                MAX_HISTORY_BYTES / 1024f64.powi(3)
            ),
            format!("record every {need:.0} steps or more"),
        ));
    }
    Ok(())
}

/// A [`SceneError::Invalid`] at `path` of the scene file of `inp`.
fn invalid(inp: &StepInputs, path: &str, message: String, fix: String) -> SceneError {
    SceneError::Invalid {
        file: inp.file.to_path_buf(),
        path: path.to_string(),
        message,
        fix,
    }
}

/// The input that sets the time step: its JSON path, what it does, and the fix.
#[derive(Debug, Clone)]
pub struct StepDriver {
    /// JSON path of the input.
    pub path: String,
    /// What it does to the step.
    pub what: String,
    /// What to change.
    pub fix: String,
    /// The input is far outside the usual range (a wave speed above 1e5 m/s, a penalty above
    /// 1e4 times Young's modulus, damping that shrinks the step a thousandfold).
    pub unusual: bool,
}

/// A non-finite value counts as infinite.
fn size(w: f64) -> f64 {
    if w.is_nan() { f64::INFINITY } else { w }
}

/// The input that drives the time step (module docs): the damping when it shrinks the stable
/// step a thousandfold; else a material with a wave speed no solid has (the one with the
/// fastest); else the largest term of the frequency bound: the elements (the triangle with the
/// highest bound: its material, or the mesh when the triangle is tiny), the contact (the law
/// with the largest penalty) or the joints (their penalty).
pub fn step_driver(inp: &StepInputs) -> StepDriver {
    let scene = inp.scene;
    let model = inp.model;
    // The damping factor of the stable step, 1 / (sqrt(1 + z^2) + z).
    let z = inp.z_high;
    let zf = 1.0 / ((1.0 + z * z).sqrt() + z);
    if zf.is_nan() || zf < 1e-3 {
        let w = inp.omega_max;
        let alpha = scene.damping.mass_proportional;
        let path = if alpha / (2.0 * w) >= 0.5 * z || (!w.is_finite() && alpha > 0.0) {
            "damping.mass_proportional"
        } else {
            "damping.viscosity_ratio"
        };
        return StepDriver {
            path: path.into(),
            what: format!(
                "the damping of the highest mode (ratio {z:.3e}) shrinks the stable step by a \
                 factor {zf:.3e}"
            ),
            fix: format!("lower {path}"),
            unusual: true,
        };
    }
    // A material no solid has: the fastest wave speed above 1e5 m/s.
    let fastest = (0..model.triangles.len())
        .map(|t| {
            let m = &model.materials[model.tri_material[t] as usize].0;
            (t, size(m.young / m.density))
        })
        .fold(None, |best: Option<(usize, f64)>, (t, c2)| match best {
            Some((_, b)) if b >= c2 => best,
            _ => Some((t, c2)),
        });
    if let Some((t, c2)) = fastest
        && c2 > MAX_WAVE_SPEED * MAX_WAVE_SPEED
    {
        let w = size(inp.elements.frequency_bound(TriId(t as u32), &model.x0));
        return element_driver(scene, model, t, w);
    }
    // The largest term of the frequency bound.
    let (mut t_max, mut w_el) = (0usize, 0.0f64);
    for t in 0..inp.elements.len() {
        let w = size(inp.elements.frequency_bound(TriId(t as u32), &model.x0));
        if w > w_el {
            (t_max, w_el) = (t, w);
        }
    }
    let w_c = size(inp.frequency.contact);
    let w_j = size(inp.frequency.joints);
    if w_el >= w_c && w_el >= w_j && !model.triangles.is_empty() {
        return element_driver(scene, model, t_max, w_el);
    }
    let e_max = model
        .materials
        .iter()
        .map(|(m, _)| m.young)
        .fold(0.0, f64::max);
    if w_c >= w_j {
        return contact_driver(scene, e_max, w_c);
    }
    let (path, p) = scene
        .fracture
        .as_ref()
        .and_then(|f| crate::input::scene::joint_materials::largest_penalty(&f.material_list()))
        .unwrap_or(("fracture.material.penalty_normal".into(), f64::NAN));
    StepDriver {
        what: format!("the joint penalty {p:.3e} Pa gives a frequency bound of {w_j:.3e} rad/s"),
        fix: format!("lower {path} (a few times Young's modulus is usual, e.g. 10 E)"),
        path,
        unusual: p.is_nan() || p > MAX_PENALTY_RATIO * e_max,
    }
}

/// The fastest wave speed `sqrt(E / rho)` of a usable material [m/s]: no solid carries waves
/// faster than about 20 km/s (diamond 18 km/s).
const MAX_WAVE_SPEED: f64 = 1e5;

/// The largest usual penalty, as a multiple of the largest Young's modulus (the default
/// contact penalty is 10 E).
const MAX_PENALTY_RATIO: f64 = 1e4;

/// The elements drive the step: triangle `t` (global) has the highest bound `w`.
fn element_driver(scene: &Scene, model: &Model, t: usize, w: f64) -> StepDriver {
    let b = model.tri_body[t] as usize;
    let spec = model.materials[model.tri_material[t] as usize].0;
    let body = &scene.bodies[b];
    let found = body.materials.iter().find(|(_, m)| {
        (m.young == spec.young || m.heterogeneity.is_some())
            && m.density == spec.density
            && m.poisson == spec.poisson
    });
    let key = found.map_or("*", |(k, _)| k.as_str());
    // a drawn modulus is set by its distribution
    let young_field = match found {
        Some((_, m)) if m.heterogeneity.is_some() => "heterogeneity.young",
        _ => "young",
    };
    let c2 = spec.young / spec.density;
    let first = model
        .tri_body
        .iter()
        .position(|&x| x as usize == b)
        .unwrap_or(0);
    if !(c2.is_finite() && c2 <= MAX_WAVE_SPEED * MAX_WAVE_SPEED) {
        // The constant farther (in decades) from a usual solid's (E 1e10 Pa, rho 2e3 kg/m^3).
        let off_e = (spec.young.log10() - 10.0).abs();
        let off_rho = (spec.density.log10() - 3.3).abs();
        let (field, fix) = if off_rho >= off_e {
            (
                "density",
                "check the density [kg/m^3] (e.g. 2500 for rock or concrete)",
            )
        } else {
            (
                young_field,
                "check Young's modulus [Pa] (e.g. 30e9 for concrete)",
            )
        };
        return StepDriver {
            path: format!("bodies[{b}].materials.{key}.{field}"),
            what: format!(
                "Young's modulus {:.3e} Pa and density {:.3e} kg/m^3 give a wave speed \
                 sqrt(E/rho) of {:.3e} m/s, faster than any solid (frequency bound {w:.3e} rad/s)",
                spec.young,
                spec.density,
                c2.sqrt()
            ),
            fix: fix.into(),
            unusual: true,
        };
    }
    StepDriver {
        path: format!("bodies[{b}].mesh"),
        what: format!(
            "triangle {} (0-based) of the mesh has the highest frequency bound, {w:.3e} rad/s",
            t - first
        ),
        fix: "remesh without tiny or slivered triangles (fdem info MESH lists the element sizes)"
            .into(),
        unusual: false,
    }
}

/// The contact drives the step: the law with the largest penalty (`e_max` the largest Young's
/// modulus, which default penalties are a multiple of).
fn contact_driver(scene: &Scene, e_max: f64, w: f64) -> StepDriver {
    let mut best: Option<(f64, String)> = None;
    if let Some(c) = &scene.contact {
        let mut laws = vec![("contact.default".to_string(), c.default)];
        laws.extend(
            c.pairs
                .iter()
                .enumerate()
                .filter(|(_, p)| p.enabled)
                .map(|(i, p)| (format!("contact.pairs[{i}].law"), p.law)),
        );
        laws.extend(
            c.walls
                .iter()
                .enumerate()
                .map(|(i, w)| (format!("contact.walls[{i}].law"), w.law)),
        );
        for (path, l) in laws {
            let p = size(l.penalty.unwrap_or(l.penalty_factor * e_max));
            let kt = size(l.tangential_penalty.unwrap_or(p));
            let (field, v) = if l.tangential_penalty.is_some() && kt > p {
                ("tangential_penalty", kt)
            } else if l.penalty.is_some() {
                ("penalty", p)
            } else {
                ("penalty_factor", p)
            };
            if best.as_ref().is_none_or(|b| v > b.0) {
                best = Some((v, format!("{path}.{field}")));
            }
        }
    }
    let (p, path) = best.unwrap_or((f64::NAN, "contact".into()));
    StepDriver {
        what: format!("the contact penalty {p:.3e} Pa gives a frequency bound of {w:.3e} rad/s"),
        fix: format!(
            "lower {path} (the default penalty is {} times Young's modulus)",
            fdem_contact::ContactLaw::DEFAULT_PENALTY_FACTOR
        ),
        path,
        unusual: p.is_nan() || p > MAX_PENALTY_RATIO * e_max,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_count_takes_whole_quotients_within_the_tolerance() {
        // (duration, h, steps): quotients that are whole numbers but not exact in binary
        for (d, h, n) in [
            (2e-5, 1e-8, 2000.0),
            (0.3, 0.1, 3.0),
            (7e-6, 1e-7, 70.0),
            (0.7, 0.1, 7.0),
            (1.1, 0.1, 11.0),
            (1e-3, 1e-6, 1000.0),
        ] {
            assert_eq!(step_count(d, h), n, "{d} / {h}");
            assert!(((d / n) - h).abs() <= 1e-12 * h);
        }
        // not whole: rounded up
        assert_eq!(step_count(1.0, 0.3), 4.0);
        assert_eq!(step_count(1e-3, 3e-7), 3334.0);
        // shorter than one step
        assert_eq!(step_count(1e-9, 1e-8), 1.0);
        // a remainder of a millionth of a step is kept: rounded up
        assert_eq!(step_count(1000.000001, 1.0), 1001.0);
        assert_eq!(step_count(1.0, 0.0), f64::INFINITY);
    }
}
