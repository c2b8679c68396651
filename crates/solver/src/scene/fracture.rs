//! The optional `"fracture"` section: the fracturing regions (exploded into joints at load
//! time) and the joint material. The fracture stage (`crate::fracture_stage`) reads it and
//! fills its joints.

use fdem_fracture::{Joint, JointMaterialInput, JointState};
use serde::{Deserialize, Serialize};

/// The scene's `"fracture"` section.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FractureSection {
    /// The fracturing regions: each names a body (optional when there is one) and its
    /// surface groups to explode (all triangles of the body when `groups` is left out).
    pub regions: Vec<Region>,
    /// The joint material (SI units): tensile_strength, cohesion, friction_angle_deg,
    /// fracture_energy_i, fracture_energy_ii, penalty_normal, penalty_tangential.
    pub material: JointMaterialInput,
    /// Pre-existing cracks: edge groups whose joints start broken, their faces in contact
    /// (default none; `crate::scene::cracks`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cracks: Vec<super::cracks::Crack>,
    /// The joints found at load time, per body (filled by `crate::fracture_stage::explode_body`).
    #[serde(skip)]
    pub joints: Vec<(usize, Vec<Joint>)>,
    /// A saved fracture state to start from (not part of the scene file): the joints'
    /// histories (damage, shear secant, mode indicator, energy books), which are broken and
    /// when, e.g. a run's `Outcome::joint_state` (`crate::summary`). The stage adopts it when
    /// attached: the broken joints stay broken and the pairs their breaks and softenings
    /// released are contact couples from the first force evaluation. `None`: the fresh
    /// state at the model's reference positions.
    #[serde(skip)]
    pub initial_state: Option<JointState>,
}

/// A fracturing region.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Region {
    /// Body name (needed when the scene has several bodies).
    #[serde(default)]
    pub body: Option<String>,
    /// Surface groups to explode (default: the whole body).
    #[serde(default)]
    pub groups: Option<Vec<String>>,
}
