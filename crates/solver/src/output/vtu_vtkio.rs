//! The frame encoder the `.vtu` files had before [`super::vtu`]: vtkio's inline base64 zlib
//! XML. Kept for the tests only, as the reference whose decoded arrays the new encoder must
//! reproduce bit for bit, and to read its files back (vtkio cannot read raw appended data).

use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, Piece,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};
use vtkio::xml::Compressor;

use super::frame::FrameData;
use super::joint_frame::JointFrame;

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
    let nodal9: Vec<f64> = frame
        .nodal_stress
        .iter()
        .flat_map(|s| [s[0], s[2], 0.0, s[2], s[1], 0.0, 0.0, 0.0, s[3]])
        .collect();
    let nodal_principal: Vec<f64> = frame.nodal_principal.iter().flat_map(|p| *p).collect();
    point.extend([
        array("nodal_stress", ElementType::Tensors, nodal9),
        array(
            "nodal_principal_stress",
            ElementType::Generic(2),
            nodal_principal,
        ),
        array(
            "nodal_von_mises",
            ElementType::Generic(1),
            frame.nodal_von_mises.clone(),
        ),
    ]);
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

fn joint_array(name: &str, data: Vec<f64>) -> Attribute {
    Attribute::DataArray(DataArray {
        name: name.into(),
        elem: ElementType::Generic(1),
        data: data.into(),
    })
}

fn int_array(name: &str, data: Vec<i32>) -> Attribute {
    Attribute::DataArray(DataArray {
        name: name.into(),
        elem: ElementType::Generic(1),
        data: data.into(),
    })
}

/// Encodes the joints as the bytes of a `.vtu` file of line cells (zlib level `level`,
/// 0 = uncompressed).
pub fn encode_joints(j: &JointFrame, level: u32) -> Result<Vec<u8>, String> {
    let n = j.len();
    let points: Vec<f64> = j.points.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
    let piece = UnstructuredGridPiece {
        points: points.into(),
        cells: Cells {
            cell_verts: VertexNumbers::XML {
                connectivity: (0..2 * n as u64).collect(),
                offsets: (1..=n as u64).map(|i| 2 * i).collect(),
            },
            types: vec![CellType::Line; n],
        },
        data: Attributes {
            point: Vec::new(),
            cell: [
                joint_array("damage", j.damage.clone()),
                int_array("mode", j.mode.clone()),
                joint_array("mode_mix", j.mode_mix.clone()),
                int_array("broken", j.broken.clone()),
                joint_array("time_of_failure", j.time_of_failure.clone()),
                joint_array("opening", j.opening.clone()),
                joint_array("sliding", j.sliding.clone()),
                joint_array("normal_traction", j.normal_traction.clone()),
                joint_array("shear_traction", j.shear_traction.clone()),
            ]
            .into_iter()
            .chain(j.properties.iter().flat_map(|p| {
                [
                    joint_array("tensile_strength", p.tensile_strength.clone()),
                    joint_array("cohesion", p.cohesion.clone()),
                    joint_array("fracture_energy_i", p.fracture_energy_i.clone()),
                    joint_array("fracture_energy_ii", p.fracture_energy_ii.clone()),
                ]
            }))
            .chain(j.fluid.iter().flat_map(|f| {
                [
                    joint_array("fluid_pressure", f.pressure.clone()),
                    joint_array("aperture", f.aperture.clone()),
                    joint_array("flow_rate", f.flow_rate.clone()),
                    int_array("wetted", f.wetted.clone()),
                ]
            }))
            .collect(),
        },
    };
    piece_bytes(piece, level)
}

/// A vtkio piece as arrays (name, VTK type, components, little-endian bytes) in the order of
/// [`super::vtu::read`]: point data, cell data, points, connectivity, offsets, types.
/// The cell arrays are labelled `Int64` as the legacy files' headers say (vtkio holds them as
/// `u64`; the bytes of indices below 2^63 are the same).
pub(crate) fn arrays_of(p: &UnstructuredGridPiece) -> Vec<(String, String, usize, Vec<u8>)> {
    use vtkio::model::IOBuffer;
    fn bytes(b: &IOBuffer) -> (String, Vec<u8>) {
        match b {
            IOBuffer::F64(v) => (
                "Float64".into(),
                v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            ),
            IOBuffer::I32(v) => (
                "Int32".into(),
                v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            ),
            IOBuffer::U64(v) => (
                "Int64".into(),
                v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            ),
            IOBuffer::U8(v) => ("UInt8".into(), v.clone()),
            other => panic!("unexpected buffer {other:?}"),
        }
    }
    let mut out = Vec::new();
    for a in p.data.point.iter().chain(&p.data.cell) {
        let Attribute::DataArray(a) = a else {
            panic!("field data")
        };
        let (ty, b) = bytes(&a.data);
        out.push((a.name.clone(), ty, a.num_comp(), b));
    }
    let (ty, b) = bytes(&p.points);
    out.push(("Points".into(), ty, 3, b));
    let VertexNumbers::XML {
        connectivity,
        offsets,
    } = &p.cells.cell_verts
    else {
        panic!("not XML cells")
    };
    for (name, v) in [("connectivity", connectivity), ("offsets", offsets)] {
        let (ty, b) = bytes(&vtkio::model::IOBuffer::U64(v.clone()));
        out.push((name.into(), ty, 1, b));
    }
    let types = p.cells.types.iter().map(|&t| t as u8).collect();
    out.push(("types".into(), "UInt8".into(), 1, types));
    out
}

#[cfg(test)]
mod tests {
    use super::super::joint_frame::{JointFluid, JointProperties};
    use super::super::{joints, vtu};
    use super::*;

    /// Values that exercise every bit pattern class: signs, -0.0, subnormals, extremes.
    fn value(k: usize) -> f64 {
        let specials = [
            0.0,
            -0.0,
            f64::MIN_POSITIVE / 3.0,
            f64::MAX,
            -1e-300,
            1.0 / 3.0,
        ];
        if k.is_multiple_of(7) {
            specials[(k / 7) % specials.len()]
        } else {
            ((k as f64) * 0.618_033_988_7).sin() * 10f64.powi((k % 23) as i32 - 11)
        }
    }

    /// A frame of `n` points and `m` triangles with contact arrays and joints (with their
    /// materials), sized so that the large arrays span several zlib blocks.
    fn frame(n: usize, m: usize) -> FrameData {
        let v2 = |s: usize| {
            (0..n)
                .map(|i| [value(s + 2 * i), value(s + 2 * i + 1)])
                .collect()
        };
        let nj = m / 2;
        let f = |s: usize, len: usize| (0..len).map(|i| value(s + i)).collect::<Vec<f64>>();
        let joints = JointFrame {
            points: (0..2 * nj).map(|i| [value(i), value(i + 5)]).collect(),
            damage: f(1, nj),
            mode: (0..nj as i32).map(|i| i % 4).collect(),
            mode_mix: f(2, nj),
            broken: (0..nj as i32).map(|i| i % 2).collect(),
            time_of_failure: f(3, nj),
            opening: f(4, nj),
            sliding: f(5, nj),
            normal_traction: f(6, nj),
            shear_traction: f(7, nj),
            properties: Some(JointProperties {
                tensile_strength: f(8, nj),
                cohesion: f(9, nj),
                fracture_energy_i: f(10, nj),
                fracture_energy_ii: f(11, nj),
            }),
            fluid: Some(JointFluid {
                pressure: f(12, nj),
                aperture: f(13, nj),
                flow_rate: f(14, nj),
                wetted: (0..nj as i32).map(|i| i % 2).collect(),
            }),
        };
        FrameData {
            time: 1.5,
            points: v2(0),
            triangles: (0..m as u32)
                .map(|t| {
                    [
                        t % n as u32,
                        (7 * t + 1) % n as u32,
                        (13 * t + 2) % n as u32,
                    ]
                })
                .collect(),
            displacement: v2(1),
            velocity: v2(2),
            force: v2(3),
            reaction: v2(4),
            stress: (0..m)
                .map(|i| [value(i), value(i + 1), value(i + 2), value(i + 3)])
                .collect(),
            principal: (0..m).map(|i| [value(i + 4), value(i + 5)]).collect(),
            von_mises: f(6, m),
            energy_density: f(7, m),
            material: (0..m as i32).map(|i| i % 3 - 1).collect(),
            body: (0..m as i32).map(|i| i / 100).collect(),
            nodal_stress: (0..n)
                .map(|i| [value(i + 9), value(i + 10), value(i + 11), value(i + 12)])
                .collect(),
            nodal_principal: v2(13),
            nodal_von_mises: f(14, n),
            extra_point_vectors: vec![("contact_force".into(), v2(8))],
            extra_cell_scalars: vec![("contact_active".into(), f(9, m))],
            joints: Some(joints),
        }
    }

    fn as_tuples(a: Vec<vtu::Array>) -> Vec<(String, String, usize, Vec<u8>)> {
        a.into_iter()
            .map(|a| (a.name, a.ty.to_string(), a.components, a.bytes))
            .collect()
    }

    fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(f)
    }

    /// The raw appended files decode to exactly the arrays (names, types, components, bytes,
    /// order) of the vtkio files written before, at levels 0, 1 and 6, and their bytes are
    /// the same on 1 and 2 threads. 6000 points: the vector arrays (144 000 bytes) span three
    /// blocks of 65 536 bytes, the last one partial; 2731 * 24 = 65 544 bytes of
    /// connectivity, one full block and 8 bytes.
    #[test]
    fn raw_appended_frames_decode_to_the_vtkio_arrays_bit_for_bit_on_any_thread_count() {
        let (mut frame_arrays, mut joint_arrays, mut files) = (0, 0, 0);
        for (n, m) in [(6000, 2731), (3, 1), (0, 0)] {
            let fr = frame(n, m);
            let j = fr.joints.as_ref().unwrap();
            for level in [0, 1, 6] {
                let one = in_pool(1, || vtu::encode(&fr, level).unwrap());
                let two = in_pool(2, || vtu::encode(&fr, level).unwrap());
                assert!(
                    one == two,
                    "frame bytes differ with the thread count, level {level}"
                );
                let got = as_tuples(vtu::read(&one).unwrap());
                let want = arrays_of(&read_back(encode(&fr, level).unwrap()));
                assert_eq!(got.len(), want.len());
                assert_eq!(got.len(), 19, "4 + 1 + 3 point, 6 + 1 cell, 4 grid arrays");
                for (g, w) in got.iter().zip(&want) {
                    assert!(g == w, "array {} differs at level {level}, {n} points", w.0);
                }
                frame_arrays = got.len();
                let text = String::from_utf8_lossy(&one[..200]);
                assert_eq!(text.contains("vtkZLibDataCompressor"), level > 0);
                let j1 = in_pool(1, || joints::encode(j, level).unwrap());
                let j2 = in_pool(2, || joints::encode(j, level).unwrap());
                assert!(j1 == j2, "joint bytes differ with the thread count");
                let got = as_tuples(vtu::read(&j1).unwrap());
                let want = arrays_of(&read_back(encode_joints(j, level).unwrap()));
                assert_eq!((got.len(), want.len()), (21, 21), "17 cell, 4 grid arrays");
                for (g, w) in got.iter().zip(&want) {
                    assert!(g == w, "joint array {} differs at level {level}", w.0);
                }
                joint_arrays = got.len();
                files += 2;
            }
        }
        fdem_figures::record(
            91,
            format!(
                "equal ({frame_arrays} frame and {joint_arrays} joint arrays each, {files} files)"
            ),
        );
    }

    #[test]
    fn compression_shrinks_a_smooth_frame_and_level_ten_is_an_error() {
        let mut fr = frame(6000, 2731);
        fr.velocity = vec![[0.0; 2]; 6000];
        let raw = vtu::encode(&fr, 0).unwrap();
        let z = vtu::encode(&fr, 1).unwrap();
        assert!(z.len() < raw.len(), "{} !< {}", z.len(), raw.len());
        assert!(vtu::encode(&fr, 10).unwrap_err().contains("above 9"));
    }
}
