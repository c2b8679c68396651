//! `fdem check`'s report ([`check_report`]): the stable step of every scheme and the
//! estimated run time of the scene ([`run_time_estimate`], [`expected_steps`]), measured on a
//! scratch copy of the run's system.

use std::fmt::Write as _;
use std::time::Instant;

use fdem_time::{SchemeKind, State};

use crate::checkpoint::pack::Enc;
use crate::error::SceneError;
use crate::input::scene::{Analysis, RelaxationMethod};
use crate::problem::load::Problem;
use crate::problem::model;
use crate::problem::stable_step::{stable_step, step_count};
use crate::stages::system::{ForceTerm, SceneSystem, StepEvents};

/// `fdem check`'s report: the stable step of every scheme and the estimated run time
/// ([`run_time_estimate`]); another scheme's row scales the scene scheme's step cost by its
/// force evaluations per step.
pub fn check_report(l: &Problem) -> String {
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
        l.omega_max(),
        l.z_high
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
    if let Some(line) = crate::stages::fluid::check_line(l) {
        let _ = writeln!(s, "{line}");
    }
    scheme_table(&mut s, l, &e);
    let _ = writeln!(
        s,
        "estimated run time {:.3} s (the steps; frames and histories come on top)",
        e.seconds
    );
    let c = &e.checkpoint;
    let _ = writeln!(
        s,
        "a checkpoint: {:.2} MB ({:.0} bytes per triangle); the run waits {:.3} s to encode it, then it is written on a thread of its own ({:.3} s with fsync in {}); at the default interval (10 min) the run waits {:.4} % of its time",
        c.bytes as f64 / 1e6,
        c.bytes as f64 / n_tri as f64,
        c.encode,
        c.write,
        std::env::temp_dir().display(),
        100.0 * c.encode / 600.0
    );
    s
}

/// `fdem check`'s table of every scheme: its `h omega` limit, stable step, step used, steps
/// and estimated time, the scene's scheme from the timed sample `e`.
fn scheme_table(s: &mut String, l: &Problem, e: &RunTimeEstimate) {
    let duration = l.scene.duration.unwrap_or(0.0);
    let safety = l.scene.integrator.safety;
    let _ = writeln!(
        s,
        "{:<20} {:>10} {:>12} {:>12} {:>10} {:>12}",
        "scheme", "h*omega", "h_limit [s]", "h used [s]", "steps", "est. time"
    );
    let own = l.scheme.cost().force_equivalents(false).max(1) as f64;
    for k in SchemeKind::ALL {
        let lim = stable_step(k, l.omega_max(), l.z_high);
        let (h, n) = if k == l.scheme {
            (l.dt, e.steps as f64)
        } else {
            let h = safety * lim;
            // the same fraction of the duration as the scene's scheme (a converging
            // relaxation stops at the same time)
            (
                h,
                step_count(duration, h) * e.steps as f64 / l.n_steps.max(1) as f64,
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
    /// One checkpoint of the run, encoded and written at the end of the sample.
    pub checkpoint: CheckpointCost,
}

/// The size and cost of one checkpoint of a run ([`run_time_estimate`]).
#[derive(Debug, Clone, Default)]
pub struct CheckpointCost {
    /// Its size [bytes] (the rows of the histories and the frames' list, which grow over the
    /// run, not counted).
    pub bytes: u64,
    /// Wall time of the encoding, the part a run waits for [s].
    pub encode: f64,
    /// Wall time of the write (file, fsync, rename) in the temporary folder, done on a
    /// thread of its own while a run goes on [s]; 0 when it could not be written.
    pub write: f64,
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
pub fn run_time_estimate(l: &Problem) -> Result<RunTimeEstimate, SceneError> {
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
    let checkpoint = stepper.checkpoint_cost(l);
    Ok(RunTimeEstimate {
        checkpoint,
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
/// of the moving walls (`ramp_integral` of the slowest ramp) when the scene has any and none
/// has a time history, else time.
fn softening_time(l: &Problem, t_s: f64, u: f64, t_end: f64) -> f64 {
    if u >= 1.0 {
        return t_s.min(t_end);
    }
    let ramp = l
        .scene
        .contact
        .as_ref()
        .filter(|c| c.walls.iter().all(|w| w.history.is_none()))
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
    fn new(l: &Problem) -> Result<Self, SceneError> {
        let mut sys = SceneSystem::new(
            l.model.clone(),
            l.elements.clone(),
            l.scene.damping.mass_proportional,
        );
        crate::stages::attach_to(l, &mut sys, l.dt, None, u64::MAX, false)?;
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

    /// The size and cost of a checkpoint of the system now: the state, the scheme's state,
    /// the system, the stages and the energy books, encoded as a run encodes them, and
    /// written (with fsync) to a temporary file that is then removed.
    fn checkpoint_cost(&mut self, l: &Problem) -> CheckpointCost {
        let start = Instant::now();
        let mut e = Enc::with_capacity(64 * self.state.x.len());
        e.put(&self.state.x);
        e.put(&self.state.v);
        e.put(&self.integ.save_state());
        self.sys.save(&mut e);
        for c in &mut self.sys.contributions {
            // no files: the stages of the sample write none
            let _ = c.save(&mut e, &self.sys.events);
        }
        let alpha = l.scene.damping.mass_proportional;
        let residuals = crate::run::books_residuals(l);
        crate::run::ledger::Books::new(&mut self.sys, &self.state, alpha, residuals).save(&mut e);
        let encode = start.elapsed().as_secs_f64();
        let tmp = std::env::temp_dir().join(format!(".fdem-check-{}.fdem", std::process::id()));
        let start = Instant::now();
        let write = match crate::checkpoint::write_durably(&tmp, &e.buf) {
            Ok(()) => start.elapsed().as_secs_f64(),
            Err(_) => 0.0,
        };
        let _ = std::fs::remove_file(&tmp);
        CheckpointCost {
            bytes: e.buf.len() as u64,
            encode,
            write,
        }
    }

    /// The largest utilisation of the joints at the current state (`sigma / f_t` in tension,
    /// `|tau| / (c + max(-sigma, 0) tan phi)` in shear; 1 once a joint softens or breaks);
    /// `None` without joints.
    fn utilisation(&self, l: &Problem) -> Option<f64> {
        let state = self
            .sys
            .contributions
            .iter()
            .find_map(|c| c.joint_state())?;
        let set = l.fracturing.set.as_ref()?;
        let x = self.state.x_nodes();
        let frame = crate::output::JointFrame::new(set, state, x);
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
    stage: crate::stages::contact::ContactStage,
    x: Vec<[f64; 2]>,
    v: Vec<[f64; 2]>,
    f: Vec<[f64; 2]>,
    events: StepEvents,
}

impl Released {
    fn new(l: &Problem) -> Option<Self> {
        l.scene.fracture.as_ref()?;
        let stage = crate::stages::contact::ContactStage::new(
            &l.scene,
            &l.model,
            l.dt,
            None,
            u64::MAX,
            false,
        )?;
        let x = l.model.x0.clone();
        let n = x.len();
        let mut r = Self {
            stage,
            x,
            v: vec![[0.0; 2]; n],
            f: vec![[0.0; 2]; n],
            events: StepEvents::default(),
        };
        r.pass();
        Some(r)
    }

    fn pass(&mut self) {
        let (x, v, e) = (&self.x, &self.v, &mut self.events);
        self.stage.forces(0.0, x, v, &mut self.f, e);
        self.stage.end_of_step(0.0, x, v, false, e);
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
/// Kinetic and adaptive damping depend on the lowest natural frequency, which the scene does
/// not give: the duration's steps, with a line saying so.
pub fn expected_steps(l: &Problem) -> (u64, String) {
    let alpha = l.scene.damping.mass_proportional;
    let tol = l.scene.integrator.relaxation_tolerance;
    if l.scene.analysis == Analysis::Relaxation && alpha == 0.0 {
        let (method, why) = l.scene.relaxation_choice();
        let (name, took) = match method {
            RelaxationMethod::ConjugateGradient => (
                "conjugate gradient".to_string(),
                "it took 4 800 iterations on a 25 920-triangle cantilever where kinetic damping took 53 200 steps",
            ),
            m => (
                format!("{} damping", m.name()),
                "kinetic damping took about (omega_max / omega_1) ln(1/tol) / 4 steps on the cantilevers (omega_1 the lowest natural frequency)",
            ),
        };
        return (
            l.n_steps,
            format!(
                "relaxation by {name}, {why}; stops when converged, at most {} steps; {took}",
                l.n_steps
            ),
        );
    }
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
