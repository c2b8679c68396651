//! One frame as an XML `.vtu` file with raw appended binary data, zlib compressed in
//! independent blocks (the writer of the triangle frames and, through [`Grid`], of the joint
//! frames).
//!
//! Point arrays: `displacement`, `velocity`, `force`, `reaction` (3 components, z = 0).
//! Cell arrays: `stress` (full 3x3 tensor, 9 components, row major, so ParaView's tensor
//! filters apply), `principal_stress` (s1, s2), `von_mises`, `strain_energy_density`,
//! `material`, `body`. Then the frame's extra arrays from the force contributions, e.g.
//! `contact_force` (points, 3 components) and `contact_active` (cells) with contact.
//!
//! The layout is VTK's own: every `<DataArray>` header carries `format="appended"` and the
//! `offset` of its data in `<AppendedData encoding="raw">`, after the `_` marker; sizes are
//! `UInt64` (`header_type="UInt64"`). At a zlib level from 1 to 9 each array is cut into
//! blocks of [`BLOCK`] bytes (the last one shorter), each compressed on its own
//! (`compressor="vtkZLibDataCompressor"`), and the array's data is the header
//! `[blocks, BLOCK, size of the last block if partial else 0, compressed size of each block]`
//! followed by the compressed blocks. Level 0 writes each array as its byte count and its raw
//! bytes, with no compressor. The blocks are compressed in parallel; since they are
//! independent and cut at fixed sizes, the file is the same for any number of threads.
//! zlib (not lz4) because meshio, VTK and ParaView all read it.

use std::borrow::Cow;

use flate2::{Compress, Compression, FlushCompress, Status};
use rayon::prelude::*;

use super::frame::FrameData;

/// Uncompressed bytes per zlib block.
pub const BLOCK: usize = 1 << 16;

/// VTK cell type of a triangle.
pub const VTK_TRIANGLE: u8 = 5;
/// VTK cell type of a line.
pub const VTK_LINE: u8 = 3;

/// One data array of a grid: its little-endian bytes with the VTK type and layout.
#[derive(Debug, Clone)]
pub struct Array {
    /// `Name` attribute.
    pub name: String,
    /// VTK type name (`Float64`, `Int32`, `Int64`, `UInt8`).
    pub ty: &'static str,
    /// Components per tuple.
    pub components: usize,
    /// The values, little endian.
    pub bytes: Vec<u8>,
}

impl Array {
    /// A `Float64` array of `components` per tuple.
    pub fn f64(name: &str, components: usize, v: &[f64]) -> Self {
        Self::new(
            name,
            "Float64",
            components,
            le_bytes(v, 8, |x, o| put(o, 0, *x)),
        )
    }

    /// An `Int32` scalar array.
    pub fn i32(name: &str, v: &[i32]) -> Self {
        let bytes = le_bytes(v, 4, |x, o| o.copy_from_slice(&x.to_le_bytes()));
        Self::new(name, "Int32", 1, bytes)
    }

    /// A `Float64` array of 3 components from 2D vectors (z = 0).
    pub fn vec3(name: &str, v: &[[f64; 2]]) -> Self {
        let bytes = le_bytes(v, 24, |p, o| {
            put(o, 0, p[0]);
            put(o, 1, p[1]);
            put(o, 2, 0.0);
        });
        Self::new(name, "Float64", 3, bytes)
    }

    fn new(name: &str, ty: &'static str, components: usize, bytes: Vec<u8>) -> Self {
        Self {
            name: name.into(),
            ty,
            components,
            bytes,
        }
    }
}

/// Writes `x` as the `k`-th f64 of `o`.
fn put(o: &mut [u8], k: usize, x: f64) {
    o[8 * k..8 * k + 8].copy_from_slice(&x.to_le_bytes());
}

/// The bytes of `src`, each item written by `write` into its `width` bytes (in parallel).
fn le_bytes<T: Sync>(src: &[T], width: usize, write: impl Fn(&T, &mut [u8]) + Sync) -> Vec<u8> {
    let mut out = vec![0u8; src.len() * width];
    const CHUNK: usize = 4096;
    out.par_chunks_mut(CHUNK * width)
        .zip(src.par_chunks(CHUNK))
        .for_each(|(o, s)| {
            for (o, x) in o.chunks_exact_mut(width).zip(s) {
                write(x, o);
            }
        });
    out
}

/// An unstructured grid of one cell type with fixed vertices per cell.
#[derive(Debug, Clone)]
pub struct Grid {
    /// Number of points.
    pub n_points: usize,
    /// Number of cells.
    pub n_cells: usize,
    /// Point coordinates (3 components `Float64`).
    pub points: Array,
    /// `connectivity` (`Int64`).
    pub connectivity: Array,
    /// `offsets` (`Int64`).
    pub offsets: Array,
    /// `types` (`UInt8`).
    pub types: Array,
    /// Point data, in order.
    pub point_data: Vec<Array>,
    /// Cell data, in order.
    pub cell_data: Vec<Array>,
    /// The point array named as the active vectors (`<PointData Vectors=..>`), if any.
    pub active_vectors: Option<String>,
    /// The cell array named as the active tensors (`<CellData Tensors=..>`), if any.
    pub active_tensors: Option<String>,
}

impl Grid {
    /// A grid of cells of `verts` vertices each and VTK type `cell_type`: `connectivity` is
    /// the little-endian `Int64` vertex list (`verts` entries per cell), `points` the point
    /// coordinates.
    pub fn new(points: &[[f64; 2]], connectivity: Vec<u8>, verts: usize, cell_type: u8) -> Self {
        let n_cells = connectivity.len() / 8 / verts.max(1);
        let offsets: Vec<i64> = (1..=n_cells as i64).map(|i| verts as i64 * i).collect();
        Self {
            n_points: points.len(),
            n_cells,
            points: Array::vec3("Points", points),
            connectivity: Array::new("connectivity", "Int64", 1, connectivity),
            offsets: Array::new(
                "offsets",
                "Int64",
                1,
                le_bytes(&offsets, 8, |x, o| o.copy_from_slice(&x.to_le_bytes())),
            ),
            types: Array::new("types", "UInt8", 1, vec![cell_type; n_cells]),
            point_data: Vec::new(),
            cell_data: Vec::new(),
            active_vectors: None,
            active_tensors: None,
        }
    }

    /// The bytes of the `.vtu` file at zlib level `level` (0: uncompressed; at most 9).
    pub fn to_bytes(&self, level: u32) -> Result<Vec<u8>, String> {
        if level > 9 {
            return Err(format!("zlib level {level} is above 9"));
        }
        let arrays: Vec<&Array> = self
            .point_data
            .iter()
            .chain(&self.cell_data)
            .chain([&self.points, &self.connectivity, &self.offsets, &self.types])
            .collect();
        let encoded = encode_arrays(&arrays, level)?;
        let mut offsets = Vec::with_capacity(encoded.len());
        let mut at = 0usize;
        for e in &encoded {
            offsets.push(at);
            at += e.iter().map(|p| p.len()).sum::<usize>();
        }
        let xml = self.xml(&offsets, level);
        let mut out = Vec::with_capacity(xml.len() + at + 64);
        out.extend_from_slice(xml.as_bytes());
        for part in encoded.iter().flatten() {
            out.extend_from_slice(part);
        }
        out.extend_from_slice(b"\n  </AppendedData>\n</VTKFile>\n");
        Ok(out)
    }

    /// The XML before the appended data, up to and including the `_` marker; `offsets` in
    /// the order point data, cell data, points, connectivity, offsets, types.
    fn xml(&self, offsets: &[usize], level: u32) -> String {
        use std::fmt::Write;
        let compressor = if level > 0 {
            " compressor=\"vtkZLibDataCompressor\""
        } else {
            ""
        };
        let mut s = String::new();
        let _ = write!(
            s,
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
             byte_order=\"LittleEndian\" header_type=\"UInt64\"{compressor}>\n  \
             <UnstructuredGrid>\n    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
            self.n_points, self.n_cells
        );
        let mut off = offsets.iter();
        let mut arrays = |s: &mut String, list: &[&Array]| {
            for a in list {
                let comps = if a.components > 1 {
                    format!(" NumberOfComponents=\"{}\"", a.components)
                } else {
                    String::new()
                };
                let _ = writeln!(
                    s,
                    "        <DataArray type=\"{}\" Name=\"{}\"{comps} format=\"appended\" \
                     offset=\"{}\"/>",
                    a.ty,
                    a.name,
                    off.next().copied().unwrap_or(0)
                );
            }
        };
        let active = |key: &str, name: &Option<String>| {
            name.as_ref()
                .map_or(String::new(), |n| format!(" {key}=\"{n}\""))
        };
        let _ = writeln!(
            s,
            "      <PointData{}>",
            active("Vectors", &self.active_vectors)
        );
        arrays(&mut s, &self.point_data.iter().collect::<Vec<_>>());
        s.push_str("      </PointData>\n");
        let _ = writeln!(
            s,
            "      <CellData{}>",
            active("Tensors", &self.active_tensors)
        );
        arrays(&mut s, &self.cell_data.iter().collect::<Vec<_>>());
        s.push_str("      </CellData>\n      <Points>\n");
        arrays(&mut s, &[&self.points]);
        s.push_str("      </Points>\n      <Cells>\n");
        arrays(&mut s, &[&self.connectivity, &self.offsets, &self.types]);
        s.push_str(
            "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  \
             <AppendedData encoding=\"raw\">\n   _",
        );
        s
    }
}

/// Each array's appended data as a list of byte parts (header, then blocks). Level 0: the
/// byte count and the raw bytes; else the zlib block header and the blocks, compressed in
/// parallel (the bytes do not depend on the number of threads).
fn encode_arrays<'a>(arrays: &[&'a Array], level: u32) -> Result<Vec<Vec<Cow<'a, [u8]>>>, String> {
    if level == 0 {
        return Ok(arrays
            .iter()
            .map(|a| {
                let n = (a.bytes.len() as u64).to_le_bytes().to_vec();
                vec![Cow::Owned(n), Cow::Borrowed(&a.bytes[..])]
            })
            .collect());
    }
    let blocks: Vec<(usize, &'a [u8])> = arrays
        .iter()
        .enumerate()
        .flat_map(|(i, a)| a.bytes.chunks(BLOCK).map(move |b| (i, b)))
        .collect();
    let compressed: Vec<Result<Vec<u8>, String>> = blocks
        .par_iter()
        .map_init(
            || Compress::new(Compression::new(level), true),
            |z, (_, b)| compress_block(z, b),
        )
        .collect();
    let mut out: Vec<Vec<Cow<'a, [u8]>>> = arrays.iter().map(|_| Vec::new()).collect();
    let mut sizes: Vec<Vec<u64>> = arrays.iter().map(|_| Vec::new()).collect();
    for ((i, _), c) in blocks.iter().zip(compressed) {
        let c = c?;
        sizes[*i].push(c.len() as u64);
        out[*i].push(Cow::Owned(c));
    }
    for ((a, parts), sizes) in arrays.iter().zip(&mut out).zip(sizes) {
        let partial = a.bytes.len() % BLOCK;
        let mut head = Vec::with_capacity(8 * (3 + sizes.len()));
        for v in [sizes.len() as u64, BLOCK as u64, partial as u64]
            .into_iter()
            .chain(sizes)
        {
            head.extend_from_slice(&v.to_le_bytes());
        }
        parts.insert(0, Cow::Owned(head));
    }
    Ok(out)
}

/// One block as a complete zlib stream; `z` is reset after use.
fn compress_block(z: &mut Compress, block: &[u8]) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(block.len() + block.len() / 1000 + 64);
    loop {
        let before = z.total_in();
        let rest = &block[(before as usize)..];
        match z.compress_vec(rest, &mut out, FlushCompress::Finish) {
            Ok(Status::StreamEnd) => break,
            Ok(_) => out.reserve(out.capacity().max(1024)),
            Err(e) => {
                z.reset();
                return Err(format!("zlib: {e}"));
            }
        }
    }
    z.reset();
    Ok(out)
}

/// Encodes a frame as the bytes of a `.vtu` file (zlib level `level`, 0 = uncompressed).
pub fn encode(frame: &FrameData, level: u32) -> Result<Vec<u8>, String> {
    let conn = le_bytes(&frame.triangles, 24, |t, o| {
        for k in 0..3 {
            o[8 * k..8 * k + 8].copy_from_slice(&(t[k] as i64).to_le_bytes());
        }
    });
    let mut grid = Grid::new(&frame.points, conn, 3, VTK_TRIANGLE);
    grid.point_data = vec![
        Array::vec3("displacement", &frame.displacement),
        Array::vec3("velocity", &frame.velocity),
        Array::vec3("force", &frame.force),
        Array::vec3("reaction", &frame.reaction),
    ];
    for (name, v) in &frame.extra_point_vectors {
        grid.point_data.push(Array::vec3(name, v));
    }
    let stress = le_bytes(&frame.stress, 72, |s, o| {
        for (k, x) in [s[0], s[2], 0.0, s[2], s[1], 0.0, 0.0, 0.0, s[3]]
            .into_iter()
            .enumerate()
        {
            put(o, k, x);
        }
    });
    let principal = le_bytes(&frame.principal, 16, |p, o| {
        put(o, 0, p[0]);
        put(o, 1, p[1]);
    });
    grid.cell_data = vec![
        Array::new("stress", "Float64", 9, stress),
        Array::new("principal_stress", "Float64", 2, principal),
        Array::f64("von_mises", 1, &frame.von_mises),
        Array::f64("strain_energy_density", 1, &frame.energy_density),
        Array::i32("material", &frame.material),
        Array::i32("body", &frame.body),
    ];
    for (name, v) in &frame.extra_cell_scalars {
        grid.cell_data.push(Array::f64(name, 1, v));
    }
    grid.active_vectors = Some("displacement".into());
    grid.active_tensors = Some("stress".into());
    grid.to_bytes(level)
}

/// Reads a file of this module's format back (the tests' and users' check of what was
/// written): each array with its name, type, components and little-endian bytes, in the
/// file's order (point data, cell data, points, connectivity, offsets, types). Only this
/// writer's layout is read (one piece, raw appended data, `UInt64` headers); anything else
/// is an error.
pub fn read(bytes: &[u8]) -> Result<Vec<Array>, String> {
    use std::io::Read;
    let marker = b"<AppendedData encoding=\"raw\">\n   _";
    let at = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .ok_or("no raw appended data")?;
    let xml = std::str::from_utf8(&bytes[..at]).map_err(|_| "the XML is not UTF-8")?;
    let data = &bytes[at + marker.len()..];
    let zlib = xml.contains("compressor=\"vtkZLibDataCompressor\"");
    let attr = |line: &str, key: &str| -> Option<String> {
        let start = line.find(&format!(" {key}=\""))? + key.len() + 3;
        Some(line[start..].split('"').next()?.to_string())
    };
    let short = || "the appended data ends early".to_string();
    let u64_at = |d: &[u8], k: usize| -> Result<usize, String> {
        let b = d.get(8 * k..8 * k + 8).ok_or_else(short)?;
        Ok(u64::from_le_bytes(b.try_into().map_err(|_| short())?) as usize)
    };
    let mut out = Vec::new();
    for line in xml.lines().filter(|l| l.contains("<DataArray")) {
        let field = |key| attr(line, key).ok_or_else(|| format!("no {key} in {line}"));
        let off: usize = field("offset")?.parse().map_err(|_| "bad offset")?;
        let d = data.get(off..).ok_or_else(short)?;
        let mut values = Vec::new();
        if zlib {
            let (n, block, partial) = (u64_at(d, 0)?, u64_at(d, 1)?, u64_at(d, 2)?);
            let mut pos = 8 * (3 + n);
            for b in 0..n {
                let size = u64_at(d, 3 + b)?;
                let part = d.get(pos..pos + size).ok_or_else(short)?;
                let before = values.len();
                flate2::read::ZlibDecoder::new(part)
                    .read_to_end(&mut values)
                    .map_err(|e| format!("zlib: {e}"))?;
                let want = if b + 1 == n && partial != 0 {
                    partial
                } else {
                    block
                };
                if values.len() - before != want {
                    return Err(format!("block {b} of {line} is not {want} bytes"));
                }
                pos += size;
            }
        } else {
            let n = u64_at(d, 0)?;
            values.extend_from_slice(d.get(8..8 + n).ok_or_else(short)?);
        }
        let ty = match field("type")?.as_str() {
            "Float64" => "Float64",
            "Int32" => "Int32",
            "Int64" => "Int64",
            "UInt8" => "UInt8",
            t => return Err(format!("unexpected type {t}")),
        };
        let components = match attr(line, "NumberOfComponents") {
            Some(c) => c.parse().map_err(|_| "bad NumberOfComponents")?,
            None => 1,
        };
        out.push(Array::new(&field("Name")?, ty, components, values));
    }
    Ok(out)
}

impl Array {
    /// The values of a `Float64` array.
    pub fn to_f64(&self) -> Vec<f64> {
        self.bytes
            .chunks_exact(8)
            .map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
            .collect()
    }

    /// The values of an `Int64` array.
    pub fn to_i64(&self) -> Vec<i64> {
        self.bytes
            .chunks_exact(8)
            .map(|b| i64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
            .collect()
    }
}
