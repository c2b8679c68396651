//! Loading a scene: the scene file, the bodies' meshes, every name the scene refers to, the
//! model, the elements and the time step, checked before anything is written ([`load`]).
//!
//! Time step: `h_limit = (h omega)_scheme / omega_max * (sqrt(1 + z^2) - z)`
//! ([`crate::problem::stable_step`]), where `omega_max` is the largest element frequency bound
//! of the mesh crate, `(h omega)_scheme` the scheme's stability limit on the undamped
//! oscillator, and `z` the damping ratio of the highest mode (element viscosity and
//! mass-proportional damping). `"auto"` takes `safety * h_limit`; a fixed step above
//! `h_limit` is an error. The step is then shortened so that a whole number of steps spans
//! the duration ([`step_count`]: `duration / h` within a relative 1e-12 of a whole number is
//! that number). The frequency bound, the steps, the frames and the history rows are checked
//! in [`crate::problem::limits`] before anything is written.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use fdem_mesh::{Elements, Mesh};
use fdem_time::SchemeKind;

use crate::error::SceneError;
use crate::input::resolve::MeshNames;
use crate::input::scene::{Analysis, Scene};
use crate::problem::Fracturing;
use crate::problem::input_checks;
use crate::problem::limits::{self, StepInputs};
use crate::problem::mesh_adapter;
use crate::problem::model::{self, Model};
use crate::problem::stable_step::{self, FrequencyTerms};
use crate::problem::static_checks;

/// A scene prepared to run: the parsed scene as it was read, and every data set derived from
/// it, each computed once by [`load`] (meshes, model, elements, joints, frequency terms, steps).
pub struct Problem {
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
    /// Damping ratio of the highest mode.
    pub z_high: f64,
    /// The stable limit of the chosen scheme [s].
    pub dt_limit: f64,
    /// The time step used [s] (0 for static).
    pub dt: f64,
    /// Number of steps (0 for static).
    pub n_steps: u64,
    /// Wall time of [`load`] [s] (0 for a `Problem` built otherwise): the first part of the
    /// run summary's `timers.setup`.
    pub load_s: f64,
    /// The joints of the fracturing bodies, the cracks resolved to joints and the joint set,
    /// built once at load (empty without a `"fracture"` section).
    pub fracturing: Fracturing,
    /// A saved fracture state to start from instead of the fresh one (not part of the scene
    /// file): the joints' histories (damage, shear secant, mode indicator, energy books),
    /// which are broken and when, e.g. a run's `Outcome::joint_state` (`crate::run::summary`).
    /// The fracture stage adopts it when attached: the broken joints stay broken and the
    /// pairs their breaks and softenings released are contact couples from the first force
    /// evaluation. `None` (as loaded): the fresh state at the model's reference positions,
    /// with the pre-existing cracks broken ([`crate::problem::cracks::initial_state`]).
    pub initial_joint_state: Option<fdem_fracture::JointState>,
    /// The terms of the a-priori frequency bound of the loaded model; `omega_max` is their
    /// combination ([`FrequencyTerms::omega_max`]).
    pub frequency: FrequencyTerms,
    /// What the scene asks for that does nothing but is not wrong (a joint material that
    /// nothing uses): each a line with the JSON path and the fix, shown by [`Problem::describe`].
    pub warnings: Vec<String>,
    /// The fluid in the crack network (`fluid`), prepared ([`crate::problem::fluid`]); `None`
    /// without the section.
    pub fluid: Option<crate::problem::fluid::FluidSetup>,
    /// The accuracy indicators the problem decides before a step is taken
    /// ([`crate::problem::accuracy::predict`]: process zone, joint compliance, mesh quality,
    /// units); `fdem check` prints them and the run reports them with what it measured.
    pub accuracy: Vec<crate::problem::indicator::Indicator>,
}

/// Reads a scene file, its meshes, and builds the model; every error names the file and field.
///
/// Order: the scene, the meshes, then every name the scene refers to ([`crate::input::resolve`]),
/// then the fracturing bodies are exploded and the model built, and last the derived
/// quantities (frequency bound, steps, frames, history rows: [`crate::problem::limits`]) are checked.
/// The file is read and handed to [`load_text`].
pub fn load(file: &Path) -> Result<Problem, SceneError> {
    let started = std::time::Instant::now();
    let text = std::fs::read_to_string(file).map_err(|e| SceneError::Io {
        file: file.to_path_buf(),
        message: e.to_string(),
    })?;
    let mut loaded = load_text(&text, file)?;
    loaded.load_s = started.elapsed().as_secs_f64();
    Ok(loaded)
}

/// Loads a scene given as JSON `text` as [`load`] loads a file: `file` names the scene in
/// every error message, and its folder is the one that relative mesh paths are resolved
/// against (the file itself need not exist). For callers that hold a scene in memory (an
/// edited scene, a scene built by a program).
pub fn load_text(text: &str, file: &Path) -> Result<Problem, SceneError> {
    let started = std::time::Instant::now();
    let scene = Scene::from_json(text, file)?;
    static_checks::check_sections(&scene, file)?;
    input_checks::check_fracture_regions(&scene, file)?;
    // The schemes' stability limits (computed once per process, the same numbers on any
    // thread) are found on a thread of their own while the meshes are read, when more than
    // one thread is allowed (not in the rayon pool: the read never waits for its workers).
    let read = std::thread::scope(|s| {
        if rayon::current_num_threads() > 1 {
            s.spawn(|| SchemeKind::CentralDifference.stability_limit());
        }
        read_meshes(&scene, file)
    })?;
    // (messages name each mesh as the scene does)
    let names: Vec<MeshNames> = read
        .iter()
        .zip(&scene.bodies)
        .map(|(m, b)| MeshNames {
            source: b.mesh.display().to_string(),
            ..MeshNames::of(m)
        })
        .collect();
    let refs = crate::input::resolve::resolve(&scene, file, &names)?;
    input_checks::check_loaded_edges(&scene, file, &read, &refs)?;
    input_checks::check_initial_overlap(&scene, file, &read, &refs)?;
    let warnings = input_checks::unused_materials(&scene);
    let mut meshes = Vec::new();
    let mut inputs = Vec::new();
    let mut bodies = Vec::new();
    for (i, mesh) in read.into_iter().enumerate() {
        let mesh = crate::problem::joints::explode_body(&scene, file, i, &refs, mesh, &mut bodies)?;
        inputs.push(mesh_adapter::to_input(&mesh));
        meshes.push(mesh);
    }
    input_checks::check_fracture_acts(&scene, file, &refs, &bodies)?;
    let cracks = crate::problem::cracks::resolve(&scene, file, &meshes, &bodies)?;
    let mut model = model::build(&scene, file, &inputs, &refs)?;
    if scene.analysis == Analysis::Static {
        static_checks::check_supports(&scene, file, &model)?;
        input_checks::check_static_range(&scene, file, &model)?;
    }
    if let Some(c) = &scene.contact {
        c.validate(file)?;
    }
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
    if (scene.integrator).equal_step_masses(scene.analysis, scene.relaxation_choice().0) {
        model.equal_step_masses();
    }
    let ms = scene.mass_scaling.clone();
    if let Some(f) = ms.as_ref().and_then(|m| m.factor) {
        limits::check_mass_factor(f, "mass_scaling.factor", &model, file)?;
        model.scale_masses(f);
    }
    let set = crate::problem::joints::joint_set(&scene, &bodies, &model, file)?;
    let mut fracturing = Fracturing {
        bodies,
        cracks,
        set,
    };
    let parts = Parts {
        scene: &scene,
        file,
        meshes: &meshes,
        refs: &refs,
        scheme,
    };
    let mut timed = parts.timed(&model, &mut fracturing)?;
    if let Some(target) = ms.as_ref().and_then(|m| m.target_step) {
        // the factor that gives the target step: the bounds fall as 1 / sqrt(factor)
        let h = scene.integrator.safety * timed.steps.dt_limit;
        let f = crate::input::scene::mass_scaling::factor_for_target(target, h, file)?;
        limits::check_mass_factor(f, "mass_scaling.target_step", &model, file)?;
        model.scale_masses(f);
        timed = parts.timed(&model, &mut fracturing)?;
    }
    let Timed {
        elements,
        frequency,
        z_high,
        steps,
    } = timed;
    let accuracy = crate::problem::accuracy::predict(&scene, &model, &elements, &fracturing);
    let fluid = crate::problem::fluid::prepare(&scene, file, &meshes, &model, &fracturing)?;
    Ok(Problem {
        file: file.to_path_buf(),
        scene,
        meshes,
        model,
        elements,
        scheme,
        z_high,
        dt_limit: steps.dt_limit,
        dt: steps.dt,
        n_steps: steps.n_steps,
        load_s: started.elapsed().as_secs_f64(),
        fracturing,
        initial_joint_state: None,
        frequency,
        warnings,
        fluid,
        accuracy,
    })
}

/// What the elements and the time step are built from.
struct Parts<'a> {
    scene: &'a Scene,
    file: &'a Path,
    meshes: &'a [Mesh],
    refs: &'a crate::input::resolve::Resolved,
    scheme: SchemeKind,
}

/// The elements of a model, its frequency bound, the damping of its highest mode and its
/// time steps.
struct Timed {
    elements: Elements,
    frequency: FrequencyTerms,
    z_high: f64,
    steps: limits::Steps,
}

impl Parts<'_> {
    /// The elements (with their initial stress) and the time step of `model`; the joint set
    /// of `fracturing` prestressed by the elements' initial stress.
    fn timed(&self, model: &Model, fracturing: &mut Fracturing) -> Result<Timed, SceneError> {
        let (scene, file) = (self.scene, self.file);
        let xi = scene.damping.viscosity_ratio;
        let mut elements =
            mesh_adapter::elements(model, xi).map_err(|message| SceneError::Invalid {
                file: file.to_path_buf(),
                path: "bodies".into(),
                message,
                fix: "check the materials and the mesh".into(),
            })?;
        elements.set_initial_stress(crate::problem::prestress::field(
            scene,
            file,
            model,
            self.meshes,
            self.refs,
        )?);
        if elements.prestressed()
            && let Some(set) = &mut fracturing.set
        {
            // refuse at load a joint that the initial stress would start broken
            let s0 = &elements.initial_stress;
            let bodies = &fracturing.bodies;
            crate::problem::prestress::prestress_joints(scene, file, model, s0, set, bodies)?;
        }
        let frequency = FrequencyTerms::of(scene, model, &elements, fracturing.set.as_ref());
        let omega_max = frequency.omega_max();
        let z_high = stable_step::high_mode_damping(scene, model, &elements, omega_max);
        let steps = limits::time_steps(&StepInputs {
            scene,
            file,
            model,
            elements: &elements,
            scheme: self.scheme,
            omega_max,
            frequency,
            z_high,
            lower_fixed_step: false,
        })?;
        Ok(Timed {
            elements,
            frequency,
            z_high,
            steps,
        })
    }
}

/// The bodies' meshes, in the scene's order.
fn read_meshes(scene: &Scene, file: &Path) -> Result<Vec<Mesh>, SceneError> {
    let dir = file.parent().unwrap_or(Path::new("."));
    let mut read = Vec::with_capacity(scene.bodies.len());
    for (i, body) in scene.bodies.iter().enumerate() {
        let path = dir.join(&body.mesh);
        let mesh = mesh_adapter::read(&path).map_err(|message| SceneError::Mesh {
            file: file.to_path_buf(),
            path: format!("bodies[{i}].mesh"),
            mesh: path.clone(),
            message,
        })?;
        read.push(mesh);
    }
    Ok(read)
}

/// The number of steps of about `h` that span `duration` ([`stable_step::step_count`]: a whole
/// `duration / h` within a relative 1e-12 is that number, else rounded up), as an integer
/// (saturating), and the step that spans the duration exactly.
pub fn step_count(duration: f64, h: f64) -> (u64, f64) {
    let n = stable_step::step_count(duration, h);
    (n as u64, duration / n)
}

impl Problem {
    /// The a-priori frequency bound [rad/s]: `sqrt(elements^2 + contact^2 + joints^2)` of
    /// [`Problem::frequency`].
    pub fn omega_max(&self) -> f64 {
        self.frequency.omega_max()
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
        let joints = match self.fracturing.n_joints() {
            0 => String::new(),
            n => format!(", {n} joints"),
        };
        let _ = write!(
            s,
            "  {} nodes, {} triangles{joints}, {} free DOFs; analysis {:?}",
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
            if let Some((f, _)) = &self.model.mass_scaling {
                let _ = write!(s, "; mass scaling {f:.4}");
            }
            if self.model.relaxation_masses.is_some() {
                let _ = write!(s, "; equal-step masses");
            }
        }
        for w in &self.warnings {
            let _ = write!(s, "\nwarning: {w}");
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The repository's `examples/` folder.
    fn examples() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
    }

    #[test]
    fn load_text_of_a_file_equals_load_of_it() {
        // a fracturing scene with a relative mesh path: the joints, the contact walls and the
        // step all come from the text and the file's folder
        let file = examples().join("brazilian-disc-fracture.json");
        let text = std::fs::read_to_string(&file).unwrap();
        let a = load(&file).unwrap();
        let b = load_text(&text, &file).unwrap();
        assert_eq!(a.file, b.file);
        assert_eq!(a.dt.to_bits(), b.dt.to_bits());
        assert_eq!(a.dt_limit.to_bits(), b.dt_limit.to_bits());
        assert_eq!(a.n_steps, b.n_steps);
        assert_eq!(a.model.triangles, b.model.triangles);
        assert_eq!(a.model.x0, b.model.x0);
        assert_eq!(a.model.mass, b.model.mass);
        assert_eq!(a.describe(), b.describe());
        assert_eq!(
            serde_json::to_string(&a.scene).unwrap(),
            serde_json::to_string(&b.scene).unwrap()
        );
    }

    #[test]
    fn load_text_resolves_meshes_from_the_named_files_folder_and_names_it_in_errors() {
        let file = examples().join("brazilian-disc-fracture.json");
        let text = std::fs::read_to_string(&file).unwrap();
        // the same text said to live elsewhere: its relative mesh is looked for there
        let elsewhere = examples().join("no-such-folder/scene.json");
        let e = load_text(&text, &elsewhere)
            .err()
            .expect("the mesh is not there");
        assert!(
            matches!(&e, SceneError::Mesh { file, path, .. } if file == &elsewhere && path == "bodies[0].mesh"),
            "{e}"
        );
        // a type error names the file given and the JSON path
        let bad = text.replace("\"young\": 30e9", "\"young\": \"abc\"");
        let e = load_text(&bad, &file)
            .err()
            .expect("a string is not a modulus");
        assert!(
            e.to_string().contains("brazilian-disc-fracture.json"),
            "{e}"
        );
        assert!(
            matches!(&e, SceneError::Parse { path, .. } if path.contains("young")),
            "{e}"
        );
    }
}
