//! The plain data of one output frame, as the solver computed it.

use fdem_mesh::{Elements, TriId};
use rayon::prelude::*;
use serde::Serialize;

use crate::input::arrays::ArraySet;
use crate::problem::model::Model;

/// One frame: node and triangle arrays in SI units. Points are the current positions.
#[derive(Debug, Clone, Default, Serialize)]
pub struct FrameData {
    /// Simulated time [s].
    pub time: f64,
    /// Current node positions [m].
    pub points: Vec<[f64; 2]>,
    /// Triangles (node indices, CCW).
    pub triangles: Vec<[u32; 3]>,
    /// Node displacement from the reference configuration [m].
    pub displacement: Vec<[f64; 2]>,
    /// Node velocity [m/s].
    pub velocity: Vec<[f64; 2]>,
    /// Total nodal force: internal + external [N].
    pub force: Vec<[f64; 2]>,
    /// Reaction at constrained DOFs (the force the support applies) [N]; zero elsewhere.
    pub reaction: Vec<[f64; 2]>,
    /// Cauchy stress per triangle: sxx, syy, sxy, szz [Pa].
    pub stress: Vec<[f64; 4]>,
    /// Principal in-plane stresses s1 >= s2 [Pa].
    pub principal: Vec<[f64; 2]>,
    /// von Mises stress [Pa].
    pub von_mises: Vec<f64>,
    /// Strain energy density per reference area [J/m^3].
    pub energy_density: Vec<f64>,
    /// Material id per triangle (one per material entry and thickness, in order of first
    /// use; the triangles of a material with drawn moduli share one).
    pub material: Vec<i32>,
    /// Body id per triangle.
    pub body: Vec<i32>,
    /// Recovered stress per node: sxx, syy, sxy, szz [Pa] ([`super::recovery`]); empty when
    /// the frame carries no nodal stress array.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub nodal_stress: Vec<[f64; 4]>,
    /// Principal in-plane stresses s1 >= s2 of the recovered nodal stress [Pa].
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub nodal_principal: Vec<[f64; 2]>,
    /// von Mises stress of the recovered nodal stress [Pa].
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub nodal_von_mises: Vec<f64>,
    /// Further point vectors from the force contributions (`contact_force` [N] when the scene
    /// has contact), written after `reaction`; empty (and absent from the files) otherwise.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub extra_point_vectors: Vec<(String, Vec<[f64; 2]>)>,
    /// Further cell scalars from the force contributions (`contact_active`, 0 or 1, when the
    /// scene has contact), written after `body`; empty (and absent from the files) otherwise.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub extra_cell_scalars: Vec<(String, Vec<f64>)>,
    /// The joints as line cells (scenes with a `"fracture"` section only; written as
    /// `joints_NNNN.vtu` beside the frame, see [`super::joints`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub joints: Option<super::joint_frame::JointFrame>,
}

/// In-plane principal stresses (s1 >= s2) of (sxx, syy, sxy).
pub fn principal(sxx: f64, syy: f64, sxy: f64) -> [f64; 2] {
    let c = 0.5 * (sxx + syy);
    let r = (0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy).sqrt();
    [c + r, c - r]
}

/// von Mises stress of (sxx, syy, sxy, szz).
pub fn von_mises(s: [f64; 4]) -> f64 {
    let [xx, yy, xy, zz] = s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2)) + 3.0 * xy * xy).sqrt()
}

impl FrameData {
    /// Fills the recovered nodal stress arrays that `arrays` asks for from the frame's cell
    /// stresses (patches cut by the broken joints of `links`, [`super::recovery`]); then
    /// drops the cell stresses when `arrays` does not ask for them. Nothing is computed when
    /// no nodal array is asked for.
    pub fn recover_nodal(
        &mut self,
        model: &Model,
        links: Option<super::recovery::Links>,
        arrays: &ArraySet,
    ) {
        if !arrays.has_nodal() {
            return;
        }
        let material: Vec<u32> = (model.tri_material.iter())
            .map(|&r| model.material_id.get(r as usize).map_or(r, |&id| id))
            .collect();
        let mesh = super::recovery::Mesh {
            x0: &model.x0,
            triangles: &model.triangles,
            material: &material,
        };
        let nodal = super::recovery::recover(
            mesh,
            &self.stress,
            links,
            super::recovery::Method::default(),
        );
        if arrays.has("nodal_principal_stress") {
            self.nodal_principal = nodal.iter().map(|s| principal(s[0], s[1], s[2])).collect();
        }
        if arrays.has("nodal_von_mises") {
            self.nodal_von_mises = nodal.iter().map(|s| von_mises(*s)).collect();
        }
        if arrays.has("nodal_stress") {
            self.nodal_stress = nodal;
        }
        if !arrays.has_any(&["stress", "principal_stress", "von_mises"]) {
            self.stress = Vec::new();
        }
    }
}

/// Builds a frame from positions, velocities, forces and reactions, with every array.
pub fn make_frame(
    model: &Model,
    elements: &Elements,
    t: f64,
    x: &[[f64; 2]],
    v: &[[f64; 2]],
    force: &[[f64; 2]],
    reaction: &[[f64; 2]],
) -> FrameData {
    make_frame_of(model, elements, t, x, v, force, reaction, &ArraySet::all())
}

/// [`make_frame`] with the arrays of `arrays` only (the others left empty, and not
/// computed: the stresses only for `stress`, `principal_stress`, `von_mises` or a nodal
/// stress array, which [`FrameData::recover_nodal`] then fills).
pub fn make_frame_of(
    model: &Model,
    elements: &Elements,
    t: f64,
    x: &[[f64; 2]],
    v: &[[f64; 2]],
    force: &[[f64; 2]],
    reaction: &[[f64; 2]],
    arrays: &ArraySet,
) -> FrameData {
    let stress: Vec<[f64; 4]> =
        if arrays.has_any(&["stress", "principal_stress", "von_mises"]) || arrays.has_nodal() {
            let mut stresses = vec![fdem_mesh::stress::Stress::default(); elements.len()];
            elements.stresses(x, v, &mut stresses);
            stresses.iter().map(|s| [s.xx, s.yy, s.xy, s.zz]).collect()
        } else {
            Vec::new()
        };
    let energy_density = if arrays.has("strain_energy_density") {
        (0..elements.len())
            .into_par_iter()
            .with_min_len(1024)
            .map(|e| {
                let td = &elements.tris[e];
                let th = 2.0 * elements.materials[td.material as usize].half_t;
                elements.element_energy(TriId(e as u32), x) / (td.area0 * th)
            })
            .collect()
    } else {
        Vec::new()
    };
    let parts = (x, v, force, reaction);
    frame_from_parts_of(model, t, parts, stress, energy_density, arrays)
}

/// Assembles a frame from node arrays and per-triangle stresses and energy densities.
pub fn frame_from_parts(
    model: &Model,
    t: f64,
    x: &[[f64; 2]],
    v: &[[f64; 2]],
    force: &[[f64; 2]],
    reaction: &[[f64; 2]],
    stress: Vec<[f64; 4]>,
    energy_density: Vec<f64>,
) -> FrameData {
    let parts = (x, v, force, reaction);
    frame_from_parts_of(model, t, parts, stress, energy_density, &ArraySet::all())
}

/// Positions, velocities, forces and reactions of the nodes.
type NodeParts<'a> = (
    &'a [[f64; 2]],
    &'a [[f64; 2]],
    &'a [[f64; 2]],
    &'a [[f64; 2]],
);

/// [`frame_from_parts`] with the arrays of `arrays` only (the others left empty).
fn frame_from_parts_of(
    model: &Model,
    t: f64,
    (x, v, force, reaction): NodeParts,
    stress: Vec<[f64; 4]>,
    energy_density: Vec<f64>,
    arrays: &ArraySet,
) -> FrameData {
    let copy = |name: &str, a: &[[f64; 2]]| {
        if arrays.has(name) {
            a.to_vec()
        } else {
            Vec::new()
        }
    };
    let when = |name: &str| arrays.has(name);
    FrameData {
        time: t,
        points: x.to_vec(),
        triangles: model.triangles.clone(),
        displacement: if when("displacement") {
            x.iter()
                .zip(&model.x0)
                .map(|(a, b)| [a[0] - b[0], a[1] - b[1]])
                .collect()
        } else {
            Vec::new()
        },
        velocity: copy("velocity", v),
        force: copy("force", force),
        reaction: copy("reaction", reaction),
        principal: if when("principal_stress") {
            stress.iter().map(|s| principal(s[0], s[1], s[2])).collect()
        } else {
            Vec::new()
        },
        von_mises: if when("von_mises") {
            stress.iter().map(|s| von_mises(*s)).collect()
        } else {
            Vec::new()
        },
        stress,
        energy_density,
        material: if when("material") {
            model
                .tri_material
                .iter()
                .map(|&r| model.material_id.get(r as usize).map_or(r, |&id| id) as i32)
                .collect()
        } else {
            Vec::new()
        },
        body: if when("body") {
            model.tri_body.iter().map(|&b| b as i32).collect()
        } else {
            Vec::new()
        },
        nodal_stress: Vec::new(),
        nodal_principal: Vec::new(),
        nodal_von_mises: Vec::new(),
        extra_point_vectors: Vec::new(),
        // Young's modulus per cell [Pa], only when some triangle's is drawn
        extra_cell_scalars: if model.drawn_young && when(crate::input::arrays::YOUNG) {
            vec![(
                crate::input::arrays::YOUNG.into(),
                model
                    .tri_material
                    .iter()
                    .map(|&r| model.materials[r as usize].0.young)
                    .collect(),
            )]
        } else {
            Vec::new()
        },
        joints: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn principal_and_von_mises_of_pure_shear() {
        // Pure shear tau: principal +-tau, von Mises sqrt(3) tau (exact up to round-off).
        let p = principal(0.0, 0.0, 2.0);
        assert!((p[0] - 2.0).abs() < 1e-15 && (p[1] + 2.0).abs() < 1e-15);
        assert!((von_mises([0.0, 0.0, 2.0, 0.0]) - 2.0 * 3f64.sqrt()).abs() < 1e-14);
        // Uniaxial: von Mises equals the stress.
        assert!((von_mises([5.0, 0.0, 0.0, 0.0]) - 5.0).abs() < 1e-14);
    }
}
