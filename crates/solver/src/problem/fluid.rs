//! The `"fluid"` section prepared at load ([`prepare`]): the section checked, the injection
//! points snapped to vertices of joints, the pressure groups resolved to joints, and the
//! joints wetted at the start (the pre-existing cracks, the pressure groups' joints and every
//! joint at an injection's vertex). Refused: a fluid in a scene without joints, a point on
//! no crack or joint, a pressure group whose edges are not joints.

use std::path::Path;

use fdem_mesh::Mesh;

use crate::error::SceneError;
use crate::input::scene::Scene;
use crate::input::scene::fluid::FlowStepping;
use crate::problem::Fracturing;
use crate::problem::model::Model;
use crate::problem::time_function::{self, History};

/// The columns of the `fluid` history probe (`crate::stages::fluid::FluidBooks::columns`).
pub const COLUMNS: [&str; 9] = [
    "fluid_initial",
    "fluid_injected",
    "fluid_boundary",
    "fluid_stored",
    "fluid_compressed",
    "fluid_leaked",
    "fluid_balance_error",
    "injection_pressure",
    "fluid_channels",
];

/// An injection resolved: the node of the vertex it feeds, its rate and its factor in time.
#[derive(Debug, Clone)]
pub struct Source {
    /// A model node of the vertex (any copy: the cavity is the vertex's).
    pub node: u32,
    /// The vertex's position [m].
    pub at: [f64; 2],
    /// Volume rate at full factor [m^3/s].
    pub rate: f64,
    /// Ramp [s].
    pub ramp: f64,
    /// Time history of the factor.
    pub history: Option<History>,
}

impl Source {
    /// The volume injected over `[t0, t1]` [m^3].
    pub fn volume(&self, t0: f64, t1: f64) -> f64 {
        let h = self.history.as_ref();
        self.rate
            * (time_function::integral(t1, self.ramp, h)
                - time_function::integral(t0, self.ramp, h))
    }
}

/// A prescribed pressure resolved: the joints of its edge group (global ids) and its value in
/// time.
#[derive(Debug, Clone)]
pub struct HeldPressure {
    /// Joints of the group (global ids, increasing).
    pub joints: Vec<u32>,
    /// Pressure at full factor [Pa].
    pub value: f64,
    /// Ramp [s].
    pub ramp: f64,
    /// Time history of the factor.
    pub history: Option<History>,
}

impl HeldPressure {
    /// The pressure at `t` [Pa].
    pub fn at(&self, t: f64) -> f64 {
        self.value * time_function::factor(t, self.ramp, self.history.as_ref())
    }
}

/// The fluid of a scene, prepared.
#[derive(Debug, Clone)]
pub struct FluidSetup {
    /// The fluid's properties.
    pub fluid: fdem_flow::Fluid,
    /// How the pressures are stepped.
    pub stepping: FlowStepping,
    /// Joints are wetted from their first softening (`fluid.wet_damaged`).
    pub wet_damaged: bool,
    /// The injections, in scene order.
    pub sources: Vec<Source>,
    /// The prescribed pressures, in scene order.
    pub pressures: Vec<HeldPressure>,
    /// Joints wet at the start (global ids, increasing).
    pub wet: Vec<u32>,
}

/// The first global joint id of each fracturing body's joints, by body index.
fn bases(fracturing: &Fracturing) -> Vec<(usize, usize, usize)> {
    let mut base = 0;
    let mut out = Vec::new();
    for (bi, js) in &fracturing.bodies {
        out.push((*bi, base, js.len()));
        base += js.len();
    }
    out
}

/// Prepares the scene's `"fluid"` section (`None` without one).
pub fn prepare(
    scene: &Scene,
    file: &Path,
    meshes: &[Mesh],
    model: &Model,
    fracturing: &Fracturing,
) -> Result<Option<FluidSetup>, SceneError> {
    let Some(section) = &scene.fluid else {
        let probe = (scene.histories.probes.iter())
            .position(|p| matches!(p, crate::input::scene::Probe::Fluid));
        if let Some(i) = probe {
            return Err(SceneError::invalid(
                file,
                format!("histories.probes[{i}]"),
                "the \"fluid\" probe records the fluid's books, and the scene has no \"fluid\" \
                 section",
                "remove the probe, or add a \"fluid\" section",
            ));
        }
        return Ok(None);
    };
    section.validate(file)?;
    let Some(set) = &fracturing.set else {
        return Err(SceneError::invalid(
            file,
            "fluid",
            "the fluid flows in the cracks and joints of fracturing bodies, and the scene has \
             none",
            "add a \"fracture\" section whose regions cover the cracks the fluid is in (and \
             \"fracture.cracks\" for the pre-existing ones), or remove the \"fluid\" section",
        ));
    };
    let bases = bases(fracturing);
    let mut wet: Vec<u32> = Vec::new();
    for c in &fracturing.cracks {
        if let Some(&(_, base, _)) = bases.iter().find(|b| b.0 == c.body) {
            wet.extend(c.joints.iter().map(|&j| (base + j as usize) as u32));
        }
    }
    let pressures = held_pressures(scene, file, meshes, fracturing, &bases, &mut wet)?;
    wet.sort_unstable();
    wet.dedup();
    let sources = sources(scene, file, model, set, &bases, &mut wet)?;
    wet.sort_unstable();
    wet.dedup();
    Ok(Some(FluidSetup {
        fluid: section.fluid(),
        stepping: section.stepping,
        wet_damaged: section.wet_damaged,
        sources,
        pressures,
        wet,
    }))
}

/// The first global joint id and the count of each fracturing body's joints, by body index.
type Bases = [(usize, usize, usize)];

/// `fluid.pressures` resolved to joints (appended to `wet`).
fn held_pressures(
    scene: &Scene,
    file: &Path,
    meshes: &[Mesh],
    fracturing: &Fracturing,
    bases: &Bases,
    wet: &mut Vec<u32>,
) -> Result<Vec<HeldPressure>, SceneError> {
    let section = scene.fluid.as_ref().expect("a fluid section");
    let mut pressures = Vec::new();
    for (i, p) in section.pressures.iter().enumerate() {
        let path = format!("fluid.pressures[{i}]");
        let bi = crate::problem::cracks::group_body(scene, meshes, p.body.as_deref(), &p.group);
        let Some(&(_, base, _)) = bases.iter().find(|b| b.0 == bi) else {
            return Err(no_joints(file, &format!("{path}.group"), bi));
        };
        let local = &fracturing
            .bodies
            .iter()
            .find(|b| b.0 == bi)
            .expect("a body")
            .1;
        let js = crate::problem::cracks::crack_joints(file, &path, &meshes[bi], &p.group, local)?;
        let joints: Vec<u32> = js.iter().map(|&j| (base + j as usize) as u32).collect();
        wet.extend(&joints);
        pressures.push(HeldPressure {
            joints,
            value: p.value,
            ramp: p.ramp,
            history: p.history.as_ref().map(History::new),
        });
    }
    Ok(pressures)
}

/// `fluid.injections` snapped to joint vertices; the joints at a vertex on no wet joint are
/// appended to `wet` (a perforation). `wet` is sorted.
fn sources(
    scene: &Scene,
    file: &Path,
    model: &Model,
    set: &fdem_fracture::JointSet,
    bases: &Bases,
    wet: &mut Vec<u32>,
) -> Result<Vec<Source>, SceneError> {
    let section = scene.fluid.as_ref().expect("a fluid section");
    let mut sources = Vec::new();
    for (i, inj) in section.injections.iter().enumerate() {
        let path = format!("fluid.injections[{i}]");
        let range = match &inj.body {
            Some(b) => {
                let bi = scene
                    .bodies
                    .iter()
                    .position(|x| x.name.as_deref() == Some(b))
                    .unwrap_or(0);
                let Some(&(_, base, n)) = bases.iter().find(|x| x.0 == bi) else {
                    return Err(no_joints(file, &format!("{path}.body"), bi));
                };
                base..base + n
            }
            None => 0..set.len(),
        };
        let (node, at) = snap(set, model, range, inj.at).map_err(|(d, near)| {
            SceneError::invalid(
                file,
                format!("{path}.at"),
                format!(
                    "the point ({:.6e}, {:.6e}) is on no crack or joint: the nearest vertex of \
                     a joint is at ({:.6e}, {:.6e}), {d:.3e} m away, more than half the length \
                     of its joints",
                    inj.at[0], inj.at[1], near[0], near[1]
                ),
                "place the injection on a vertex of a crack (fracture.cracks) or of the joints \
                 of a fracture region",
            )
        })?;
        // a vertex on no crack is perforated: its joints are wetted
        let at_vertex: Vec<u32> = (0..set.len() as u32)
            .filter(|&j| {
                set.nodes[j as usize]
                    .iter()
                    .any(|&k| model.x0[k as usize] == at)
            })
            .collect();
        if !at_vertex.iter().any(|j| wet.binary_search(j).is_ok()) {
            wet.extend(at_vertex);
            wet.sort_unstable();
            wet.dedup();
        }
        sources.push(Source {
            node,
            at,
            rate: inj.rate,
            ramp: inj.ramp,
            history: inj.history.as_ref().map(History::new),
        });
    }
    Ok(sources)
}

/// The error of a group or body with no joints.
fn no_joints(file: &Path, path: &str, bi: usize) -> SceneError {
    SceneError::invalid(
        file,
        path,
        format!("body {bi} has no joints: no fracture region covers it"),
        "add a fracture region over the body (fracture.regions), or name a fracturing body",
    )
}

/// The joint node nearest to `p` among the joints `range` at the reference positions, and its
/// position, when within half the length of the shortest joint at that vertex; else the
/// distance and the nearest vertex.
fn snap(
    set: &fdem_fracture::JointSet,
    model: &Model,
    range: std::ops::Range<usize>,
    p: [f64; 2],
) -> Result<(u32, [f64; 2]), (f64, [f64; 2])> {
    let dist = |x: [f64; 2]| ((x[0] - p[0]).powi(2) + (x[1] - p[1]).powi(2)).sqrt();
    let nearest = set.nodes[range.clone()]
        .iter()
        .flatten()
        .map(|&k| (dist(model.x0[k as usize]), k))
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let Some((d, k)) = nearest else {
        return Err((f64::INFINITY, p));
    };
    let x = model.x0[k as usize];
    let h = range
        .filter(|&j| set.nodes[j].iter().any(|&n| model.x0[n as usize] == x))
        .map(|j| set.ref_length[j])
        .fold(f64::INFINITY, f64::min);
    if d <= 0.5 * h {
        Ok((k, x))
    } else {
        Err((d, x))
    }
}
