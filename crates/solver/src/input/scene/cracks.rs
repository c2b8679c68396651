//! Pre-existing cracks of the `"fracture"` section (`fracture.cracks`): edge groups of a
//! fracturing body whose joints start broken, their faces in contact through the scene's
//! contact law. `crate::problem::cracks` resolves them to joints at load time (into the prepared
//! problem, `crate::problem::Fracturing::cracks`) and makes the joint state they start from.

use serde::{Deserialize, Serialize};

/// A pre-existing crack: the edges of an edge (dimension-1) group of a body's mesh, every one
/// an internal edge of the body's fracture region. Its joints start broken; its faces touch
/// through the contact law of the body with itself (`contact.pairs` or `contact.default`).
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Crack {
    /// Body name (needed when several bodies have an edge group of this name).
    #[serde(default)]
    pub body: Option<String>,
    /// The edge group whose edges are the crack.
    pub group: String,
}
