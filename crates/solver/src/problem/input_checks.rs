//! Whole-scene checks at load time, on the bodies' meshes as read (before the fracturing
//! bodies are exploded): rules that no single field can check.
//!
//! - **Loads act on the boundary** ([`check_loaded_edges`]): a pressure or traction acts on
//!   the edges of an edge group, from the one triangle beside each. An internal edge (a
//!   triangle on both sides) has no outside: loading it would push on one side chosen by the
//!   mesh's numbering. It is refused, unless the edge is on a pre-existing crack
//!   (`fracture.cracks`), whose two faces are then both loaded.
//! - **Sections act on something** ([`check_fracture_acts`], [`unused_materials`]): a
//!   fracture section with no region, a region with an empty `groups` list and a fracturing
//!   body that ends up with no joint are refused; a named joint material that no region or
//!   interface uses is a warning.
//! - **Bodies start apart** ([`check_initial_overlap`]): two bodies in contact that overlap at
//!   t = 0 (a node or triangle centroid of one lies inside the other, deeper than
//!   [`OVERLAP_TOL`] times the smaller mean edge length), or a body that starts behind a rigid
//!   wall, would start with the penalty energy of the whole overlap. Refused, naming the two
//!   and the depth, unless the scene says the overlap is deliberate
//!   (`allow_initial_overlap` on the contact pair or the wall).
//! - **A static solution is a number** ([`check_static_range`]): a linear static solve scales
//!   with its loads, so a load whose strain estimate `s` ([`crate::problem::strains::input_strains`])
//!   gives an energy density `s^2 E` beyond the floating-point range would give a solution
//!   that cannot be written, and one with `s` below `MIN_POSITIVE / EPSILON` (about 1e-292)
//!   displacements that underflow to zero. Refused at the load's JSON path before the solve.

use std::collections::HashSet;
use std::path::Path;

use fdem_mesh::Mesh;

use crate::error::SceneError;
use crate::input::resolve::Resolved;
use crate::input::scene::{BoundaryCondition, Scene};

/// An overlap deeper than this fraction of the smaller mean edge length of the two bodies is
/// refused (bodies that touch along a shared boundary, up to round-off, are not overlapping).
pub const OVERLAP_TOL: f64 = 1e-6;

/// At most this many points found inside the other body are measured for the depth (evenly
/// spread over those found, each standing for its share in the count reported).
const MAX_DEPTH_POINTS: usize = 20_000;

/// How a body is named in messages: `'name'` or `bodies[i]`.
fn body_label(scene: &Scene, i: usize) -> String {
    match &scene.bodies[i].name {
        Some(n) => format!("body '{n}'"),
        None => format!("bodies[{i}]"),
    }
}

/// The crack edges of body `bi` (sorted node pairs of the mesh as read).
fn crack_edges(scene: &Scene, meshes: &[Mesh], bi: usize) -> HashSet<(u32, u32)> {
    let mut set = HashSet::new();
    let Some(f) = &scene.fracture else {
        return set;
    };
    for c in &f.cracks {
        let here = match &c.body {
            Some(name) => scene.bodies[bi].name.as_deref() == Some(name.as_str()),
            None => true,
        };
        if !here {
            continue;
        }
        let group = meshes[bi]
            .groups
            .iter()
            .find(|g| g.dim == 1 && g.name == c.group);
        for e in group.iter().flat_map(|g| g.edges.iter()) {
            set.insert((e[0].0.min(e[1].0), e[0].0.max(e[1].0)));
        }
    }
    set
}

/// Refuses a pressure or traction on an internal edge (a triangle on both sides) that is not
/// on a pre-existing crack (module docs). `meshes`: the bodies' meshes as read;
/// `refs.conditions`: the body of each boundary condition.
pub fn check_loaded_edges(
    scene: &Scene,
    file: &Path,
    meshes: &[Mesh],
    refs: &Resolved,
) -> Result<(), SceneError> {
    for (i, bc) in scene.boundary_conditions.iter().enumerate() {
        let kind = match bc {
            BoundaryCondition::Pressure(_) => "pressure",
            BoundaryCondition::Traction(_) => "traction",
            _ => continue,
        };
        let bi = refs.conditions.get(i).copied().unwrap_or(0);
        let mesh = &meshes[bi];
        let Some(group) = mesh
            .groups
            .iter()
            .find(|g| g.dim == 1 && g.name == bc.group())
        else {
            continue;
        };
        // the mesh's internal edges, by sorted node pair: built once per loaded group
        let internal: HashSet<(u32, u32)> = (mesh.edges.iter())
            .filter(|m| m.right.is_some())
            .map(|m| {
                (
                    m.nodes[0].0.min(m.nodes[1].0),
                    m.nodes[0].0.max(m.nodes[1].0),
                )
            })
            .collect();
        let mut interior = (group.edges.iter())
            .filter(|e| internal.contains(&(e[0].0.min(e[1].0), e[0].0.max(e[1].0))));
        let Some(first) = interior.next() else {
            continue;
        };
        let cracks = crack_edges(scene, meshes, bi);
        let count = 1 + interior.count();
        let on_crack =
            |e: &[fdem_mesh::NodeId; 2]| cracks.contains(&(e[0].0.min(e[1].0), e[0].0.max(e[1].0)));
        if cracks.is_empty() || !group.edges.iter().all(on_crack) {
            let tag = |n: fdem_mesh::NodeId| mesh.node_tags[n.idx()];
            return Err(SceneError::invalid(
                file,
                format!("boundary_conditions[{i}].{kind}.group"),
                format!(
                    "group '{}' of {} has {count} internal edge(s) (a triangle on both sides; the first between nodes {} and {}): a {kind} there would push on one side only, chosen by the mesh's numbering",
                    group.name,
                    body_label(scene, bi),
                    tag(first[0]),
                    tag(first[1]),
                ),
                format!(
                    "load only boundary edges (an edge group on the body's outline), or make the edges a pre-existing crack (`fracture.cracks`, group '{}'), whose two faces are then both loaded",
                    group.name
                ),
            ));
        }
    }
    Ok(())
}

/// Refuses the fracture section's parts that would explode nothing: no region at all, a
/// region with an empty `groups` list (leave `groups` out for the whole body). Checked on the
/// scene alone, before the meshes are read.
pub fn check_fracture_regions(scene: &Scene, file: &Path) -> Result<(), SceneError> {
    let Some(f) = &scene.fracture else {
        return Ok(());
    };
    if f.regions.is_empty() {
        return Err(SceneError::invalid(
            file,
            "fracture.regions",
            "the fracture section has no region: it would explode no triangle and the run would be elastic",
            "add a region (e.g. {\"regions\": [{}]} for the whole body), or remove the \"fracture\" section",
        ));
    }
    for (i, r) in f.regions.iter().enumerate() {
        if r.groups.as_ref().is_some_and(|g| g.is_empty()) {
            return Err(SceneError::invalid(
                file,
                format!("fracture.regions[{i}].groups"),
                "an empty list of groups explodes no triangle",
                "name the surface groups that fracture, or leave `groups` out to fracture the whole body",
            ));
        }
    }
    Ok(())
}

/// Refuses a fracturing body (one with a region) that has no joint once exploded: its regions
/// have no internal edge (e.g. a single triangle). `bodies` holds the joints found per body
/// ([`crate::problem::Fracturing::bodies`]).
pub fn check_fracture_acts(
    scene: &Scene,
    file: &Path,
    refs: &Resolved,
    bodies: &[(usize, Vec<fdem_fracture::Joint>)],
) -> Result<(), SceneError> {
    for (bi, regions) in refs.fracture_regions.iter().enumerate() {
        let Some(&ri) = regions.first() else {
            continue;
        };
        let joints = bodies
            .iter()
            .filter(|(b, _)| *b == bi)
            .map(|(_, j)| j.len())
            .sum::<usize>();
        if joints == 0 {
            return Err(SceneError::invalid(
                file,
                format!("fracture.regions[{ri}]"),
                format!(
                    "the fracture regions of {} have no internal edge: no joint, nothing can fracture",
                    body_label(scene, bi)
                ),
                "name surface groups with at least two adjacent triangles, or refine the mesh",
            ));
        }
    }
    Ok(())
}

/// The warnings for named joint materials (`fracture.materials`) that no region and no
/// interface uses.
pub fn unused_materials(scene: &Scene) -> Vec<String> {
    let Some(f) = &scene.fracture else {
        return Vec::new();
    };
    let used: HashSet<&str> = (f.regions.iter().filter_map(|r| r.material.as_deref()))
        .chain(f.interfaces.iter().map(|i| i.material.as_str()))
        .collect();
    f.materials
        .keys()
        .filter(|k| !used.contains(k.as_str()))
        .map(|k| {
            format!(
                "fracture.materials.{k}: no region or interface uses this joint material; name it in a region's or an interface's `material`, or remove it"
            )
        })
        .collect()
}

/// The mean edge length of a mesh's triangles [m].
fn mean_edge(mesh: &Mesh) -> f64 {
    let mut sum = 0.0;
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (
                mesh.nodes[t[k] as usize],
                mesh.nodes[t[(k + 1) % 3] as usize],
            );
            sum += ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        }
    }
    sum / (3 * mesh.triangles.len()).max(1) as f64
}

/// Bounding box `[xmin, ymin, xmax, ymax]` of a mesh's nodes.
fn bbox(mesh: &Mesh) -> [f64; 4] {
    mesh.nodes.iter().fold(
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ],
        |b, p| {
            [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ]
        },
    )
}

/// Distance from `p` to the segment `a b`.
fn seg_dist(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
    let l2 = ex * ex + ey * ey;
    let s = if l2 > 0.0 {
        (((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (dx, dy) = (p[0] - a[0] - s * ex, p[1] - a[1] - s * ey);
    (dx * dx + dy * dy).sqrt()
}

/// A uniform grid of a mesh's triangles by bounding box, for point location.
struct TriGrid<'a> {
    mesh: &'a Mesh,
    origin: [f64; 2],
    cell: f64,
    dims: [usize; 2],
    cells: Vec<Vec<u32>>,
}

impl<'a> TriGrid<'a> {
    fn new(mesh: &'a Mesh) -> Self {
        let b = bbox(mesh);
        let n = mesh.triangles.len().max(1) as f64;
        let area = ((b[2] - b[0]) * (b[3] - b[1])).max(f64::MIN_POSITIVE);
        let cell = (area / n).sqrt().max(1e-300) * 2.0;
        let dim = |lo: f64, hi: f64| (((hi - lo) / cell).floor() as usize + 1).min(4096);
        let dims = [dim(b[0], b[2]), dim(b[1], b[3])];
        let mut cells = vec![Vec::new(); dims[0] * dims[1]];
        let origin = [b[0], b[1]];
        let at = |v: f64, o: f64, d: usize| (((v - o) / cell).floor().max(0.0) as usize).min(d - 1);
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let p = tri.map(|i| mesh.nodes[i as usize]);
            let (x0, x1) = (
                p[0][0].min(p[1][0]).min(p[2][0]),
                p[0][0].max(p[1][0]).max(p[2][0]),
            );
            let (y0, y1) = (
                p[0][1].min(p[1][1]).min(p[2][1]),
                p[0][1].max(p[1][1]).max(p[2][1]),
            );
            for i in at(x0, origin[0], dims[0])..=at(x1, origin[0], dims[0]) {
                for j in at(y0, origin[1], dims[1])..=at(y1, origin[1], dims[1]) {
                    cells[j * dims[0] + i].push(t as u32);
                }
            }
        }
        Self {
            mesh,
            origin,
            cell,
            dims,
            cells,
        }
    }

    /// True when `p` lies in a triangle of the mesh (on its edges included).
    fn contains(&self, p: [f64; 2]) -> bool {
        let (fx, fy) = (
            (p[0] - self.origin[0]) / self.cell,
            (p[1] - self.origin[1]) / self.cell,
        );
        if !(fx >= 0.0 && fy >= 0.0) {
            return false;
        }
        let (i, j) = (fx.floor() as usize, fy.floor() as usize);
        if i >= self.dims[0] || j >= self.dims[1] {
            return false;
        }
        self.cells[j * self.dims[0] + i].iter().any(|&t| {
            let [a, b, c] = self.mesh.triangles[t as usize].map(|n| self.mesh.nodes[n as usize]);
            let cross = |u: [f64; 2], v: [f64; 2]| {
                (v[0] - u[0]) * (p[1] - u[1]) - (v[1] - u[1]) * (p[0] - u[0])
            };
            cross(a, b) >= 0.0 && cross(b, c) >= 0.0 && cross(c, a) >= 0.0
        })
    }

    /// The distance from `p` to the mesh's boundary.
    fn depth(&self, p: [f64; 2]) -> f64 {
        let m = self.mesh;
        m.boundary_edges
            .iter()
            .map(|e| {
                let [a, b] = m.edges[e.idx()].nodes;
                seg_dist(p, m.nodes[a.idx()], m.nodes[b.idx()])
            })
            .fold(f64::INFINITY, f64::min)
    }
}

/// The deepest point of `b` (its nodes and triangle centroids) inside `a`, deeper than `tol`:
/// (depth, point, how many points are inside deeper than `tol`).
fn deepest_inside(a: &Mesh, b: &Mesh, tol: f64) -> Option<(f64, [f64; 2], usize)> {
    let (ba, bb) = (bbox(a), bbox(b));
    if ba[0] > bb[2] || bb[0] > ba[2] || ba[1] > bb[3] || bb[1] > ba[3] {
        return None;
    }
    let grid = TriGrid::new(a);
    let centroids = b.triangles.iter().map(|t| {
        let p = t.map(|i| b.nodes[i as usize]);
        [
            (p[0][0] + p[1][0] + p[2][0]) / 3.0,
            (p[0][1] + p[1][1] + p[2][1]) / 3.0,
        ]
    });
    let inside: Vec<[f64; 2]> = (b.nodes.iter().copied())
        .chain(centroids)
        .filter(|&p| grid.contains(p))
        .collect();
    let stride = inside.len().div_ceil(MAX_DEPTH_POINTS).max(1);
    let mut deepest: Option<(f64, [f64; 2])> = None;
    let mut count = 0;
    for &p in inside.iter().step_by(stride) {
        let d = grid.depth(p);
        if d > tol {
            count += stride;
            if deepest.is_none_or(|(best, _)| d > best) {
                deepest = Some((d, p));
            }
        }
    }
    deepest.map(|(d, p)| (d, p, count))
}

/// Refuses bodies in contact that overlap at t = 0, and bodies that start behind a rigid
/// wall (module docs), unless the contact pair or the wall allows it.
pub fn check_initial_overlap(
    scene: &Scene,
    file: &Path,
    meshes: &[Mesh],
    refs: &Resolved,
) -> Result<(), SceneError> {
    let Some(c) = scene.contact.as_ref().filter(|c| c.enabled) else {
        return Ok(());
    };
    if meshes.len() < 2 && c.walls.is_empty() {
        return Ok(());
    }
    // the bodies where they start: each mesh moved by its body's offset
    let placed: Vec<std::borrow::Cow<Mesh>> = (meshes.iter().zip(&scene.bodies))
        .map(|(m, b)| match b.offset {
            [0.0, 0.0] => std::borrow::Cow::Borrowed(m),
            [dx, dy] => {
                let mut m = m.clone();
                m.nodes.iter_mut().for_each(|p| *p = [p[0] + dx, p[1] + dy]);
                std::borrow::Cow::Owned(m)
            }
        })
        .collect();
    let meshes = &placed[..];
    let edge: Vec<f64> = meshes.iter().map(|m| mean_edge(m)).collect();
    for i in 0..meshes.len() {
        for j in i + 1..meshes.len() {
            let pair =
                (refs.pairs.iter().zip(&c.pairs)).position(|(b, _)| *b == [i, j] || *b == [j, i]);
            let spec = pair.map(|k| &c.pairs[k]);
            if spec.is_some_and(|p| !p.enabled || p.allow_initial_overlap) {
                continue;
            }
            let tol = OVERLAP_TOL * edge[i].min(edge[j]);
            let found = [(i, j), (j, i)]
                .into_iter()
                .filter_map(|(a, b)| deepest_inside(&meshes[a], &meshes[b], tol).map(|d| (a, b, d)))
                .max_by(|x, y| x.2.0.total_cmp(&y.2.0));
            if let Some((a, b, (depth, p, count))) = found {
                let fix = match pair {
                    Some(k) => format!(
                        "move the bodies apart (a gap, or boundaries that touch), or, if the overlap is deliberate (a press fit), set \"allow_initial_overlap\": true in contact.pairs[{k}]"
                    ),
                    None => "move the bodies apart (a gap, or boundaries that touch), or, if the overlap is deliberate (a press fit), add a contact pair for the two bodies with \"allow_initial_overlap\": true".into(),
                };
                return Err(SceneError::invalid(
                    file,
                    format!("bodies[{b}]"),
                    format!(
                        "{} and {} overlap at t = 0: {count} node(s) and triangle centroid(s) of {} lie inside {}, the deepest {depth:.4e} m inside, at ({:.6e}, {:.6e}); contact would start with the penalty energy of the whole overlap",
                        body_label(scene, i),
                        body_label(scene, j),
                        body_label(scene, b),
                        body_label(scene, a),
                        p[0],
                        p[1],
                    ),
                    fix,
                ));
            }
        }
    }
    for (w, wall) in c.walls.iter().enumerate() {
        if wall.allow_initial_overlap {
            continue;
        }
        let len = (wall.normal[0].powi(2) + wall.normal[1].powi(2)).sqrt();
        let n = [wall.normal[0] / len, wall.normal[1] / len];
        for (bi, mesh) in meshes.iter().enumerate() {
            let tol = OVERLAP_TOL * edge[bi];
            let behind = mesh
                .nodes
                .iter()
                .map(|p| -((p[0] - wall.point[0]) * n[0] + (p[1] - wall.point[1]) * n[1]));
            let (count, deepest) = behind.enumerate().filter(|(_, d)| *d > tol).fold(
                (0usize, None::<(usize, f64)>),
                |(k, best), (i, d)| {
                    let best = match best {
                        Some((_, bd)) if bd >= d => best,
                        _ => Some((i, d)),
                    };
                    (k + 1, best)
                },
            );
            if let Some((node, depth)) = deepest {
                let p = mesh.nodes[node];
                return Err(SceneError::invalid(
                    file,
                    format!("contact.walls[{w}].point"),
                    format!(
                        "{} starts behind wall '{}': {count} node(s) lie behind it at t = 0, the deepest {depth:.4e} m, at ({:.6e}, {:.6e}); contact would start with the penalty energy of the whole overlap",
                        body_label(scene, bi),
                        wall.name.clone().unwrap_or_else(|| format!("wall{w}")),
                        p[0],
                        p[1],
                    ),
                    "place the wall at or outside the body's boundary (the normal points away from the solid, into the free side), or set \"allow_initial_overlap\": true on the wall if the overlap is deliberate",
                ));
            }
        }
    }
    Ok(())
}

/// Refuses, in a static analysis, a load or prescribed motion whose solution would overflow
/// the floating-point range (module docs); `model`: the scene's model.
pub fn check_static_range(
    scene: &Scene,
    file: &Path,
    model: &crate::problem::model::Model,
) -> Result<(), SceneError> {
    if scene.analysis != crate::input::scene::Analysis::Static {
        return Ok(());
    }
    let young = (model.materials.iter())
        .map(|m| m.0.young)
        .fold(0.0, f64::max);
    // a load whose displacements would be subnormal or zero (the solve loses them): its
    // force against the stiffest E t L, compared without forming the tiny strain
    let et_l = {
        let t = model.tri_thickness.iter().copied().fold(0.0, f64::max);
        let (lo, hi) = model.x0.iter().fold(
            ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
            |(lo, hi), p| {
                (
                    [lo[0].min(p[0]), lo[1].min(p[1])],
                    [hi[0].max(p[0]), hi[1].max(p[1])],
                )
            },
        );
        young * t * (hi[0] - lo[0]).hypot(hi[1] - lo[1])
    };
    let loaded = scene
        .boundary_conditions
        .iter()
        .enumerate()
        .filter(|(_, bc)| {
            matches!(
                bc,
                BoundaryCondition::Pressure(_)
                    | BoundaryCondition::Traction(_)
                    | BoundaryCondition::PointLoad(_)
            )
        });
    for ((i, _), load) in loaded.zip(&model.loads) {
        let f = load.forces.iter().map(|(_, f)| f.abs()).fold(0.0, f64::max);
        if f > 0.0 && f < f64::MIN_POSITIVE / f64::EPSILON * et_l {
            return Err(SceneError::invalid(
                file,
                format!("boundary_conditions[{i}]"),
                format!(
                    "a nodal force of {f:.3e} N against a stiffness E t L of {et_l:.3e} N: the static solution's displacements would underflow the floating-point range (a strain below about 1e-292)"
                ),
                "check the magnitude and units of the load (N for point loads, Pa for pressures and tractions) against the material (young in Pa)",
            ));
        }
    }
    let inputs = crate::problem::strains::input_strains(scene, model);
    match inputs.first() {
        Some(l) if !(l.strain * l.strain * young).is_finite() => Err(SceneError::invalid(
            file,
            l.path.clone(),
            format!(
                "{}: a strain of about {:.2e}; the static solution (stresses, energy densities) would overflow the floating-point range",
                l.what, l.strain
            ),
            "check the magnitude and units of the load (N for point loads, Pa for pressures and tractions, m for displacements) against the material (young in Pa)",
        )),
        _ => Ok(()),
    }
}
