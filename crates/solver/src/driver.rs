//! Loading a scene (scene file, meshes, model, time step) and running it: the dynamic and
//! relaxation loops over the time crate's schemes, the static solve, frames, histories and
//! the run summary.
//!
//! Time step: `h_limit = (h omega)_scheme / omega_max * (sqrt(1 + z^2) - z)`, where
//! `omega_max` is the largest element frequency bound of the mesh crate, `(h omega)_scheme`
//! the scheme's stability limit on the undamped oscillator, and `z` the damping ratio of the
//! highest mode (element viscosity and mass-proportional damping). `"auto"` takes
//! `safety * h_limit`; a fixed step above `h_limit` is an error. The step is then shortened so
//! that a whole number of steps spans the duration ([`step_count`]: `duration / h` within a
//! relative 1e-12 of a whole number is that number). The frequency bound, the steps, the
//! frames and the history rows are checked in [`crate::limits`] before anything is written.
//!
//! Every 100 steps the loop checks for non-finite values and for energy growth: the
//! mechanical energy `E = K + U + stored (contact, joints)` may not exceed the energy supplied
//! `S = E_0 + |W_loads + W_gravity| + |W_supports| + |W_walls| + K_prescribed` (damping,
//! friction and fracture only remove energy) by more than the step-synchronisation factor:
//! `E > 2 S / (1 - (h / h_limit)^2)` while `E` grew since the last check
//! stops the run with an `Unstable` error naming the scheme, the step, the predicted limit and
//! the fix ([`energy_growth`]).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use fdem_mesh::{Elements, Mesh, TriId};
use fdem_time::{SchemeKind, State};
use rayon::prelude::*;
use serde::Serialize;

use crate::diagnosis::{self, Found, InversionWatch};
use crate::error::{RunError, SceneError};
pub use crate::ledger::Energies;
use crate::ledger::{Books, kinetic_energy};
use crate::limits::{self, StepInputs};
use crate::mesh_adapter;
use crate::model::{self, Model};
use crate::output::{Collection, FrameData, HistoryWriter, JointSeries, frame, vtu, write_atomic};
use crate::resolve::MeshNames;
use crate::scene::{Analysis, Probe, Scene, TimeStep};
use crate::static_solve;
use crate::system::{ForceContribution, SceneSystem, StageTimers};

/// A scene with its meshes and model, ready to run.
pub struct Loaded {
    /// The scene file.
    pub file: PathBuf,
    /// The parsed scene.
    pub scene: Scene,
    /// The bodies' meshes.
    pub meshes: Vec<Mesh>,
    /// The assembled model.
    pub model: Model,
    /// The elements for the force kernels.
    pub elements: Elements,
    /// The scheme.
    pub scheme: SchemeKind,
    /// Largest element frequency bound [rad/s].
    pub omega_max: f64,
    /// Damping ratio of the highest mode.
    pub z_high: f64,
    /// The stable limit of the chosen scheme [s].
    pub dt_limit: f64,
    /// The time step used [s] (0 for static).
    pub dt: f64,
    /// Number of steps (0 for static).
    pub n_steps: u64,
    /// Further force terms (contact, joints) for the dynamic loop; empty by default, and then
    /// they cost nothing. Add them with [`Loaded::add_contribution`], which also lowers the
    /// time step for their frequency bound.
    pub contributions: Vec<Box<dyn ForceContribution>>,
}

/// Reads a scene file, its meshes, and builds the model; every error names the file and field.
///
/// Order: the scene, the meshes, then every name the scene refers to ([`crate::resolve`]),
/// then the fracturing bodies are exploded and the model built, and last the derived
/// quantities (frequency bound, steps, frames, history rows: [`crate::limits`]) are checked.
pub fn load(file: &Path) -> Result<Loaded, SceneError> {
    let mut scene = Scene::from_file(file)?;
    static_solve::check_sections(&scene, file)?;
    let dir = file.parent().unwrap_or(Path::new("."));
    let mut read = Vec::new();
    for i in 0..scene.bodies.len() {
        let path = dir.join(&scene.bodies[i].mesh);
        let mesh = mesh_adapter::read(&path).map_err(|message| SceneError::Mesh {
            file: file.to_path_buf(),
            path: format!("bodies[{i}].mesh"),
            mesh: path.clone(),
            message,
        })?;
        read.push(mesh);
    }
    // (messages name each mesh as the scene does)
    let names: Vec<MeshNames> = read
        .iter()
        .zip(&scene.bodies)
        .map(|(m, b)| MeshNames {
            source: b.mesh.display().to_string(),
            ..MeshNames::of(m)
        })
        .collect();
    let refs = crate::resolve::resolve(&scene, file, &names)?;
    let mut meshes = Vec::new();
    let mut inputs = Vec::new();
    for (i, mesh) in read.into_iter().enumerate() {
        let region = refs.fracture_region[i];
        let mesh = crate::fracture_stage::explode_body(&mut scene, file, i, region, mesh)?;
        inputs.push(mesh_adapter::to_input(&mesh));
        meshes.push(mesh);
    }
    let model = model::build(&scene, file, &inputs, &refs)?;
    if scene.analysis == Analysis::Static {
        static_solve::check_supports(&scene, file, &model)?;
    }
    crate::stages::validate(&scene, file)?;
    let xi = scene.damping.viscosity_ratio;
    let elements = mesh_adapter::elements(&model, xi).map_err(|message| SceneError::Invalid {
        file: file.to_path_buf(),
        path: "bodies".into(),
        message,
        fix: "check the materials and the mesh".into(),
    })?;
    let scheme: SchemeKind = scene
        .integrator
        .scheme
        .parse()
        .map_err(|_| SceneError::Invalid {
            file: file.to_path_buf(),
            path: "integrator.scheme".into(),
            message: format!("unknown scheme '{}'", scene.integrator.scheme),
            fix: format!("use one of {}", SchemeKind::valid_names()),
        })?;
    let omega_max = crate::stages::omega_max(
        &scene,
        &model,
        file,
        elements.max_frequency_bound(&model.x0),
    )?;
    let z_visc = (0..elements.len())
        .map(|t| elements.high_mode_damping(TriId(t as u32), &model.x0))
        .fold(0.0, f64::max);
    let z_high = z_visc + scene.damping.mass_proportional / (2.0 * omega_max);
    let steps = limits::time_steps(&StepInputs {
        scene: &scene,
        file,
        model: &model,
        elements: &elements,
        scheme,
        omega_max,
        z_high,
        lower_fixed_step: false,
    })?;
    Ok(Loaded {
        file: file.to_path_buf(),
        scene,
        meshes,
        model,
        elements,
        scheme,
        omega_max,
        z_high,
        dt_limit: steps.dt_limit,
        dt: steps.dt,
        n_steps: steps.n_steps,
        contributions: Vec::new(),
    })
}

/// The number of steps of about `h` that span `duration` ([`limits::step_count`]: a whole
/// `duration / h` within a relative 1e-12 is that number, else rounded up), as an integer
/// (saturating), and the step that spans the duration exactly.
pub fn step_count(duration: f64, h: f64) -> (u64, f64) {
    let n = limits::step_count(duration, h);
    (n as u64, duration / n)
}

/// The stable step of `scheme` for highest frequency `omega` and its damping ratio `z`.
pub fn stable_step(scheme: SchemeKind, omega: f64, z: f64) -> f64 {
    scheme.stability_limit() / omega * ((1.0 + z * z).sqrt() - z)
}

impl Loaded {
    /// Adds a force contribution (contact, joints). The highest frequency becomes
    /// `sqrt(omega_elements^2 + omega_c^2)`, and the time step and step count are recomputed
    /// and checked with it ([`crate::limits::time_steps`]; an explicit `time_step` above the
    /// new limit is lowered to it).
    pub fn add_contribution(&mut self, c: Box<dyn ForceContribution>) -> Result<(), SceneError> {
        let wc = c.frequency_bound();
        self.contributions.push(c);
        if wc > 0.0 && self.scene.analysis != Analysis::Static {
            let omega_max = (self.omega_max * self.omega_max + wc * wc).sqrt();
            let steps = limits::time_steps(&StepInputs {
                scene: &self.scene,
                file: &self.file,
                model: &self.model,
                elements: &self.elements,
                scheme: self.scheme,
                omega_max,
                z_high: self.z_high,
                lower_fixed_step: true,
            })?;
            self.omega_max = omega_max;
            self.dt_limit = steps.dt_limit;
            self.dt = steps.dt;
            self.n_steps = steps.n_steps;
        }
        Ok(())
    }

    /// A short description: meshes, model size, analysis, time step.
    pub fn describe(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "scene {}{}",
            self.file.display(),
            if self.scene.title.is_empty() {
                String::new()
            } else {
                format!(": {}", self.scene.title)
            }
        );
        for (b, m) in self.scene.bodies.iter().zip(&self.meshes) {
            let _ = writeln!(
                s,
                "  body {}: {} ({} nodes, {} triangles)",
                b.name.as_deref().unwrap_or("-"),
                b.mesh.display(),
                m.nodes.len(),
                m.triangles.len()
            );
        }
        let free = self.model.constrained.iter().filter(|c| !**c).count();
        let _ = write!(
            s,
            "  {} nodes, {} triangles, {} free DOFs; analysis {:?}",
            self.model.n_nodes(),
            self.model.triangles.len(),
            free,
            self.scene.analysis
        );
        if self.scene.analysis != Analysis::Static {
            let _ = write!(
                s,
                "; {} with h = {:.4e} s (limit {:.4e} s), {} steps",
                self.scheme, self.dt, self.dt_limit, self.n_steps
            );
        }
        s
    }
}

/// `fdem check`'s report: the stable step of every scheme and the estimated run time
/// ([`run_time_estimate`]); another scheme's row scales the scene scheme's step cost by its
/// force evaluations per step.
pub fn check_report(l: &Loaded) -> String {
    let mut s = String::new();
    let n_tri = l.elements.len().max(1);
    let x = &l.model.x0;
    let mut f = vec![[0.0; 2]; x.len()];
    let mut scratch = fdem_mesh::ForceScratch::new(&l.elements);
    // one untimed pass warms the caches and the thread pool
    l.elements.internal_forces(x, x, &mut f, &mut scratch);
    let start = Instant::now();
    let mut evals = 0;
    while evals < 3 || (start.elapsed().as_secs_f64() < 0.05 && evals < 100) {
        l.elements.internal_forces(x, x, &mut f, &mut scratch);
        evals += 1;
    }
    let per_eval = start.elapsed().as_secs_f64() / evals as f64;
    let _ = writeln!(
        s,
        "highest element frequency bound {:.4e} rad/s; damping ratio of that mode {:.3}",
        l.omega_max, l.z_high
    );
    let _ = writeln!(
        s,
        "one force evaluation of the elements: {:.3e} s ({:.1} M triangles/s)",
        per_eval,
        n_tri as f64 / per_eval / 1e6
    );
    if l.scene.analysis == Analysis::Static {
        let _ = writeln!(s, "static analysis: one sparse Cholesky solve");
        return s;
    }
    let e = match run_time_estimate(l) {
        Ok(e) => e,
        Err(e) => {
            let _ = writeln!(s, "no run-time estimate: {e}");
            return s;
        }
    };
    let sample = &e.sample;
    let _ = writeln!(
        s,
        "one step of {} (timed over {} steps from the start, {}): {:.3e} s",
        l.scheme,
        sample.steps,
        if sample.stages.is_empty() {
            "elements only".to_string()
        } else {
            sample
                .stages
                .iter()
                .map(|(n, t)| format!("{n} {t:.2e} s"))
                .collect::<Vec<_>>()
                .join(", ")
        },
        sample.per_step,
    );
    if let Some(r) = &e.released {
        let _ = writeln!(
            s,
            "contact with every bonded pair released ({} couples): {:.3e} s per step; joints \
             expected to soften from {:.0} % of the run on: {:.3e} s per step ({:.3} s if no \
             joint softens, {:.3} s if all were released from the start)",
            r.couples,
            r.per_step,
            100.0 * (1.0 - e.softening_part),
            e.per_step,
            e.intact,
            e.all_released
        );
    }
    if !e.why.is_empty() {
        let _ = writeln!(s, "{}", e.why);
    }
    let duration = l.scene.duration.unwrap_or(0.0);
    let safety = l.scene.integrator.safety;
    let _ = writeln!(
        s,
        "{:<20} {:>10} {:>12} {:>12} {:>10} {:>12}",
        "scheme", "h*omega", "h_limit [s]", "h used [s]", "steps", "est. time"
    );
    let own = l.scheme.cost().force_equivalents(false).max(1) as f64;
    for k in SchemeKind::ALL {
        let lim = stable_step(k, l.omega_max, l.z_high);
        let (h, n) = if k == l.scheme {
            (l.dt, e.steps as f64)
        } else {
            let h = safety * lim;
            // the same fraction of the duration as the scene's scheme (a converging
            // relaxation stops at the same time)
            (
                h,
                limits::step_count(duration, h) * e.steps as f64 / l.n_steps.max(1) as f64,
            )
        };
        let est = n * e.per_step * k.cost().force_equivalents(false) as f64 / own;
        let _ = writeln!(
            s,
            "{:<20} {:>10.4} {:>12.4e} {:>12.4e} {:>10} {:>11.3}s{}",
            k.name(),
            k.stability_limit(),
            lim,
            h,
            n.ceil(),
            est,
            if k == l.scheme { "  <- scene" } else { "" }
        );
    }
    let _ = writeln!(
        s,
        "estimated run time {:.3} s (the steps; frames and histories come on top)",
        e.seconds
    );
    s
}

/// The estimated stepping time of a run ([`run_time_estimate`]).
#[derive(Debug, Clone)]
pub struct RunTimeEstimate {
    /// The estimate [s]: `per_step * steps`.
    pub seconds: f64,
    /// Estimated wall time of one step [s].
    pub per_step: f64,
    /// Steps expected ([`expected_steps`]).
    pub steps: u64,
    /// Why `steps` differs from the scene's step count (empty when it does not).
    pub why: String,
    /// The timed steps from the start.
    pub sample: StepSample,
    /// Contact with every bonded pair released (scenes with contact and joints).
    pub released: Option<ReleasedContact>,
    /// The estimate if no joint softened over the run (the sample's step cost) [s].
    pub intact: f64,
    /// The estimate if every bonded pair were released from the start [s].
    pub all_released: f64,
    /// The part of the run after the first joint is expected to soften (0 to 1).
    pub softening_part: f64,
}

/// The part of the bonded pairs counted as released from the first softening of a joint to
/// the end of a fracturing run (time average over that part of the run; see
/// [`run_time_estimate`]). The shipped fracturing examples release 36 % (a disc split along
/// one diameter) to 76 % (a fragmenting block) of their pairs by the end.
pub const RELEASED_FRACTION: f64 = 0.4;

/// The least part of the extra cost of releasing every bonded pair that a scene with contact
/// and joints is counted for, softening or not: loaded contact (engaged couples, the active
/// frequency bound) and damaged joints cost more than at the start even where few pairs are
/// released (the split disc's contact averages a tenth of the all-released cost).
pub const RELEASED_FLOOR: f64 = 0.1;

/// The estimated stepping time of a dynamic or relaxation run, measured rather than modelled:
/// it times steps of the scene's scheme on a scratch copy of the system with its contact and
/// joint stages attached as a run attaches them (elements, loads, damping, joints, contact
/// forces and detection, the scheme's own loops), from the run's initial state. In a scene
/// with contact and joints, softening joints hand their triangle pairs to contact over the
/// run, so contact costs more later than at the start: it also times the contact stage with
/// every bonded pair released, and adds [`RELEASED_FRACTION`] of that extra cost over the part
/// of the run after the first joint softens (at least [`RELEASED_FLOOR`] of it). That time is extrapolated from the sample: the
/// largest joint utilisation `u` at its end `t_s` (normal traction over the tensile strength,
/// shear traction over the Coulomb strength) grows about in proportion to time under a
/// steady loading, so softening starts near `t_s / u`. The step cost times
/// [`expected_steps`] is the estimate. Frames and histories are not counted.
pub fn run_time_estimate(l: &Loaded) -> Result<RunTimeEstimate, SceneError> {
    let (steps, why) = expected_steps(l);
    let mut stepper = Stepper::new(l)?;
    let mut released = Released::new(l);
    // Rounds of a batch of steps then a batch of released-contact passes, so that both see
    // the same load of the machine; the median batch of each is its cost (robust to the
    // machine's other work stopping the process now and then). At least seven rounds and
    // 0.2 s (about 0.2 s of steps and 0.15 s of contact); a batch is at most an eighth of
    // the run's steps, and a short run is started again when its steps are used up.
    let rounds = 7;
    let batch_steps = stepper.left.div_ceil(8).max(2);
    let mut step_batches: Vec<(f64, Vec<f64>)> = Vec::new();
    let mut contact_batches = Vec::new();
    let mut timed = 0u64;
    let start = Instant::now();
    let mut r = 0;
    loop {
        match stepper.batch(0.2 / rounds as f64, batch_steps) {
            Some(b) => step_batches.push(b),
            // a run of at most two steps: nothing to time
            None if stepper.steps == 0 => break,
            None => {
                // a short run's steps are used up: start it again, so that the sample
                // spans the budget's wall time (and the machine's load over it)
                timed += stepper.steps;
                stepper = Stepper::new(l)?;
                continue;
            }
        }
        if let Some(c) = &mut released {
            contact_batches.push(c.batch(0.15 / rounds as f64));
        }
        r += 1;
        // a run of slow steps stops after the budget
        let el = start.elapsed().as_secs_f64();
        if (r >= rounds && el >= 0.2) || (r >= 3 && el > 0.6) || r >= 64 {
            break;
        }
    }
    timed += stepper.steps;
    step_batches.sort_by(|a, b| a.0.total_cmp(&b.0));
    contact_batches.sort_by(f64::total_cmp);
    let (per_step, stage_times) = step_batches
        .get(step_batches.len() / 2)
        .cloned()
        .unwrap_or((0.0, Vec::new()));
    let sample = StepSample {
        steps: timed,
        per_step,
        stages: stepper
            .sys
            .contributions
            .iter()
            .zip(stage_times.into_iter().chain(std::iter::repeat(0.0)))
            .map(|(c, t)| (c.name().to_string(), t))
            .collect(),
    };
    let released = released.map(|c| ReleasedContact {
        // one contact pass per force evaluation, one commit per step
        per_step: contact_batches[contact_batches.len() / 2]
            * f64::from(l.scheme.cost().forces.max(1)),
        couples: c.stage.n_couples(),
    });
    let contact_now = sample
        .stages
        .iter()
        .find(|(n, _)| n == "contact")
        .map_or(0.0, |(_, t)| *t);
    let extra = released
        .as_ref()
        .map_or(0.0, |r| (r.per_step - contact_now).max(0.0));
    // the part of the run after the first softening (0 when the sample saw no load)
    let t_s = stepper.state.t;
    let t_end = l.n_steps as f64 * l.dt;
    let after = match (&released, stepper.utilisation(l)) {
        (Some(_), Some(u)) if u > 0.0 && t_end > 0.0 => {
            let t_soft = softening_time(l, t_s, u, t_end);
            (t_end - t_soft) / t_end
        }
        _ => 0.0,
    };
    let per_step = sample.per_step + (RELEASED_FRACTION * after).max(RELEASED_FLOOR) * extra;
    Ok(RunTimeEstimate {
        seconds: per_step * steps as f64,
        per_step,
        steps,
        why,
        intact: sample.per_step * steps as f64,
        all_released: (sample.per_step + extra) * steps as f64,
        softening_part: after,
        sample,
        released,
    })
}

/// When the first joint is expected to soften, from its utilisation `u` at time `t_s`
/// (capped at `t_end`): the utilisation grows in proportion to the loading, the displacement
/// of the moving walls (`ramp_integral` of the slowest ramp) when the scene has any, else
/// time.
fn softening_time(l: &Loaded, t_s: f64, u: f64, t_end: f64) -> f64 {
    if u >= 1.0 {
        return t_s.min(t_end);
    }
    let ramp = l
        .scene
        .contact
        .as_ref()
        .map(|c| {
            c.walls
                .iter()
                .filter(|w| w.velocity != [0.0, 0.0])
                .map(|w| w.ramp)
                .fold(f64::NAN, f64::max)
        })
        .unwrap_or(f64::NAN);
    if ramp.is_nan() {
        return (t_s / u).min(t_end);
    }
    let load = |t: f64| model::ramp_integral(t, ramp);
    let target = load(t_s) / u;
    if load(t_end) <= target {
        return t_end;
    }
    // bisection: load() increases with t
    let (mut lo, mut hi) = (t_s, t_end);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if load(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// The contact stage with every bonded pair released (see [`run_time_estimate`]).
#[derive(Debug, Clone)]
pub struct ReleasedContact {
    /// Wall time of the contact stage per step [s].
    pub per_step: f64,
    /// Triangle couples.
    pub couples: usize,
}

/// A timed sample of a run's steps (see [`run_time_estimate`]).
#[derive(Debug, Clone)]
pub struct StepSample {
    /// Steps timed.
    pub steps: u64,
    /// Wall time of one step [s].
    pub per_step: f64,
    /// The stages attached (`"fracture"`, `"contact"`) and the wall time of each per step [s].
    pub stages: Vec<(String, f64)>,
}

/// Steps of the scene's scheme on a scratch copy of the system (model and elements cloned,
/// the scene's stages attached as a run attaches them but writing no files), from the run's
/// initial state at the run's step, at most the run's own step count.
struct Stepper {
    sys: SceneSystem,
    state: State,
    integ: Box<dyn fdem_time::Integrator>,
    h: f64,
    /// Steps left to time.
    left: u64,
    /// Steps timed.
    steps: u64,
}

impl Stepper {
    /// The system at the start of the run, after two untimed steps.
    fn new(l: &Loaded) -> Result<Self, SceneError> {
        let mut sys = SceneSystem::new(
            l.model.clone(),
            l.elements.clone(),
            l.scene.damping.mass_proportional,
        );
        crate::stages::attach_to(&l.scene, &l.file, &mut sys, l.dt, None, u64::MAX)?;
        let n = sys.model.n_nodes();
        let mut x0 = sys.model.x0.as_flattened().to_vec();
        let mut v0 = sys.model.v0.as_flattened().to_vec();
        for &d in sys.constrained() {
            v0[d] = 0.0;
        }
        fdem_time::SecondOrderSystem::prescribe(&mut sys, 0.0, &mut x0, &mut v0);
        let mut state = State::new(0.0, x0, v0);
        let mut integ = l.scheme.build(2 * n);
        let warm = 2.min(l.n_steps);
        for _ in 0..warm {
            integ.step(&mut sys, &mut state, l.dt);
        }
        Ok(Self {
            sys,
            state,
            integ,
            h: l.dt,
            left: l.n_steps - warm,
            steps: 0,
        })
    }

    /// The largest utilisation of the joints at the current state (`sigma / f_t` in tension,
    /// `|tau| / (c + max(-sigma, 0) tan phi)` in shear; 1 once a joint softens or breaks);
    /// `None` without joints.
    fn utilisation(&self, l: &Loaded) -> Option<f64> {
        let state = self
            .sys
            .contributions
            .iter()
            .find_map(|c| c.joint_state())?;
        let set = crate::fracture_stage::joint_set(&l.scene, &self.sys.model, &l.file).ok()??;
        let x = self.state.x_nodes();
        let frame = crate::output::JointFrame::new(&set, state, x);
        let mut u = 0.0f64;
        for j in 0..frame.len() {
            if frame.damage[j] > 0.0 || frame.broken[j] != 0 {
                return Some(1.0);
            }
            let m = &set.materials[set.material[j] as usize];
            let sigma = frame.normal_traction[j];
            let shear = m.cohesion + (-sigma).max(0.0) * m.tan_phi;
            if m.ft > 0.0 {
                u = u.max(sigma / m.ft);
            }
            if shear > 0.0 {
                u = u.max(frame.shear_traction[j].abs() / shear);
            }
        }
        Some(u)
    }

    /// A batch of at least two steps (fewer at the end of the run), for about `secs` seconds
    /// and at most `max_steps`: the wall time of one step and of each stage per step [s];
    /// `None` once the run's steps are used up.
    fn batch(&mut self, secs: f64, max_steps: u64) -> Option<(f64, Vec<f64>)> {
        if self.left == 0 {
            return None;
        }
        self.sys
            .contribution_times
            .iter_mut()
            .for_each(|t| *t = 0.0);
        let b0 = Instant::now();
        let mut k = 0u64;
        while self.left > 0 && k < max_steps && (k < 2 || b0.elapsed().as_secs_f64() < secs) {
            self.integ.step(&mut self.sys, &mut self.state, self.h);
            self.left -= 1;
            self.steps += 1;
            k += 1;
        }
        let per = |t: f64| t / k as f64;
        Some((
            per(b0.elapsed().as_secs_f64()),
            self.sys
                .contribution_times
                .iter()
                .map(|t| per(*t))
                .collect(),
        ))
    }
}

/// The contact stage with every bonded pair released, as if the scene's fracture regions
/// were broken into separate triangles from the start, at the reference positions (its first
/// pass, untimed, detects). Only for scenes with contact and joints (without joints nothing
/// is ever released).
struct Released {
    stage: crate::contact_stage::ContactStage,
    x: Vec<[f64; 2]>,
    v: Vec<[f64; 2]>,
    f: Vec<[f64; 2]>,
}

impl Released {
    fn new(l: &Loaded) -> Option<Self> {
        l.scene.fracture.as_ref()?;
        let (stage, _) =
            crate::contact_stage::ContactStage::new(&l.scene, &l.model, l.dt, None, u64::MAX)?;
        let x = l.model.x0.clone();
        let n = x.len();
        let mut r = Self {
            stage,
            x,
            v: vec![[0.0; 2]; n],
            f: vec![[0.0; 2]; n],
        };
        r.pass();
        Some(r)
    }

    fn pass(&mut self) {
        self.stage.add_forces(0.0, &self.x, &self.v, &mut self.f);
        self.stage.end_of_step(0.0, &self.x, &self.v);
    }

    /// The wall time of one force pass and commit, over a batch of about `secs` seconds [s].
    fn batch(&mut self, secs: f64) -> f64 {
        let b0 = Instant::now();
        let mut k = 0u32;
        while k < 1 || (b0.elapsed().as_secs_f64() < secs && k < 200) {
            self.pass();
            k += 1;
        }
        b0.elapsed().as_secs_f64() / f64::from(k)
    }
}

/// The number of steps a run is expected to take, and a line saying why when it is not the
/// scene's step count. A relaxation stops when the relative residual reaches
/// `relaxation_tolerance`: with mass-proportional damping `alpha` no mode decays faster than
/// `exp(-alpha t / 2)` (the rate of an underdamped mode; an overdamped one is slower), so the
/// residual falls by `tol` no sooner than `t = 2 ln(1/tol) / alpha`, the expected time (a
/// lower bound, the answer when the lowest mode is underdamped); the duration caps it.
pub fn expected_steps(l: &Loaded) -> (u64, String) {
    let alpha = l.scene.damping.mass_proportional;
    let tol = l.scene.integrator.relaxation_tolerance;
    if l.scene.analysis == Analysis::Relaxation
        && alpha > 0.0
        && tol > 0.0
        && tol < 1.0
        && l.dt > 0.0
    {
        let t = 2.0 * (1.0 / tol).ln() / alpha;
        let steps = ((t / l.dt).ceil() as u64).clamp(1, l.n_steps.max(1));
        if steps < l.n_steps {
            return (
                steps,
                format!(
                    "relaxation: the residual reaches {tol:e} after about t = 2 ln(1/tol) / alpha = {t:.3e} s ({steps} of at most {} steps)",
                    l.n_steps
                ),
            );
        }
    }
    (l.n_steps, String::new())
}

/// Options of a run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Output folder (created).
    pub out_dir: PathBuf,
    /// Also write each frame's arrays as JSON (`frame_NNNN.json`).
    pub raw: bool,
}

/// Progress of a run, passed to the caller's callback.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    /// Steps done.
    pub step: u64,
    /// Steps planned.
    pub steps: u64,
    /// Simulated time [s].
    pub time: f64,
}

impl Progress {
    /// Fraction done, 0 to 1.
    pub fn fraction(&self) -> f64 {
        if self.steps == 0 {
            1.0
        } else {
            self.step as f64 / self.steps as f64
        }
    }
}

/// The run summary (also written as `summary.json`).
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// The scene file.
    pub scene: String,
    /// Analysis kind.
    pub analysis: String,
    /// Scheme name.
    pub scheme: String,
    /// Nodes.
    pub nodes: usize,
    /// Triangles.
    pub triangles: usize,
    /// Time step [s].
    pub time_step: f64,
    /// Stable limit [s].
    pub time_step_limit: f64,
    /// Steps done.
    pub steps: u64,
    /// Force evaluations.
    pub force_evaluations: u64,
    /// Simulated time [s].
    pub simulated_time: f64,
    /// Wall time of the whole run [s].
    pub wall_time: f64,
    /// Triangles times steps per second of stepping wall time.
    pub element_steps_per_second: f64,
    /// Per-stage wall times [s].
    pub timers: StageTimers,
    /// The energy ledger at the end (`crate::ledger`).
    pub energy: Energies,
    /// Frames written.
    pub frames: usize,
    /// Relaxation: whether the residual tolerance was reached.
    pub converged: Option<bool>,
    /// Relaxation: final |residual| / |load|.
    pub relative_residual: Option<f64>,
    /// Largest displacement magnitude at the end [m].
    pub max_displacement: f64,
    /// Threads used.
    pub threads: usize,
    /// Details of the optional stages (contact, joints), by name.
    pub stages: serde_json::Value,
    /// An `"adaptive"` step: the smallest and the largest step taken [s].
    pub time_step_range: Option<[f64; 2]>,
}

impl Summary {
    /// A few lines for the terminal.
    pub fn describe(&self) -> String {
        let mut s = if self.analysis == "static" {
            format!(
                "static solve (sparse Cholesky, {} DOFs) in {:.3} s, {:.2} s wall\n",
                2 * self.nodes,
                self.timers.internal_forces,
                self.wall_time
            )
        } else {
            format!(
                "{} steps of {:.4e} s ({}), {} force evaluations, {:.2} s wall, {:.3e} element-steps/s\n",
                self.steps,
                self.time_step,
                self.scheme,
                self.force_evaluations,
                self.wall_time,
                self.element_steps_per_second
            )
        };
        let t = &self.timers;
        let _ = writeln!(
            s,
            "time: internal forces {:.3} s, loads {:.3} s, damping {:.3} s, contributions {:.3} s, integration {:.3} s, histories {:.3} s, output {:.3} s",
            t.internal_forces,
            t.external_loads,
            t.mass_damping,
            t.contributions,
            t.integration,
            t.histories,
            t.output
        );
        let _ = write!(
            s,
            "{}\nmax |u| {:.4e} m",
            self.energy.describe(),
            self.max_displacement
        );
        if let (Some(c), Some(r)) = (self.converged, self.relative_residual) {
            let _ = write!(s, "\nrelaxation converged: {c} (relative residual {r:.3e})");
        }
        s
    }
}

/// The state of a finished run, for tests and callers that want the numbers.
pub struct Outcome {
    /// The summary.
    pub summary: Summary,
    /// The last frame's data.
    pub last_frame: FrameData,
    /// The joints' committed history at the end (scenes with joints): a later run starts
    /// from it through `scene.fracture.initial_state`.
    pub joint_state: Option<fdem_fracture::JointState>,
}

/// Runs a loaded scene, writing output under `options.out_dir`.
pub fn run(
    l: &mut Loaded,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Summary, RunError> {
    run_outcome(l, options, progress).map(|o| o.summary)
}

/// Output files of a run.
struct Writer {
    dir: PathBuf,
    pvd: Collection,
    raw: bool,
    level: u32,
    frames: usize,
    joints: JointSeries,
}

impl Writer {
    /// Claims the output folder: creates it, and removes the files of an earlier run
    /// (`output::folder`) so that none is mistaken for this run's.
    fn new(options: &RunOptions, level: u32) -> Result<Self, RunError> {
        crate::output::folder::claim(&options.out_dir).map_err(|e| RunError::Output {
            file: options.out_dir.clone(),
            message: format!("cannot prepare the output folder: {e}"),
        })?;
        Ok(Self {
            dir: options.out_dir.clone(),
            pvd: Collection::new(&options.out_dir.join("results.pvd")),
            raw: options.raw,
            level,
            frames: 0,
            joints: JointSeries::default(),
        })
    }

    fn frame(&mut self, data: &FrameData) -> Result<(), RunError> {
        let check_finite = data
            .points
            .iter()
            .chain(&data.velocity)
            .chain(&data.force)
            .all(|p| p[0].is_finite() && p[1].is_finite())
            && data.stress.iter().flatten().all(|s| s.is_finite())
            && data.energy_density.iter().all(|e| e.is_finite());
        if !check_finite {
            return Err(RunError::Unstable {
                step: 0,
                time: data.time,
                message: "non-finite positions, velocities, forces or stresses in an output frame (not written)\n  fix: lower the time step (`integrator.safety`), and check the materials (young, density) and the loads".into(),
            });
        }
        let name = format!("frame_{:04}.vtu", self.frames);
        let out = |file: PathBuf, e: String| RunError::Output { file, message: e };
        let bytes = vtu::encode(data, self.level).map_err(|e| out(self.dir.join(&name), e))?;
        write_atomic(&self.dir.join(&name), &bytes)
            .map_err(|e| out(self.dir.join(&name), e.to_string()))?;
        self.joints
            .write(&self.dir, self.frames, data, self.level)
            .map_err(|(file, e)| out(file, e))?;
        if self.raw {
            let raw = format!("frame_{:04}.json", self.frames);
            let text =
                serde_json::to_vec(data).map_err(|e| out(self.dir.join(&raw), e.to_string()))?;
            write_atomic(&self.dir.join(&raw), &text)
                .map_err(|e| out(self.dir.join(&raw), e.to_string()))?;
        }
        self.pvd
            .push(data.time, &name)
            .map_err(|e| out(self.dir.join("results.pvd"), e.to_string()))?;
        self.frames += 1;
        Ok(())
    }

    fn summary(&self, s: &Summary) -> Result<(), RunError> {
        let p = self.dir.join("summary.json");
        let text = serde_json::to_vec_pretty(s).map_err(|e| RunError::Output {
            file: p.clone(),
            message: e.to_string(),
        })?;
        write_atomic(&p, &text).map_err(|e| RunError::Output {
            file: p,
            message: e.to_string(),
        })
    }
}

/// Builds a frame from positions, velocities, forces and reactions.
pub fn make_frame(
    model: &Model,
    elements: &Elements,
    t: f64,
    x: &[[f64; 2]],
    v: &[[f64; 2]],
    force: &[[f64; 2]],
    reaction: &[[f64; 2]],
) -> FrameData {
    let mut stresses = vec![fdem_mesh::stress::Stress::default(); elements.len()];
    elements.stresses(x, v, &mut stresses);
    let stress: Vec<[f64; 4]> = stresses.iter().map(|s| [s.xx, s.yy, s.xy, s.zz]).collect();
    let energy_density = (0..elements.len())
        .into_par_iter()
        .with_min_len(1024)
        .map(|e| {
            let td = &elements.tris[e];
            let th = 2.0 * elements.materials[td.material as usize].half_t;
            elements.element_energy(TriId(e as u32), x) / (td.area0 * th)
        })
        .collect();
    frame_from_parts(model, t, x, v, force, reaction, stress, energy_density)
}

/// Assembles a frame from node arrays and per-triangle stresses and energy densities.
pub fn frame_from_parts(
    model: &Model,
    t: f64,
    x: &[[f64; 2]],
    v: &[[f64; 2]],
    force: &[[f64; 2]],
    reaction: &[[f64; 2]],
    stress: Vec<[f64; 4]>,
    energy_density: Vec<f64>,
) -> FrameData {
    FrameData {
        time: t,
        points: x.to_vec(),
        triangles: model.triangles.clone(),
        displacement: x
            .iter()
            .zip(&model.x0)
            .map(|(a, b)| [a[0] - b[0], a[1] - b[1]])
            .collect(),
        velocity: v.to_vec(),
        force: force.to_vec(),
        reaction: reaction.to_vec(),
        principal: stress
            .iter()
            .map(|s| frame::principal(s[0], s[1], s[2]))
            .collect(),
        von_mises: stress.iter().map(|s| frame::von_mises(*s)).collect(),
        stress,
        energy_density,
        material: model.tri_material.iter().map(|&m| m as i32).collect(),
        body: model.tri_body.iter().map(|&b| b as i32).collect(),
        extra_point_vectors: Vec::new(),
        extra_cell_scalars: Vec::new(),
        joints: None,
    }
}

/// History columns and their evaluation.
struct Histories {
    writer: HistoryWriter,
    every: u64,
    groups: Vec<Vec<u32>>,
    /// Whether an energy probe is recorded (then the ledger is computed at each record).
    energy: bool,
}

impl Histories {
    fn new(l: &Loaded, model: &Model, dir: &Path) -> Option<Self> {
        let probes = &l.scene.histories.probes;
        if probes.is_empty() {
            return None;
        }
        let mut cols = vec!["time".to_string()];
        let mut groups = Vec::new();
        for (i, p) in probes.iter().enumerate() {
            match p {
                Probe::Displacement(g) | Probe::Velocity(g) | Probe::Reaction(g) => {
                    let kind = match p {
                        Probe::Displacement(_) => "u",
                        Probe::Velocity(_) => "v",
                        _ => "reaction",
                    };
                    // the body the resolver found (`v_x[body/group]` when another body has a
                    // group of that name)
                    let body = model.probe_body.get(i).copied().flatten().unwrap_or(0);
                    let label = model.group_label(&l.scene, body, &g.group);
                    cols.push(format!("{kind}_x[{label}]"));
                    cols.push(format!("{kind}_y[{label}]"));
                    let nodes = model
                        .group_nodes(body, &g.group)
                        .map(<[u32]>::to_vec)
                        .unwrap_or_default();
                    groups.push(nodes);
                }
                Probe::Energy => {
                    // the ledger's terms, named as in summary.json and the console
                    cols.extend(Energies::column_names().map(String::from));
                    groups.push(Vec::new());
                }
            }
        }
        let every = l
            .scene
            .histories
            .every
            .map(|e| e as u64)
            .unwrap_or((l.n_steps / 1000).max(1));
        Some(Self {
            writer: HistoryWriter::new(&dir.join("histories.csv"), &cols),
            every,
            groups,
            energy: probes.iter().any(|p| matches!(p, Probe::Energy)),
        })
    }

    fn record(
        &mut self,
        l: &Loaded,
        x0: &[[f64; 2]],
        t: f64,
        x: &[[f64; 2]],
        v: &[[f64; 2]],
        reaction: &[[f64; 2]],
        energy: &Energies,
    ) {
        let mut row = vec![t];
        for (p, nodes) in l.scene.histories.probes.iter().zip(&self.groups) {
            match p {
                Probe::Displacement(_) => {
                    let k = nodes.len().max(1) as f64;
                    let (mut ux, mut uy) = (0.0, 0.0);
                    for &n in nodes {
                        ux += x[n as usize][0] - x0[n as usize][0];
                        uy += x[n as usize][1] - x0[n as usize][1];
                    }
                    row.extend([ux / k, uy / k]);
                }
                Probe::Velocity(_) => {
                    let k = nodes.len().max(1) as f64;
                    let (mut vx, mut vy) = (0.0, 0.0);
                    for &n in nodes {
                        vx += v[n as usize][0];
                        vy += v[n as usize][1];
                    }
                    row.extend([vx / k, vy / k]);
                }
                Probe::Reaction(_) => {
                    let (mut rx, mut ry) = (0.0, 0.0);
                    for &n in nodes {
                        rx += reaction[n as usize][0];
                        ry += reaction[n as usize][1];
                    }
                    row.extend([rx, ry]);
                }
                Probe::Energy => row.extend(energy.columns().map(|(_, v)| v)),
            }
        }
        self.writer.push(&row);
    }
}

/// Runs a loaded scene and returns the summary with the last frame.
pub fn run_outcome(
    l: &mut Loaded,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Outcome, RunError> {
    let wall = Instant::now();
    if l.scene.analysis == Analysis::Static {
        // Solved (and checked: a singular stiffness is bad input) before the folder is touched.
        let (frame, mut summary) = static_solve::solve(l)?;
        // the static terms as a ledger (gravity's work `1/2 sum m g . u` taken apart)
        let gravity = l.model.gravity.map_or(0.0, |g| {
            0.5 * l
                .model
                .mass
                .iter()
                .zip(&frame.displacement)
                .map(|(m, u)| m * (g[0] * u[0] + g[1] * u[1]))
                .sum::<f64>()
        });
        summary.energy = Energies::from_static(&summary.energy, gravity);
        let mut writer = Writer::new(options, l.scene.output.compression)?;
        let s = Instant::now();
        if l.scene.output.frames > 0 {
            writer.frame(&frame)?;
        }
        summary.timers.output = s.elapsed().as_secs_f64();
        summary.frames = writer.frames;
        summary.wall_time = wall.elapsed().as_secs_f64();
        let mut h = Histories::new(l, &l.model, &options.out_dir);
        if let Some(h) = &mut h {
            let x: Vec<[f64; 2]> = frame.points.clone();
            h.record(
                l,
                &l.model.x0,
                0.0,
                &x,
                &frame.velocity,
                &frame.reaction,
                &summary.energy,
            );
            h.writer.flush().map_err(|e| RunError::Output {
                file: options.out_dir.join("histories.csv"),
                message: e.to_string(),
            })?;
        }
        writer.summary(&summary)?;
        progress(&Progress {
            step: 1,
            steps: 1,
            time: 0.0,
        });
        return Ok(Outcome {
            summary,
            last_frame: frame,
            joint_state: None,
        });
    }
    // the stages' own input, checked before the folder is claimed
    crate::fracture_stage::check_initial_state(&l.scene, &l.file)?;
    let writer = Writer::new(options, l.scene.output.compression)?;
    dynamic(l, options, progress, writer, wall)
}

/// A dynamic run. The model and elements are moved out of `l` into the run's system (no
/// copy: the run only reads them) and put back when it ends, on the error paths too, with
/// the scene's own contributions; the contact and fracture stages attached for the run are
/// dropped (a second run attaches fresh stages). Only a panic inside the run leaves `l`
/// without its model.
fn dynamic(
    l: &mut Loaded,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
    writer: Writer,
    wall: Instant,
) -> Result<Outcome, RunError> {
    let alpha = l.scene.damping.mass_proportional;
    let model = std::mem::take(&mut l.model);
    let elements = std::mem::take(&mut l.elements);
    let mut sys = SceneSystem::new(model, elements, alpha);
    sys.contributions = std::mem::take(&mut l.contributions);
    let n_own = sys.contributions.len();
    let outcome = dynamic_run(l, &mut sys, options, progress, writer, wall);
    sys.contributions.truncate(n_own);
    l.contributions = std::mem::take(&mut sys.contributions);
    l.model = std::mem::take(&mut sys.model);
    l.elements = std::mem::take(&mut sys.elements);
    outcome
}

/// The body of [`dynamic`], on the system `sys` that holds the model and elements of `l`.
fn dynamic_run(
    l: &Loaded,
    sys: &mut SceneSystem,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
    mut writer: Writer,
    wall: Instant,
) -> Result<Outcome, RunError> {
    let relaxation = l.scene.analysis == Analysis::Relaxation;
    let every = l
        .scene
        .histories
        .every
        .unwrap_or((l.n_steps / 1000).max(1) as usize) as u64;
    crate::stages::attach(&l.scene, &l.file, &mut *sys, l.dt, &options.out_dir, every)?;
    let n = sys.model.n_nodes();
    let mut x0 = sys.model.x0.as_flattened().to_vec();
    let mut v0 = sys.model.v0.as_flattened().to_vec();
    for &d in sys.constrained() {
        v0[d] = 0.0;
    }
    fdem_time::SecondOrderSystem::prescribe(&mut *sys, 0.0, &mut x0, &mut v0);
    let mut state = State::new(0.0, x0, v0);
    let mut integ = l.scheme.build(2 * n);
    let mut h = l.dt;
    let n_steps = l.n_steps;
    // Adaptive step (central difference): every `adapt_every` steps the step becomes
    // `safety x 2 / omega` with `omega` the active bound (`stages::omega_active_ahead`: the
    // contact engaged now, or engaged at the positions extrapolated over twice the interval
    // to the next recomputation, with the elements and the joints).
    let adaptive = l.scene.integrator.time_step == TimeStep::Adaptive;
    let t_end = l.scene.duration.unwrap_or(0.0);
    let adapt_every = l.scene.integrator.adapt_every.max(1);
    let (omega_el, omega_j) = if adaptive {
        (
            sys.elements.max_frequency_bound(&sys.model.x0),
            crate::stages::omega_joints(&l.scene, &sys.model, &l.file).unwrap_or(0.0),
        )
    } else {
        (0.0, 0.0)
    };
    let mut h_limit = l.dt_limit;
    let mut look_ahead = Vec::new();
    let mut h_min = f64::INFINITY;
    let mut h_max = 0.0f64;
    let frames = l.scene.output.frames;
    let mut next_frame = 0usize;
    let mut hist = Histories::new(l, &sys.model, &options.out_dir);

    let mut acc = vec![0.0; 2 * n];
    // The residuals of the element law and the contact potential are booked when the run
    // records the ledger in histories.csv (they cost about a tenth of the step).
    let book_residuals = l
        .scene
        .histories
        .probes
        .iter()
        .any(|p| matches!(p, Probe::Energy));
    Books::prepare(&mut *sys, book_residuals);
    fdem_time::SecondOrderSystem::acceleration(&mut *sys, 0.0, &state.x, &state.v, &mut acc);
    // The energy ledger's running books (crate::ledger), from the force at t = 0.
    let mut books = Books::new(
        &mut *sys,
        &state,
        l.scene.damping.mass_proportional,
        book_residuals,
    );

    let emit =
        |sys: &mut SceneSystem, state: &State, writer: &mut Writer| -> Result<(), RunError> {
            let s = Instant::now();
            let saved = sys.timers;
            let mut a = vec![0.0; state.x.len()];
            fdem_time::SecondOrderSystem::acceleration(sys, state.t, &state.x, &state.v, &mut a);
            sys.timers = saved;
            let reaction = sys.reactions();
            let mut fr = make_frame(
                &sys.model,
                &sys.elements,
                state.t,
                state.x_nodes(),
                state.v_nodes(),
                &sys.force,
                &reaction,
            );
            for c in &sys.contributions {
                c.frame_fields(state.x_nodes(), &mut fr);
            }
            writer.frame(&fr)?;
            sys.timers.output += s.elapsed().as_secs_f64();
            Ok(())
        };

    if frames > 0 {
        emit(&mut *sys, &state, &mut writer)?;
        next_frame = 1;
    }
    let load_norm = {
        let mut f = vec![0.0; 2 * n];
        sys.model.add_external(f64::INFINITY, &mut f);
        f.iter().map(|v| v * v).sum::<f64>().sqrt()
    };
    let mut converged = None;
    let mut rel_res = None;
    let mut step_time = 0.0;
    let mut last_progress = Instant::now();
    let check_every = 100u64;
    // Energy-growth check (every `check_every` steps): the mechanical energy
    // `E = K + U + stored (contact, joints)` may not exceed the energy supplied
    // `S = E_0 + |W_loads + W_gravity| + |W_supports| + |W_walls| + K_prescribed`
    // (damping, friction and fracture only remove energy). `E` above that by more than the
    // bound of `energy_growth` while growing is an unstable mode, reported long before it
    // overflows.
    let mut e_prev_check = books.initial();
    // Triangles turned inside out, looked for at the same checks: the cause of an instability.
    let mut inversions = InversionWatch::default();
    let mut steps_done = 0u64;
    let mut step = 0u64;
    loop {
        if !adaptive && step >= n_steps {
            break;
        }
        step += 1;
        if adaptive && (step - 1).is_multiple_of(adapt_every) {
            let ahead = 2.0 * adapt_every as f64 * h;
            let w = crate::stages::omega_active_ahead(
                &mut *sys,
                state.x_nodes(),
                state.v_nodes(),
                ahead,
                omega_el,
                omega_j,
                &mut look_ahead,
            );
            h_limit = stable_step(l.scheme, w, l.z_high);
            h = l.scene.integrator.safety * h_limit;
            for c in &mut sys.contributions {
                c.set_time_step(h);
            }
        }
        let h_step = if adaptive {
            h.min(t_end - state.t).max(f64::MIN_POSITIVE)
        } else {
            h
        };
        let s = Instant::now();
        integ.step(&mut *sys, &mut state, h_step);
        step_time += s.elapsed().as_secs_f64();
        steps_done = step;
        if adaptive {
            h_min = h_min.min(h_step);
            h_max = h_max.max(h_step);
        }
        // the last step: the step count, or (adaptive) the end time reached
        let last = if adaptive {
            state.t >= t_end * (1.0 - 1e-12)
        } else {
            step >= n_steps
        };
        // Works and dissipations of this step.
        books.step(&mut *sys, &state);
        if step.is_multiple_of(check_every) || last {
            inversions.scan(&sys.model, state.x_nodes(), step, state.t);
            let unstable = |sys: &SceneSystem, watch: &InversionWatch, found| {
                diagnosis::unstable(&l.scene, &sys.model, watch, step, state.t, found)
            };
            if let Some(message) = crate::stages::first_error(sys) {
                let _ = writer.summary(&partial_summary(
                    l, sys, steps_done, &state, wall, step_time, &writer, &books,
                ));
                return Err(unstable(sys, &inversions, Found::Stage(message)));
            }
            if !state.x.iter().all(|v| v.is_finite()) || !state.v.iter().all(|v| v.is_finite()) {
                let _ = writer.summary(&partial_summary(
                    l, sys, steps_done, &state, wall, step_time, &writer, &books,
                ));
                return Err(unstable(sys, &inversions, Found::NonFinite));
            }
            let (stored, walls) =
                stage_report(sys, state.x_nodes()).map_or((0.0, 0.0), |r| (r.stored, r.wall_work));
            let e_now = kinetic_energy(&books.mass_dof, &state.v)
                + sys.elements.strain_energy(state.x_nodes())
                + stored;
            let supplied = books.supplied_bound(&sys.model, &state, walls);
            if let Some(message) = energy_growth(
                e_now,
                e_prev_check,
                supplied,
                l.scheme,
                h_step,
                h_limit,
                step.saturating_sub(check_every),
            ) {
                let _ = writer.summary(&partial_summary(
                    l, sys, steps_done, &state, wall, step_time, &writer, &books,
                ));
                return Err(unstable(sys, &inversions, Found::EnergyGrowth(message)));
            }
            e_prev_check = e_now;
            if relaxation {
                let f = sys.force.as_flattened();
                let mut r2 = 0.0;
                for d in 0..2 * n {
                    if !sys.model.constrained[d] {
                        r2 += f[d] * f[d];
                    }
                }
                // Scale: applied loads, or the reactions when the loading is by supports.
                let reac: f64 = sys
                    .constrained()
                    .iter()
                    .map(|&d| f[d] * f[d])
                    .sum::<f64>()
                    .sqrt();
                let scale = load_norm.max(reac).max(f64::MIN_POSITIVE);
                let r = r2.sqrt() / scale;
                rel_res = Some(r);
                if r <= l.scene.integrator.relaxation_tolerance {
                    converged = Some(true);
                }
            }
        }
        if let Some(hh) = &mut hist
            && (step.is_multiple_of(hh.every) || last || converged == Some(true))
        {
            let s = Instant::now();
            let reaction = sys.reactions();
            let e = if hh.energy {
                let r = stage_report(sys, state.x_nodes());
                books.ledger(sys, &state, r.as_ref())
            } else {
                Energies::default()
            };
            hh.record(
                l,
                &sys.model.x0,
                state.t,
                state.x_nodes(),
                state.v_nodes(),
                &reaction,
                &e,
            );
            sys.timers.histories += s.elapsed().as_secs_f64();
        }
        let frame_due = frames > 0
            && if adaptive {
                state.t >= (next_frame as f64) * t_end / (frames as f64) * (1.0 - 1e-12)
            } else {
                let tf = (next_frame as f64) * (n_steps as f64) / (frames as f64);
                (step as f64) >= tf.round()
            };
        if frame_due || (frames > 0 && (last || converged == Some(true)) && next_frame <= frames) {
            if let Err(e) = emit(&mut *sys, &state, &mut writer) {
                // a frame with non-finite values: the same diagnosis as at the checks
                return Err(match e {
                    RunError::Unstable { .. } => {
                        let _ = writer.summary(&partial_summary(
                            l, sys, steps_done, &state, wall, step_time, &writer, &books,
                        ));
                        diagnosis::unstable(
                            &l.scene,
                            &sys.model,
                            &inversions,
                            step,
                            state.t,
                            Found::Frame,
                        )
                    }
                    e => e,
                });
            }
            next_frame += 1;
            if let Some(hh) = &hist {
                let _ = hh.writer.flush();
            }
        }
        if last_progress.elapsed().as_secs_f64() > 0.2 || last {
            last_progress = Instant::now();
            progress(&Progress {
                step,
                steps: if adaptive {
                    // estimate from the time reached
                    ((step as f64) * t_end / state.t.max(f64::MIN_POSITIVE)).ceil() as u64
                } else {
                    n_steps
                },
                time: state.t,
            });
        }
        if converged == Some(true) || last {
            break;
        }
    }
    if relaxation && converged.is_none() {
        converged = Some(false);
    }
    let (stage_report, stage_details) = crate::stages::reports(sys, state.x_nodes());
    for c in &mut sys.contributions {
        c.finish();
    }
    if let Some(hh) = &hist {
        hh.writer.flush().map_err(|e| RunError::Output {
            file: options.out_dir.join("histories.csv"),
            message: e.to_string(),
        })?;
    }
    let mut summary = partial_summary(l, sys, steps_done, &state, wall, step_time, &writer, &books);
    summary.energy = books.ledger(sys, &state, Some(&stage_report));
    summary.converged = converged;
    summary.relative_residual = rel_res;
    summary.force_evaluations = integ.counters().forces;
    summary.stages = stage_details;
    if adaptive {
        summary.time_step_range = Some([h_min, h_max]);
    }
    writer.summary(&summary)?;
    let reaction = sys.reactions();
    let mut last_frame = make_frame(
        &sys.model,
        &sys.elements,
        state.t,
        state.x_nodes(),
        state.v_nodes(),
        &sys.force,
        &reaction,
    );
    for c in &sys.contributions {
        c.frame_fields(state.x_nodes(), &mut last_frame);
    }
    let joint_state = sys
        .contributions
        .iter()
        .find_map(|c| c.joint_state().cloned());
    Ok(Outcome {
        summary,
        last_frame,
        joint_state,
    })
}

/// Margin of the energy-growth check: the mechanical energy may exceed the energy supplied by
/// this factor over the step-synchronisation factor `1 / (1 - (h / h_limit)^2)` (see
/// [`energy_growth`]) before a run is called unstable.
pub const ENERGY_GROWTH_BOUND: f64 = 2.0;

/// The driver's energy-growth check: `Some(message)` when the mechanical energy `e_now`
/// exceeds `ENERGY_GROWTH_BOUND / (1 - min(h / h_limit, 0.995)^2)` times the energy
/// `supplied` and has grown since the last check (`e_prev`, at step `prev_step`), or is not
/// finite. The message names the scheme, the step used and the predicted stable limit.
///
/// Why the factor `1 / (1 - (h / h_limit)^2)`: `K + U` taken at the steps is not what a
/// scheme conserves. For central difference on a mode of frequency `omega` the conserved
/// quantity is `K + U (1 - (h omega / 2)^2)`, so a legitimate `K + U` reaches up to
/// `1 / (1 - (h omega / 2)^2)` times the energy, 50 at `h omega = 1.98`; with
/// `h / h_limit = h omega_max / 2` (`omega_max` an upper bound of every mode's frequency) the
/// factor bounds every mode. The same form is used for every scheme (their step-synchronised
/// energies degenerate the same way at their limits); at 0.9 of the limit it is 5.3, at 0.5
/// it is 1.33.
pub fn energy_growth(
    e_now: f64,
    e_prev: f64,
    supplied: f64,
    scheme: SchemeKind,
    h: f64,
    h_limit: f64,
    prev_step: u64,
) -> Option<String> {
    let r = (h / h_limit).min(0.995);
    let bound = ENERGY_GROWTH_BOUND / (1.0 - r * r);
    let bad = !e_now.is_finite() || (e_now > bound * supplied && e_now > e_prev);
    bad.then(|| {
        format!(
            "energy growth: kinetic + strain (+ contact/joint) energy {e_now:.3e} J is {:.3e} times the energy supplied (more than the allowed {bound:.3}; {supplied:.3e} J: initial energy and work of loads, gravity, supports and walls) and grew {:.3e}-fold since step {prev_step}; {scheme} with h = {h:.4e} s is past its stable step on this scene (predicted limit {h_limit:.4e} s, h / limit = {:.3})",
            e_now / supplied.max(f64::MIN_POSITIVE),
            e_now / e_prev.max(f64::MIN_POSITIVE),
            h / h_limit
        )
    })
}

/// The stages' summed report at positions `x` (`None` without stages).
fn stage_report(sys: &SceneSystem, x: &[[f64; 2]]) -> Option<crate::system::StageReport> {
    (!sys.contributions.is_empty()).then(|| crate::stages::reports(sys, x).0)
}

fn partial_summary(
    l: &Loaded,
    sys: &SceneSystem,
    steps: u64,
    state: &State,
    wall: Instant,
    step_time: f64,
    writer: &Writer,
    books: &Books,
) -> Summary {
    let mut timers = sys.timers;
    timers.integration = (step_time
        - timers.internal_forces
        - timers.external_loads
        - timers.mass_damping
        - timers.contributions)
        .max(0.0);
    let max_u = state
        .x_nodes()
        .iter()
        .zip(&sys.model.x0)
        .map(|(a, b)| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt())
        .fold(0.0, f64::max);
    Summary {
        scene: l.file.display().to_string(),
        analysis: format!("{:?}", l.scene.analysis).to_lowercase(),
        scheme: l.scheme.name().into(),
        nodes: sys.model.n_nodes(),
        triangles: sys.elements.len(),
        time_step: l.dt,
        time_step_limit: l.dt_limit,
        steps,
        force_evaluations: sys.evaluations,
        simulated_time: state.t,
        wall_time: wall.elapsed().as_secs_f64(),
        element_steps_per_second: if step_time > 0.0 {
            sys.elements.len() as f64 * steps as f64 / step_time
        } else {
            0.0
        },
        timers,
        energy: books.ledger(sys, state, stage_report(sys, state.x_nodes()).as_ref()),
        frames: writer.frames,
        converged: None,
        relative_residual: None,
        max_displacement: max_u,
        threads: rayon::current_num_threads(),
        stages: serde_json::Value::Null,
        time_step_range: None,
    }
}
