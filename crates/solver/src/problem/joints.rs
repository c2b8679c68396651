//! The joints of a scene at load time: the mesh crate's explode of the fracturing regions of
//! the scene's `"fracture"` section ([`crate::input::scene::fracture`]) into joints per body
//! ([`explode_body`]), the joint set in the model's numbering ([`joint_set`]) and its term of
//! the frequency bound ([`omega_joints`]: the fracture crate's Gershgorin bound
//! `joint_omega_sq_bound`, about `3 (p/h) l (1/A_1 + 1/A_2)/rho`).

use std::path::Path;

use fdem_fracture::{FractureError, Joint, JointSet, JointState, joint_omega_sq_bound_intact};
use fdem_mesh::Mesh;
use rayon::prelude::*;

use crate::error::SceneError;
use crate::input::resolve::Resolved;
use crate::input::scene::Scene;
use crate::problem::model::Model;

/// Explodes body `bi`'s mesh when fracture regions name the body (as
/// [`crate::input::resolve::resolve`] found them in `refs`): the union of their groups (the whole
/// body when one names none). Records its joints (local node and triangle ids, the material
/// of each from [`crate::problem::joint_assign::assign`]) in `bodies`
/// ([`crate::problem::Fracturing::bodies`]); returns the mesh the body uses.
pub fn explode_body(
    scene: &Scene,
    file: &Path,
    bi: usize,
    refs: &Resolved,
    mesh: Mesh,
    bodies: &mut Vec<(usize, Vec<Joint>)>,
) -> Result<Mesh, SceneError> {
    let regions = &refs.fracture_regions[bi];
    let b = &scene.bodies[bi];
    let label = match &b.name {
        Some(n) => format!("body '{n}' ({})", b.mesh.display()),
        None => format!("bodies[{bi}] ({})", b.mesh.display()),
    };
    let (Some(section), Some(&ri)) = (scene.fracture.as_ref(), regions.first()) else {
        return Ok(mesh);
    };
    let mut names: Option<Vec<&str>> = Some(Vec::new());
    for &r in regions {
        match (&section.regions[r].groups, names.as_mut()) {
            (Some(g), Some(n)) => n.extend(g.iter().map(|s| s.as_str())),
            _ => names = None,
        }
    }
    let ex = fdem_mesh::explode(&mesh, names.as_deref()).map_err(|e| SceneError::Invalid {
        file: file.to_path_buf(),
        path: format!("fracture.regions[{ri}]"),
        message: e.to_string(),
        fix: "name surface groups of the body's mesh".into(),
    })?;
    let tris: Vec<[u32; 2]> = ex
        .internal_edges
        .iter()
        .map(|e| e.tris.map(|t| t.0))
        .collect();
    let body = crate::problem::joint_assign::BodyMeshes {
        index: bi,
        label,
        original: &mesh,
        exploded: &ex.mesh,
    };
    let materials = crate::problem::joint_assign::assign(section, file, refs, &body, &tris)?;
    // in parallel, in edge order
    let joints = (ex.internal_edges.par_iter())
        .zip(materials)
        .with_min_len(4096)
        .map(|(e, material)| {
            let n = e.nodes.map(|n| n.0);
            let (p, q) = (ex.mesh.nodes[n[0] as usize], ex.mesh.nodes[n[1] as usize]);
            Joint {
                nodes: n,
                triangles: e.tris.map(|t| t.0),
                ref_length: ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt(),
                material,
            }
        })
        .collect();
    bodies.push((bi, joints));
    Ok(ex.mesh)
}

/// All joints of `bodies` ([`crate::problem::Fracturing::bodies`]) in the model's numbering.
pub(crate) fn global_joints(bodies: &[(usize, Vec<Joint>)], model: &Model) -> Vec<Joint> {
    let mut out = Vec::with_capacity(bodies.iter().map(|(_, j)| j.len()).sum());
    for (bi, joints) in bodies {
        let node_base = model.body_nodes[*bi].start;
        let tri_base = model
            .tri_body
            .iter()
            .position(|&b| b as usize == *bi)
            .unwrap_or(0) as u32;
        // in parallel, in joint order
        out.par_extend(joints.par_iter().with_min_len(4096).map(|j| Joint {
            nodes: j.nodes.map(|n| n + node_base),
            triangles: j.triangles.map(|t| t + tri_base),
            ..*j
        }));
    }
    out
}

/// Builds the joint set of a scene whose fracturing bodies have the joints `bodies`
/// ([`crate::problem::Fracturing::bodies`]; thickness: that of the first fracturing body).
pub fn joint_set(
    scene: &Scene,
    bodies: &[(usize, Vec<Joint>)],
    model: &Model,
    file: &Path,
) -> Result<Option<JointSet>, SceneError> {
    let Some(section) = &scene.fracture else {
        return Ok(None);
    };
    let mut joints = global_joints(bodies, model);
    if joints.is_empty() {
        return Ok(None);
    }
    let th = bodies
        .first()
        .map_or(1.0, |(bi, _)| scene.bodies[*bi].thickness);
    let list = section.material_list();
    let rows = crate::problem::joint_assign::rows(file, &list, &mut joints)?;
    JointSet::new(&joints, &rows, model.n_nodes(), th)
        .map(Some)
        .map_err(|e| {
            let m = match &e {
                FractureError::FractureEnergyTooSmall { material, .. }
                | FractureError::InvalidMaterial { material, .. } => list.get(*material as usize),
                _ => None,
            };
            SceneError::Invalid {
                file: file.to_path_buf(),
                path: m.map_or("fracture.material".into(), |m| m.path()),
                message: e.to_string(),
                fix:
                    "see the message: raise the penalty or the fracture energy, or refine the mesh"
                        .into(),
            }
        })
}

/// Checks that a saved fracture state to start from (`Problem::initial_joint_state`) has as
/// many joints as the scene (`n_joints`): `Ok` without a saved state.
pub fn check_initial_state(
    state: Option<&JointState>,
    n_joints: usize,
    file: &Path,
) -> Result<(), SceneError> {
    let Some(s) = state else {
        return Ok(());
    };
    if s.intact.len() != n_joints {
        return Err(SceneError::Invalid {
            file: file.to_path_buf(),
            path: "fracture".into(),
            message: format!(
                "the saved fracture state has {} joints, the scene {n_joints}",
                s.intact.len()
            ),
            fix: "start from a state saved by a run of this scene".into(),
        });
    }
    Ok(())
}

/// The joints' term of the frequency bound [rad/s], over every joint (intact, as a fresh
/// state has them).
pub fn omega_joints(set: &JointSet, model: &Model) -> f64 {
    joint_omega_sq_bound_intact(set, &model.mass).sqrt()
}
