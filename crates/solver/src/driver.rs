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

/// `fdem check`'s report: the stable step of every scheme and the estimated run time, from a
/// timed force evaluation.
pub fn check_report(l: &Loaded) -> String {
    let mut s = String::new();
    let n_tri = l.elements.len().max(1);
    let x = &l.model.x0;
    let mut f = vec![[0.0; 2]; x.len()];
    let mut scratch = fdem_mesh::ForceScratch::new(&l.elements);
    let start = Instant::now();
    let mut evals = 0;
    while evals < 3 || (start.elapsed().as_secs_f64() < 0.2 && evals < 100) {
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
        "one force evaluation: {:.3e} s ({:.1} M triangles/s)",
        per_eval,
        n_tri as f64 / per_eval / 1e6
    );
    if l.scene.analysis == Analysis::Static {
        let _ = writeln!(s, "static analysis: one sparse Cholesky solve");
        return s;
    }
    let duration = l.scene.duration.unwrap_or(0.0);
    let safety = l.scene.integrator.safety;
    let _ = writeln!(
        s,
        "{:<20} {:>10} {:>12} {:>12} {:>10} {:>12}",
        "scheme", "h*omega", "h_limit [s]", "h used [s]", "steps", "est. time"
    );
    for k in SchemeKind::ALL {
        let lim = stable_step(k, l.omega_max, l.z_high);
        let h = if k == l.scheme { l.dt } else { safety * lim };
        let steps = (duration / h).ceil();
        let est = steps * k.cost().force_equivalents(false) as f64 * per_eval * 1.15;
        let _ = writeln!(
            s,
            "{:<20} {:>10.4} {:>12.4e} {:>12.4e} {:>10} {:>11.1}s{}",
            k.name(),
            k.stability_limit(),
            lim,
            h,
            steps,
            est,
            if k == l.scheme { "  <- scene" } else { "" }
        );
    }
    s
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
