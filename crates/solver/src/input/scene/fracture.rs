//! The optional `"fracture"` section: the fracturing regions (exploded into joints at load
//! time) and the joint materials (`super::joint_materials`: named materials, interfaces,
//! heterogeneity). Loading explodes its regions into the prepared problem's joints (`crate::problem`).

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::joint_materials::{Interface, JointMaterialSpec, NamedMaterial, material_list};
use crate::error::SceneError;

/// The scene's `"fracture"` section.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FractureSection {
    /// The fracturing regions: each names a body (optional when there is one), its surface
    /// groups to explode (all triangles of the body when `groups` is left out) and its joint
    /// material (default `material`). A body may have several regions.
    pub regions: Vec<Region>,
    /// The joint material of the regions that name none (SI units): tensile_strength,
    /// cohesion, friction_angle_deg, fracture_energy_i, fracture_energy_ii, penalty_normal,
    /// penalty_tangential, optional heterogeneity.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<JointMaterialSpec>,
    /// Named joint materials, for regions and interfaces (default none).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub materials: BTreeMap<String, JointMaterialSpec>,
    /// Interfaces: the joints between two surface groups take their own material.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub interfaces: Vec<Interface>,
    /// Pre-existing cracks: edge groups whose joints start broken, their faces in contact
    /// (default none; `crate::input::scene::cracks`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cracks: Vec<super::cracks::Crack>,
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
    /// A key of `fracture.materials` (default: `fracture.material`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

impl FractureSection {
    /// The joint materials in index order (`super::joint_materials::material_list`).
    pub fn material_list(&self) -> Vec<NamedMaterial<'_>> {
        material_list(self.material.as_ref(), &self.materials)
    }

    /// Checks the joint materials (`super::joint_materials::validate`).
    pub fn validate(&self, file: &Path) -> Result<(), SceneError> {
        let bare = self.regions.iter().position(|r| r.material.is_none());
        super::joint_materials::validate(file, &self.material_list(), bare)
    }

    /// True when the joints differ in material: several materials, or one drawn per joint
    /// (the joint series then carries the strengths and energies of every joint).
    pub fn varied_joints(&self) -> bool {
        let list = self.material_list();
        list.len() > 1 || list.iter().any(|m| m.spec.is_heterogeneous())
    }
}
