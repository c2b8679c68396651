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

use super::FrameData;

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
    Ok(bytes)
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
        let back = vtkio::xml::VTKFile::parse(std::io::Cursor::new(bytes)).unwrap();
        let vtk: Vtk = back.try_into().unwrap();
        let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
            panic!("not an unstructured grid")
        };
        let Piece::Inline(p) = &pieces[0] else {
            panic!("not inline")
        };
        let pts: Vec<f64> = p.points.cast_into().unwrap();
        assert_eq!(pts, vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        let Attribute::DataArray(s) = &p.data.cell[0] else {
            panic!()
        };
        let s: Vec<f64> = s.data.cast_into().unwrap();
        assert_eq!(s, vec![1.0, 3.0, 0.0, 3.0, 2.0, 0.0, 0.0, 0.0, 0.5]);
    }
}
