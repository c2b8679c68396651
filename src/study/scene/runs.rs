//! The scene runs: one scheme at one fraction of its predicted stable step, its cost, its
//! energy verdict and its measures.
//!
//! Each scheme runs the scene at fractions `f` of its own predicted stable step
//! `h_pred = (h omega)_scheme / omega_max` (`omega_max` the element frequency bound; the
//! scene's own step and safety are ignored): `h = f h_pred`, rounded down so that a whole
//! number of steps spans the duration. A run is *unstable* when the solver stops it
//! (non-finite values) or when its final energy `K + U` exceeds the energy put in (external
//! and support work plus the initial kinetic energy) by more than 0.1 %: stable runs of every
//! scheme stay within 3e-4 of it on the bar pulse (Gear schemes below 1, the others within
//! 1e-5), while a growing mode shows first as a gain (OMF32 in its weak unstable band
//! `h omega` in [3.122, 3.160], spectral radius 1.019, gains 0.35 % in 240 steps before it
//! would blow up in a longer run). Cost: wall time of the run, force evaluations,
//! triangle-steps per second.

use std::path::Path;

use anyhow::Result;
use fdem_solver::RunError;
use fdem_solver::driver::{self, RunOptions};
use fdem_time::SchemeKind;
use serde::Serialize;

use super::measures::{analytical_error, read_csv_column};
use super::side_file::Analytical;

/// A run whose final energy exceeds this many times the energy put in is unstable.
const ENERGY_BOUND: f64 = 1.001;

/// One scheme at one step.
#[derive(Clone, Debug, Serialize)]
pub(super) struct Run {
    pub(super) scheme: String,
    pub(super) fraction: f64,
    pub(super) dt: f64,
    pub(super) dt_predicted: f64,
    pub(super) steps: u64,
    pub(super) stable: bool,
    pub(super) force_evaluations: u64,
    pub(super) wall_time: f64,
    pub(super) triangle_steps_per_second: f64,
    /// Final K + U over the energy put in.
    pub(super) energy_ratio: Option<f64>,
    pub(super) error_vs_reference: Option<f64>,
    pub(super) error_analytical: Option<f64>,
    /// The analytical measure itself (arrival time [s] or frequency [Hz]).
    pub(super) measured: Option<f64>,
    /// Second measure (collision: momentum error; fracture: crack mean |x| / R).
    pub(super) measured2: Option<f64>,
    /// Collision/fracture: `|measured - reference's| / |reference's|`.
    pub(super) error_measure: Option<f64>,
    /// Collision: momentum error itself; fracture: `|crack - reference's crack|` (units of R).
    pub(super) error_measure2: Option<f64>,
    /// Primary error (analytical when declared, else the measure's against the reference
    /// when declared, else the displacements' against the reference).
    pub(super) error: Option<f64>,
}

/// Final displacements and histories of one run.
pub(super) struct Raw {
    pub(super) run: Run,
    pub(super) displacement: Vec<[f64; 2]>,
}

/// Runs `scene` with `scheme` at `fraction` of its predicted stable step into `out`: its cost,
/// its energy verdict and, when stable, its measures (`analytical`) and final displacements.
pub(super) fn one_run(
    scene: &Path,
    scheme: SchemeKind,
    fraction: f64,
    out: &Path,
    analytical: Option<&Analytical>,
) -> Result<Raw> {
    let mut l = driver::load(scene)?;
    l.scheme = scheme;
    l.dt_limit = driver::stable_step(scheme, l.omega_max(), l.z_high);
    l.scene.integrator.scheme = scheme.name().into();
    l.scene.output.frames = 0;
    let duration = l.scene.duration.unwrap_or(0.0);
    if duration <= 0.0 || l.scene.analysis != fdem_solver::input::scene::Analysis::Dynamic {
        return Err(crate::bad_input(format!(
            "{}: the study needs a dynamic analysis with a positive duration",
            scene.display()
        )));
    }
    (l.n_steps, l.dt) = driver::step_count(duration, fraction * l.dt_limit);
    let e_kin0 = l.model.kinetic_energy(&l.model.v0);
    let mut run = Run {
        scheme: scheme.name().into(),
        fraction,
        dt: l.dt,
        dt_predicted: l.dt_limit,
        steps: l.n_steps,
        stable: false,
        force_evaluations: 0,
        wall_time: 0.0,
        triangle_steps_per_second: 0.0,
        energy_ratio: None,
        error_vs_reference: None,
        error_analytical: None,
        measured: None,
        measured2: None,
        error_measure: None,
        error_measure2: None,
        error: None,
    };
    let options = RunOptions {
        out_dir: out.to_path_buf(),
        raw: false,
        ..Default::default()
    };
    let start = std::time::Instant::now();
    match driver::run_outcome(&mut l, &options, &mut |_| {}) {
        Ok(o) => {
            let s = &o.summary;
            run.wall_time = s.wall_time;
            run.force_evaluations = s.force_evaluations;
            run.triangle_steps_per_second = s.triangle_steps_per_second;
            let input = (s.energy.external_work + s.energy.gravity_work + s.energy.support_work)
                .abs()
                + s.energy.wall_work.abs()
                + e_kin0;
            let e = s.energy.kinetic + s.energy.strain;
            let ratio = e / input.max(f64::MIN_POSITIVE);
            let finite = o
                .last_frame
                .displacement
                .iter()
                .all(|u| u[0].is_finite() && u[1].is_finite());
            run.stable = finite && ratio.is_finite() && ratio <= ENERGY_BOUND;
            run.energy_ratio = ratio.is_finite().then_some(ratio);
            if run.stable {
                let kinetic = (s.energy.kinetic, e_kin0);
                measure(
                    &mut run,
                    analytical,
                    &l,
                    &o.last_frame.velocity,
                    kinetic,
                    out,
                )?;
                return Ok(Raw {
                    run,
                    displacement: o.last_frame.displacement,
                });
            }
        }
        Err(RunError::Unstable { step, .. }) => {
            run.wall_time = start.elapsed().as_secs_f64();
            run.steps = step;
        }
        Err(e) => return Err(e.into()),
    }
    Ok(Raw {
        run,
        displacement: Vec::new(),
    })
}

/// The measures of a stable run (`measured`, `measured2`, and what can be told without the
/// reference run: the analytical error, the collision's momentum error), from the run of the
/// loaded scene `l` (final velocities `velocity`, kinetic energy at the end and at the start
/// `(k_end, e_kin0)`) and its files in `out`.
fn measure(
    run: &mut Run,
    analytical: Option<&Analytical>,
    l: &driver::Problem,
    velocity: &[[f64; 2]],
    (k_end, e_kin0): (f64, f64),
    out: &Path,
) -> Result<()> {
    match analytical {
        Some(Analytical::Collision {}) => {
            let mom = |v: &[[f64; 2]]| {
                l.model
                    .mass
                    .iter()
                    .zip(v)
                    .fold([0.0, 0.0], |p, (m, v)| [p[0] + m * v[0], p[1] + m * v[1]])
            };
            let (p0, p1) = (mom(&l.model.v0), mom(velocity));
            run.measured = Some(k_end / e_kin0.max(f64::MIN_POSITIVE));
            let dp = ((p1[0] - p0[0]).powi(2) + (p1[1] - p0[1]).powi(2)).sqrt();
            let p = (p0[0] * p0[0] + p0[1] * p0[1])
                .sqrt()
                .max(f64::MIN_POSITIVE);
            run.measured2 = Some(dp / p);
            run.error_measure2 = Some(dp / p);
        }
        Some(Analytical::Fracture { wall, radius }) => {
            let (_, f) = read_csv_column(&out.join("walls.csv"), &format!("force_y[{wall}]"))?;
            run.measured = Some(f.iter().fold(0.0, |a, b| a.max(b.abs())));
            let (_, x) = read_csv_column(&out.join("fractures.csv"), "x")?;
            run.measured2 = (!x.is_empty())
                .then(|| x.iter().map(|v| v.abs()).sum::<f64>() / x.len() as f64 / radius);
        }
        Some(a) => {
            if let Some((m, err)) = analytical_error(a, out)? {
                run.measured = Some(m);
                run.error_analytical = Some(err);
            }
        }
        None => {}
    }
    Ok(())
}
