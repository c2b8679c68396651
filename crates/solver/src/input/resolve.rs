//! Name resolution: every name a scene refers to is resolved here, once, against the scene's
//! bodies and their meshes, before anything else uses it.
//!
//! The names are: body names (unique when given), the keys of `bodies[i].materials` (material
//! regions of that body's mesh, or `"*"`), the `group` and `body` of every boundary condition
//! and history probe, the `body`, `groups` and `material` of every fracture region and
//! interface (a material: a key of `fracture.materials`), the `body` and `group` of every
//! pre-existing crack (an edge group), the `bodies` of every contact pair,
//! and the wall names (unique, `wall<i>` for an unnamed wall). [`walk`] visits
//! each of them with its JSON path; [`reference_fields`] lists them (the tests derive from
//! it the wrong-name cases, so a field cannot be left out), and [`resolve`] checks them, each
//! failure a [`SceneError::Invalid`] with the JSON path, what is wrong and the valid names.
//!
//! Also refused here, because they would make a name mean two things: an interface whose two
//! groups lie in different bodies, two contact pairs for the same two bodies, two identical history probes (the same
//! columns twice), and body or wall names with the characters `, [ ] /` that the CSV column
//! names use.

use std::path::Path;

use fdem_mesh::Mesh;

use crate::error::SceneError;
use crate::input::mesh_input::MeshInput;
use crate::input::scene::{BoundaryCondition, FractureSection, Probe, Scene};

/// The names a mesh offers to a scene.
#[derive(Debug, Clone, Default)]
pub struct MeshNames {
    /// The mesh file, for messages.
    pub source: String,
    /// Material regions: the surface groups that are the first group of some triangle, and
    /// `"default"` when some triangle is in none.
    pub regions: Vec<String>,
    /// Surface (dimension-2) groups.
    pub surfaces: Vec<String>,
    /// Edge (dimension-1) groups.
    pub edges: Vec<String>,
    /// Every physical group (any dimension).
    pub all: Vec<String>,
}

impl MeshNames {
    /// The names of `mesh`.
    pub fn of(mesh: &Mesh) -> Self {
        let of_dim = |d: Option<u8>| -> Vec<String> {
            let mut v: Vec<String> = mesh
                .groups
                .iter()
                .filter(|g| d.is_none_or(|d| g.dim == d))
                .map(|g| g.name.clone())
                .collect();
            v.sort();
            v.dedup();
            v
        };
        Self {
            source: mesh.source.clone(),
            regions: mesh.regions.clone(),
            surfaces: of_dim(Some(2)),
            edges: of_dim(Some(1)),
            all: of_dim(None),
        }
    }
}

impl MeshNames {
    /// The names of a mesh given as the solver's [`MeshInput`] (which keeps no group
    /// dimensions: its surface groups are taken to be its material regions).
    pub fn of_input(mesh: &MeshInput, source: &str) -> Self {
        let mut regions: Vec<String> = Vec::new();
        for g in &mesh.triangle_group {
            if !regions.contains(g) {
                regions.push(g.clone());
            }
        }
        let mut all: Vec<String> = mesh
            .node_groups
            .keys()
            .chain(mesh.edge_groups.keys())
            .cloned()
            .collect();
        all.sort();
        all.dedup();
        Self {
            source: source.to_string(),
            surfaces: regions.clone(),
            regions,
            edges: mesh.edge_groups.keys().cloned().collect(),
            all,
        }
    }
}

/// What a name field is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RefKind {
    /// A body's own name (`bodies[i].name`): unique among the bodies.
    BodyName,
    /// A wall's own name (`contact.walls[i].name`): unique among the walls.
    WallName,
    /// A body, by name.
    Body,
    /// A key of `bodies[i].materials`: a material region of the body's mesh, or `"*"`.
    MaterialKey,
    /// A physical group of any dimension (fixed, velocity, point load, probes).
    Group,
    /// An edge (dimension-1) group: pressure, traction and cracks.
    EdgeGroup,
    /// A surface (dimension-2) group: fracture regions and interfaces.
    SurfaceGroup,
    /// A joint material: a key of `fracture.materials` (fracture regions and interfaces).
    JointMaterial,
}

/// One name field of a scene.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RefField {
    /// The JSON path, as error messages give it (e.g. `fracture.regions[0].body`).
    pub path: String,
    /// The JSON pointer (RFC 6901) of the value; for a material key, of the entry whose key is
    /// the name.
    pub pointer: String,
    /// What the name is.
    pub kind: RefKind,
    /// The name the scene gives.
    pub name: String,
}

/// Where a resolved body goes (internal to [`resolve`]).
#[derive(Debug, Clone, Copy)]
enum Slot {
    None,
    Condition(usize),
    Probe(usize),
    Region(usize),
    Interface(usize, usize),
    Pair(usize, usize),
    InitialStress(usize),
}

/// A name field as [`walk`] visits it, with what its check needs.
struct Ref<'a> {
    path: String,
    pointer: String,
    kind: RefKind,
    name: &'a str,
    /// Material keys: the body. Groups: the body field beside it (or the only body).
    body: Scope<'a>,
    slot: Slot,
}

#[derive(Debug, Clone, Copy)]
enum Scope<'a> {
    None,
    Index(usize),
    Named(Option<&'a str>),
}

/// Escapes a JSON pointer token.
fn token(s: &str) -> String {
    s.replace('~', "~0").replace('/', "~1")
}

/// The kind name of a boundary condition, as in the scene (`fixed`, `point-load`, ...).
fn condition_kind(bc: &BoundaryCondition) -> &'static str {
    match bc {
        BoundaryCondition::Fixed(_) => "fixed",
        BoundaryCondition::Velocity(_) => "velocity",
        BoundaryCondition::Pressure(_) => "pressure",
        BoundaryCondition::Traction(_) => "traction",
        BoundaryCondition::PointLoad(_) => "point-load",
        BoundaryCondition::Displacement(_) => "displacement",
    }
}

/// Visits every name field of `scene`, in scene order (a `body` before the `group` beside it).
fn walk<'a>(
    scene: &'a Scene,
    f: &mut dyn FnMut(Ref<'a>) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    walk_bodies(scene, f)?;
    walk_conditions(scene, f)?;
    walk_probes(scene, f)?;
    if let Some(fr) = &scene.fracture {
        walk_regions(fr, f)?;
        walk_interfaces(fr, f)?;
        walk_cracks(fr, f)?;
    }
    walk_initial_stress(scene, f)?;
    if let Some(fl) = &scene.fluid {
        walk_fluid(fl, f)?;
    }
    walk_contact(scene, f)
}

/// The names of the `"fluid"` section (the injections' bodies, the pressures' bodies and
/// edge groups), for [`walk`].
fn walk_fluid<'a>(
    fl: &'a crate::input::scene::fluid::FluidSection,
    f: &mut dyn FnMut(Ref<'a>) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    for (i, inj) in fl.injections.iter().enumerate() {
        if let Some(b) = &inj.body {
            f(Ref {
                path: format!("fluid.injections[{i}].body"),
                pointer: format!("/fluid/injections/{i}/body"),
                kind: RefKind::Body,
                name: b,
                body: Scope::None,
                slot: Slot::None,
            })?;
        }
    }
    for (i, p) in fl.pressures.iter().enumerate() {
        if let Some(b) = &p.body {
            f(Ref {
                path: format!("fluid.pressures[{i}].body"),
                pointer: format!("/fluid/pressures/{i}/body"),
                kind: RefKind::Body,
                name: b,
                body: Scope::None,
                slot: Slot::None,
            })?;
        }
        f(Ref {
            path: format!("fluid.pressures[{i}].group"),
            pointer: format!("/fluid/pressures/{i}/group"),
            kind: RefKind::EdgeGroup,
            name: &p.group,
            body: Scope::Named(p.body.as_deref()),
            slot: Slot::None,
        })?;
    }
    Ok(())
}

/// The bodies' names and material keys, for [`walk`].
fn walk_bodies<'a>(
    scene: &'a Scene,
    f: &mut dyn FnMut(Ref<'a>) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    for (i, b) in scene.bodies.iter().enumerate() {
        if let Some(n) = &b.name {
            f(Ref {
                path: format!("bodies[{i}].name"),
                pointer: format!("/bodies/{i}/name"),
                kind: RefKind::BodyName,
                name: n,
                body: Scope::None,
                slot: Slot::None,
            })?;
        }
    }
    for (i, b) in scene.bodies.iter().enumerate() {
        for key in b.materials.keys() {
            f(Ref {
                path: format!("bodies[{i}].materials.{key}"),
                pointer: format!("/bodies/{i}/materials/{}", token(key)),
                kind: RefKind::MaterialKey,
                name: key,
                body: Scope::Index(i),
                slot: Slot::None,
            })?;
        }
    }
    Ok(())
}

/// The bodies and groups of `boundary_conditions`, for [`walk`].
fn walk_conditions<'a>(
    scene: &'a Scene,
    f: &mut dyn FnMut(Ref<'a>) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    for (i, bc) in scene.boundary_conditions.iter().enumerate() {
        let k = condition_kind(bc);
        if let Some(b) = bc.body() {
            f(Ref {
                path: format!("boundary_conditions[{i}].{k}.body"),
                pointer: format!("/boundary_conditions/{i}/{k}/body"),
                kind: RefKind::Body,
                name: b,
                body: Scope::None,
                slot: Slot::None,
            })?;
        }
        let edge = matches!(
            bc,
            BoundaryCondition::Pressure(_) | BoundaryCondition::Traction(_)
        );
        f(Ref {
            path: format!("boundary_conditions[{i}].{k}.group"),
            pointer: format!("/boundary_conditions/{i}/{k}/group"),
            kind: if edge {
                RefKind::EdgeGroup
            } else {
                RefKind::Group
            },
            name: bc.group(),
            body: Scope::Named(bc.body()),
            slot: Slot::Condition(i),
        })?;
    }
    Ok(())
}

/// The bodies and groups of `histories.probes`, for [`walk`].
fn walk_probes<'a>(
    scene: &'a Scene,
    f: &mut dyn FnMut(Ref<'a>) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    for (i, p) in scene.histories.probes.iter().enumerate() {
        let (k, g) = match p {
            Probe::Displacement(g) => ("displacement", g),
            Probe::Velocity(g) => ("velocity", g),
            Probe::Reaction(g) => ("reaction", g),
            Probe::Energy | Probe::Fluid => continue,
        };
        if let Some(b) = &g.body {
            f(Ref {
                path: format!("histories.probes[{i}].{k}.body"),
                pointer: format!("/histories/probes/{i}/{k}/body"),
                kind: RefKind::Body,
                name: b,
                body: Scope::None,
                slot: Slot::None,
            })?;
        }
        f(Ref {
            path: format!("histories.probes[{i}].{k}.group"),
            pointer: format!("/histories/probes/{i}/{k}/group"),
            kind: RefKind::Group,
            name: &g.group,
            body: Scope::Named(g.body.as_deref()),
            slot: Slot::Probe(i),
        })?;
    }
    Ok(())
}

/// The bodies, groups and materials of `fracture.regions`, for [`walk`].
fn walk_regions<'a>(
    fr: &'a FractureSection,
    f: &mut dyn FnMut(Ref<'a>) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    for (i, r) in fr.regions.iter().enumerate() {
        if let Some(b) = &r.body {
            f(Ref {
                path: format!("fracture.regions[{i}].body"),
                pointer: format!("/fracture/regions/{i}/body"),
                kind: RefKind::Body,
                name: b,
                body: Scope::None,
                slot: Slot::Region(i),
            })?;
        }
        for (j, g) in r.groups.iter().flatten().enumerate() {
            f(Ref {
                path: format!("fracture.regions[{i}].groups[{j}]"),
                pointer: format!("/fracture/regions/{i}/groups/{j}"),
                kind: RefKind::SurfaceGroup,
                name: g,
                body: Scope::Named(r.body.as_deref()),
                slot: Slot::None,
            })?;
        }
        if let Some(m) = &r.material {
            f(Ref {
                path: format!("fracture.regions[{i}].material"),
                pointer: format!("/fracture/regions/{i}/material"),
                kind: RefKind::JointMaterial,
                name: m,
                body: Scope::None,
                slot: Slot::None,
            })?;
        }
    }
    Ok(())
}

/// The bodies of `contact.pairs` and the names of `contact.walls`, for [`walk`].
fn walk_contact<'a>(
    scene: &'a Scene,
    f: &mut dyn FnMut(Ref<'a>) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    if let Some(c) = &scene.contact {
        for (i, p) in c.pairs.iter().enumerate() {
            for (k, b) in p.bodies.iter().enumerate() {
                f(Ref {
                    path: format!("contact.pairs[{i}].bodies[{k}]"),
                    pointer: format!("/contact/pairs/{i}/bodies/{k}"),
                    kind: RefKind::Body,
                    name: b,
                    body: Scope::None,
                    slot: Slot::Pair(i, k),
                })?;
            }
        }
        for (i, w) in c.walls.iter().enumerate() {
            if let Some(n) = &w.name {
                f(Ref {
                    path: format!("contact.walls[{i}].name"),
                    pointer: format!("/contact/walls/{i}/name"),
                    kind: RefKind::WallName,
                    name: n,
                    body: Scope::None,
                    slot: Slot::None,
                })?;
            }
        }
    }
    Ok(())
}

/// The names of `fracture.cracks` (bodies and edge groups), for [`walk`].
fn walk_cracks<'a>(
    fr: &'a FractureSection,
    f: &mut dyn FnMut(Ref<'a>) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    for (i, c) in fr.cracks.iter().enumerate() {
        if let Some(b) = &c.body {
            f(Ref {
                path: format!("fracture.cracks[{i}].body"),
                pointer: format!("/fracture/cracks/{i}/body"),
                kind: RefKind::Body,
                name: b,
                body: Scope::None,
                slot: Slot::None,
            })?;
        }
        f(Ref {
            path: format!("fracture.cracks[{i}].group"),
            pointer: format!("/fracture/cracks/{i}/group"),
            kind: RefKind::EdgeGroup,
            name: &c.group,
            body: Scope::Named(c.body.as_deref()),
            slot: Slot::None,
        })?;
    }
    Ok(())
}

/// The names of `fracture.interfaces`, for [`walk`].
fn walk_interfaces<'a>(
    fr: &'a crate::input::scene::FractureSection,
    f: &mut dyn FnMut(Ref<'a>) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    for (i, it) in fr.interfaces.iter().enumerate() {
        if let Some(b) = &it.body {
            f(Ref {
                path: format!("fracture.interfaces[{i}].body"),
                pointer: format!("/fracture/interfaces/{i}/body"),
                kind: RefKind::Body,
                name: b,
                body: Scope::None,
                slot: Slot::None,
            })?;
        }
        for (k, g) in it.groups.iter().enumerate() {
            f(Ref {
                path: format!("fracture.interfaces[{i}].groups[{k}]"),
                pointer: format!("/fracture/interfaces/{i}/groups/{k}"),
                kind: RefKind::SurfaceGroup,
                name: g,
                body: Scope::Named(it.body.as_deref()),
                slot: Slot::Interface(i, k),
            })?;
        }
        f(Ref {
            path: format!("fracture.interfaces[{i}].material"),
            pointer: format!("/fracture/interfaces/{i}/material"),
            kind: RefKind::JointMaterial,
            name: &it.material,
            body: Scope::None,
            slot: Slot::None,
        })?;
    }
    Ok(())
}

/// The names of `scene.initial_stress` for [`walk`]: each entry's `body`, then its `groups`.
fn walk_initial_stress<'a>(
    scene: &'a Scene,
    f: &mut dyn FnMut(Ref<'a>) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    for (i, e) in scene.initial_stress.iter().enumerate() {
        if let Some(b) = &e.body {
            f(Ref {
                path: format!("initial_stress[{i}].body"),
                pointer: format!("/initial_stress/{i}/body"),
                kind: RefKind::Body,
                name: b,
                body: Scope::None,
                slot: Slot::InitialStress(i),
            })?;
        }
        for (j, g) in e.groups.iter().flatten().enumerate() {
            f(Ref {
                path: format!("initial_stress[{i}].groups[{j}]"),
                pointer: format!("/initial_stress/{i}/groups/{j}"),
                kind: RefKind::SurfaceGroup,
                name: g,
                body: Scope::Named(e.body.as_deref()),
                slot: Slot::InitialStress(i),
            })?;
        }
    }
    Ok(())
}

/// Every name field of `scene` that [`resolve`] checks, with its JSON path and pointer.
pub fn reference_fields(scene: &Scene) -> Vec<RefField> {
    let mut out = Vec::new();
    let _ = walk(scene, &mut |r| {
        out.push(RefField {
            path: r.path,
            pointer: r.pointer,
            kind: r.kind,
            name: r.name.to_string(),
        });
        Ok(())
    });
    out
}

/// The bodies the scene's names resolve to (indices into `scene.bodies`).
#[derive(Debug, Clone, Default)]
pub struct Resolved {
    /// The body of each boundary condition.
    pub conditions: Vec<usize>,
    /// The body of each history probe (`None`: the energy probe).
    pub probes: Vec<Option<usize>>,
    /// For each body, the fracture regions that explode it (none: it does not fracture).
    pub fracture_regions: Vec<Vec<usize>>,
    /// The body of the two groups of each fracture interface.
    pub interfaces: Vec<[usize; 2]>,
    /// The two bodies of each contact pair.
    pub pairs: Vec<[usize; 2]>,
    /// The body of each `initial_stress` entry.
    pub initial_stress: Vec<usize>,
}

/// A list of names for a message: `a, b, c`, or `(none)`.
fn list<S: AsRef<str>>(names: &[S]) -> String {
    if names.is_empty() {
        "(none)".into()
    } else {
        names
            .iter()
            .map(|s| s.as_ref())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// What the checks of [`resolve`] share: the scene, its file and its bodies' mesh names.
struct Resolver<'a> {
    scene: &'a Scene,
    file: &'a Path,
    meshes: &'a [MeshNames],
    /// The bodies' names, in scene order.
    named: Vec<&'a str>,
}

impl<'a> Resolver<'a> {
    fn bad(&self, path: &str, message: String, fix: String) -> SceneError {
        SceneError::Invalid {
            file: self.file.to_path_buf(),
            path: path.to_string(),
            message,
            fix,
        }
    }

    /// The fix for a body name that names no body.
    fn body_fix(&self) -> String {
        if self.named.is_empty() {
            "no body has a name: give the body a \"name\" and use it here".to_string()
        } else {
            format!("use one of: {}", list(&self.named))
        }
    }

    fn body_index(&self, name: &str) -> Option<usize> {
        self.scene
            .bodies
            .iter()
            .position(|b| b.name.as_deref() == Some(name))
    }

    /// A body as messages name it: by name or index, with its mesh file.
    fn label(&self, bi: usize) -> String {
        match &self.scene.bodies[bi].name {
            Some(n) => format!("body '{n}' ({})", self.meshes[bi].source),
            None => format!("bodies[{bi}] ({})", self.meshes[bi].source),
        }
    }

    /// A body's or a wall's own name: no characters of the CSV column names; bodies unique.
    fn own_name(&self, r: &Ref<'_>) -> Result<(), SceneError> {
        let what = if r.kind == RefKind::BodyName {
            "body"
        } else {
            "wall"
        };
        if r.name.is_empty() || r.name.contains([',', '[', ']', '/']) {
            return Err(self.bad(
                &r.path,
                format!(
                    "the {what} name '{}' is empty or has one of the characters , [ ] / \
                     that the CSV column names use",
                    r.name
                ),
                format!("give the {what} a name without them"),
            ));
        }
        if r.kind == RefKind::BodyName {
            let first = self.body_index(r.name).unwrap_or(0);
            if format!("bodies[{first}].name") != r.path {
                return Err(self.bad(
                    &r.path,
                    format!("bodies[{first}] is also named '{}'", r.name),
                    "give every body its own name".into(),
                ));
            }
        }
        Ok(())
    }

    /// A body named by a condition, probe, fracture region or contact pair.
    fn body(&self, r: &Ref<'_>, out: &mut Resolved) -> Result<(), SceneError> {
        let Some(bi) = self.body_index(r.name) else {
            return Err(self.bad(
                &r.path,
                format!("no body is named '{}'", r.name),
                self.body_fix(),
            ));
        };
        match r.slot {
            Slot::Region(i) => out.fracture_regions[bi].push(i),
            Slot::Pair(i, k) => out.pairs[i][k] = bi,
            Slot::InitialStress(i) => out.initial_stress[i] = bi,
            _ => {}
        }
        Ok(())
    }

    /// A key of a body's materials: a surface group of its mesh, or `"*"`.
    fn material_key(&self, r: &Ref<'_>) -> Result<(), SceneError> {
        let Scope::Index(bi) = r.body else {
            return Ok(());
        };
        let m = &self.meshes[bi];
        if r.name != "*" && !m.regions.iter().any(|g| g == r.name) {
            return Err(self.bad(
                &r.path,
                format!(
                    "the mesh {} has no surface group named '{}'",
                    m.source, r.name
                ),
                format!(
                    "use one of: {} (or \"*\" for every triangle)",
                    list(&m.regions)
                ),
            ));
        }
        Ok(())
    }

    /// A group of the named body's mesh (or of the only body's that has it), of the
    /// dimension the field needs.
    fn group(&self, r: &Ref<'_>, out: &mut Resolved) -> Result<(), SceneError> {
        let Scope::Named(body) = r.body else {
            return Ok(());
        };
        let names_of = |bi: usize| -> &Vec<String> {
            match r.kind {
                RefKind::EdgeGroup => &self.meshes[bi].edges,
                RefKind::SurfaceGroup => &self.meshes[bi].surfaces,
                _ => &self.meshes[bi].all,
            }
        };
        let what = match r.kind {
            RefKind::EdgeGroup => "edge group (dimension 1)",
            RefKind::SurfaceGroup => "surface group (dimension 2)",
            _ => "group",
        };
        let note = match r.kind {
            RefKind::EdgeGroup => {
                " (pressure, traction and cracks act on the edges of an edge group)"
            }
            RefKind::SurfaceGroup => {
                " (fracture regions and interfaces are made of surface groups)"
            }
            _ => "",
        };
        let bodies: Vec<usize> = match body {
            // the body field was resolved just before
            Some(b) => self.body_index(b).into_iter().collect(),
            None => (0..self.scene.bodies.len()).collect(),
        };
        let hits: Vec<usize> = bodies
            .iter()
            .copied()
            .filter(|&bi| names_of(bi).iter().any(|g| g == r.name))
            .collect();
        let bi = match (hits.len(), body) {
            (1, _) => hits[0],
            (0, _) if bodies.len() == 1 => {
                let bi = bodies[0];
                let other = if r.kind != RefKind::Group
                    && self.meshes[bi].all.iter().any(|g| g == r.name)
                {
                    " (a group of another dimension has this name)"
                } else {
                    ""
                };
                return Err(self.bad(
                    &r.path,
                    format!("{} has no {what} named '{}'{other}", self.label(bi), r.name),
                    format!("use one of: {}{note}", list(names_of(bi))),
                ));
            }
            (0, _) => {
                let mut all: Vec<String> = Vec::new();
                for &bi in &bodies {
                    for g in names_of(bi) {
                        let n = match &self.scene.bodies[bi].name {
                            Some(b) => format!("{g} (body {b})"),
                            None => format!("{g} (bodies[{bi}])"),
                        };
                        all.push(n);
                    }
                }
                return Err(self.bad(
                    &r.path,
                    format!("no body's mesh has a {what} named '{}'", r.name),
                    format!("use one of: {}{note}", list(&all)),
                ));
            }
            _ => {
                let which: Vec<String> = hits.iter().map(|&b| self.label(b)).collect();
                let names: Vec<&str> = hits
                    .iter()
                    .filter_map(|&b| self.scene.bodies[b].name.as_deref())
                    .collect();
                let parent = r.path.rsplit_once('.').map_or("", |p| p.0);
                return Err(self.bad(
                    &r.path,
                    format!(
                        "several bodies have a {what} named '{}': {}",
                        r.name,
                        list(&which)
                    ),
                    if names.len() == hits.len() {
                        format!("add \"body\" to {parent}: one of: {}", list(&names))
                    } else {
                        format!("name the bodies (\"name\") and add \"body\" to {parent}")
                    },
                ));
            }
        };
        match r.slot {
            Slot::Condition(i) => out.conditions[i] = bi,
            Slot::Probe(i) => out.probes[i] = Some(bi),
            Slot::Interface(i, k) => out.interfaces[i][k] = bi,
            Slot::InitialStress(i) => {
                let named = self.scene.initial_stress[i].body.is_some();
                if !named && r.path.ends_with("groups[0]") {
                    out.initial_stress[i] = bi;
                } else if out.initial_stress[i] != bi {
                    return Err(self.bad(
                        &r.path,
                        format!(
                            "the group '{}' is in {}, the entry's other groups in {}",
                            r.name,
                            self.label(bi),
                            self.label(out.initial_stress[i])
                        ),
                        "give each body its own entry, with \"body\"".into(),
                    ));
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// A key of `fracture.materials`.
    fn joint_material(&self, r: &Ref<'_>) -> Result<(), SceneError> {
        let Some(fr) = &self.scene.fracture else {
            return Ok(());
        };
        if fr.materials.contains_key(r.name) {
            return Ok(());
        }
        let names: Vec<&String> = fr.materials.keys().collect();
        Err(self.bad(
            &r.path,
            format!("no joint material is named '{}'", r.name),
            if names.is_empty() {
                "name the materials under fracture.materials and use one of their keys here".into()
            } else {
                format!(
                    "use one of: {} (the keys of fracture.materials)",
                    list(&names)
                )
            },
        ))
    }

    /// The two groups of an interface lie in one body, which fractures.
    fn interfaces_in_one_body(&self, out: &Resolved) -> Result<(), SceneError> {
        for (i, b) in out.interfaces.iter().enumerate() {
            if b[0] != b[1] {
                return Err(self.bad(
                    &format!("fracture.interfaces[{i}].groups"),
                    format!(
                        "the groups lie in different bodies: {} and {}",
                        self.label(b[0]),
                        self.label(b[1])
                    ),
                    "an interface joins two groups of one body: add \"body\" to it".into(),
                ));
            }
            if out.fracture_regions[b[0]].is_empty() {
                return Err(self.bad(
                    &format!("fracture.interfaces[{i}]"),
                    format!(
                        "{} has no fracture region, so no joint lies between the groups",
                        self.label(b[0])
                    ),
                    "add a fracture region for the body (its joints are made by the explode \
                     of the regions)"
                        .into(),
                ));
            }
        }
        Ok(())
    }

    /// Fracture regions without a body: the only body (several bodies refused before).
    fn regions_without_body(&self, out: &mut Resolved) -> Result<(), SceneError> {
        if let Some(fr) = &self.scene.fracture {
            for (i, r) in fr.regions.iter().enumerate() {
                if r.body.is_some() {
                    continue;
                }
                out.fracture_regions[0].push(i);
            }
        }
        Ok(())
    }

    /// Every material region of every body has a material.
    fn materials_cover_regions(&self) -> Result<(), SceneError> {
        for (bi, (b, m)) in self.scene.bodies.iter().zip(self.meshes).enumerate() {
            if b.materials.contains_key("*") {
                continue;
            }
            if let Some(g) = m.regions.iter().find(|g| !b.materials.contains_key(*g)) {
                return Err(self.bad(
                    &format!("bodies[{bi}].materials"),
                    format!(
                        "the surface group '{g}' of {} has no material (given: {})",
                        m.source,
                        list(&b.materials.keys().collect::<Vec<_>>())
                    ),
                    format!("add a material for \"{g}\" or a default under \"*\""),
                ));
            }
        }
        Ok(())
    }

    /// Wall names, given or default (`wall<i>`, as in walls.csv), are unique; one law per
    /// pair of bodies.
    fn contact_names(&self, out: &Resolved) -> Result<(), SceneError> {
        if let Some(c) = &self.scene.contact {
            let names: Vec<String> = c
                .walls
                .iter()
                .enumerate()
                .map(|(i, w)| w.name.clone().unwrap_or_else(|| format!("wall{i}")))
                .collect();
            for (j, n) in names.iter().enumerate() {
                if let Some(i) = names[..j].iter().position(|m| m == n) {
                    let path = if c.walls[j].name.is_some() {
                        format!("contact.walls[{j}].name")
                    } else {
                        format!("contact.walls[{i}].name")
                    };
                    return Err(self.bad(
                        &path,
                        format!(
                            "contact.walls[{i}] and contact.walls[{j}] are both named '{n}' (an unnamed wall i is 'wall<i>')"
                        ),
                        "give every wall its own name".into(),
                    ));
                }
            }
            // One law per pair of bodies.
            for j in 0..out.pairs.len() {
                let key = |p: [usize; 2]| [p[0].min(p[1]), p[0].max(p[1])];
                if let Some(i) = (0..j).find(|&i| key(out.pairs[i]) == key(out.pairs[j])) {
                    return Err(self.bad(
                        &format!("contact.pairs[{j}].bodies"),
                        format!("contact.pairs[{i}] is already the pair of these two bodies"),
                        "give each pair of bodies one entry".into(),
                    ));
                }
            }
        }
        Ok(())
    }

    /// No two probes give the same columns.
    fn probes_unique(&self, out: &Resolved) -> Result<(), SceneError> {
        for j in 0..self.scene.histories.probes.len() {
            let same = |i: usize| {
                let (a, b) = (
                    &self.scene.histories.probes[i],
                    &self.scene.histories.probes[j],
                );
                std::mem::discriminant(a) == std::mem::discriminant(b)
                    && out.probes[i] == out.probes[j]
                    && match (a, b) {
                        (
                            Probe::Displacement(x) | Probe::Velocity(x) | Probe::Reaction(x),
                            Probe::Displacement(y) | Probe::Velocity(y) | Probe::Reaction(y),
                        ) => x.group == y.group,
                        _ => true,
                    }
            };
            if let Some(i) = (0..j).find(|&i| same(i)) {
                return Err(self.bad(
                    &format!("histories.probes[{j}]"),
                    format!("the same probe as histories.probes[{i}] (its columns would repeat)"),
                    "remove one of the two".into(),
                ));
            }
        }
        Ok(())
    }
}

/// Resolves every name of `scene` against its bodies' meshes (`meshes[i]` of `bodies[i]`).
pub fn resolve(scene: &Scene, file: &Path, meshes: &[MeshNames]) -> Result<Resolved, SceneError> {
    let cx = Resolver {
        scene,
        file,
        meshes,
        named: scene
            .bodies
            .iter()
            .filter_map(|b| b.name.as_deref())
            .collect(),
    };
    if let Some(fr) = &scene.fracture
        && scene.bodies.len() > 1
        && let Some(i) = fr.regions.iter().position(|r| r.body.is_none())
    {
        return Err(cx.bad(
            &format!("fracture.regions[{i}]"),
            "the scene has several bodies and the region names none".into(),
            format!("add \"body\": {}", cx.body_fix()),
        ));
    }
    let mut out = Resolved {
        conditions: vec![0; scene.boundary_conditions.len()],
        probes: vec![None; scene.histories.probes.len()],
        fracture_regions: vec![Vec::new(); scene.bodies.len()],
        interfaces: vec![[0, 0]; scene.fracture.as_ref().map_or(0, |f| f.interfaces.len())],
        pairs: vec![[0, 0]; scene.contact.as_ref().map_or(0, |c| c.pairs.len())],
        initial_stress: vec![0; scene.initial_stress.len()],
    };
    if scene.bodies.len() > 1
        && let Some(i) = scene
            .initial_stress
            .iter()
            .position(|e| e.body.is_none() && e.groups.is_none())
    {
        return Err(cx.bad(
            &format!("initial_stress[{i}]"),
            "the scene has several bodies and the entry names neither a body nor groups".into(),
            format!("add \"body\": {}", cx.body_fix()),
        ));
    }
    walk(scene, &mut |r: Ref<'_>| match r.kind {
        RefKind::BodyName | RefKind::WallName => cx.own_name(&r),
        RefKind::Body => cx.body(&r, &mut out),
        RefKind::MaterialKey => cx.material_key(&r),
        RefKind::Group | RefKind::EdgeGroup | RefKind::SurfaceGroup => cx.group(&r, &mut out),
        RefKind::JointMaterial => cx.joint_material(&r),
    })?;
    cx.regions_without_body(&mut out)?;
    for r in &mut out.fracture_regions {
        r.sort_unstable();
    }
    cx.interfaces_in_one_body(&out)?;
    cx.materials_cover_regions()?;
    cx.contact_names(&out)?;
    cx.probes_unique(&out)?;
    Ok(out)
}
