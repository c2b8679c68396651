//! Which joint material each joint of a fracturing body takes, and the per-joint material
//! rows of a scene's joint set.
//!
//! A joint bonds two triangles `T1`, `T2` of one body. Its material is, in order:
//!
//! 1. the material of the interface (`fracture.interfaces`) with `T1` in one of its groups and
//!    `T2` in the other (two interfaces claiming one joint are refused);
//! 2. else the material of the region(s) of `T1` and `T2` (a side outside every region is
//!    not exploded and adds nothing); two regions of different materials meeting at a joint
//!    without an interface are refused, as are two overlapping regions of different
//!    materials.
//!
//! The materials are indices into `FractureSection::material_list`. A material with a
//! heterogeneity gives each of its joints its own row ([`rows`]), drawn by the joint's index
//! in the scene's joint set; a scene without one keeps one row per material, so its joint
//! set and results are those of a scene of one material.

use std::path::Path;

use fdem_fracture::{FractureError, Joint, JointMaterialInput};
use fdem_mesh::Mesh;

use crate::error::SceneError;
use crate::input::resolve::Resolved;
use crate::input::scene::FractureSection;
use crate::input::scene::joint_materials::NamedMaterial;

/// The index of a region's material in the material list.
fn region_material(section: &FractureSection, ri: usize) -> u32 {
    let named = u32::from(section.material.is_some());
    match &section.regions[ri].material {
        Some(n) => named + section.materials.keys().position(|k| k == n).unwrap_or(0) as u32,
        None => 0,
    }
}

/// The list index of a material key (resolved before).
fn named_material(section: &FractureSection, name: &str) -> u32 {
    u32::from(section.material.is_some())
        + section
            .materials
            .keys()
            .position(|k| k == name)
            .unwrap_or(0) as u32
}

/// Per triangle of `mesh`: is it in the surface group `name`.
fn members(mesh: &Mesh, name: &str) -> Vec<bool> {
    let mut m = vec![false; mesh.triangles.len()];
    for g in mesh.groups.iter().filter(|g| g.name == name && g.dim == 2) {
        for t in &g.triangles {
            m[t.idx()] = true;
        }
    }
    m
}

/// The name of a material for messages.
fn material_name(list: &[NamedMaterial<'_>], m: u32) -> String {
    list.get(m as usize).map_or("?".into(), |n| match n.name {
        Some(n) => format!("'{n}'"),
        None => "fracture.material".into(),
    })
}

/// The region of each triangle of body `bi` (the first region that covers it), refusing two
/// overlapping regions of different materials.
fn triangle_regions(
    section: &FractureSection,
    file: &Path,
    regions: &[usize],
    body: &BodyMeshes<'_>,
) -> Result<Vec<Option<usize>>, SceneError> {
    let mesh = body.exploded;
    let list = section.material_list();
    let mut of_tri: Vec<Option<usize>> = vec![None; mesh.triangles.len()];
    for &ri in regions {
        let cover = match &section.regions[ri].groups {
            None => vec![true; mesh.triangles.len()],
            Some(gs) => {
                let mut c = vec![false; mesh.triangles.len()];
                for g in gs {
                    for (t, m) in members(mesh, g).into_iter().enumerate() {
                        c[t] |= m;
                    }
                }
                c
            }
        };
        let mine = region_material(section, ri);
        for (t, _) in cover.iter().enumerate().filter(|(_, c)| **c) {
            match of_tri[t] {
                None => of_tri[t] = Some(ri),
                Some(prev) if region_material(section, prev) != mine => {
                    return Err(SceneError::invalid(
                        file,
                        format!("fracture.regions[{ri}]"),
                        format!(
                            "the region overlaps fracture.regions[{prev}] (triangle {t} of {} \
                             lies in both) and their materials differ ({} and {})",
                            body.label,
                            material_name(&list, mine),
                            material_name(&list, region_material(section, prev))
                        ),
                        "give overlapping regions one material, or make their groups disjoint \
                         (the joints between two materials take an interface's material)",
                    ));
                }
                Some(_) => {}
            }
        }
    }
    Ok(of_tri)
}

/// A body of the scene as messages name it, and its meshes before and after the explode.
pub struct BodyMeshes<'a> {
    /// Index of the body.
    pub index: usize,
    /// `body 'NAME' (MESH)` or `bodies[i] (MESH)`.
    pub label: String,
    /// The mesh before the explode (which edges the groups share).
    pub original: &'a Mesh,
    /// The exploded mesh (the same triangles and groups).
    pub exploded: &'a Mesh,
}

/// A group of a region for messages: its first group, or a placeholder.
fn a_group_of(section: &FractureSection, ri: usize) -> String {
    match section.regions[ri].groups.as_deref() {
        Some([g, ..]) => format!("\"{g}\""),
        _ => format!("<a group of fracture.regions[{ri}]>"),
    }
}

/// The material (list index) of each joint of the body `body`, whose joints bond the triangle
/// pairs `tris` of its exploded mesh.
pub fn assign(
    section: &FractureSection,
    file: &Path,
    refs: &Resolved,
    body: &BodyMeshes<'_>,
    tris: &[[u32; 2]],
) -> Result<Vec<u32>, SceneError> {
    let (bi, mesh) = (body.index, body.exploded);
    let list = section.material_list();
    let of_tri = triangle_regions(section, file, &refs.fracture_regions[bi], body)?;
    // the interfaces of this body: (index, members of group A, of group B, material)
    let mut faces = Vec::new();
    for (i, it) in section.interfaces.iter().enumerate() {
        if refs.interfaces.get(i).is_none_or(|b| b[0] != bi) {
            continue;
        }
        if it.groups[0] == it.groups[1] {
            return Err(SceneError::invalid(
                file,
                format!("fracture.interfaces[{i}].groups"),
                format!("both groups are '{}'", it.groups[0]),
                "an interface joins two different groups; the joints inside one group take \
                 its region's material",
            ));
        }
        let (a, b) = (members(mesh, &it.groups[0]), members(mesh, &it.groups[1]));
        faces.push((i, a, b, named_material(section, &it.material), 0usize));
    }
    let mut out = Vec::with_capacity(tris.len());
    for &[t1, t2] in tris {
        let (t1, t2) = (t1 as usize, t2 as usize);
        let mut claimed: Option<(usize, u32)> = None;
        for (i, a, b, m, n) in faces.iter_mut() {
            if (a[t1] && b[t2]) || (b[t1] && a[t2]) {
                if let Some((prev, _)) = claimed {
                    return Err(SceneError::invalid(
                        file,
                        format!("fracture.interfaces[{i}]"),
                        format!(
                            "the interface claims the joint between triangles {t1} and {t2} of \
                             {}, which fracture.interfaces[{prev}] claims too",
                            body.label
                        ),
                        "make the groups of the two interfaces disjoint (a joint takes one \
                         interface's material)",
                    ));
                }
                claimed = Some((*i, *m));
                *n += 1;
            }
        }
        let m = match (claimed, of_tri[t1], of_tri[t2]) {
            (Some((_, m)), _, _) => m,
            (None, Some(r), None) | (None, None, Some(r)) => region_material(section, r),
            (None, Some(r1), Some(r2)) => {
                let (m1, m2) = (region_material(section, r1), region_material(section, r2));
                if m1 != m2 {
                    let (lo, hi) = (r1.min(r2), r1.max(r2));
                    return Err(SceneError::invalid(
                        file,
                        format!("fracture.regions[{hi}]"),
                        format!(
                            "the joint between triangles {t1} and {t2} of {} bonds \
                             fracture.regions[{r1}] (material {}) to fracture.regions[{r2}] \
                             (material {}), and no interface gives it a material",
                            body.label,
                            material_name(&list, m1),
                            material_name(&list, m2)
                        ),
                        format!(
                            "add to fracture.interfaces {{\"groups\": [{}, {}], \"material\": \
                             <name>}} for the joints between the two regions",
                            a_group_of(section, lo),
                            a_group_of(section, hi)
                        ),
                    ));
                }
                m1
            }
            // (every joint has an exploded side)
            (None, None, None) => 0,
        };
        out.push(m);
    }
    for (i, _, _, _, n) in &faces {
        if *n == 0 {
            return Err(no_joint(section, file, *i, body));
        }
    }
    Ok(out)
}

/// The error of an interface that claims no joint: its groups share no edge, or they do but
/// neither side of it fractures.
fn no_joint(section: &FractureSection, file: &Path, i: usize, body: &BodyMeshes<'_>) -> SceneError {
    let mesh = body.original;
    let it = &section.interfaces[i];
    let (a, b) = (members(mesh, &it.groups[0]), members(mesh, &it.groups[1]));
    let touch = mesh.edges.iter().any(|e| {
        e.right.is_some_and(|r| {
            let (l, r) = (e.left.idx(), r.idx());
            (a[l] && b[r]) || (b[l] && a[r])
        })
    });
    let (g0, g1) = (&it.groups[0], &it.groups[1]);
    if touch {
        SceneError::invalid(
            file,
            format!("fracture.interfaces[{i}]"),
            format!(
                "no joint lies between '{g0}' and '{g1}' of {}: they share edges, but no \
                 fracture region covers either side",
                body.label
            ),
            format!("add a fracture region with the group '{g0}' or '{g1}'"),
        )
    } else {
        SceneError::invalid(
            file,
            format!("fracture.interfaces[{i}]"),
            format!(
                "the groups '{g0}' and '{g1}' of {} do not touch (they share no edge), so \
                 no joint lies between them",
                body.label
            ),
            "name two surface groups that share edges",
        )
    }
}

/// The material rows of a joint set: one per material of `list` (in list order, a
/// heterogeneous one included with its first joint's values), then one per joint of a
/// heterogeneous material, drawn by the joint's index; `joints[j].material` is re-pointed to
/// its row. Each drawn row is checked against its joint's edge (the fracture energy above the
/// pre-peak work), the error naming the material.
pub fn rows(
    file: &Path,
    list: &[NamedMaterial<'_>],
    joints: &mut [Joint],
) -> Result<Vec<JointMaterialInput>, SceneError> {
    let mut rows: Vec<JointMaterialInput> = list.iter().map(|m| m.spec.row(0)).collect();
    if !list.iter().any(|m| m.spec.is_heterogeneous()) {
        return Ok(rows);
    }
    for (j, joint) in joints.iter_mut().enumerate() {
        let m = &list[joint.material as usize];
        if !m.spec.is_heterogeneous() {
            continue;
        }
        let row = m.spec.row(j as u64);
        let checked = row
            .validate(joint.material)
            .and_then(|v| v.check_edge(j as u32, joint.material, joint.ref_length));
        if let Err(e) = checked {
            return Err(drawn_error(file, m, j, &row, &e));
        }
        joint.material = rows.len() as u32;
        rows.push(row);
    }
    Ok(rows)
}

/// A drawn row that fails its joint's check.
fn drawn_error(
    file: &Path,
    m: &NamedMaterial<'_>,
    j: usize,
    row: &JointMaterialInput,
    e: &FractureError,
) -> SceneError {
    let seed = m.spec.heterogeneity.map_or(0, |h| h.seed);
    SceneError::invalid(
        file,
        format!("{}.heterogeneity", m.path()),
        format!(
            "the values drawn for joint {j} (seed {seed}: tensile_strength {:.4e} Pa, cohesion \
             {:.4e} Pa, fracture_energy_i {:.4e} J/m^2, fracture_energy_ii {:.4e} J/m^2) fail \
             its check: {e}",
            row.tensile_strength, row.cohesion, row.fracture_energy_i, row.fracture_energy_ii
        ),
        match e {
            FractureError::FractureEnergyTooSmall { .. } => format!(
                "every drawn joint must store less work before its peak than its fracture \
                 energy: raise {path}.penalty_normal/penalty_tangential, refine the mesh, raise \
                 the fracture energy (or the scale of its distribution), or narrow the \
                 strength's distribution (a larger Weibull modulus, a smaller cov)",
                path = m.path()
            ),
            _ => "the distribution draws values that are not finite and positive: bring its \
                  parameters into the usual range (a Weibull modulus of about 1 to 50, a cov \
                  below about 1)"
                .into(),
        },
    )
}
