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

use std::path::Path;

use fdem_mesh::Mesh;

use crate::error::SceneError;
use crate::model::Model;
use crate::resolve::Resolved;
use crate::scene::Scene;

/// One initial stress `[sxx, syy, sxy]` [Pa] per triangle of `model`, or an empty vector
/// when the scene has none. `meshes[i]` is body `i`'s mesh as the model holds it; `refs`
/// gives each entry's body. Errors: an entry on a fracturing body, a gravity entry with a
/// node above its surface.
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
        if !refs.fracture_regions[bi].is_empty() {
            return Err(SceneError::invalid(
                file,
                path,
                "an initial stress on a fracturing body is not supported: its joints would start unloaded while the triangles carry the stress",
                "remove the entry, or the body's fracture region",
            ));
        }
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
            for k in 0..3 {
                s0[mt][k] += add[k];
            }
        }
    }
    Ok(s0)
}
