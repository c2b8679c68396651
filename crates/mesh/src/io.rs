//! Mesh readers and the JSON writer. The format is found from the content: a file that starts
//! with `$MeshFormat` is Gmsh (4.1 ASCII/binary or 2.2 ASCII), one that starts with `{` is JSON.

mod cursor;
mod gmsh;
mod json;

pub use json::{JsonGroup, JsonMesh};

use crate::error::MeshError;
use crate::mesh::Mesh;
use std::path::Path;

/// Reads and validates a mesh file (Gmsh `.msh` 4.1 or 2.2, or JSON).
pub fn read_mesh(path: impl AsRef<Path>) -> Result<Mesh, MeshError> {
    let p = path.as_ref();
    let name = p.display().to_string();
    let bytes = std::fs::read(p).map_err(|e| MeshError::Io {
        path: name.clone(),
        source: e,
    })?;
    read_mesh_bytes(&bytes, &name)
}

/// Reads and validates a mesh from the bytes of a file; `name` is used in messages.
pub fn read_mesh_bytes(bytes: &[u8], name: &str) -> Result<Mesh, MeshError> {
    if bytes.starts_with(&[0xEF, 0xBB, 0xBF]) {
        return Err(MeshError::Parse {
            path: name.to_string(),
            line: 1,
            message: "the file starts with a UTF-8 byte-order mark (bytes EF BB BF); save it \
                      as UTF-8 without a byte-order mark (BOM)"
                .into(),
        });
    }
    let start = bytes.iter().position(|c| !c.is_ascii_whitespace());
    let raw = match start.map(|i| bytes[i]) {
        Some(b'$') => gmsh::read_gmsh(bytes, name)?,
        Some(b'{') => json::read_json(bytes, name)?,
        _ => {
            return Err(MeshError::Parse {
                path: name.to_string(),
                line: 1,
                message: "not a mesh file: expected a Gmsh .msh file ($MeshFormat) or a JSON mesh ({...})".into(),
            });
        }
    };
    Mesh::from_parts(raw)
}

/// Writes a mesh as JSON, whole or not at all (temporary file, then rename).
pub fn write_json(mesh: &Mesh, path: impl AsRef<Path>) -> Result<(), MeshError> {
    let p = path.as_ref();
    let name = p.display().to_string();
    let io = |e| MeshError::Io {
        path: name.clone(),
        source: e,
    };
    let s = serde_json::to_vec(&JsonMesh::from_mesh(mesh)).map_err(|e| MeshError::Json {
        path: name.clone(),
        source: e,
    })?;
    let tmp = p.with_extension("json.tmp");
    std::fs::write(&tmp, s).map_err(io)?;
    std::fs::rename(&tmp, p).map_err(io)
}
