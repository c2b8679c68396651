//! Which arrays a frame carries (`output.arrays`): every array the scene offers (the
//! default, `"all"`), or the listed ones. The names, in the order the files hold them:
//!
//! - `frame_NNNN.vtu` point data: `displacement`, `velocity`, `force`, `reaction`, then
//!   `contact_force` (scenes with contact), then the recovered nodal stresses
//!   `nodal_stress`, `nodal_principal_stress`, `nodal_von_mises` ([`crate::output::recovery`]);
//! - its cell data: `stress`, `principal_stress`, `von_mises`, `strain_energy_density`,
//!   `material`, `body`, then `young` (scenes whose Young's modulus is drawn per triangle) and
//!   `contact_active` (scenes with contact);
//! - `joints_NNNN.vtu` cell data (scenes with a `"fracture"` section): `damage`, `mode`,
//!   `mode_mix`, `broken`, `time_of_failure`, `opening`, `sliding`, `normal_traction`,
//!   `shear_traction`, then `tensile_strength`, `cohesion`, `fracture_energy_i`,
//!   `fracture_energy_ii` (scenes whose joints differ in material), then `fluid_pressure`,
//!   `aperture`, `flow_rate`, `wetted` (scenes with a `"fluid"` section, [`FLUID`]).
//!
//! The points and cells (`Points`, `connectivity`, `offsets`, `types`) are always written; a
//! list without any joint array writes no joint series.

/// Point arrays of every frame.
pub const POINT: [&str; 4] = ["displacement", "velocity", "force", "reaction"];
/// The recovered nodal stress arrays of every frame (point data, [`crate::output::recovery`]).
pub const NODAL: [&str; 3] = ["nodal_stress", "nodal_principal_stress", "nodal_von_mises"];
/// Cell arrays of every frame.
pub const CELL: [&str; 6] = [
    "stress",
    "principal_stress",
    "von_mises",
    "strain_energy_density",
    "material",
    "body",
];
/// The cell array of a scene whose Young's modulus is drawn per triangle.
pub const YOUNG: &str = "young";
/// The point and cell arrays of a scene with contact.
pub const CONTACT: [&str; 2] = ["contact_force", "contact_active"];
/// The joint arrays of a fracturing scene.
pub const JOINT: [&str; 9] = [
    "damage",
    "mode",
    "mode_mix",
    "broken",
    "time_of_failure",
    "opening",
    "sliding",
    "normal_traction",
    "shear_traction",
];
/// The joint arrays of a scene whose joints differ in material.
pub const JOINT_PROPERTIES: [&str; 4] = [
    "tensile_strength",
    "cohesion",
    "fracture_energy_i",
    "fracture_energy_ii",
];

/// The joint arrays of a scene with a fluid in its cracks (`fdem_flow`): the pressure of the
/// joint's two end cavities (mean), the aperture (mean of its ends, within the residual and
/// maximum apertures), the volume flow along the channel from end P to end Q, and 1 for a
/// wetted joint; 0 on the dry joints.
pub const FLUID: [&str; 4] = ["fluid_pressure", "aperture", "flow_rate", "wetted"];

/// What a scene has that adds arrays to its frames.
#[derive(Debug, Clone, Copy, Default)]
pub struct Offer {
    /// Contact (`contact_force`, `contact_active`).
    pub contact: bool,
    /// Young's modulus drawn per triangle (`young`).
    pub drawn_young: bool,
    /// A fracture section (the joint arrays).
    pub fracture: bool,
    /// Joints that differ in material (the joint property arrays).
    pub varied_joints: bool,
    /// A fluid in the cracks (the joint fluid arrays).
    pub fluid: bool,
}

impl Offer {
    /// The array names of the scene, in the files' order (frame point data, cell data,
    /// joints).
    pub fn names(&self) -> Vec<&'static str> {
        let mut v: Vec<&'static str> = POINT.to_vec();
        if self.contact {
            v.push(CONTACT[0]);
        }
        v.extend(NODAL);
        v.extend(CELL);
        if self.drawn_young {
            v.push(YOUNG);
        }
        if self.contact {
            v.push(CONTACT[1]);
        }
        if self.fracture {
            v.extend(JOINT);
            if self.varied_joints {
                v.extend(JOINT_PROPERTIES);
            }
            if self.fluid {
                v.extend(FLUID);
            }
        }
        v
    }

    /// Why `name` is not an array of this scene: it needs something the scene lacks, or it
    /// is no array at all.
    pub fn missing(&self, name: &str) -> String {
        if CONTACT.contains(&name) {
            format!(
                "'{name}' needs contact, and this scene has none (no enabled \"contact\" section)"
            )
        } else if name == YOUNG {
            format!(
                "'{name}' needs a material whose Young's modulus is drawn (\"heterogeneity\"), and this scene has none"
            )
        } else if FLUID.contains(&name) {
            format!(
                "'{name}' is a joint array of the fluid, and this scene has no \"fluid\" section"
            )
        } else if JOINT.contains(&name) {
            format!("'{name}' is a joint array, and this scene has no \"fracture\" section")
        } else if JOINT_PROPERTIES.contains(&name) {
            if self.fracture {
                format!(
                    "'{name}' is written only where the joints differ in material, and this scene's joints share one (its value is that of the fracture material)"
                )
            } else {
                format!("'{name}' is a joint array, and this scene has no \"fracture\" section")
            }
        } else {
            format!("unknown array '{name}'")
        }
    }
}

/// The arrays a run's frames carry.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ArraySet {
    /// `None`: all.
    only: Option<Vec<String>>,
}

impl ArraySet {
    /// Every array.
    pub fn all() -> Self {
        Self { only: None }
    }

    /// Only the arrays `names`.
    pub fn only<S: Into<String>>(names: impl IntoIterator<Item = S>) -> Self {
        Self {
            only: Some(names.into_iter().map(Into::into).collect()),
        }
    }

    /// True when the frames carry the array `name`.
    pub fn has(&self, name: &str) -> bool {
        self.only
            .as_ref()
            .is_none_or(|v| v.iter().any(|n| n == name))
    }

    /// True when the frames carry any of `names`.
    pub fn has_any(&self, names: &[&str]) -> bool {
        names.iter().any(|n| self.has(n))
    }

    /// True when every array is written.
    pub fn is_all(&self) -> bool {
        self.only.is_none()
    }

    /// True when the frames carry an array of the stages (contact, joints).
    pub fn has_stage_arrays(&self) -> bool {
        self.has_any(&CONTACT) || self.has_joints()
    }

    /// True when the frames carry a recovered nodal stress array.
    pub fn has_nodal(&self) -> bool {
        self.has_any(&NODAL)
    }

    /// True when the frames carry a joint array (and so a joint series is written).
    pub fn has_joints(&self) -> bool {
        self.has_any(&JOINT) || self.has_any(&JOINT_PROPERTIES) || self.has_any(&FLUID)
    }
}
