//! Typed indices into the mesh arrays.

use serde::{Deserialize, Serialize};

macro_rules! typed_id {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(
            Copy, Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize,
        )]
        #[serde(transparent)]
        pub struct $name(pub u32);

        impl $name {
            /// The index as a `usize`, for indexing arrays.
            #[inline]
            pub fn idx(self) -> usize {
                self.0 as usize
            }
        }

        impl From<$name> for usize {
            #[inline]
            fn from(id: $name) -> usize {
                id.0 as usize
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "{}", self.0)
            }
        }
    };
}

typed_id!(
    /// Index of a node in [`crate::Mesh::nodes`] (0-based).
    NodeId
);
typed_id!(
    /// Index of a triangle in [`crate::Mesh::triangles`] (0-based).
    TriId
);
typed_id!(
    /// Index of an edge in [`crate::Mesh::edges`] (0-based).
    EdgeId
);
typed_id!(
    /// Index of a material region in [`crate::Mesh::regions`] (0-based).
    RegionId
);
