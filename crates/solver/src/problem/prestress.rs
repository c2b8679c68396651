//! The initial (in-situ) stress of every triangle from the scene's `"initial_stress"`
//! entries ([`field`]), handed to the mesh crate's kernels
//! ([`fdem_mesh::Elements::set_initial_stress`]).
//!
//! A uniform entry gives its `[sxx, syy, sxy]` to each of its triangles; a gravity entry
//! gives `syy = -rho g (surface_y - y_c)`, `sxx = k0 syy`, `sxy = 0` at the triangle's
//! reference centroid `y_c`: for a field linear in `y` that is its exact mean over the
//! triangle, so `sum -A t sigma grad N` is exactly the consistent load of the linear field
//! (its boundary tractions and its divergence `rho g`, which the lumped gravity load
//! `rho A t g / 3` per corner equals for the constant-strain triangle). Overlapping entries
//! add up.
//!
//! The joints of a fracturing body are prestressed to match ([`prestress_joints`]): joint `j`
//! between triangles T1 and T2 gets the traction `t0 = sigma0 . nn` on its reference edge
//! (`nn` from T1 to T2), `sigma0` the mean of the two triangles' initial stresses, split
//! into its normal part `sigma_n0 = nn . t0` (tension-positive) and its shear part
//! `tau0 = tt . t0`; the fracture crate turns it into offsets of the joint's opening and
//! sliding (`fdem_fracture::JointSet::set_initial_tractions`), so that the joint carries
//! `t0` at zero deformation and the body starts at rest.

use std::path::Path;

use fdem_fracture::{FractureError, JointSet, kinematics};
use fdem_mesh::Mesh;

use crate::error::SceneError;
use crate::input::resolve::Resolved;
use crate::input::scene::Scene;
use crate::problem::model::Model;

/// The initial traction `[sigma_n0, tau0]` (Pa) of every joint of `set` from the triangles'
/// initial stresses `s0` (`[sxx, syy, sxy]` per model triangle, in the reference): the mean
/// of its two triangles' stresses applied to the joint's reference normal `nn` (from T1 to
/// T2), normal part tension-positive, shear part along `tt` (the traction on T1's face).
pub fn joint_tractions(set: &JointSet, x0: &[[f64; 2]], s0: &[[f64; 3]]) -> Vec<[f64; 2]> {
    (0..set.len())
        .map(|j| {
            let k = kinematics(&set.gather(j, x0), set.ref_length[j]);
            let [a, b] = set.triangles[j].map(|t| s0[t as usize]);
            let s = [
                0.5 * (a[0] + b[0]),
                0.5 * (a[1] + b[1]),
                0.5 * (a[2] + b[2]),
            ];
            let t = [
                s[0] * k.nn[0] + s[2] * k.nn[1],
                s[2] * k.nn[0] + s[1] * k.nn[1],
            ];
            [
                t[0] * k.nn[0] + t[1] * k.nn[1],
                t[0] * k.tt[0] + t[1] * k.tt[1],
            ]
        })
        .collect()
}

/// Prestresses the joints of `set` ([`joint_tractions`]) when the scene has an initial stress
/// (`s0` non-empty; nothing is done otherwise). `bodies`: the joints per body
/// ([`crate::problem::Fracturing::bodies`]), for the messages. Error: a joint whose initial tension or shear
/// reaches its strength (it would start broken), naming the joint's material.
pub fn prestress_joints(
    scene: &Scene,
    file: &Path,
    model: &Model,
    s0: &[[f64; 3]],
    set: &mut JointSet,
    bodies: &[(usize, Vec<fdem_fracture::Joint>)],
) -> Result<(), SceneError> {
    if s0.is_empty() {
        return Ok(());
    }
    let t0 = joint_tractions(set, &model.x0, s0);
    set.set_initial_tractions(&t0).map_err(|e| {
        let FractureError::InitialTractionTooHigh { joint, what, .. } = &e else {
            return SceneError::invalid(
                file,
                "initial_stress",
                e.to_string(),
                "check the initial stress",
            );
        };
        let j = *joint as usize;
        let section = scene.fracture.as_ref();
        let path = section
            .and_then(|sec| {
                let list = sec.material_list();
                let joints = crate::problem::joints::global_joints(bodies, model);
                joints
                    .get(j)
                    .and_then(|jt| list.get(jt.material as usize))
                    .map(|m| m.path())
            })
            .unwrap_or_else(|| "fracture.material".into());
        let x = set.gather(j, &model.x0);
        SceneError::invalid(
            file,
            path,
            format!(
                "{e} (the joint between triangles {} and {}, at ({:.4e}, {:.4e}) m)",
                set.triangles[j][0],
                set.triangles[j][1],
                0.5 * (x[0][0] + x[1][0]),
                0.5 * (x[0][1] + x[1][1])
            ),
            if *what == "shear" {
                "raise the material's cohesion (or friction_angle_deg) so that the shear \
                 strength exceeds the initial shear traction, or check the initial stress's \
                 sxy"
            } else {
                "raise the material's tensile_strength above the initial tension, or make the \
                 initial stress compressive across the joints (in-situ rock is in compression; \
                 tension is positive)"
            },
        )
    })
}

/// One initial stress `[sxx, syy, sxy]` [Pa] per triangle of `model`, or an empty vector
/// when the scene has none. `meshes[i]` is body `i`'s mesh as the model holds it; `refs`
/// gives each entry's body. Error: a gravity entry with a node above its surface. The joints
/// of a fracturing body get their share with [`prestress_joints`].
pub fn field(
    scene: &Scene,
    file: &Path,
    model: &Model,
    meshes: &[Mesh],
    refs: &Resolved,
) -> Result<Vec<[f64; 3]>, SceneError> {
    if scene.initial_stress.is_empty() {
        return Ok(Vec::new());
    }
    let mut first = Vec::with_capacity(meshes.len());
    let mut n = 0;
    for m in meshes {
        first.push(n);
        n += m.triangles.len();
    }
    let mut s0 = vec![[0.0; 3]; model.triangles.len()];
    for (i, e) in scene.initial_stress.iter().enumerate() {
        let path = format!("initial_stress[{i}]");
        let bi = refs.initial_stress[i];
        let mesh = &meshes[bi];
        // the entry's triangles, in the body's numbering
        let tris: Vec<usize> = match &e.groups {
            None => (0..mesh.triangles.len()).collect(),
            Some(gs) => {
                let mut v: Vec<usize> = mesh
                    .groups
                    .iter()
                    .filter(|g| g.dim == 2 && gs.contains(&g.name))
                    .flat_map(|g| g.triangles.iter().map(|t| t.idx()))
                    .collect();
                v.sort_unstable();
                v.dedup();
                v
            }
        };
        for t in tris {
            let mt = first[bi] + t;
            let add = match (&e.uniform, &e.gravity) {
                (Some(u), _) => *u,
                (None, Some(g)) => {
                    let nodes = model.triangles[mt].map(|k| model.x0[k as usize]);
                    let top = nodes.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
                    let tol = 1e-9 * g.surface_y.abs().max(1.0);
                    if top > g.surface_y + tol {
                        return Err(SceneError::invalid(
                            file,
                            format!("{path}.gravity.surface_y"),
                            format!(
                                "a triangle of the entry has a node at y = {top} m, above the surface y = {} m (the stress would be tension there)",
                                g.surface_y
                            ),
                            "set surface_y at or above the top of the entry's triangles",
                        ));
                    }
                    let yc = (nodes[0][1] + nodes[1][1] + nodes[2][1]) / 3.0;
                    let rho = g.density.unwrap_or_else(|| {
                        model.materials[model.tri_material[mt] as usize].0.density
                    });
                    let sv = -rho * g.g * (g.surface_y - yc);
                    [g.k0 * sv, sv, 0.0]
                }
                (None, None) => [0.0; 3],
            };
            check_strain(scene, file, model, &path, e, (mt, t), add)?;
            for k in 0..3 {
                s0[mt][k] += add[k];
            }
        }
    }
    Ok(s0)
}

/// The initial strain of entry `path` on triangle `mt` of the model (`local` in its body), its stress `add` over the
/// triangle's Young's modulus, must stay below [`crate::problem::model::LARGE_STRAIN`] (the
/// triangles represent strains well below 1): a larger one is an input far outside its
/// range (a unit slip: MPa for Pa), and the error names the entry, not the stiffness or the
/// step it would break.
fn check_strain(
    scene: &Scene,
    file: &Path,
    model: &Model,
    path: &str,
    e: &crate::input::scene::InitialStress,
    (mt, local): (usize, usize),
    add: [f64; 3],
) -> Result<(), SceneError> {
    let young = model.materials[model.tri_material[mt] as usize].0.young;
    let s = add.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let strain = s / young;
    if strain <= crate::problem::model::LARGE_STRAIN {
        return Ok(());
    }
    let b = model.tri_body[mt] as usize;
    let body = scene.bodies[b]
        .name
        .as_deref()
        .map_or(format!("{b}"), |n| format!("'{}'", fdem_mesh::excerpt(n)));
    let (at, fix) = if e.uniform.is_some() {
        (
            format!("{path}.uniform"),
            "check the magnitude and units of the stress (Pa, tension positive) against the material's young (Pa)",
        )
    } else {
        (
            format!("{path}.gravity"),
            "check g (m/s^2), density (kg/m^3) and surface_y (m) against the material's young (Pa)",
        )
    };
    Err(SceneError::invalid(
        file,
        at,
        format!(
            "the initial stress {s:.3e} Pa on triangle {local} of body {body} is {strain:.3e} times its Young's modulus {young:.3e} Pa: a strain far above what the triangles represent (at most {})",
            crate::problem::model::LARGE_STRAIN
        ),
        fix,
    ))
}
