//! Pre-existing cracks (`fracture.cracks`, [`crate::input::scene::cracks`]): each crack's edge group
//! resolved to joints of its body's fracture region at load time ([`resolve`]), and the joint
//! state a run starts from ([`initial_state`]): the fresh state at the reference positions
//! with the crack's joints broken (damage 1, no force, no time of failure). The fracture
//! stage adopts it as it adopts a saved state (`Problem::initial_joint_state`): the broken
//! joints' own pairs and the vertex pairs of their end nodes' stars leave the bonded set
//! before the first force evaluation, so the contact stage's first detection makes the crack
//! faces contact couples, with the contact law of the body with itself.
//!
//! A crack is a set of joints, so every edge of its group must be an internal edge of the
//! body with at least one exploded triangle beside it (a fracture region covers it); a crack
//! that ends inside a body needs nothing more: the joints beyond its tips are intact and
//! fracture by the joint law. Edges outside every fracture region, or on the body's boundary,
//! are refused: the mesh is not cut there.

use std::collections::HashMap;
use std::path::Path;

use fdem_fracture::{Joint, JointState};
use fdem_mesh::Mesh;

use crate::error::SceneError;
use crate::input::scene::Scene;
use crate::problem::model::Model;
use crate::problem::{CrackJoints, Fracturing};

/// Resolves every crack of the scene to joints of its body, after the fracturing bodies were
/// exploded (`meshes[i]` of `bodies[i]`, as exploded; `joints`: the bodies' joints,
/// [`crate::problem::Fracturing::bodies`]). The names were resolved before
/// ([`crate::input::resolve`]): the group is an edge group of the crack's body, or of the only body
/// that has it. Errors: a crack without contact between its faces, a crack edge that is not a
/// joint.
pub fn resolve(
    scene: &Scene,
    file: &Path,
    meshes: &[Mesh],
    joints: &[(usize, Vec<Joint>)],
) -> Result<Vec<CrackJoints>, SceneError> {
    let Some(section) = &scene.fracture else {
        return Ok(Vec::new());
    };
    let mut out = Vec::with_capacity(section.cracks.len());
    for (i, c) in section.cracks.iter().enumerate() {
        let path = format!("fracture.cracks[{i}]");
        let bi = group_body(scene, meshes, c.body.as_deref(), &c.group);
        contact_between_faces(scene, file, &path, bi)?;
        let local = joints
            .iter()
            .find(|(b, _)| *b == bi)
            .map(|(_, j)| j.as_slice())
            .unwrap_or(&[]);
        let joints = crack_joints(file, &path, &meshes[bi], &c.group, local)?;
        out.push(CrackJoints { body: bi, joints });
    }
    Ok(out)
}

/// The body of an edge group named by `body` or, without a name, the first body whose mesh has
/// the group (the names were resolved before: the first body otherwise).
pub(crate) fn group_body(scene: &Scene, meshes: &[Mesh], body: Option<&str>, group: &str) -> usize {
    match body {
        Some(b) => scene
            .bodies
            .iter()
            .position(|x| x.name.as_deref() == Some(b)),
        None => meshes.iter().position(|m| edge_group(m, group).is_some()),
    }
    .unwrap_or(0)
}

/// The edge (dimension-1) group `name` of `mesh`.
fn edge_group<'a>(mesh: &'a Mesh, name: &str) -> Option<&'a fdem_mesh::PhysicalGroup> {
    mesh.groups.iter().find(|g| g.dim == 1 && g.name == name)
}

/// A crack's faces touch through contact: the scene has an enabled `contact` section and the
/// body's contact with itself is not switched off.
fn contact_between_faces(
    scene: &Scene,
    file: &Path,
    path: &str,
    bi: usize,
) -> Result<(), SceneError> {
    let fix = "add \"contact\": {} to the scene: a crack's faces touch through the contact law \
               of the body with itself (contact.pairs, or contact.default with its friction)";
    let Some(c) = scene.contact.as_ref().filter(|c| c.enabled) else {
        return Err(SceneError::invalid(
            file,
            path,
            "a pre-existing crack needs contact between its faces, and the scene has no \
             enabled \"contact\" section",
            fix,
        ));
    };
    let name = scene.bodies[bi].name.as_deref();
    if let Some(k) = c
        .pairs
        .iter()
        .position(|p| !p.enabled && name.is_some_and(|n| p.bodies.iter().all(|b| b == n)))
    {
        return Err(SceneError::invalid(
            file,
            path,
            format!(
                "contact.pairs[{k}] switches off the contact of the crack's body with itself, \
                 so the crack's faces would pass through each other"
            ),
            "remove that pair or set its \"enabled\" to true",
        ));
    }
    Ok(())
}

/// The joints (indices into `joints`, the body's joint list) on the edges of the edge group
/// `group` of the exploded `mesh`: a group edge is a joint when its two nodes are the `P, Q`
/// or the `S, R` nodes of one joint.
pub(crate) fn crack_joints(
    file: &Path,
    path: &str,
    mesh: &Mesh,
    group: &str,
    joints: &[Joint],
) -> Result<Vec<u32>, SceneError> {
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut of_edge = HashMap::with_capacity(2 * joints.len());
    for (j, jt) in joints.iter().enumerate() {
        let [p, q, r, s] = jt.nodes;
        of_edge.insert(key(p, q), j as u32);
        of_edge.insert(key(s, r), j as u32);
    }
    let Some(g) = edge_group(mesh, group) else {
        return Err(SceneError::invalid(
            file,
            format!("{path}.group"),
            format!("the body's mesh has no edge group named '{group}'"),
            "name an edge (dimension-1) group",
        ));
    };
    let mut out = Vec::with_capacity(g.edges.len() / 2 + 1);
    for e in &g.edges {
        match of_edge.get(&key(e[0].0, e[1].0)) {
            Some(&j) => out.push(j),
            None => {
                let (a, b) = (mesh.nodes[e[0].idx()], mesh.nodes[e[1].idx()]);
                return Err(SceneError::invalid(
                    file,
                    format!("{path}.group"),
                    format!(
                        "the edge of group '{group}' from ({:.6e}, {:.6e}) to ({:.6e}, {:.6e}) \
                         is not a joint: it is on the body's boundary or outside every fracture \
                         region (a crack is made of joints; the mesh is not cut)",
                        a[0], a[1], b[0], b[1]
                    ),
                    "make the fracture region cover the crack (fracture.regions: the whole \
                     body, or surface groups on both sides of the crack), and keep the crack's \
                     edges off the body's boundary",
                ));
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    if out.is_empty() {
        return Err(SceneError::invalid(
            file,
            format!("{path}.group"),
            format!("the edge group '{group}' has no edges"),
            "name an edge group with at least one edge inside the fracture region",
        ));
    }
    Ok(out)
}

/// The state a run starts from when the scene has cracks and no saved state: the fresh state
/// at the model's reference positions with every crack joint broken. `None` without cracks
/// (nothing is computed then). The crack's joints are found in the joint set by the joint
/// order of `crate::problem::joints::joint_set` (the bodies' joint lists one after another, in
/// the order the bodies were exploded).
pub fn initial_state(fracturing: &Fracturing, model: &Model) -> Option<JointState> {
    let set = fracturing.set.as_ref()?;
    if fracturing.cracks.is_empty() {
        return None;
    }
    let mut state = JointState::new(set, &model.x0);
    for c in &fracturing.cracks {
        let mut base = 0usize;
        for (bi, joints) in &fracturing.bodies {
            if *bi == c.body {
                for &j in &c.joints {
                    break_at_start(&mut state, base + j as usize);
                }
            }
            base += joints.len();
        }
    }
    Some(state)
}

/// Joint `j` broken before the run: damage 1 at both points, nothing stored, no energy
/// booked, no time of failure (a pre-existing crack is not a fracture event).
fn break_at_start(state: &mut JointState, j: usize) {
    if !state.intact[j] {
        return;
    }
    state.stored_initial -= state.stored_at_start[j];
    state.stored_at_start[j] = 0.0;
    let h = &mut state.history;
    h.damage[j] = [1.0; 2];
    h.shear_secant[j] = [f64::INFINITY; 2];
    h.mode_mix[j] = [0.0; 2];
    h.local[j] = [0.0; 4];
    h.normal[j] = [0.0; 2];
    h.stored[j] = 0.0;
    h.dissipated[j] = 0.0;
    state.intact[j] = false;
    state.broken_at[j] = None;
    state.n_broken += 1;
}
