//! Fracture events: what the solver hands to contact and writes to the events CSV when a
//! joint breaks.

use crate::set::JointId;

/// The mode of a fracture, from the mode indicator `m = (2/pi) atan2(d_II, d_I)` averaged over
/// the joint's two points (`d_I`, `d_II`: the normalised opening and slip beyond their peaks
/// when the damage last grew): I below 1/6 (15 degrees), II above 5/6 (75 degrees), else mixed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FractureMode {
    /// Opening (tensile) fracture.
    I,
    /// Sliding (shear) fracture.
    II,
    /// Both.
    Mixed,
}

impl FractureMode {
    /// Classifies a mode indicator in `[0, 1]`.
    pub fn from_mix(mix: f64) -> Self {
        if mix < 1.0 / 6.0 {
            FractureMode::I
        } else if mix > 5.0 / 6.0 {
            FractureMode::II
        } else {
            FractureMode::Mixed
        }
    }

    /// "I", "II" or "mixed" (for CSV output).
    pub fn as_str(self) -> &'static str {
        match self {
            FractureMode::I => "I",
            FractureMode::II => "II",
            FractureMode::Mixed => "mixed",
        }
    }
}

/// A joint broke (both its points reached `D = 1`) at the commit of a step. From then on the
/// joint carries no force and the solver must let contact act between `triangles`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FractureEvent {
    /// The joint.
    pub joint: JointId,
    /// Its two triangles T1, T2: the new contact couple.
    pub triangles: [u32; 2],
    /// Time of the commit at which it broke (s).
    pub time: f64,
    /// Position: the mean of its four nodes (m).
    pub position: [f64; 2],
    /// Mode of the fracture.
    pub mode: FractureMode,
    /// Mode indicator in `[0, 1]` (0 pure I, 1 pure II).
    pub mode_mix: f64,
    /// Energy dissipated by the joint over its life (J): `G l t` in a pure mode.
    pub energy_released: f64,
    /// Elastic energy still stored at the break (J), e.g. normal compression: it leaves the
    /// joint's books here (a "switch loss" unless contact picks it up).
    pub stored_at_break: f64,
}
