//! The assembled model of a scene: all bodies' nodes and triangles in one numbering, the
//! materials of the triangles, the constrained degrees of freedom and the loads.
//!
//! Loads are consistent nodal forces in the reference configuration (dead loads):
//!
//! - pressure `p` on an edge of length `L` (outward unit normal `n`): `-p n L t / 2` on each
//!   of its two nodes (positive `p` pushes into the body);
//! - traction `T`: `T L t / 2` on each node;
//! - point load `P` on a group of `k` nodes: `P / k` on each;
//! - gravity `g`: `m_i g` on node `i` (lumped mass `m_i = sum rho A0 t / 3`).
//!
//! Each load is scaled by its ramp `min(1, t / ramp)` (1 when `ramp` = 0), or by its time
//! history ([`crate::problem::time_function`]).

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use crate::error::SceneError;
pub use crate::input::mesh_input::MeshInput;
use crate::input::resolve::Resolved;
use crate::input::scene::{BoundaryCondition, HistorySpec, MaterialSpec, Scene};
use crate::problem::time_function::{self, History};
pub use crate::problem::time_function::{ramp_factor, ramp_integral};

/// A strain estimate above this (50 %) marks an input as far too large for the material: the
/// constant-strain triangles represent strains well below 1 (`crate::run::diagnosis`, the initial
/// stress's check in `crate::problem::prestress`).
pub const LARGE_STRAIN: f64 = 0.5;

/// A load with a ramp or a time history: nodal forces (DOF, value) at full strength (factor 1).
#[derive(Debug, Clone)]
pub struct RampedLoad {
    /// Ramp time [s] (0: a step).
    pub ramp: f64,
    /// (DOF index, force [N]) pairs.
    pub forces: Vec<(u32, f64)>,
    /// The time history of the factor, in place of the ramp.
    pub history: Option<Arc<History>>,
}

impl RampedLoad {
    /// The factor on the forces at time `t`.
    pub fn factor(&self, t: f64) -> f64 {
        time_function::factor(t, self.ramp, self.history.as_deref())
    }

    /// The factor of the static solve and of the relaxation's load scale: 1 with a ramp (the
    /// full load), the history's at `t` otherwise.
    pub fn static_factor(&self, t: f64) -> f64 {
        self.history.as_ref().map_or(1.0, |h| h.value(t))
    }
}

/// A DOF with a prescribed velocity or displacement.
#[derive(Debug, Clone)]
pub struct PrescribedDof {
    /// DOF index (2 node + component).
    pub dof: u32,
    /// Full velocity [m/s] (a displacement [m] when `displacement`).
    pub velocity: f64,
    /// Ramp time [s].
    pub ramp: f64,
    /// The time history of the factor, in place of the ramp.
    pub history: Option<Arc<History>>,
    /// A prescribed displacement `velocity f(t)` (its velocity `velocity f'(t)`), not a
    /// velocity.
    pub displacement: bool,
}

impl PrescribedDof {
    /// The displacement from the reference and the velocity at time `t`.
    pub fn motion(&self, t: f64) -> (f64, f64) {
        let h = self.history.as_deref();
        if self.displacement {
            (
                self.velocity * time_function::factor(t, self.ramp, h),
                self.velocity * time_function::rate(t, self.ramp, h),
            )
        } else {
            (
                self.velocity * time_function::integral(t, self.ramp, h),
                self.velocity * time_function::factor(t, self.ramp, h),
            )
        }
    }

    /// The displacement of the static solve at time `t` (the duration): a velocity's
    /// integral to `t`; a displacement's history at `t`, or its full value with a ramp.
    pub fn static_displacement(&self, t: f64) -> f64 {
        match (self.displacement, &self.history) {
            (true, None) => self.velocity,
            (true, Some(h)) => self.velocity * h.value(t),
            (false, h) => self.velocity * time_function::integral(t, self.ramp, h.as_deref()),
        }
    }
}

/// The evaluator of an optional history spec.
fn evaluator(h: Option<&HistorySpec>) -> Option<Arc<History>> {
    h.map(|h| Arc::new(History::new(h)))
}

/// A relaxation's equal-step masses ([`Model::equal_step_masses`]).
#[derive(Debug, Clone, Default)]
pub struct EqualStepMasses {
    /// The true lumped masses [kg], for the weight.
    pub true_mass: Vec<f64>,
    /// Each triangle's mass over its true mass `rho A t`.
    pub density_factor: Vec<f64>,
}

/// The whole scene in one node numbering.
#[derive(Debug, Clone, Default)]
pub struct Model {
    /// Reference node positions [m].
    pub x0: Vec<[f64; 2]>,
    /// Initial node velocities [m/s].
    pub v0: Vec<[f64; 2]>,
    /// Triangles (global node indices).
    pub triangles: Vec<[u32; 3]>,
    /// Material index of each triangle into `materials`.
    pub tri_material: Vec<u32>,
    /// Body index of each triangle.
    pub tri_body: Vec<u32>,
    /// Thickness of each triangle [m].
    pub tri_thickness: Vec<f64>,
    /// The distinct (material, thickness [m]) pairs, and one row per triangle of a material
    /// with a heterogeneity (its Young's modulus drawn for that triangle).
    pub materials: Vec<(MaterialSpec, f64)>,
    /// Whether some triangle's Young's modulus is drawn (a material with a heterogeneity):
    /// the frames then write each cell's `young`.
    pub drawn_young: bool,
    /// The material id of each row of `materials`, as the frames' `material` array shows it:
    /// the row itself, except that the rows drawn for one material entry share one id (ids
    /// numbered in order of first use).
    pub material_id: Vec<u32>,
    /// First node of each body, and one past the last.
    pub body_nodes: Vec<std::ops::Range<u32>>,
    /// Lumped node masses [kg] (times the mass scaling factor, if any).
    pub mass: Vec<f64>,
    /// Mass scaling: the factor on every lumped mass and the true masses, which the weight
    /// `m g` uses (`None`: the masses are the true ones).
    pub mass_scaling: Option<(f64, Vec<f64>)>,
    /// A relaxation's equal-step masses, if it has them ([`Model::equal_step_masses`]).
    pub relaxation_masses: Option<EqualStepMasses>,
    /// Constrained DOFs (fixed or prescribed velocity), one flag per DOF.
    pub constrained: Vec<bool>,
    /// DOFs with a prescribed nonzero velocity.
    pub prescribed: Vec<PrescribedDof>,
    /// External loads.
    pub loads: Vec<RampedLoad>,
    /// Gravity [m/s^2], if any.
    pub gravity: Option<[f64; 2]>,
    /// Node groups by (body index, name), global node indices.
    pub groups: Vec<(u32, String, Vec<u32>)>,
    /// The body of each history probe of the scene (`None`: the energy probe), as resolved.
    pub probe_body: Vec<Option<usize>>,
}

impl Model {
    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.x0.len()
    }

    /// Kinetic energy `sum m_i |v_i|^2 / 2` [J] of the node velocities `v` (one per node)
    /// with the lumped masses, summed in node order.
    pub fn kinetic_energy(&self, v: &[[f64; 2]]) -> f64 {
        self.mass
            .iter()
            .zip(v)
            .map(|(m, v)| 0.5 * m * (v[0] * v[0] + v[1] * v[1]))
            .sum()
    }

    /// The masses of the weight `m g` [kg]: the true lumped masses, also under mass scaling
    /// and with a relaxation's equal-step masses.
    pub fn weight_mass(&self) -> &[f64] {
        match (&self.relaxation_masses, &self.mass_scaling) {
            (Some(r), _) => &r.true_mass,
            (None, Some((_, m))) => m,
            (None, None) => &self.mass,
        }
    }

    /// The factor on the density of triangle `e` that its mass has: the equal-step masses'
    /// (1 with the true masses), not the mass scaling's.
    pub fn density_factor(&self, e: usize) -> f64 {
        self.relaxation_masses
            .as_ref()
            .map_or(1.0, |r| r.density_factor[e])
    }

    /// Gives every triangle the mass `m_e = c E_e t_e` in place of `rho_e A_e t_e`, with one
    /// `c` for the model that keeps the total mass, and lumps them (a third to each corner):
    /// a constant-strain triangle's stiffness scales with `E t` alone, so every triangle's
    /// frequency bound (over `sqrt(m_e)`) is then set by its shape and Poisson's ratio, not
    /// by its size. The true masses stay for the weight. Call it before any mass scaling.
    pub fn equal_step_masses(&mut self) {
        let n = self.triangles.len();
        let (mut true_total, mut et_total) = (0.0, 0.0);
        let mut true_tri = Vec::with_capacity(n);
        for e in 0..n {
            let mat = &self.materials[self.tri_material[e] as usize].0;
            let m = mat.density * self.area(e) * self.tri_thickness[e];
            true_tri.push(m);
            true_total += m;
            et_total += mat.young * self.tri_thickness[e];
        }
        let c = true_total / et_total;
        let mut mass = vec![0.0; self.x0.len()];
        let mut density_factor = Vec::with_capacity(n);
        for (e, t) in self.triangles.iter().enumerate() {
            let mat = &self.materials[self.tri_material[e] as usize].0;
            let m = c * mat.young * self.tri_thickness[e];
            density_factor.push(m / true_tri[e]);
            for &i in t {
                mass[i as usize] += m / 3.0;
            }
        }
        let true_mass = std::mem::replace(&mut self.mass, mass);
        self.relaxation_masses = Some(EqualStepMasses {
            true_mass,
            density_factor,
        });
    }

    /// The reference area of triangle `e` [m^2].
    fn area(&self, e: usize) -> f64 {
        let [a, b, c] = self.triangles[e].map(|i| self.x0[i as usize]);
        (0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))).abs()
    }

    /// The mass scaling factor (1 without mass scaling).
    pub fn mass_factor(&self) -> f64 {
        self.mass_scaling.as_ref().map_or(1.0, |(f, _)| *f)
    }

    /// Scales every lumped mass by `f` (the weight keeps the true masses), from the true
    /// masses: a second call replaces the first.
    pub fn scale_masses(&mut self, f: f64) {
        let true_mass = match self.mass_scaling.take() {
            Some((_, m)) => m,
            None => self.mass.clone(),
        };
        self.mass = true_mass.iter().map(|m| m * f).collect();
        self.mass_scaling = Some((f, true_mass));
    }

    /// External load vector (flat DOFs) at time t, gravity included, added to `f`.
    pub fn add_external(&self, t: f64, f: &mut [f64]) {
        for l in &self.loads {
            let s = l.factor(t);
            for &(d, v) in &l.forces {
                f[d as usize] += s * v;
            }
        }
        if let Some(g) = self.gravity {
            for (i, m) in self.weight_mass().iter().enumerate() {
                f[2 * i] += m * g[0];
                f[2 * i + 1] += m * g[1];
            }
        }
    }

    /// The static load vector (flat DOFs), gravity included, added to `f`: ramped loads at
    /// full strength, loads with a history at its value at `t` ([`RampedLoad::static_factor`]).
    pub fn add_external_static(&self, t: f64, f: &mut [f64]) {
        for l in &self.loads {
            let s = l.static_factor(t);
            for &(d, v) in &l.forces {
                f[d as usize] += s * v;
            }
        }
        if let Some(g) = self.gravity {
            for (i, m) in self.weight_mass().iter().enumerate() {
                f[2 * i] += m * g[0];
                f[2 * i + 1] += m * g[1];
            }
        }
    }

    /// Whether some load has a time history.
    pub fn loads_have_histories(&self) -> bool {
        self.loads.iter().any(|l| l.history.is_some())
    }

    /// The nodes of group `name` of body `body` (global node indices), if it has one.
    pub fn group_nodes(&self, body: usize, name: &str) -> Option<&[u32]> {
        self.groups
            .iter()
            .find(|(b, n, _)| *b as usize == body && n == name)
            .map(|g| g.2.as_slice())
    }

    /// The label of group `name` of body `body` in column names: `name`, or `body/name` when
    /// another body has a group of that name too (`bodies[i]` stands for an unnamed body).
    pub fn group_label(&self, scene: &Scene, body: usize, name: &str) -> String {
        let ambiguous = self
            .groups
            .iter()
            .any(|(b, n, _)| *b as usize != body && n == name);
        if ambiguous {
            match scene.bodies.get(body).and_then(|b| b.name.as_deref()) {
                Some(b) => format!("{b}/{name}"),
                None => format!("bodies[{body}]/{name}"),
            }
        } else {
            name.to_string()
        }
    }
}

/// The error for a name the resolver did not check against these meshes (a caller that
/// built the model without [`crate::input::resolve::resolve`]).
fn unresolved(file: &Path, path: String, what: String) -> SceneError {
    SceneError::Invalid {
        file: file.to_path_buf(),
        path,
        message: format!("{what} (the scene was not resolved against these meshes)"),
        fix: "load the scene with fdem_solver::load".into(),
    }
}

/// Builds the model from a scene, the bodies' meshes (in the order of `scene.bodies`) and
/// the bodies its names resolve to ([`crate::input::resolve::resolve`], which checks every name).
pub fn build(
    scene: &Scene,
    file: &Path,
    meshes: &[MeshInput],
    refs: &Resolved,
) -> Result<Model, SceneError> {
    let mut m = Model {
        gravity: scene.gravity,
        probe_body: refs.probes.clone(),
        ..Default::default()
    };
    let edge_groups = add_bodies(&mut m, scene, file, meshes)?;
    lump_masses(&mut m);
    constrain_and_load(&mut m, scene, file, refs, &edge_groups)?;
    Ok(m)
}

/// A Young's modulus drawn by the heterogeneity of `spec` (material `key` of body `bi`) for
/// the body's triangle `ti`: finite and positive, else the error names the distribution (its
/// parameters, valid each, draw values no material has: a spread so wide that a draw
/// overflows, or underflows to 0).
fn check_drawn_young(
    file: &Path,
    bi: usize,
    key: &str,
    spec: &MaterialSpec,
    young: f64,
    ti: usize,
) -> Result<(), SceneError> {
    if young.is_finite() && young > 0.0 {
        return Ok(());
    }
    let law = spec.heterogeneity.map_or("", |h| h.young.law());
    let path = format!("bodies[{bi}].materials.{key}.heterogeneity.young.{law}");
    Err(SceneError::invalid(
        file,
        path,
        format!(
            "the distribution drew Young's modulus {young} Pa for triangle {ti} of the body: its spread is so wide that a draw is not a positive finite number"
        ),
        "narrow the distribution: a larger Weibull `modulus`, a smaller `cov` (a spread of a few to some tens of percent is usual), and check the units of `scale` or `mean` (Pa)",
    ))
}

/// Every body's edge groups in the model's numbering: (body, group name, edges).
type EdgeGroups = Vec<(u32, String, Vec<[u32; 2]>)>;

/// Appends the bodies' nodes, triangles, materials and node groups to `m`; returns their
/// edge groups.
fn add_bodies(
    m: &mut Model,
    scene: &Scene,
    file: &Path,
    meshes: &[MeshInput],
) -> Result<EdgeGroups, SceneError> {
    let mut edge_groups: EdgeGroups = Vec::new();
    // The rows shared by triangles (materials without heterogeneity), searched for reuse.
    let mut shared: Vec<usize> = Vec::new();
    // The id of each drawn material entry: ((body, key), id).
    let mut drawn_ids: Vec<((usize, &str), u32)> = Vec::new();
    let mut next_id = 0u32;
    let (n_nodes, n_tris) = meshes.iter().fold((0, 0), |(n, t), mesh| {
        (n + mesh.nodes.len(), t + mesh.triangles.len())
    });
    m.x0.reserve(n_nodes);
    m.v0.reserve(n_nodes);
    m.triangles.reserve(n_tris);
    m.tri_material.reserve(n_tris);
    m.tri_body.reserve(n_tris);
    m.tri_thickness.reserve(n_tris);
    for (bi, (body, mesh)) in scene.bodies.iter().zip(meshes).enumerate() {
        let base = m.x0.len() as u32;
        m.body_nodes.push(base..base + mesh.nodes.len() as u32);
        m.x0.extend(
            mesh.nodes
                .iter()
                .map(|p| [p[0] + body.offset[0], p[1] + body.offset[1]]),
        );
        m.v0.extend(std::iter::repeat_n(body.initial_velocity, mesh.nodes.len()));
        // the material of the last group looked up (consecutive triangles share a group)
        let mut last = None;
        for (ti, t) in mesh.triangles.iter().enumerate() {
            let g = &mesh.triangle_group[ti];
            let (key, spec) = match last {
                Some((lg, found)) if lg == g => found,
                _ => {
                    let found = (body.materials.get_key_value(g))
                        .or_else(|| body.materials.get_key_value("*"))
                        .ok_or_else(|| {
                            unresolved(
                                file,
                                format!("bodies[{bi}].materials"),
                                format!("triangle {ti} is in group '{g}', which has no material"),
                            )
                        })?;
                    last = Some((g, found));
                    found
                }
            };
            let mi = if spec.heterogeneity.is_some() {
                // its own row: Young's modulus drawn for its global index
                m.drawn_young = true;
                let row = spec.row(m.triangles.len() as u64);
                check_drawn_young(file, bi, key, spec, row.young, ti)?;
                m.materials.push((row, body.thickness));
                let id = match drawn_ids.iter().find(|(k, _)| *k == (bi, key.as_str())) {
                    Some(&(_, id)) => id,
                    None => {
                        drawn_ids.push(((bi, key.as_str()), next_id));
                        next_id += 1;
                        next_id - 1
                    }
                };
                m.material_id.push(id);
                m.materials.len() - 1
            } else {
                match shared.iter().copied().find(|&i| {
                    let x = &m.materials[i];
                    same(&x.0, spec) && x.1 == body.thickness
                }) {
                    Some(i) => i,
                    None => {
                        m.materials.push((*spec, body.thickness));
                        m.material_id.push(next_id);
                        next_id += 1;
                        shared.push(m.materials.len() - 1);
                        m.materials.len() - 1
                    }
                }
            };
            m.triangles.push([t[0] + base, t[1] + base, t[2] + base]);
            m.tri_material.push(mi as u32);
            m.tri_body.push(bi as u32);
            m.tri_thickness.push(body.thickness);
        }
        for (name, nodes) in &mesh.node_groups {
            m.groups.push((
                bi as u32,
                name.clone(),
                nodes.iter().map(|&n| n + base).collect(),
            ));
        }
        for (name, edges) in &mesh.edge_groups {
            edge_groups.push((
                bi as u32,
                name.clone(),
                edges.iter().map(|e| [e[0] + base, e[1] + base]).collect(),
            ));
        }
    }
    Ok(edge_groups)
}

/// Lumped masses `m_i = sum rho A0 t / 3`.
fn lump_masses(m: &mut Model) {
    m.mass = vec![0.0; m.x0.len()];
    for (e, t) in m.triangles.iter().enumerate() {
        let [a, b, c] = t.map(|i| m.x0[i as usize]);
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
        let mat = &m.materials[m.tri_material[e] as usize].0;
        let third = mat.density * area.abs() * m.tri_thickness[e] / 3.0;
        for &i in t {
            m.mass[i as usize] += third;
        }
    }
}

/// The constrained and prescribed DOFs and the ramped loads of the scene's boundary
/// conditions (the groups of body `refs.conditions[i]`).
fn constrain_and_load(
    m: &mut Model,
    scene: &Scene,
    file: &Path,
    refs: &Resolved,
    edge_groups: &EdgeGroups,
) -> Result<(), SceneError> {
    // Edge -> opposite node (outward normals) and node thickness, for loaded edges: built
    // only for a scene with a pressure or traction.
    let mut opposite: HashMap<(u32, u32), u32> = HashMap::new();
    let mut node_thickness = Vec::new();
    if (scene.boundary_conditions.iter()).any(|bc| {
        matches!(
            bc,
            BoundaryCondition::Pressure(_) | BoundaryCondition::Traction(_)
        )
    }) {
        (opposite, node_thickness) = edge_tables(m);
    }
    m.constrained = vec![false; 2 * m.x0.len()];
    for (i, bc) in scene.boundary_conditions.iter().enumerate() {
        let path = format!("boundary_conditions[{i}]");
        let bi = refs.conditions.get(i).copied().unwrap_or(0);
        let nodes_of = |name: &str| -> Result<Vec<u32>, SceneError> {
            m.group_nodes(bi, name).map(<[u32]>::to_vec).ok_or_else(|| {
                unresolved(
                    file,
                    format!("{path}.group"),
                    format!("body {bi} has no group '{name}'"),
                )
            })
        };
        let edges_of = |name: &str| -> Result<&Vec<[u32; 2]>, SceneError> {
            edge_groups
                .iter()
                .find(|(b, n, _)| *b as usize == bi && n == name)
                .map(|g| &g.2)
                .ok_or_else(|| {
                    unresolved(
                        file,
                        format!("{path}.group"),
                        format!("body {bi} has no edge group '{name}'"),
                    )
                })
        };
        match bc {
            BoundaryCondition::Fixed(f) => {
                let nodes = nodes_of(&f.group)?;
                for n in nodes {
                    if f.x {
                        m.constrained[2 * n as usize] = true;
                    }
                    if f.y {
                        m.constrained[2 * n as usize + 1] = true;
                    }
                }
            }
            BoundaryCondition::Velocity(_) | BoundaryCondition::Displacement(_) => {
                let (group, xy, ramp, displacement) = match bc {
                    BoundaryCondition::Velocity(v) => (&v.group, [v.x, v.y], v.ramp, false),
                    BoundaryCondition::Displacement(v) => (&v.group, [v.x, v.y], v.ramp, true),
                    _ => unreachable!(),
                };
                let history = evaluator(bc.history());
                let nodes = nodes_of(group)?;
                for n in nodes {
                    for (c, val) in xy.into_iter().enumerate() {
                        if let Some(val) = val {
                            let dof = 2 * n + c as u32;
                            m.constrained[dof as usize] = true;
                            m.prescribed.push(PrescribedDof {
                                dof,
                                velocity: val,
                                ramp,
                                history: history.clone(),
                                displacement,
                            });
                        }
                    }
                }
            }
            BoundaryCondition::Pressure(_) | BoundaryCondition::Traction(_) => {
                let (group, ramp) = match bc {
                    BoundaryCondition::Pressure(p) => (&p.group, p.ramp),
                    BoundaryCondition::Traction(p) => (&p.group, p.ramp),
                    _ => unreachable!(),
                };
                let history = evaluator(bc.history());
                let edges = edges_of(group)?;
                let forces = edge_forces(m, bc, group, edges, &opposite, &node_thickness).map_err(
                    |message| SceneError::Invalid {
                        file: file.to_path_buf(),
                        path: format!("{path}.group"),
                        message,
                        fix: "mesh the edge group conforming with the surface".into(),
                    },
                )?;
                m.loads.push(RampedLoad {
                    ramp,
                    forces,
                    history,
                });
            }
            BoundaryCondition::PointLoad(p) => {
                let nodes = nodes_of(&p.group)?;
                let k = nodes.len() as f64;
                let forces = nodes
                    .iter()
                    .flat_map(|&n| [(2 * n, p.force[0] / k), (2 * n + 1, p.force[1] / k)])
                    .collect();
                m.loads.push(RampedLoad {
                    ramp: p.ramp,
                    forces,
                    history: evaluator(bc.history()),
                });
            }
        }
    }
    Ok(())
}

/// The node opposite each edge of the model's triangles (key: sorted node pair; the last
/// triangle listed wins), and each node's thickness (that of the last triangle listed with it).
fn edge_tables(m: &Model) -> (HashMap<(u32, u32), u32>, Vec<f64>) {
    let mut opposite = HashMap::with_capacity(3 * m.triangles.len());
    for t in &m.triangles {
        for k in 0..3 {
            let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            opposite.insert((a.min(b), a.max(b)), c);
        }
    }
    let mut th = vec![0.0; m.x0.len()];
    for (e, t) in m.triangles.iter().enumerate() {
        for &i in t {
            th[i as usize] = m.tri_thickness[e];
        }
    }
    (opposite, th)
}

/// The consistent nodal forces (DOF, value) at full strength of a pressure or traction `bc`
/// on `edges` of group `group` (module docs); `opposite`: the node opposite each edge (key:
/// sorted node pair), for the outward normal. An edge of no triangle is an error (message).
fn edge_forces(
    m: &Model,
    bc: &BoundaryCondition,
    group: &str,
    edges: &[[u32; 2]],
    opposite: &HashMap<(u32, u32), u32>,
    node_thickness: &[f64],
) -> Result<Vec<(u32, f64)>, String> {
    let mut forces = Vec::with_capacity(4 * edges.len());
    for &[a, b] in edges {
        let Some(&c) = opposite.get(&(a.min(b), a.max(b))) else {
            return Err(format!(
                "edge ({a}, {b}) of group '{group}' is not an edge of any triangle"
            ));
        };
        let (pa, pb, pc) = (m.x0[a as usize], m.x0[b as usize], m.x0[c as usize]);
        let e = [pb[0] - pa[0], pb[1] - pa[1]];
        let len = (e[0] * e[0] + e[1] * e[1]).sqrt();
        let mut n = [e[1] / len, -e[0] / len];
        // Outward: away from the opposite node.
        if n[0] * (pc[0] - pa[0]) + n[1] * (pc[1] - pa[1]) > 0.0 {
            n = [-n[0], -n[1]];
        }
        let th = node_thickness[a as usize];
        let fvec = match bc {
            BoundaryCondition::Pressure(p) => [-p.value * n[0], -p.value * n[1]],
            BoundaryCondition::Traction(p) => match (p.value, p.local) {
                (Some(v), _) => v,
                // [normal, tangential] on (n, s), s = n turned 90 degrees counter-clockwise
                (None, Some([tn, ts])) => [tn * n[0] - ts * n[1], tn * n[1] + ts * n[0]],
                (None, None) => [0.0, 0.0],
            },
            _ => unreachable!(),
        };
        for node in [a, b] {
            for k in 0..2 {
                forces.push((2 * node + k as u32, 0.5 * fvec[k] * len * th));
            }
        }
    }
    Ok(forces)
}

fn same(a: &MaterialSpec, b: &MaterialSpec) -> bool {
    a.law == b.law
        && a.young == b.young
        && a.poisson == b.poisson
        && a.density == b.density
        && a.plane == b.plane
}
