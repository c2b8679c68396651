//! The plain data of one output frame, as the solver computed it.

use serde::Serialize;

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
    /// Material id per triangle.
    pub material: Vec<i32>,
    /// Body id per triangle.
    pub body: Vec<i32>,
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
