//! One frame as a zlib-compressed XML `.vtu` (the only module that uses vtkio).
//!
//! Point arrays: `displacement`, `velocity`, `force`, `reaction` (3 components, z = 0).
//! Cell arrays: `stress` (full 3x3 tensor, 9 components, row major, so ParaView's tensor
//! filters apply), `principal_stress` (s1, s2), `von_mises`, `strain_energy_density`,
//! `material`, `body`. Then the frame's extra arrays from the force contributions, e.g.
//! `contact_force` (points, 3 components) and `contact_active` (cells) with contact. zlib is read by meshio, VTK and ParaView (lz4 is not read by meshio).

use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, Piece,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};
use vtkio::xml::Compressor;

use super::frame::FrameData;

fn vec3(v: &[[f64; 2]]) -> Vec<f64> {
    let mut out = Vec::with_capacity(v.len() * 3);
    for p in v {
        out.extend_from_slice(&[p[0], p[1], 0.0]);
    }
    out
}

fn array(name: &str, elem: ElementType, data: Vec<f64>) -> Attribute {
    Attribute::DataArray(DataArray {
        name: name.into(),
        elem,
        data: data.into(),
    })
}

/// Encodes a frame as the bytes of a `.vtu` file (zlib level `level`, 0 = uncompressed).
pub fn encode(frame: &FrameData, level: u32) -> Result<Vec<u8>, String> {
    let n_cells = frame.triangles.len();
    let connectivity: Vec<u64> = frame
        .triangles
        .iter()
        .flat_map(|t| t.iter().map(|&i| i as u64))
        .collect();
    let offsets: Vec<u64> = (1..=n_cells as u64).map(|i| 3 * i).collect();
    let stress9: Vec<f64> = frame
        .stress
        .iter()
        .flat_map(|s| [s[0], s[2], 0.0, s[2], s[1], 0.0, 0.0, 0.0, s[3]])
        .collect();
    let principal: Vec<f64> = frame.principal.iter().flat_map(|p| *p).collect();
    let mut point = vec![
        array(
            "displacement",
            ElementType::Vectors,
            vec3(&frame.displacement),
        ),
        array("velocity", ElementType::Vectors, vec3(&frame.velocity)),
        array("force", ElementType::Vectors, vec3(&frame.force)),
        array("reaction", ElementType::Vectors, vec3(&frame.reaction)),
    ];
    for (name, v) in &frame.extra_point_vectors {
        point.push(array(name, ElementType::Vectors, vec3(v)));
    }
    let piece = UnstructuredGridPiece {
        points: vec3(&frame.points).into(),
        cells: Cells {
            cell_verts: VertexNumbers::XML {
                connectivity,
                offsets,
            },
            types: vec![CellType::Triangle; n_cells],
        },
        data: Attributes {
            point,
            cell: [
                array("stress", ElementType::Tensors, stress9),
                array("principal_stress", ElementType::Generic(2), principal),
                array(
                    "von_mises",
                    ElementType::Generic(1),
                    frame.von_mises.clone(),
                ),
                array(
                    "strain_energy_density",
                    ElementType::Generic(1),
                    frame.energy_density.clone(),
                ),
                Attribute::DataArray(DataArray {
                    name: "material".into(),
                    elem: ElementType::Generic(1),
                    data: frame.material.clone().into(),
                }),
                Attribute::DataArray(DataArray {
                    name: "body".into(),
                    elem: ElementType::Generic(1),
                    data: frame.body.clone().into(),
                }),
            ]
            .into_iter()
            .chain(
                frame
                    .extra_cell_scalars
                    .iter()
                    .map(|(name, v)| array(name, ElementType::Generic(1), v.clone())),
            )
            .collect(),
        },
    };
    piece_bytes(piece, level)
}

/// One unstructured-grid piece as the bytes of a `.vtu` file: zlib-compressed binary
/// appended data at `level` (1-9), or uncompressed for 0. Shared by the triangle and joint
/// series.
pub(crate) fn piece_bytes(piece: UnstructuredGridPiece, level: u32) -> Result<Vec<u8>, String> {
    let vtk = Vtk {
        version: Version::new_xml(1, 0),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::UnstructuredGrid {
            meta: None,
            pieces: vec![Piece::Inline(Box::new(piece))],
        },
    };
    let compressor = if level == 0 {
        Compressor::None
    } else {
        Compressor::ZLib
    };
    let xml = vtk
        .try_into_xml_format(compressor, level)
        .map_err(|e| e.to_string())?;
    let mut bytes = Vec::new();
    xml.write(&mut bytes).map_err(|e| e.to_string())?;
    cells_as_int64(bytes)
}

/// Relabels the `connectivity` and `offsets` arrays of the piece's `<Cells>` from `UInt64`
/// to `Int64`, VTK's own type for both (meshio reads `UInt64` connectivity as float64, so
/// `points[cells]` fails in a user's script).
///
/// vtkio holds cell vertex numbers as `u64` (`VertexNumbers::XML`) and keeps the XML model's
/// fields private, so the type is changed in the written header. This is exact: the values
/// are vertex indices and offsets, far below `2^63`, whose `u64` and `i64` bytes are the
/// same; the data (inline base64, compressed or not) and its block headers do not depend on
/// the type name. Only the `type` attribute of those two headers inside `<Cells>` changes,
/// and each must be found exactly once, so a change in vtkio's output is an error rather
/// than a silently mislabelled file. Writing the grid ourselves instead would duplicate
/// vtkio's whole encoder (zlib blocks, base64, ranges) for two attribute values.
fn cells_as_int64(bytes: Vec<u8>) -> Result<Vec<u8>, String> {
    let text = String::from_utf8(bytes).map_err(|_| "vtkio wrote a frame that is not UTF-8")?;
    let (Some(start), Some(end)) = (text.find("<Cells>"), text.find("</Cells>")) else {
        return Err("vtkio wrote no <Cells> element".into());
    };
    let mut cells = text[start..end].to_string();
    for name in ["connectivity", "offsets"] {
        let from = format!("<DataArray type=\"UInt64\" Name=\"{name}\"");
        if cells.matches(&from).count() != 1 {
            return Err(format!(
                "vtkio wrote an unexpected header for the cell {name} (expected one UInt64 array)"
            ));
        }
        cells = cells.replacen(
            &from,
            &format!("<DataArray type=\"Int64\" Name=\"{name}\""),
            1,
        );
    }
    let mut out = String::with_capacity(text.len());
    out.push_str(&text[..start]);
    out.push_str(&cells);
    out.push_str(&text[end..]);
    Ok(out.into_bytes())
}

/// Reads the bytes of a `.vtu` file back with vtkio into its one inline piece (the tests'
/// read-back of the triangle and joint frames).
#[cfg(test)]
pub(crate) fn read_back(bytes: Vec<u8>) -> UnstructuredGridPiece {
    let back = vtkio::xml::VTKFile::parse(std::io::Cursor::new(bytes)).unwrap();
    let vtk: Vtk = back.try_into().unwrap();
    let DataSet::UnstructuredGrid { mut pieces, .. } = vtk.data else {
        panic!("not an unstructured grid")
    };
    let Piece::Inline(p) = pieces.swap_remove(0) else {
        panic!("not inline")
    };
    *p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoded_frame_is_zlib_compressed_unstructured_grid_that_vtkio_reads_back() {
        let frame = FrameData {
            time: 0.0,
            points: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            triangles: vec![[0, 1, 2]],
            displacement: vec![[0.1, 0.2]; 3],
            velocity: vec![[0.0; 2]; 3],
            force: vec![[1.0, -1.0]; 3],
            reaction: vec![[0.0; 2]; 3],
            stress: vec![[1.0, 2.0, 3.0, 0.5]],
            principal: vec![[4.0, -1.0]],
            von_mises: vec![5.0],
            energy_density: vec![6.0],
            material: vec![1],
            body: vec![0],
            ..Default::default()
        };
        let bytes = encode(&frame, 6).unwrap();
        let text = String::from_utf8(bytes.clone()).unwrap();
        assert!(text.contains("vtkZLibDataCompressor"));
        assert!(text.contains("Name=\"stress\"") && text.contains("NumberOfComponents=\"9\""));
        let p = &read_back(bytes);
        let pts: Vec<f64> = p.points.cast_into().unwrap();
        assert_eq!(pts, vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        let Attribute::DataArray(s) = &p.data.cell[0] else {
            panic!()
        };
        let s: Vec<f64> = s.data.cast_into().unwrap();
        assert_eq!(s, vec![1.0, 3.0, 0.0, 3.0, 2.0, 0.0, 0.0, 0.0, 0.5]);
    }

    #[test]
    fn connectivity_and_offsets_are_int64_compressed_or_not_and_read_back_exactly() {
        let frame = FrameData {
            points: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]],
            triangles: vec![[0, 1, 2], [1, 3, 2]],
            displacement: vec![[0.0; 2]; 4],
            velocity: vec![[0.0; 2]; 4],
            force: vec![[0.0; 2]; 4],
            reaction: vec![[0.0; 2]; 4],
            stress: vec![[0.0; 4]; 2],
            principal: vec![[0.0; 2]; 2],
            von_mises: vec![0.0; 2],
            energy_density: vec![0.0; 2],
            material: vec![0; 2],
            body: vec![0; 2],
            ..Default::default()
        };
        for level in [0, 6] {
            let bytes = encode(&frame, level).unwrap();
            let text = String::from_utf8(bytes.clone()).unwrap();
            assert!(text.contains("<DataArray type=\"Int64\" Name=\"connectivity\""));
            assert!(text.contains("<DataArray type=\"Int64\" Name=\"offsets\""));
            assert!(!text.contains("UInt64\" Name=\"connectivity"));
            assert!(!text.contains("UInt64\" Name=\"offsets"));
            // the cell types stay UInt8, the header type of the compressed blocks UInt64
            assert!(text.contains("<DataArray type=\"UInt8\" Name=\"types\""));
            let p = &read_back(bytes);
            let VertexNumbers::XML {
                connectivity,
                offsets,
            } = &p.cells.cell_verts
            else {
                panic!("not XML cells")
            };
            assert_eq!(connectivity, &vec![0, 1, 2, 1, 3, 2], "level {level}");
            assert_eq!(offsets, &vec![3, 6], "level {level}");
        }
    }

    #[test]
    fn an_unexpected_cells_header_is_an_error_not_a_mislabelled_file() {
        let xml = b"<Cells><DataArray type=\"UInt32\" Name=\"connectivity\"></Cells>".to_vec();
        assert!(cells_as_int64(xml).unwrap_err().contains("connectivity"));
        assert!(cells_as_int64(b"<Piece></Piece>".to_vec()).is_err());
    }
}
