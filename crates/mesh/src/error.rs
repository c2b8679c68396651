//! Errors of mesh reading and validation. Each names the file, the item and the fault.

use crate::excerpt::{excerpt, shorten};
use crate::ids::{NodeId, TriId};

/// Everything that can go wrong when reading or validating a mesh.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file could not be read or written.
    #[error("{path}: cannot access the file: {source}")]
    Io {
        /// The file.
        path: String,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The file is not a mesh of a known format, or is truncated or malformed.
    #[error("{path}:{line}: {}", shorten(message))]
    Parse {
        /// The file.
        path: String,
        /// 1-based line number (in a binary file: the line where the binary block began).
        line: usize,
        /// What was expected and found.
        message: String,
    },
    /// A Gmsh format version that fdem does not read.
    #[error(
        "{path}: Gmsh format version {} is not supported; fdem reads 4.1 (ASCII or binary) and 2.2 (ASCII): re-save with `gmsh in.msh -save -format msh41 -o out.msh`",
        excerpt(version)
    )]
    UnsupportedVersion {
        /// The file.
        path: String,
        /// The version found in the header.
        version: String,
    },
    /// A binary file written on a machine of the other byte order.
    #[error(
        "{path}: binary mesh written with the other byte order (big-endian); re-save it as ASCII (`gmsh in.msh -save -format msh41 -o out.msh` with Mesh.Binary=0)"
    )]
    WrongEndianness {
        /// The file.
        path: String,
    },
    /// An element type other than points, 2-node lines and 3-node triangles.
    #[error(
        "{path}: element {element} has Gmsh type {gmsh_type} ({name}), which fdem does not support: mesh with linear triangles only (Mesh.ElementOrder = 1, no recombination)"
    )]
    UnsupportedElement {
        /// The file.
        path: String,
        /// Element tag in the file.
        element: u64,
        /// Gmsh element type number.
        gmsh_type: i64,
        /// Name of the type, where known.
        name: &'static str,
    },
    /// An element refers to a node tag that the file does not define.
    #[error("{path}: element {element} refers to node {node}, which the file does not define")]
    UnknownNode {
        /// The file.
        path: String,
        /// Element tag in the file (or index in a JSON file).
        element: u64,
        /// The missing node tag.
        node: u64,
    },
    /// A node tag defined twice.
    #[error("{path}: node tag {node} is defined twice")]
    DuplicateNodeTag {
        /// The file.
        path: String,
        /// The node tag.
        node: u64,
    },
    /// The mesh has no triangles.
    #[error("{path}: the mesh has no triangles (is the surface in a physical group?)")]
    NoTriangles {
        /// The file.
        path: String,
    },
    /// A triangle of zero (or numerically zero) area.
    #[error(
        "{path}: triangle {tri} (file element {element}) has zero area ({area:e}); nodes {nodes:?} are collinear or repeated: remesh"
    )]
    ZeroArea {
        /// The file.
        path: String,
        /// Triangle index.
        tri: TriId,
        /// Element tag in the file.
        element: u64,
        /// Signed area found.
        area: f64,
        /// Node tags of the triangle in the file.
        nodes: [u64; 3],
    },
    /// Two nodes at the same position.
    #[error(
        "{path}: nodes {a} and {b} (file tags {tag_a} and {tag_b}) are both at ({x}, {y}): merge duplicate nodes (Gmsh: Coherence Mesh)"
    )]
    DuplicateNodes {
        /// The file.
        path: String,
        /// First node.
        a: NodeId,
        /// Second node.
        b: NodeId,
        /// File tag of the first node.
        tag_a: u64,
        /// File tag of the second node.
        tag_b: u64,
        /// x position.
        x: f64,
        /// y position.
        y: f64,
    },
    /// A node that no triangle uses.
    #[error(
        "{path}: node {node} (file tag {tag}) at ({x}, {y}) belongs to no triangle: remove it (it would have no mass)"
    )]
    UnusedNode {
        /// The file.
        path: String,
        /// Node index.
        node: NodeId,
        /// File tag.
        tag: u64,
        /// x position.
        x: f64,
        /// y position.
        y: f64,
    },
    /// A coordinate that is not finite.
    #[error("{path}: node {tag} has a non-finite coordinate")]
    NonFinite {
        /// The file.
        path: String,
        /// File tag.
        tag: u64,
    },
    /// A group that lists the same node, edge (in either direction) or triangle twice.
    #[error(
        "{path}: group \"{}\" lists {entity} twice: a group is a set, and a repeat would be counted (loaded, fixed, exploded) twice; remove the repeat",
        excerpt(group)
    )]
    RepeatedInGroup {
        /// The file.
        path: String,
        /// The group's name.
        group: String,
        /// The entity repeated, with its file tags (e.g. `the edge between nodes 3 and 4`).
        entity: String,
    },
    /// A physical group asked for by name is not in the mesh.
    #[error("mesh has no physical group named \"{}\"; it has: {}", excerpt(name), shorten(&format!("{available:?}")))]
    MissingGroup {
        /// The requested name.
        name: String,
        /// Group names the mesh has.
        available: Vec<String>,
    },
    /// A JSON mesh that does not follow the schema.
    #[error("{path}: invalid JSON mesh: {}", shorten(&source.to_string()))]
    Json {
        /// The file.
        path: String,
        /// The serde error (with line and column).
        source: serde_json::Error,
    },
    /// A material parameter out of range.
    #[error("material {index}: {field} = {value} is out of range: {fix}")]
    Material {
        /// Index of the material (its region).
        index: usize,
        /// The parameter.
        field: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        fix: &'static str,
    },
    /// The number of materials does not match the regions of the mesh.
    #[error("the mesh has {regions} material regions {} but {given} materials were given", shorten(&format!("{names:?}")))]
    MaterialCount {
        /// Regions in the mesh.
        regions: usize,
        /// Their names.
        names: Vec<String>,
        /// Materials given.
        given: usize,
    },
}
