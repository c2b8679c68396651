//! The prepared problem: a scene loaded ([`load`](mod@load)) into the data sets a run reads,
//! each computed once at load, while the parsed scene ([`crate::input::scene::Scene`]) stays
//! as it was read:
//!
//! - [`model`]: all bodies in one node numbering, constraints, consistent nodal loads;
//!   [`mesh_adapter`]: the meshes read and the elements built; [`time_function`]: the factor
//!   of a condition in time.
//! - [`Fracturing`]: the joints of the exploded bodies ([`joint_assign`]: their materials),
//!   the pre-existing cracks resolved to joints ([`cracks`]), the joint set, prestressed by the
//!   initial stress ([`prestress`]).
//! - [`stable_step`]: the terms of the frequency bound and the stable step built from them;
//!   [`limits`]: the step, the steps, the frames and the rows checked.
//! - [`input_checks`], [`static_checks`]: what the scene asks checked against what it acts on.

pub mod accuracy;
pub mod contact_laws;
pub mod cracks;
pub mod fluid;
pub mod indicator;
pub mod input_checks;
pub mod joint_assign;
pub mod joints;
pub mod limits;
pub mod load;
pub mod mesh_adapter;
pub mod model;
pub mod plausibility;
pub mod prestress;
pub mod stable_step;
pub mod static_checks;
pub mod strains;
pub mod time_function;

use fdem_fracture::{Joint, JointSet};

/// A pre-existing crack (`fracture.cracks[i]`) resolved to joints.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CrackJoints {
    /// The body the crack lies in (an index into `bodies`).
    pub body: usize,
    /// The crack's joints, as indices into that body's joint list ([`Fracturing::bodies`]),
    /// sorted, each once.
    pub joints: Vec<u32>,
}

/// The joints of a scene's fracturing bodies, found when they were exploded.
#[derive(Debug, Clone, Default)]
pub struct Fracturing {
    /// Per fracturing body, in the order the bodies were exploded (the scene's order): the
    /// body's index and its joints in the body's own node and triangle numbering.
    pub bodies: Vec<(usize, Vec<Joint>)>,
    /// `fracture.cracks`, in the scene's order, resolved to joints.
    pub cracks: Vec<CrackJoints>,
    /// Every joint in the model's numbering with its material row, prestressed by the initial
    /// stress when the scene has one; `None` without joints.
    pub set: Option<JointSet>,
}

impl Fracturing {
    /// The number of joints of every body.
    pub fn n_joints(&self) -> usize {
        self.bodies.iter().map(|(_, j)| j.len()).sum()
    }
}
