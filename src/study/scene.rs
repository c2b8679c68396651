//! `fdem study scene SCENE`: the speed/accuracy trade of every time-integration scheme on a
//! real scene.
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
//! would blow up in a longer run). When every listed fraction is
//! stable, the study goes on at 1.1, 1.2, 1.35, 1.5, 1.75, 2, 2.25, 2.5, 3, 3.5, 4, 5, 6, 8, 10, 12 and 16
//! (times `r`, below) until one is not: the observed limit lies between the largest stable
//! fraction and the first unstable one.
//!
//! **Measured stability** (the observed limit): a fraction is stable when the scene run is
//! (above) *and* its *stability probe* is: the scene's mesh, supports and stages (contact,
//! joints) with no loads, no gravity and the walls at rest, started from a velocity field
//! concentrated in the highest modes (40 power iterations `v <- M^-1 K v` through the whole
//! system's forces: elements, contact and joints), run for `omega_top t` = 5000 (796 periods
//! of the state's highest mode: `omega_top` is the Rayleigh quotient of the last power
//! iteration, at most the true highest frequency, so the probe spans at least that many of
//! its periods; it is kept within [1/4, 1] of the frequency bound); it is
//! unstable when the solver stops it or the mean `K + U + stored` (contact, joints) over its
//! last fifth exceeds that over its first fifth by more than 1 %. The centres of the fifths are 4000 apart in
//! `omega_top t`, so 1 % is an amplitude growth rate of 1.24e-6 per unit `omega_top t`: the
//! time crate's own definition of a stable step (`rho(T(h)) <= 1 + 1e-6 h`,
//! docs/time-integration.md), applied to the mesh's highest modes. (Measured in units of the
//! bound instead, which overestimates the top frequency 1.3-1.8 times, the probe was that
//! much shorter, and PC-4's slow growth passed on the collision at 2.05 times its limit.)
//! Schemes that are stable again in a window above their limit (PC-4, OMF30, OMF32:
//! `fdem_time::stability::stable_windows`) also get a **broadband probe** at each fraction
//! whose top-mode probe is stable: the same run from the field after 2 power iterations (the
//! upper part of the spectrum), since with the top modes inside a window the unstable band
//! lies among lower modes that the top-mode field barely excites; the fraction is stable when
//! both are. These schemes also get **band probes**: at the steps that put the measured top
//! frequency into their first unstable band, `h omega_top = L (1 + j (W/L - 1)/2)`, `j = -1, 0,
//! 1`, with `L` the limit and `W` the start of the window ([`band_fractions`]); they join the
//! list, or the ladder below, in order. The band above OMF32's limit is only 1.2 % wide
//! (spectral radius up to 1.019 per step): on a scene whose top modes sit above a gap in the
//! spectrum (the collision's and the fracture disc's contact modes) a ladder of fractions
//! steps over it and the scheme reads stable up to its window's end, 1.8 times past its limit,
//! although every step that puts the top mode in the band is unstable. The observed limit is
//! the first instability as the step grows, so the band is looked for. Probes run from 0.99 of
//! the predicted step up, until one is unstable (after that every fraction counts unstable).
//! Unlike the scene run alone, the probe also finds the weak growth of PC-4, PC-5 and OMF32
//! past their limits.
//!
//! **Active prediction** (scenes with contact): the a-priori contact term of `omega_max`
//! assumes every edge of every triangle pressed flat along its whole length, which a collision
//! of curved bodies or a fracture whose crack faces never re-close does not reach. The study
//! first runs the scene once with central difference at half its a-priori step and records at
//! the end of every step the bound of the contact engaged in that state
//! (`fdem_contact::active_bound`); the active bound is `sqrt(omega_el^2 + omega_joints^2 +
//! omega_c,active^2)` with the largest engaged term over that run, and the active predicted
//! step `h_active = r h_pred`, `r = omega_max / omega_active`. The listed fractions stay
//! fractions of `h_pred` (the step a run takes by default), but once they are all stable the
//! ladder goes on in units of the active prediction, `r x` 0.5, 0.7, 0.9, 1, 1.1, 1.2, 1.35,
//! 1.5, 1.75, 2, 2.25, 2.5, 3, 3.5, 4, ... (the first above the last fraction run; without contact
//! `r = 1` and this is the ladder above), and each scheme's limit is reported against both
//! predictions (`observed_over_active_*`).
//!
//! Errors of a stable run:
//! - `error_vs_reference`: `max_i |u_i - u_ref,i| / max_i |u_ref,i|` over the nodes at the final
//!   time, against the highest-order scheme at the smallest fraction (OMF32 when run);
//! - `error_analytical`, when a side file `SCENE.study.json` declares an analytical answer:
//!   - `{"reference": {"bar-arrival": {"probe", "length", "wave_speed", "particle_velocity"}}}`:
//!     the free end of a bar under a pressure step moves at `2 v_p (t - L/c)` after arrival;
//!     a straight-line fit of the probe's displacement over `[1.25, 1.5] L/c` gives the arrival
//!     time; error `|t_arr - L/c| / (L/c)`;
//!   - `{"reference": {"first-frequency": {"probe", "frequency"}}}`: the first frequency from
//!     the upward crossings of the probe's displacement through its mean; error
//!     `|f - f_ref| / f_ref`;
//! - `error_measure` (and `error_measure2`), when the side file declares a measure without an
//!   analytical value, against the reference run's:
//!   - `{"reference": {"collision": {}}}`: `K_end / K_0` (kinetic energy after separation over
//!     before), relative error; second, the momentum error `|P_end - P_0| / |P_0|` itself;
//!   - `{"reference": {"fracture": {"wall", "radius"}}}`: the peak of `|force_y[wall]|`
//!     (`walls.csv`), relative error; second, the crack path: mean `|x| / radius` of the
//!     broken joints (`fractures.csv`), absolute difference.
//!
//! The side file may also hold `"set": {"/json/pointer": value, ...}` (changes to the scene for
//! the study: a shorter or coarser version, written to `OUT/study-SCENE.json`), default
//! `"fractions"` and `"schemes"` (the command line wins), and `"probe_from": T` [s]: the
//! probes then start from the scene's state at `T` with the walls held there (bodies pressed
//! together stay pressed: the contact is active through the probe), and their growth is
//! measured against the high-mode field's own energy ([`ProbeStart`]); or `"probe_from":
//! "active"`: from the state where the bound run's engaged contact bound peaks, frozen
//! (velocities zeroed, held by loads balancing its forces; length `omega_active t` = 5000,
//! growth of the mean kinetic energy), so that a collision's contact stays engaged through
//! the probe. With joints, either start also carries the joints' state at T (broken joints,
//! damage histories, the contact pairs released by breaks and softenings): the probe's
//! fracture stage adopts it, so re-closed crack faces stay in contact through the probe. `"probe_amplitude"`: the probe field's largest displacement relative to the
//! model size (default 1e-7; the fracture disc 1e-9, to keep the joints' pre-peak law linear
//! over it). `"reference"` may be left out (errors against the reference run only).
//!
//! The primary `error` is the analytical one when declared, else the measure's when declared,
//! else the displacements' against the reference. Cost: wall time of the run, force evaluations, element-steps per second.
//! Output (in `--out`): `runs.csv`, `study.json`, and the charts `work_precision`,
//! `error_vs_step` (x = `h / h_pred`, the predicted limit at 1, each scheme's observed limit
//! in its legend), the same two with the error against the reference
//! (`*_reference`, when the primary error is analytical) and `energy_vs_step` (final energy
//! over energy put in), as PNG and SVG.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use fdem_solver::RunError;
use fdem_solver::driver::{self, RunOptions};
use fdem_time::SchemeKind;
use serde::{Deserialize, Serialize};

use crate::plot::{Plot, Scale, Series};

/// Settings of the scene study.
#[derive(Args, Clone, Debug)]
pub struct SceneArgs {
    /// The scene file (a dynamic analysis).
    pub scene: PathBuf,
    /// Output folder (default out/study-<scene name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Schemes, comma separated (default: all).
    #[arg(long, value_delimiter = ',')]
    pub schemes: Vec<String>,
    /// Fractions of each scheme's predicted stable step, comma separated (default: the side
    /// file's `fractions`, else 0.1,0.2,0.4,0.7,0.9,0.99,1.01,1.05).
    #[arg(long, value_delimiter = ',')]
    pub fractions: Vec<f64>,
}

/// The default fractions of the predicted stable step.
const DEFAULT_FRACTIONS: [f64; 8] = [0.1, 0.2, 0.4, 0.7, 0.9, 0.99, 1.01, 1.05];

/// Fractions tried after the list when all of it was stable, to find the observed limit: these
/// times `r = h_active / h_pred` (the active prediction over the a-priori one; 1 without
/// contact), the first one above the last fraction run, and on until one is unstable. (Beyond
/// 3: the weakly unstable schemes, whose growth a short contact does not show.)
const PROBES: [f64; 21] = [
    0.5, 0.7, 0.9, 1.0, 1.1, 1.2, 1.35, 1.5, 1.75, 2.0, 2.25, 2.5, 3.0, 3.5, 4.0, 5.0, 6.0, 8.0,
    10.0, 12.0, 16.0,
];
/// A run whose final energy exceeds this many times the energy put in is unstable.
const ENERGY_BOUND: f64 = 1.001;

/// Length of a stability probe run, in units of `omega_top t` (796 periods of the probed
/// state's highest mode, as measured by the power iteration's Rayleigh quotient).
const PROBE_OMEGA_T: f64 = 5000.0;
/// A probe is unstable when the mean energy over its last fifth exceeds that over its first
/// fifth by this factor: the centres are `0.8 x 5000 = 4000` apart in `omega_top t`, so 1 %
/// is an amplitude growth rate of `ln(1.01) / 2 / 4000 = 1.24e-6` per unit `omega_top t`, the
/// time crate's definition of stability (`rho(T(h)) <= 1 + 1e-6 h`).
const PROBE_GROWTH: f64 = 1.01;
/// Power iterations that concentrate a probe's initial velocity in the highest modes.
const PROBE_POWER_ITERATIONS: usize = 40;
/// Power iterations of the broadband probe's field: the modes weighted by `(omega/omega_top)^4`
/// (the upper part of the spectrum, where a scheme with a stable window above its limit,
/// OMF32, has its unstable band when the top modes sit in the window).
const PROBE_BROAD_ITERATIONS: usize = 2;
/// Default largest displacement of a probe's field (its largest speed over `omega_max`),
/// relative to the model size.
const PROBE_AMPLITUDE: f64 = 1e-7;

/// The analytical answer a scene may declare in `SCENE.study.json`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
enum Analytical {
    /// Arrival of a pressure step at the free end of a bar.
    BarArrival {
        probe: String,
        length: f64,
        wave_speed: f64,
        particle_velocity: f64,
    },
    /// First natural frequency [Hz] seen at a probe.
    FirstFrequency { probe: String, frequency: f64 },
    /// A collision of free bodies: measure `K_end / K_0` (kinetic energy after separation
    /// over before), second measure `|P_end - P_0| / |P_0|` (momentum); no analytical value:
    /// the error is against the reference run's measure.
    Collision {},
    /// A fracturing specimen loaded by a wall: measure the peak of `|force_y[wall]|` in
    /// `walls.csv` [N], second measure the mean `|x| / radius` of the broken joints in
    /// `fractures.csv` (the crack path); errors against the reference run.
    Fracture { wall: String, radius: f64 },
}

impl Analytical {
    /// Whether the answer is analytical (else the measure is compared with the reference run).
    fn is_analytical(&self) -> bool {
        matches!(self, Self::BarArrival { .. } | Self::FirstFrequency { .. })
    }
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SideFile {
    /// The answer the runs are measured against (default: the reference run's displacements).
    #[serde(default)]
    reference: Option<Analytical>,
    /// Changes to the scene for the study, by JSON pointer (e.g. `"/duration": 2e-4`): a
    /// shorter or coarser version of the shipped scene, so that the study fits in minutes.
    #[serde(default)]
    set: std::collections::BTreeMap<String, serde_json::Value>,
    /// Default fractions for this scene (the command line's `--fractions` wins).
    #[serde(default)]
    fractions: Option<Vec<f64>>,
    /// Default schemes for this scene (the command line's `--schemes` wins).
    #[serde(default)]
    schemes: Option<Vec<String>>,
    /// Start the stability probes from the scene's state at this time [s] (bodies in
    /// contact), or `"active"`: from the state where the bound run's engaged contact bound
    /// peaks, frozen there; not from the reference state: see [`ProbeStart`].
    #[serde(default)]
    probe_from: Option<ProbeFrom>,
    /// Largest displacement of the probes' high-mode field, relative to the model size
    /// (default [`PROBE_AMPLITUDE`]): small enough that the joints' and the contact's laws
    /// stay linear over it.
    #[serde(default)]
    probe_amplitude: Option<f64>,
}

/// Where the stability probes start (side file `"probe_from"`).
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(untagged)]
enum ProbeFrom {
    /// The scene's state at this time [s], walls held there, velocities kept.
    Time(f64),
    /// `"active"`: the state of the bound run's largest engaged contact bound, frozen.
    Named(ProbeFromName),
}

/// The named probe start.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
enum ProbeFromName {
    /// The state where the active contact bound peaks ([`Active::omega_contact_active_time`]).
    Active,
}

/// The state a stability probe starts from when the side file sets `probe_from` = T: the
/// scene run to T with central difference at half its predicted step (loads, walls and
/// initial velocities as in the scene), giving node positions and velocities and the walls'
/// positions at T. The probe then runs from there with the walls held at those positions and
/// no loads: bodies pressed together stay pressed, so the contact is active during the probe.
/// With joints, the probe also starts from the joints' state at T (which are broken, their
/// damage, shear secant and mode histories): the joints hold the damaged state, and the
/// contact pairs released by the breaks and softenings up to T are contact couples from the
/// start, so re-closed crack faces stay in contact through the probe.
///
/// `"probe_from": "active"` takes T where the bound run's engaged contact bound peaks (the
/// state the active prediction comes from) and *freezes* it: velocities zeroed and constant
/// nodal loads `F = -M a(x_T, 0)` added, so that the state is an equilibrium (a collision's
/// discs at peak compression would otherwise separate within a fraction of the probe). The
/// probe then oscillates about that state, its contact engaged as at the peak, for the whole
/// `omega_top t` = [`PROBE_OMEGA_T`], and its growth is measured on the kinetic energy alone
/// (the loads' work makes `K + U` exchange first-order terms with them): mean `K` over the
/// last fifth over that over the first.
struct ProbeStart {
    displacement: Vec<[f64; 2]>,
    velocity: Vec<[f64; 2]>,
    /// Each wall's displacement at T [m].
    walls: Vec<[f64; 2]>,
    /// The joints' history at T (scenes with joints): the probe's fracture stage adopts it
    /// (`FractureSection::initial_state`), so the joints broken by T stay broken, the
    /// damaged ones keep their damage, and crack faces in contact at T are contact couples
    /// from the probe's first force evaluation.
    joints: Option<fdem_fracture::JointState>,
    /// Frozen (`"active"`): velocities zeroed, the state held by balancing loads.
    frozen: bool,
    /// The time of the state [s].
    time: f64,
    /// The frequency bound of a frozen state [rad/s] (its active bound; else the probe takes
    /// `omega_max`): the measured top frequency that sets a probe's length is kept within
    /// [1/4, 1] of it.
    omega: Option<f64>,
}

fn probe_start(scene: &Path, t: f64, omega: Option<f64>, out: &Path) -> Result<ProbeStart> {
    let frozen = omega.is_some();
    let mut l = driver::load(scene)?;
    let k = SchemeKind::CentralDifference;
    l.scheme = k;
    l.dt_limit = driver::stable_step(k, l.omega_max, l.z_high);
    l.scene.integrator.scheme = k.name().into();
    l.scene.output.frames = 0;
    l.scene.duration = Some(t);
    (l.n_steps, l.dt) = driver::step_count(t, 0.5 * l.dt_limit);
    let options = RunOptions {
        out_dir: out.to_path_buf(),
        raw: false,
    };
    std::fs::create_dir_all(out)?;
    let o = driver::run_outcome(&mut l, &options, &mut |_| {})
        .with_context(|| format!("running {} to the probe's start {t} s", scene.display()))?;
    let walls = l
        .scene
        .contact
        .as_ref()
        .map(|c| {
            c.walls
                .iter()
                .map(|w| {
                    let r = fdem_solver::model::ramp_integral(t, w.ramp);
                    [w.velocity[0] * r, w.velocity[1] * r]
                })
                .collect()
        })
        .unwrap_or_default();
    Ok(ProbeStart {
        displacement: o.last_frame.displacement,
        velocity: o.last_frame.velocity,
        walls,
        joints: o.joint_state,
        frozen,
        time: t,
        omega,
    })
}

/// The active prediction ([`active_bound_run`]).
#[derive(Clone, Debug, Serialize)]
struct Active {
    /// The a-priori frequency bound of the scene (elements, contact as if pressed flat
    /// everywhere, joints) [rad/s].
    omega_a_priori: f64,
    /// The active bound: `sqrt(omega_el^2 + omega_joints^2 + omega_c,active^2)`, the contact
    /// term the largest over the bound run's states [rad/s].
    omega_active: f64,
    /// That largest active contact term [rad/s] and when [s].
    omega_contact_active: f64,
    omega_contact_active_time: f64,
    /// `h_active / h_pred = omega_a_priori / omega_active`.
    ratio: f64,
}

/// The active prediction: the scene (as studied) run once with central difference at half its
/// a-priori predicted step, recording at the end of every step the bound of the contact
/// engaged in that state (`fdem_contact::active_bound`, the contact stage's
/// `omega_active_max`). The active bound is the largest over the run's states combined with
/// the elements' and the joints' terms; `None` without contact (the a-priori bound is then
/// the active one).
fn active_bound_run(scene: &Path, out: &Path) -> Result<Option<Active>> {
    let mut l = driver::load(scene)?;
    if !l.scene.contact.as_ref().is_some_and(|c| c.enabled) {
        return Ok(None);
    }
    let omega_el = l.elements.max_frequency_bound(&l.model.x0);
    let omega_j = fdem_solver::stages::omega_joints(&l.scene, &l.model, &l.file)?;
    let k = SchemeKind::CentralDifference;
    l.scheme = k;
    l.dt_limit = driver::stable_step(k, l.omega_max, l.z_high);
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
    let omega_active = (omega_el * omega_el + omega_j * omega_j + wc * wc).sqrt();
    Ok(Some(Active {
        omega_a_priori: l.omega_max,
        omega_active,
        omega_contact_active: wc,
        omega_contact_active_time: tc,
        ratio: l.omega_max / omega_active,
    }))
}

/// One scheme at one step.
#[derive(Clone, Debug, Serialize)]
struct Run {
    scheme: String,
    fraction: f64,
    dt: f64,
    dt_predicted: f64,
    steps: u64,
    stable: bool,
    force_evaluations: u64,
    wall_time: f64,
    element_steps_per_second: f64,
    /// Final K + U over the energy put in.
    energy_ratio: Option<f64>,
    error_vs_reference: Option<f64>,
    error_analytical: Option<f64>,
    /// The analytical measure itself (arrival time [s] or frequency [Hz]).
    measured: Option<f64>,
    /// Second measure (collision: momentum error; fracture: crack mean |x| / R).
    measured2: Option<f64>,
    /// Collision/fracture: `|measured - reference's| / |reference's|`.
    error_measure: Option<f64>,
    /// Collision: momentum error itself; fracture: `|crack - reference's crack|` (units of R).
    error_measure2: Option<f64>,
    /// Primary error (analytical when declared, else the measure's against the reference
    /// when declared, else the displacements' against the reference).
    error: Option<f64>,
}

/// Per scheme: predicted and observed stable steps.
#[derive(Clone, Debug, Serialize)]
struct Limit {
    scheme: String,
    dt_predicted: f64,
    /// Largest stable fraction tried.
    observed_at_least: f64,
    /// Smallest unstable fraction tried (None: none found up to the last probe).
    observed_below: Option<f64>,
    /// Stability probes ([`stability_probe`]).
    probes: Vec<Probe>,
    /// The active predicted step `h_pred r` [s] (`r` = [`Active::ratio`], 1 without contact).
    dt_active: f64,
    /// The observed limit over the active prediction: `observed_at_least / r`.
    observed_over_active_at_least: f64,
    /// `observed_below / r`.
    observed_over_active_below: Option<f64>,
}

#[derive(Serialize)]
struct Report<'a> {
    scene: String,
    analytical: Option<&'a Analytical>,
    reference_run: String,
    nodes: usize,
    triangles: usize,
    /// The active prediction (scenes with contact).
    active: Option<&'a Active>,
    /// The time of the state the probes start from [s] (None: the reference state, at rest).
    probe_from: Option<f64>,
    /// Whether that state is frozen (`"probe_from": "active"`, [`ProbeStart`]).
    probe_frozen: bool,
    /// Broken joints in that state (scenes with joints; their pairs are contact couples
    /// through the probes).
    probe_start_broken: Option<usize>,
    /// The probes' field amplitude, relative to the model size.
    probe_amplitude: f64,
    limits: &'a [Limit],
    runs: &'a [Run],
}

/// Final displacements and histories of one run.
struct Raw {
    run: Run,
    displacement: Vec<[f64; 2]>,
}

fn side_file(scene: &Path) -> Result<Option<SideFile>> {
    let p = scene.with_extension("study.json");
    if !p.exists() {
        return Ok(None);
    }
    let text = std::fs::read_to_string(&p).with_context(|| format!("reading {}", p.display()))?;
    let s: SideFile = serde_json::from_str(&text).map_err(|e| {
        crate::bad_input(format!(
            "{}: {}",
            p.display(),
            fdem_solver::shorten(&e.to_string())
        ))
    })?;
    Ok(Some(s))
}

/// The scene with the side file's `set` applied, written into `out` (mesh paths made
/// absolute); the scene itself when there is nothing to set.
fn study_scene(scene: &Path, side: Option<&SideFile>, out: &Path) -> Result<PathBuf> {
    let Some(side) = side.filter(|s| !s.set.is_empty()) else {
        return Ok(scene.to_path_buf());
    };
    let text = std::fs::read_to_string(scene)
        .map_err(|e| crate::bad_input(format!("{}: cannot read the file: {e}", scene.display())))?;
    let mut v: serde_json::Value = serde_json::from_str(&text).map_err(|e| {
        crate::bad_input(format!(
            "{}: {}",
            scene.display(),
            fdem_solver::shorten(&e.to_string())
        ))
    })?;
    let side_path = scene.with_extension("study.json");
    for (ptr, val) in &side.set {
        let slot = v.pointer_mut(ptr).ok_or_else(|| {
            crate::bad_input(format!(
                "{}: `set` names {}, which is not in {} (a JSON pointer to an existing field, e.g. /duration)",
                side_path.display(),
                fdem_solver::excerpt(ptr),
                scene.display()
            ))
        })?;
        *slot = val.clone();
    }
    let dir = scene.parent().unwrap_or(Path::new("."));
    let dir = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    if let Some(bodies) = v.get_mut("bodies").and_then(|b| b.as_array_mut()) {
        for b in bodies {
            if let Some(m) = b.get("mesh").and_then(|m| m.as_str()) {
                let abs = dir.join(m).display().to_string();
                b["mesh"] = serde_json::Value::String(abs);
            }
        }
    }
    let name = scene
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_else(|| "scene.json".into());
    let p = out.join(format!("study-{name}"));
    crate::write_atomically(&p, serde_json::to_string_pretty(&v)?.as_bytes())?;
    Ok(p)
}

fn read_history(out: &Path, probe: &str) -> Result<(Vec<f64>, Vec<f64>)> {
    read_csv_column(&out.join("histories.csv"), probe)
}

/// The first column and the column named `probe` of a CSV file with a header.
fn read_csv_column(p: &Path, probe: &str) -> Result<(Vec<f64>, Vec<f64>)> {
    let text = std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?;
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let col = head
        .iter()
        .position(|h| *h == probe)
        .with_context(|| format!("no history column '{probe}' (columns: {})", head.join(",")))?;
    let (mut t, mut u) = (Vec::new(), Vec::new());
    for l in lines {
        let f: Vec<f64> = l
            .split(',')
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect();
        if f.len() > col {
            t.push(f[0]);
            u.push(f[col]);
        }
    }
    Ok((t, u))
}

/// The analytical measure and its relative error.
fn analytical_error(a: &Analytical, out: &Path) -> Result<Option<(f64, f64)>> {
    match a {
        Analytical::BarArrival {
            probe,
            length,
            wave_speed,
            ..
        } => {
            let (t, u) = read_history(out, probe)?;
            let tc = length / wave_speed;
            let pts: Vec<(f64, f64)> = t
                .iter()
                .zip(&u)
                .filter(|(t, _)| **t >= 1.25 * tc && **t <= 1.5 * tc)
                .map(|(t, u)| (*t, *u))
                .collect();
            if pts.len() < 2 {
                return Ok(None);
            }
            let n = pts.len() as f64;
            let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
            let sxx: f64 = pts.iter().map(|p| p.0 * p.0).sum();
            let sxy: f64 = pts.iter().map(|p| p.0 * p.1).sum();
            let b = (n * sxy - sx * sy) / (n * sxx - sx * sx);
            let a0 = (sy - b * sx) / n;
            let arr = -a0 / b;
            Ok(arr.is_finite().then(|| (arr, (arr - tc).abs() / tc)))
        }
        Analytical::FirstFrequency { probe, frequency } => {
            let (t, u) = read_history(out, probe)?;
            let mean = u.iter().sum::<f64>() / u.len().max(1) as f64;
            let mut ups = Vec::new();
            for i in 1..u.len() {
                let (a, b) = (u[i - 1] - mean, u[i] - mean);
                if a < 0.0 && b >= 0.0 {
                    ups.push(t[i - 1] + (t[i] - t[i - 1]) * (-a) / (b - a));
                }
            }
            if ups.len() < 2 {
                return Ok(None);
            }
            let f = (ups.len() - 1) as f64 / (ups[ups.len() - 1] - ups[0]);
            Ok(Some((f, (f - frequency).abs() / frequency)))
        }
        Analytical::Collision {} | Analytical::Fracture { .. } => Ok(None),
    }
}

fn one_run(
    scene: &Path,
    scheme: SchemeKind,
    fraction: f64,
    out: &Path,
    analytical: Option<&Analytical>,
) -> Result<Raw> {
    let mut l = driver::load(scene)?;
    l.scheme = scheme;
    l.dt_limit = driver::stable_step(scheme, l.omega_max, l.z_high);
    l.scene.integrator.scheme = scheme.name().into();
    l.scene.output.frames = 0;
    let duration = l.scene.duration.unwrap_or(0.0);
    if duration <= 0.0 || l.scene.analysis != fdem_solver::scene::Analysis::Dynamic {
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
        element_steps_per_second: 0.0,
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
    };
    let start = std::time::Instant::now();
    match driver::run_outcome(&mut l, &options, &mut |_| {}) {
        Ok(o) => {
            let s = &o.summary;
            run.wall_time = s.wall_time;
            run.force_evaluations = s.force_evaluations;
            run.element_steps_per_second = s.element_steps_per_second;
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
                match analytical {
                    Some(Analytical::Collision {}) => {
                        let mom =
                            |v: &[[f64; 2]]| {
                                l.model.mass.iter().zip(v).fold([0.0, 0.0], |p, (m, v)| {
                                    [p[0] + m * v[0], p[1] + m * v[1]]
                                })
                            };
                        let (p0, p1) = (mom(&l.model.v0), mom(&o.last_frame.velocity));
                        run.measured = Some(s.energy.kinetic / e_kin0.max(f64::MIN_POSITIVE));
                        let dp = ((p1[0] - p0[0]).powi(2) + (p1[1] - p0[1]).powi(2)).sqrt();
                        let p = (p0[0] * p0[0] + p0[1] * p0[1])
                            .sqrt()
                            .max(f64::MIN_POSITIVE);
                        run.measured2 = Some(dp / p);
                        run.error_measure2 = Some(dp / p);
                    }
                    Some(Analytical::Fracture { wall, radius }) => {
                        let (_, f) =
                            read_csv_column(&out.join("walls.csv"), &format!("force_y[{wall}]"))?;
                        run.measured = Some(f.iter().fold(0.0, |a, b| a.max(b.abs())));
                        let (_, x) = read_csv_column(&out.join("fractures.csv"), "x")?;
                        run.measured2 = (!x.is_empty()).then(|| {
                            x.iter().map(|v| v.abs()).sum::<f64>() / x.len() as f64 / radius
                        });
                    }
                    Some(a) => {
                        if let Some((m, err)) = analytical_error(a, out)? {
                            run.measured = Some(m);
                            run.error_analytical = Some(err);
                        }
                    }
                    None => {}
                }
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

/// The fractions of the predicted step `h_pred` that put the probed state's measured top
/// frequency `omega_top` into a scheme's first unstable band `(L, W)` (from its limit `L` to
/// the start `W` of its first stable window): `h omega_top = L (1 + j (W/L - 1) / 2)` for
/// `j = -1, 0, 1`, rounded to 4 digits. The Rayleigh estimate is at most the true top
/// frequency `omega_true = omega_top (1 + delta)`, and within about 1 % of it after 40 power
/// iterations; the three points put the true top mode in the band for every `delta` in
/// `[0, 1.5 (W/L - 1)]` (OMF32's band is 1.2 % wide, its spectral radius there up to 1.019 per
/// step). Without them the ladder of fractions steps over so narrow a band, and on a scene
/// whose top modes sit above a gap in the spectrum such a scheme is then seen stable up to
/// its window's end.
fn band_fractions(band: [f64; 2], omega_top: f64, h_pred: f64) -> Vec<f64> {
    let [l, w] = band;
    if !(omega_top > 0.0 && h_pred > 0.0 && w > l) {
        return Vec::new();
    }
    [-1.0, 0.0, 1.0]
        .iter()
        .map(|j| {
            let hw = l * (1.0 + j * (w / l - 1.0) / 2.0);
            (hw / (omega_top * h_pred) * 1e4).round() / 1e4
        })
        .collect()
}

/// Inserts the fractions of `extra` above `after` into the sorted tail `list[from..]`, leaving
/// out those within 1e-4 of one already listed; returns how many it inserted.
fn insert_fractions(list: &mut Vec<f64>, from: usize, extra: &[f64], after: f64) -> usize {
    let mut added = 0;
    for &x in extra {
        if x <= after * 1.0001 || list.iter().any(|y| (x - y).abs() <= 1e-4 * y.abs()) {
            continue;
        }
        let at = from + list[from..].partition_point(|y| *y < x);
        list.insert(at, x);
        added += 1;
    }
    added
}

/// An initial velocity field concentrated in the highest modes of the scene: power iteration
/// `v <- M^-1 K v` (with `M^-1 K v = -(a(x_0 + eps v) - a(x_0)) / eps`, `a` the whole
/// system's acceleration at rest: elements and the stages, contact and joints, so that the
/// field reaches the contact and joint modes; constrained DOFs zero), scaled to a largest
/// nodal speed of `amplitude omega_max` times the model size (small strain). `dir` receives
/// the stages' files. Also returns `a(x_0)` at rest (flat DOFs, loads and gravity left out),
/// the field after [`PROBE_BROAD_ITERATIONS`] iterations (the upper part of the spectrum,
/// same scaling), and the highest frequency measured by the last iteration's Rayleigh
/// quotient `omega^2 = (v . K v)/(v . M v)` (at most the true highest frequency of the
/// state, for any `v`).
fn top_mode_velocity(l: &driver::Loaded, amplitude: f64, dir: &Path) -> Result<ProbeSeeds> {
    use fdem_time::SecondOrderSystem;
    let n = l.model.n_nodes();
    let mut sys = fdem_solver::system::SceneSystem::new(l.model.clone(), l.elements.clone(), 0.0);
    sys.set_timing(false);
    sys.model.loads.clear();
    sys.model.gravity = None;
    std::fs::create_dir_all(dir)?;
    fdem_solver::stages::attach(&l.scene, &l.file, &mut sys, l.dt, dir, u64::MAX)?;
    let x0: Vec<f64> = l.model.x0.as_flattened().to_vec();
    let zero = vec![0.0; 2 * n];
    let mut a0 = vec![0.0; 2 * n];
    sys.acceleration(0.0, &x0, &zero, &mut a0);
    let mut seed = 12345u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let free = |d: usize| !l.model.constrained[d] && l.model.mass[d / 2] > 0.0;
    let mut v: Vec<f64> = (0..2 * n)
        .map(|d| if free(d) { rnd() } else { 0.0 })
        .collect();
    let scale_of = |v: &[f64]| {
        v.iter()
            .map(|a| a.abs())
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE)
    };
    let size = l
        .model
        .x0
        .iter()
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut x = x0.clone();
    let mut a = vec![0.0; 2 * n];
    let mut w = vec![0.0; 2 * n];
    let mut broad = Vec::new();
    let mut omega_sq = 0.0;
    for it in 0..PROBE_POWER_ITERATIONS {
        if it == PROBE_BROAD_ITERATIONS {
            broad.clone_from(&v);
        }
        let s = scale_of(&v);
        let eps = amplitude * size / s;
        for d in 0..2 * n {
            x[d] = x0[d] + eps * v[d];
        }
        sys.acceleration(0.0, &x, &zero, &mut a);
        for d in 0..2 * n {
            w[d] = if free(d) { -(a[d] - a0[d]) / eps } else { 0.0 };
        }
        // Rayleigh quotient (v . M w)/(v . M v) with w = M^-1 K v
        let (mut num, mut den) = (0.0, 0.0);
        for d in 0..2 * n {
            let m = l.model.mass[d / 2];
            num += m * v[d] * w[d];
            den += m * v[d] * v[d];
        }
        omega_sq = num / den.max(f64::MIN_POSITIVE);
        std::mem::swap(&mut v, &mut w);
        let s = scale_of(&v);
        v.iter_mut().for_each(|vi| *vi /= s);
    }
    // a largest speed of amplitude x omega_max x the largest coordinate: displacements
    // ~amplitude of it
    let amp = amplitude * l.omega_max * size;
    let scaled = |v: &[f64]| -> Vec<[f64; 2]> {
        let s = scale_of(v);
        v.chunks_exact(2)
            .map(|a| [amp * a[0] / s, amp * a[1] / s])
            .collect()
    };
    Ok(ProbeSeeds {
        top: scaled(&v),
        broad: scaled(&broad),
        a0,
        omega_top: omega_sq.max(0.0).sqrt(),
    })
}

/// The initial fields of a stability probe ([`top_mode_velocity`]).
struct ProbeSeeds {
    /// Concentrated in the highest modes ([`PROBE_POWER_ITERATIONS`] power iterations).
    top: Vec<[f64; 2]>,
    /// The upper part of the spectrum ([`PROBE_BROAD_ITERATIONS`] power iterations).
    broad: Vec<[f64; 2]>,
    /// The acceleration at rest at the probe's start (flat DOFs).
    a0: Vec<f64>,
    /// The state's highest frequency measured by the Rayleigh quotient [rad/s].
    omega_top: f64,
}

/// One stability probe's outcome, as `study.json` records it.
#[derive(Clone, Debug, Serialize)]
struct Probe {
    /// The fraction of the predicted step.
    fraction: f64,
    /// Stable: the top-mode probe and, where run, the broadband one.
    stable: bool,
    /// Energy ratio (last fifth over first) of the top-mode probe (`None`: stopped).
    ratio: Option<f64>,
    /// The same for the broadband probe, run for the schemes with stable windows above their
    /// limit (PC-4, OMF30, OMF32) when the top-mode probe is stable.
    broad_ratio: Option<f64>,
    /// The frequency the probe's length is measured in [rad/s]: the Rayleigh estimate of the
    /// state's highest frequency.
    omega_probe: f64,
}

/// The measured-stability probe of one scheme at one fraction of its predicted step: the
/// scene's mesh, supports and optional stages (contact, joints), with no loads, no gravity and
/// the walls at rest, started from [`top_mode_velocity`] (its top-mode field, or with `broad`
/// its broadband field) and run for `omega_top t` = [`PROBE_OMEGA_T`]. Returns whether it is
/// stable (solver did not stop it and the mean of `K + U` over the last fifth is at most
/// [`PROBE_GROWTH`] times that over the first fifth), that ratio, and `omega_top`.
fn stability_probe(
    scene: &Path,
    scheme: SchemeKind,
    fraction: f64,
    out: &Path,
    start: Option<&ProbeStart>,
    amplitude: f64,
    broad: bool,
) -> Result<ProbeVerdict> {
    let mut l = driver::load(scene)?;
    l.scheme = scheme;
    l.dt_limit = driver::stable_step(scheme, l.omega_max, l.z_high);
    l.scene.integrator.scheme = scheme.name().into();
    l.scene.output.frames = 0;
    l.model.loads.clear();
    l.model.gravity = None;
    for p in &mut l.model.prescribed {
        p.velocity = 0.0;
    }
    if let Some(c) = &mut l.scene.contact {
        for (i, w) in c.walls.iter_mut().enumerate() {
            if let Some(d) = start.and_then(|s| s.walls.get(i)) {
                w.point = [w.point[0] + d[0], w.point[1] + d[1]];
            }
            w.velocity = [0.0, 0.0];
        }
    }
    // The joints' history at T (scenes with joints): adopted by the fracture stage of the
    // seed's system and of the probe run.
    if let (Some(f), Some(js)) = (&mut l.scene.fracture, start.and_then(|s| s.joints.as_ref())) {
        f.initial_state = Some(js.clone());
    }
    // From a contact state: the positions become the start (the elements keep their own
    // reference shape, built at load), and the velocities are the state's.
    let mut v_start = vec![[0.0; 2]; l.model.n_nodes()];
    if let Some(s) = start {
        for (x, u) in l.model.x0.iter_mut().zip(&s.displacement) {
            *x = [x[0] + u[0], x[1] + u[1]];
        }
        if !s.frozen {
            v_start.clone_from(&s.velocity);
        }
    }
    let seeds = top_mode_velocity(&l, amplitude, &out.join("seed"))?;
    let a0 = &seeds.a0;
    let seed = if broad { &seeds.broad } else { &seeds.top };
    let frozen = start.is_some_and(|s| s.frozen);
    if frozen {
        // the state held by constant loads that balance its forces: `F = -M a(x_T, 0)`
        let forces = a0
            .iter()
            .enumerate()
            .filter(|&(d, a)| !l.model.constrained[d] && *a != 0.0)
            .map(|(d, a)| (d as u32, -l.model.mass[d / 2] * a))
            .collect();
        l.model.loads = vec![fdem_solver::model::RampedLoad { ramp: 0.0, forces }];
    }
    let e_seed = l.model.kinetic_energy(seed);
    l.model.v0 = seed
        .iter()
        .zip(&v_start)
        .map(|(a, b)| [a[0] + b[0], a[1] + b[1]])
        .collect();
    // `omega t` = PROBE_OMEGA_T of the probed state's highest frequency as measured (the
    // Rayleigh estimate, at most the true one, so the probe spans at least that many
    // radians of the top mode): the growth tolerance is per unit `omega t` of that mode. The
    // bound (`omega_max`, or the active bound from a frozen active state) overestimates it,
    // 1.8 times on the collision's state, where a probe measured in the bound's radians let
    // PC-4's slow growth pass 1.8 times too long a step. Kept within [1/4, 1] of the bound.
    let bound = start.and_then(|s| s.omega).unwrap_or(l.omega_max);
    let omega_t = if seeds.omega_top.is_finite() {
        seeds.omega_top.clamp(0.25 * bound, bound)
    } else {
        bound
    };
    let duration = PROBE_OMEGA_T / omega_t;
    l.scene.duration = Some(duration);
    (l.n_steps, l.dt) = driver::step_count(duration, fraction * l.dt_limit);
    // every step: sampled more sparsely, the fast oscillation of `K + U` near a scheme's
    // limit aliases into slow beats that bias the means of the fifths by ~1 %
    l.scene.histories.every = Some(1);
    l.scene.histories.probes = vec![fdem_solver::scene::Probe::Energy];
    let options = RunOptions {
        out_dir: out.to_path_buf(),
        raw: false,
    };
    match driver::run_outcome(&mut l, &options, &mut |_| {}) {
        Ok(_) => {}
        Err(RunError::Unstable { .. }) => {
            return Ok(ProbeVerdict {
                stable: false,
                ratio: None,
                omega: omega_t,
            });
        }
        Err(e) => return Err(e.into()),
    }
    let (_, k) = read_history(out, "kinetic")?;
    let e: Vec<f64> = if frozen {
        // about an equilibrium held by loads: the kinetic energy (its mean over a fifth is
        // half the oscillation's energy; `K + U` trades first-order terms with the loads' work)
        k
    } else {
        let (_, u) = read_history(out, "strain")?;
        let (_, st) = read_history(out, "stored")?;
        k.iter()
            .zip(&u)
            .zip(&st)
            .map(|((a, b), c)| a + b + c)
            .collect()
    };
    let m = e.len() / 5;
    if m == 0 {
        return Ok(ProbeVerdict {
            stable: true,
            ratio: None,
            omega: omega_t,
        });
    }
    let first = e[..m].iter().sum::<f64>() / m as f64;
    let last = e[e.len() - m..].iter().sum::<f64>() / m as f64;
    // From a pressed state the static strain and contact energy (0.147 J on the tests' two
    // blocks) and the vibration left by the loading (~2e-4 J) dwarf the energy of the
    // high-mode field (~1e-5 J): the growth is measured against the field's own energy, its
    // initial kinetic energy (from rest that is the whole energy, as before).
    let ratio = if start.is_some() && !frozen {
        1.0 + (last - first) / e_seed.max(f64::MIN_POSITIVE)
    } else {
        last / first.max(f64::MIN_POSITIVE)
    };
    Ok(ProbeVerdict {
        stable: ratio.is_finite() && ratio <= PROBE_GROWTH,
        ratio: Some(ratio),
        omega: omega_t,
    })
}

/// What [`stability_probe`] finds.
struct ProbeVerdict {
    stable: bool,
    /// Energy ratio, last fifth over first (`None`: stopped by the solver, or too short).
    ratio: Option<f64>,
    /// The frequency the probe's length was measured in [rad/s].
    omega: f64,
}

fn schemes(names: &[String]) -> Result<Vec<SchemeKind>> {
    if names.is_empty() {
        return Ok(SchemeKind::ALL.to_vec());
    }
    names
        .iter()
        .map(|n| {
            n.parse::<SchemeKind>().map_err(|_| {
                crate::bad_input(format!(
                    "unknown scheme '{}': use one of {}",
                    fdem_solver::excerpt(n),
                    SchemeKind::valid_names()
                ))
            })
        })
        .collect()
}

fn csv(runs: &[Run]) -> String {
    let mut s = String::from(
        "scheme,fraction,dt,dt_predicted,steps,stable,force_evaluations,wall_time,element_steps_per_second,energy_ratio,error_vs_reference,error_analytical,measured,error,measured2,error_measure,error_measure2\n",
    );
    let o = |v: Option<f64>| v.map(|v| format!("{v:e}")).unwrap_or_default();
    for r in runs {
        let _ = writeln!(
            s,
            "{},{},{:e},{:e},{},{},{},{:e},{:e},{},{},{},{},{},{},{},{}",
            r.scheme,
            r.fraction,
            r.dt,
            r.dt_predicted,
            r.steps,
            r.stable,
            r.force_evaluations,
            r.wall_time,
            r.element_steps_per_second,
            o(r.energy_ratio),
            o(r.error_vs_reference),
            o(r.error_analytical),
            o(r.measured),
            o(r.error),
            o(r.measured2),
            o(r.error_measure),
            o(r.error_measure2)
        );
    }
    s
}

/// Runs the study.
pub fn run(args: &SceneArgs) -> Result<()> {
    let side = side_file(&args.scene)?;
    let kinds = match side.as_ref().and_then(|s| s.schemes.clone()) {
        Some(list) if args.schemes.is_empty() => schemes(&list)?,
        _ => schemes(&args.schemes)?,
    };
    let mut fractions = if !args.fractions.is_empty() {
        args.fractions.clone()
    } else if let Some(f) = side.as_ref().and_then(|s| s.fractions.clone()) {
        f
    } else {
        DEFAULT_FRACTIONS.to_vec()
    };
    if fractions.is_empty() || fractions.iter().any(|f| !(*f > 0.0 && f.is_finite())) {
        return Err(crate::bad_input(
            "--fractions must be positive numbers, e.g. 0.1,0.5,0.9",
        ));
    }
    fractions.sort_by(f64::total_cmp);
    fractions.dedup();
    // Bad input (exit code 2): the scene must load, as a dynamic analysis; checked before
    // anything is written unless the side file edits the scene (then on the edited scene).
    let validate = |scene: &Path| -> Result<()> {
        let l0 = driver::load(scene)?;
        if l0.scene.analysis != fdem_solver::scene::Analysis::Dynamic {
            return Err(crate::bad_input(format!(
                "{}: the study needs a dynamic analysis with a positive duration",
                args.scene.display()
            )));
        }
        Ok(())
    };
    let edits = side.as_ref().is_some_and(|s| !s.set.is_empty());
    if !edits {
        validate(&args.scene)?;
    }
    let stem = args
        .scene
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("scene")
        .to_string();
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("out/study-{stem}")));
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let scene = study_scene(&args.scene, side.as_ref(), &out)?;
    if edits {
        validate(&scene)?;
    }
    let active = active_bound_run(&scene, &out.join("runs").join("active-bound"))?;
    let r_active = active.as_ref().map(|a| a.ratio).unwrap_or(1.0);
    let start_dir = out.join("runs").join("probe-start");
    let start = match side.as_ref().and_then(|s| s.probe_from) {
        Some(ProbeFrom::Time(t)) => Some(probe_start(&scene, t, None, &start_dir)?),
        Some(ProbeFrom::Named(ProbeFromName::Active)) => {
            let (t, w) = active
                .as_ref()
                .filter(|a| a.omega_contact_active > 0.0)
                .map(|a| (a.omega_contact_active_time, a.omega_active))
                .with_context(|| {
                    format!(
                        "{}: `\"probe_from\": \"active\"` needs contact engaged during the scene (none was): leave it out to probe from rest",
                        args.scene.with_extension("study.json").display()
                    )
                })?;
            Some(probe_start(&scene, t, Some(w), &start_dir)?)
        }
        None => None,
    };
    let amplitude = side
        .as_ref()
        .and_then(|s| s.probe_amplitude)
        .unwrap_or(PROBE_AMPLITUDE);
    if !(amplitude > 0.0 && amplitude < 1e-2) {
        return Err(crate::bad_input(format!(
            "`probe_amplitude` must be in (0, 1e-2) of the model size (default {PROBE_AMPLITUDE})"
        )));
    }
    let analytical = side.and_then(|s| s.reference);
    let l0 = driver::load(&scene)?;
    let (nodes, triangles) = (l0.model.n_nodes(), l0.model.triangles.len());
    drop(l0);

    // The reference: the highest-order scheme at the smallest fraction.
    // (OMF32 when it is run: of the fourth-order schemes its error constant is by far the
    // smallest, 2e-8 against 2e-6 for CHIN and Forest & Ruth on the oscillator,
    // docs/time-integration.md)
    let ref_kind = if kinds.contains(&SchemeKind::Omf32) {
        SchemeKind::Omf32
    } else {
        kinds
            .iter()
            .copied()
            .max_by_key(|k| k.measured_order())
            .unwrap_or(SchemeKind::ForestRuth)
    };
    let bar = indicatif::ProgressBar::new((kinds.len() * fractions.len()) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} runs {msg} [{elapsed_precise}, ETA {eta}]",
        )
        .expect("valid template"),
    );
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let run_dir = |k: SchemeKind, f: f64| out.join("runs").join(format!("{}-{f}", k.name()));
    let mut raws: Vec<Raw> = Vec::new();
    let mut limits = Vec::new();
    for &k in &kinds {
        let mut first_unstable = None;
        let mut last_stable: f64 = 0.0;
        let mut probes: Vec<Probe> = Vec::new();
        // a scheme stable again above its limit also gets a broadband probe, and probes at
        // the steps that put the measured top mode into its unstable band
        let band = fdem_time::stability::stable_windows(k, 8.0)
            .first()
            .map(|w| [k.stability_limit(), w[0]]);
        let windows = band.is_some();
        let mut band_added = false;
        // band fractions above the listed ones, tried in order with the ladder
        let mut pending: Vec<f64> = Vec::new();
        let mut list: Vec<f64> = fractions.clone();
        let mut i = 0;
        while i < list.len() {
            let f = list[i];
            bar.set_message(format!("{} at {f} h_pred", k.name()));
            let r = one_run(&scene, k, f, &run_dir(k, f), analytical.as_ref())?;
            // The measured-stability probe from 0.99 up, until one is unstable.
            let probe_stable = if f >= 0.99 && probes.iter().all(|p| p.stable) {
                bar.set_message(format!("{} at {f} h_pred (stability probe)", k.name()));
                let top = stability_probe(
                    &scene,
                    k,
                    f,
                    &run_dir(k, f).join("probe"),
                    start.as_ref(),
                    amplitude,
                    false,
                )?;
                let broad = if top.stable && windows {
                    bar.set_message(format!("{} at {f} h_pred (broadband probe)", k.name()));
                    Some(stability_probe(
                        &scene,
                        k,
                        f,
                        &run_dir(k, f).join("probe-broad"),
                        start.as_ref(),
                        amplitude,
                        true,
                    )?)
                } else {
                    None
                };
                let ok = top.stable && broad.as_ref().is_none_or(|b| b.stable);
                if let Some(b) = band.filter(|_| !band_added) {
                    band_added = true;
                    // those among the listed fractions join the list now, the others the
                    // ladder below
                    let last = fractions.last().copied().unwrap_or(f);
                    let (now, later): (Vec<f64>, Vec<f64>) =
                        band_fractions(b, top.omega, r.run.dt_predicted)
                            .into_iter()
                            .partition(|x| *x < last);
                    let added = insert_fractions(&mut list, i + 1, &now, f);
                    bar.inc_length(added as u64);
                    pending = later;
                }
                probes.push(Probe {
                    fraction: f,
                    stable: ok,
                    ratio: top.ratio,
                    broad_ratio: broad.and_then(|b| b.ratio),
                    omega_probe: top.omega,
                });
                ok
            } else {
                probes.iter().all(|p| p.stable)
            };
            // the observed limit: the largest fraction below which every fraction tried is
            // stable (a stable run above an unstable one does not count: on the fracture
            // disc the scene runs' verdicts past the first unstable step are erratic)
            if r.run.stable && probe_stable {
                if first_unstable.is_none() {
                    last_stable = last_stable.max(f);
                }
            } else if first_unstable.is_none() {
                first_unstable = Some(f);
            }
            raws.push(r);
            bar.inc(1);
            i += 1;
            if i == list.len() && first_unstable.is_none() {
                // rounded to 4 digits: a readable fraction in the tables and file names
                let ladder = PROBES
                    .iter()
                    .map(|p| (p * r_active * 1e4).round() / 1e4)
                    .find(|p| *p > f * 1.0001);
                let band_next = pending.iter().copied().find(|p| *p > f * 1.0001);
                let next = match (ladder, band_next) {
                    (Some(a), Some(b)) => Some(a.min(b)),
                    (a, b) => a.or(b),
                };
                if let Some(p) = next {
                    list.push(p);
                    bar.inc_length(1);
                }
            }
            // past the first instability only the listed fractions still run (their errors)
            if first_unstable.is_some() && list[i..].iter().all(|x| !fractions.contains(x)) {
                break;
            }
        }
        let dt_predicted = raws.last().map(|r| r.run.dt_predicted).unwrap_or(0.0);
        limits.push(Limit {
            scheme: k.name().into(),
            dt_predicted,
            observed_at_least: last_stable,
            observed_below: first_unstable,
            probes,
            dt_active: dt_predicted * r_active,
            observed_over_active_at_least: last_stable / r_active,
            observed_over_active_below: first_unstable.map(|b| b / r_active),
        });
    }
    bar.finish_and_clear();
    let f_min = fractions[0];
    let ref_raw = raws
        .iter()
        .find(|r| r.run.scheme == ref_kind.name() && r.run.fraction == f_min && r.run.stable);
    let reference = ref_raw.map(|r| r.displacement.clone());
    let (m_ref, m2_ref) = ref_raw
        .map(|r| (r.run.measured, r.run.measured2))
        .unwrap_or((None, None));
    let by_measure = analytical.as_ref().is_some_and(|a| !a.is_analytical());
    if by_measure {
        for r in raws.iter_mut().filter(|r| r.run.stable) {
            if let (Some(m), Some(mr)) = (r.run.measured, m_ref) {
                r.run.error_measure = Some((m - mr).abs() / mr.abs().max(f64::MIN_POSITIVE));
            }
            if let Some(Analytical::Fracture { .. }) = analytical
                && let (Some(c), Some(cr)) = (r.run.measured2, m2_ref)
            {
                r.run.error_measure2 = Some((c - cr).abs());
            }
        }
    }
    if let Some(u_ref) = &reference {
        let scale = u_ref
            .iter()
            .map(|u| u[0].abs().max(u[1].abs()))
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        for r in raws.iter_mut().filter(|r| r.run.stable) {
            let d = r
                .displacement
                .iter()
                .zip(u_ref)
                .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
                .fold(0.0, f64::max);
            r.run.error_vs_reference = Some(d / scale);
        }
    }
    let runs: Vec<Run> = raws
        .into_iter()
        .map(|mut r| {
            r.run.error = if by_measure {
                r.run.error_measure
            } else if analytical.is_some() {
                r.run.error_analytical
            } else {
                r.run.error_vs_reference
            };
            r.run
        })
        .collect();
    crate::write_atomically(&out.join("runs.csv"), csv(&runs).as_bytes())?;
    let report = Report {
        scene: args.scene.display().to_string(),
        analytical: analytical.as_ref(),
        reference_run: format!("{} at {f_min} h_pred", ref_kind.name()),
        nodes,
        triangles,
        active: active.as_ref(),
        probe_from: start.as_ref().map(|s| s.time),
        probe_start_broken: start
            .as_ref()
            .and_then(|s| s.joints.as_ref())
            .map(|j| j.n_broken),
        probe_frozen: start.as_ref().is_some_and(|s| s.frozen),
        probe_amplitude: amplitude,
        limits: &limits,
        runs: &runs,
    };
    crate::write_atomically(
        &out.join("study.json"),
        serde_json::to_string_pretty(&report)?.as_bytes(),
    )?;
    let primary = match &analytical {
        Some(a) if a.is_analytical() => Primary::Analytical,
        Some(Analytical::Collision {}) => Primary::Measure("kinetic energy ratio after/before"),
        Some(_) => Primary::Measure("peak load"),
        None => Primary::Reference,
    };
    let files = plots(&out, &stem, &kinds, &runs, &limits, primary, r_active)?;

    // The table on stdout.
    println!(
        "{stem}: {nodes} nodes, {triangles} triangles; reference {}",
        report.reference_run
    );
    if let Some(a) = &active {
        println!(
            "frequency bound: a priori {:.4e} rad/s, active {:.4e} rad/s (contact engaged: {:.4e} at t = {:.3e} s): h_active = {:.4} h_pred",
            a.omega_a_priori,
            a.omega_active,
            a.omega_contact_active,
            a.omega_contact_active_time,
            a.ratio
        );
    }
    println!(
        "{:<20} {:>12} {:>18} {:>12} {:>20}",
        "scheme", "h_pred (s)", "observed / h_pred", "h_active (s)", "observed / h_active"
    );
    for l in &limits {
        let below = l
            .observed_below
            .map(|b| format!("{b}"))
            .unwrap_or_else(|| ">".into());
        let below_a = l
            .observed_over_active_below
            .map(|b| format!("{b:.3}"))
            .unwrap_or_else(|| ">".into());
        println!(
            "{:<20} {:>12.4e} {:>18} {:>12.4e} {:>20}",
            l.scheme,
            l.dt_predicted,
            format!("[{}, {below})", l.observed_at_least),
            l.dt_active,
            format!("[{:.3}, {below_a})", l.observed_over_active_at_least),
        );
    }
    println!(
        "{:<20} {:>6} {:>10} {:>8} {:>10} {:>12} {:>12}",
        "scheme", "h/hp", "wall (s)", "forces", "Mel-st/s", "err vs ref", "err analyt."
    );
    let o = |v: Option<f64>| v.map(|v| format!("{v:.3e}")).unwrap_or_else(|| "-".into());
    for r in &runs {
        println!(
            "{:<20} {:>6} {:>10.3} {:>8} {:>10.2} {:>12} {:>12}{}",
            r.scheme,
            r.fraction,
            r.wall_time,
            r.force_evaluations,
            r.element_steps_per_second / 1e6,
            o(r.error_vs_reference),
            o(r.error_analytical),
            if r.stable { "" } else { "  UNSTABLE" }
        );
    }
    println!(
        "wrote {} and {}",
        out.join("runs.csv").display(),
        out.join("study.json").display()
    );
    for f in files {
        println!("wrote {}", f.display());
    }
    Ok(())
}

/// Which error the first pair of charts shows.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Primary {
    /// Against the scene's analytical answer.
    Analytical,
    /// A scalar measure (named) against the reference run's.
    Measure(&'static str),
    /// The displacements against the reference run.
    Reference,
}

/// Picks one error of a run.
type ErrorOf = fn(&Run) -> Option<f64>;

fn plots(
    out: &Path,
    stem: &str,
    kinds: &[SchemeKind],
    runs: &[Run],
    limits: &[Limit],
    primary: Primary,
    r_active: f64,
) -> Result<Vec<PathBuf>> {
    let label = |k: &SchemeKind| {
        let l = limits.iter().find(|l| l.scheme == k.name());
        match l {
            Some(Limit {
                observed_at_least,
                observed_below: Some(b),
                ..
            }) => format!(
                "{} (observed limit in [{observed_at_least}, {b}) h_pred)",
                k.name()
            ),
            Some(l) => format!(
                "{} (observed limit > {} h_pred)",
                k.name(),
                l.observed_at_least
            ),
            None => k.name().into(),
        }
    };
    let series = |pick: &dyn Fn(&Run) -> Option<(f64, f64)>, with_label: bool| -> Vec<Series> {
        kinds
            .iter()
            .map(|k| Series {
                name: if with_label {
                    label(k)
                } else {
                    k.name().into()
                },
                points: runs
                    .iter()
                    .filter(|r| r.scheme == k.name() && r.stable)
                    .filter_map(pick)
                    .collect(),
            })
            .collect()
    };
    // The primary error (analytical when declared), and the error against the reference run
    // as a second pair of charts when the primary one is analytical.
    let mut kinds_of_error: Vec<(&str, String, ErrorOf)> = Vec::new();
    match primary {
        Primary::Analytical => kinds_of_error.push((
            "",
            "relative error against the analytical answer".into(),
            |r| r.error_analytical,
        )),
        Primary::Measure(what) => kinds_of_error.push((
            "",
            format!("relative error of the {what} against the reference run"),
            |r| r.error_measure,
        )),
        Primary::Reference => {}
    }
    kinds_of_error.push((
        if primary == Primary::Reference {
            ""
        } else {
            "_reference"
        },
        "relative error of the displacements against the reference run".into(),
        |r| r.error_vs_reference,
    ));
    let mut plots = Vec::new();
    for (suffix, what, pick) in kinds_of_error {
        let mut err_vs_step = series(&|r| pick(r).map(|e| (r.fraction, e)), true);
        let ys: Vec<f64> = runs.iter().filter_map(pick).filter(|e| *e > 0.0).collect();
        let (lo, hi) = ys
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(*v), b.max(*v)));
        if lo.is_finite() {
            err_vs_step.push(Series {
                name: "predicted stable step (all schemes)".into(),
                points: vec![(1.0, lo), (1.0, hi)],
            });
            if r_active != 1.0 {
                err_vs_step.push(Series {
                    name: format!("active prediction ({r_active:.3} h_pred, all schemes)"),
                    points: vec![(r_active, lo), (r_active, hi)],
                });
            }
        }
        plots.push((
            format!("work_precision{suffix}"),
            Plot {
                title: format!("{stem}: work-precision (stable runs)"),
                x_label: "wall time of the run (s)".into(),
                y_label: what.clone(),
                x_scale: Scale::Log,
                y_scale: Scale::Log,
                series: series(&|r| pick(r).map(|e| (r.wall_time, e)), false),
                y_range: None,
                lines: false,
            },
        ));
        plots.push((
            format!("error_vs_step{suffix}"),
            Plot {
                title: format!("{stem}: error against the time step"),
                x_label: "h / h_pred (h_pred: scheme limit over the element frequency bound)"
                    .into(),
                y_label: what.clone(),
                x_scale: Scale::Log,
                y_scale: Scale::Log,
                series: err_vs_step,
                y_range: None,
                lines: true,
            },
        ));
    }
    let mut energy = series(&|r| r.energy_ratio.map(|e| (r.fraction, e)), true);
    energy.push(Series {
        name: "predicted stable step (all schemes)".into(),
        points: vec![(1.0, 0.1), (1.0, 10.0)],
    });
    plots.push((
        "energy_vs_step".to_string(),
        Plot {
            title: format!("{stem}: final energy / energy put in (stable runs)"),
            x_label: "h / h_pred".into(),
            y_label: "(K + U) / (work in + K0)".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            series: energy,
            y_range: None,
            lines: true,
        },
    ));
    let mut files = Vec::new();
    for (name, p) in plots {
        files.extend(p.write(&out.join(name))?);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// OMF32's band: the middle point and the upper one put `h omega_top` inside `(L, W)`,
    /// the lower one half a band below `L` (to 4-digit rounding of the fraction, 1e-4
    /// relative).
    #[test]
    fn band_fractions_put_the_top_mode_in_the_unstable_band() {
        let k = SchemeKind::Omf32;
        let w = fdem_time::stability::stable_windows(k, 8.0)[0][0];
        let l = k.stability_limit();
        let (omega_top, h_pred) = (1.819e6, l / 3.135e6);
        let f = band_fractions([l, w], omega_top, h_pred);
        let hw: Vec<f64> = f.iter().map(|f| f * h_pred * omega_top).collect();
        assert_eq!(hw.len(), 3);
        assert!((hw[0] / (l - 0.5 * (w - l)) - 1.0).abs() < 1e-4, "{hw:?}");
        assert!(hw[1] > l && hw[1] < w && hw[2] > l && hw[2] < w, "{hw:?}");
        // the collision's figures: the band lies 1.72 times above the predicted step
        assert!((f[1] - 3.135 / 1.819).abs() < 1e-3, "{f:?}");
    }

    #[test]
    fn inserted_fractions_keep_the_list_sorted_and_skip_duplicates() {
        let mut list = vec![0.1, 0.99, 1.01, 1.05];
        let n = insert_fractions(&mut list, 2, &[1.3, 1.02, 1.01, 0.5], 0.99);
        assert_eq!(n, 2);
        assert_eq!(list, vec![0.1, 0.99, 1.01, 1.02, 1.05, 1.3]);
        assert!(band_fractions([3.0, 2.0], 1.0, 1.0).is_empty());
    }
}
