//! One frame as an XML `.vtu` file with raw appended binary data, zlib compressed in
//! independent blocks (the writer of the triangle frames and, through [`Grid`], of the joint
//! frames).
//!
//! Point arrays: `displacement`, `velocity`, `force`, `reaction` (3 components, z = 0), the
//! extra point arrays (`contact_force`), then the recovered `nodal_stress` (9 components, as
//! `stress`), `nodal_principal_stress` (s1, s2) and `nodal_von_mises`.
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

use flate2::{Compress, Compression, FlushCompress, Status};
use rayon::prelude::*;

use std::path::{Path, PathBuf};

use super::atomic::write_atomic_with;
use super::frame::FrameData;
use crate::input::arrays::ArraySet;

/// Uncompressed bytes per zlib block.
pub const BLOCK: usize = 1 << 16;

/// VTK cell type of a triangle.
pub const VTK_TRIANGLE: u8 = 5;
/// VTK cell type of a line.
pub const VTK_LINE: u8 = 3;

/// One data array as read back by [`read`]: its little-endian bytes with the VTK type and
/// layout.
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
    fn new(name: &str, ty: &'static str, components: usize, bytes: Vec<u8>) -> Self {
        Self {
            name: name.into(),
            ty,
            components,
            bytes,
        }
    }
}

/// The values of an array to be written, borrowed where they lie (no copy is made: each
/// block's bytes are produced when the block is compressed or written).
#[derive(Debug, Clone, Copy)]
pub enum Values<'a> {
    /// `Float64` values as they are.
    F64(&'a [f64]),
    /// `Int32` values.
    I32(&'a [i32]),
    /// 2D vectors as three `Float64` components (z = 0).
    Vec3(&'a [[f64; 2]]),
    /// Pairs of `Float64`.
    Pair(&'a [[f64; 2]]),
    /// In-plane stress (xx, yy, xy, zz) as the full 3x3 tensor, row major (9 `Float64`).
    Tensor(&'a [[f64; 4]]),
    /// Triangles as three `Int64` node indices each.
    Triangles(&'a [[u32; 3]]),
    /// `0, 1, .., n - 1` as `Int64` (the connectivity of cells with their own points).
    Count(usize),
    /// `verts, 2 verts, .., n verts` as `Int64` (the offsets of `n` cells of `verts` points).
    Offsets(usize, usize),
    /// `n` copies of one `UInt8` (the cell types).
    Repeat(u8, usize),
}

impl Values<'_> {
    /// Bytes per entry.
    fn width(&self) -> usize {
        match self {
            Values::F64(_) | Values::Count(_) | Values::Offsets(..) => 8,
            Values::I32(_) => 4,
            Values::Vec3(_) | Values::Triangles(_) => 24,
            Values::Pair(_) => 16,
            Values::Tensor(_) => 72,
            Values::Repeat(..) => 1,
        }
    }

    /// Number of entries.
    fn len(&self) -> usize {
        match self {
            Values::F64(v) => v.len(),
            Values::I32(v) => v.len(),
            Values::Vec3(v) | Values::Pair(v) => v.len(),
            Values::Tensor(v) => v.len(),
            Values::Triangles(v) => v.len(),
            Values::Count(n) | Values::Offsets(_, n) | Values::Repeat(_, n) => *n,
        }
    }

    /// Bytes in all.
    pub fn byte_len(&self) -> usize {
        self.len() * self.width()
    }

    /// VTK type name.
    fn vtk_type(&self) -> &'static str {
        match self {
            Values::I32(_) => "Int32",
            Values::Triangles(_) | Values::Count(_) | Values::Offsets(..) => "Int64",
            Values::Repeat(..) => "UInt8",
            _ => "Float64",
        }
    }

    /// Writes entries `i..` into `out` (a whole number of entries).
    fn put_entries(&self, i: usize, out: &mut [u8]) {
        fn f64s<const N: usize>(out: &mut [u8], items: impl Iterator<Item = [f64; N]>) {
            for (o, x) in out.chunks_exact_mut(8 * N).zip(items) {
                for (o, x) in o.chunks_exact_mut(8).zip(x) {
                    o.copy_from_slice(&x.to_le_bytes());
                }
            }
        }
        fn i64s(out: &mut [u8], items: impl Iterator<Item = i64>) {
            for (o, x) in out.chunks_exact_mut(8).zip(items) {
                o.copy_from_slice(&x.to_le_bytes());
            }
        }
        match *self {
            Values::F64(v) => f64s::<1>(out, v[i..].iter().map(|x| [*x])),
            Values::I32(v) => {
                for (o, x) in out.chunks_exact_mut(4).zip(&v[i..]) {
                    o.copy_from_slice(&x.to_le_bytes());
                }
            }
            Values::Vec3(v) => f64s(out, v[i..].iter().map(|p| [p[0], p[1], 0.0])),
            Values::Pair(v) => f64s(out, v[i..].iter().copied()),
            Values::Tensor(v) => f64s(
                out,
                v[i..]
                    .iter()
                    .map(|s| [s[0], s[2], 0.0, s[2], s[1], 0.0, 0.0, 0.0, s[3]]),
            ),
            Values::Triangles(v) => {
                for (o, t) in out.chunks_exact_mut(24).zip(&v[i..]) {
                    for (o, k) in o.chunks_exact_mut(8).zip(t) {
                        o.copy_from_slice(&i64::from(*k).to_le_bytes());
                    }
                }
            }
            Values::Count(_) => i64s(out, i as i64..),
            Values::Offsets(verts, _) => i64s(out, (i as i64 + 1..).map(|k| verts as i64 * k)),
            Values::Repeat(b, _) => out.fill(b),
        }
    }

    /// Fills `out` with the bytes from byte `at` on (entries cut at any byte).
    fn fill(&self, at: usize, out: &mut [u8]) {
        let w = self.width();
        let mut scratch = [0u8; 72];
        let (mut pos, end, mut o) = (at, at + out.len(), 0);
        while pos < end {
            let (i, r) = (pos / w, pos % w);
            if r == 0 && end - pos >= w {
                let n = (end - pos) / w;
                self.put_entries(i, &mut out[o..o + n * w]);
                pos += n * w;
                o += n * w;
            } else {
                self.put_entries(i, &mut scratch[..w]);
                let take = (w - r).min(end - pos);
                out[o..o + take].copy_from_slice(&scratch[r..r + take]);
                pos += take;
                o += take;
            }
        }
    }

    /// All the bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = vec![0u8; self.byte_len()];
        self.fill(0, &mut out);
        out
    }
}

/// One named array of a grid to be written.
#[derive(Debug, Clone, Copy)]
pub struct Column<'a> {
    /// `Name` attribute.
    pub name: &'a str,
    /// Components per tuple.
    pub components: usize,
    /// The values.
    pub values: Values<'a>,
}

impl<'a> Column<'a> {
    /// The array `name` of `components` per tuple.
    pub fn new(name: &'a str, components: usize, values: Values<'a>) -> Self {
        Self {
            name,
            components,
            values,
        }
    }
}

/// An unstructured grid of one cell type with fixed vertices per cell, its arrays borrowed.
#[derive(Debug, Clone)]
pub struct Grid<'a> {
    /// Number of points.
    pub n_points: usize,
    /// Number of cells.
    pub n_cells: usize,
    /// Point coordinates (3 components `Float64`).
    pub points: Column<'a>,
    /// `connectivity` (`Int64`).
    pub connectivity: Column<'a>,
    /// `offsets` (`Int64`).
    pub offsets: Column<'a>,
    /// `types` (`UInt8`).
    pub types: Column<'a>,
    /// Point data, in order.
    pub point_data: Vec<Column<'a>>,
    /// Cell data, in order.
    pub cell_data: Vec<Column<'a>>,
    /// The point array named as the active vectors (`<PointData Vectors=..>`), if any.
    pub active_vectors: Option<&'a str>,
    /// The cell array named as the active tensors (`<CellData Tensors=..>`), if any.
    pub active_tensors: Option<&'a str>,
}

/// The appended data of one array, in pieces: owned bytes (headers, compressed blocks), or
/// an array's raw bytes (level 0), produced as they are written.
enum Part<'a> {
    Owned(Vec<u8>),
    Raw(Values<'a>),
}

impl Part<'_> {
    fn len(&self) -> usize {
        match self {
            Part::Owned(b) => b.len(),
            Part::Raw(v) => v.byte_len(),
        }
    }
}

/// A grid encoded for writing: the XML head and the appended data in pieces, in file order.
pub struct Encoded<'a> {
    head: String,
    parts: Vec<Part<'a>>,
}

/// The end of every file.
const TAIL: &[u8] = b"\n  </AppendedData>\n</VTKFile>\n";

impl Encoded<'_> {
    /// Bytes of the file.
    pub fn len(&self) -> usize {
        self.head.len() + self.parts.iter().map(Part::len).sum::<usize>() + TAIL.len()
    }

    /// True when the file has no bytes (never: it has its XML).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Writes the file's bytes to `w`, piece by piece in order.
    pub fn write_to(&self, w: &mut dyn std::io::Write) -> std::io::Result<()> {
        w.write_all(self.head.as_bytes())?;
        let mut buf = Vec::new();
        for p in &self.parts {
            match p {
                Part::Owned(b) => w.write_all(b)?,
                Part::Raw(v) => {
                    buf.resize(BLOCK.min(v.byte_len()), 0);
                    let mut at = 0;
                    while at < v.byte_len() {
                        let n = BLOCK.min(v.byte_len() - at);
                        v.fill(at, &mut buf[..n]);
                        w.write_all(&buf[..n])?;
                        at += n;
                    }
                }
            }
        }
        w.write_all(TAIL)
    }

    /// The file's bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.len());
        let _ = self.write_to(&mut out);
        out
    }
}

impl<'a> Grid<'a> {
    /// A grid of `n_cells` cells of `verts` vertices each and VTK type `cell_type`, with the
    /// node indices `connectivity` (`verts` per cell) and the point coordinates `points`.
    pub fn new(
        points: &'a [[f64; 2]],
        connectivity: Values<'a>,
        n_cells: usize,
        verts: usize,
        cell_type: u8,
    ) -> Self {
        Self {
            n_points: points.len(),
            n_cells,
            points: Column::new("Points", 3, Values::Vec3(points)),
            connectivity: Column::new("connectivity", 1, connectivity),
            offsets: Column::new("offsets", 1, Values::Offsets(verts, n_cells)),
            types: Column::new("types", 1, Values::Repeat(cell_type, n_cells)),
            point_data: Vec::new(),
            cell_data: Vec::new(),
            active_vectors: None,
            active_tensors: None,
        }
    }

    /// The grid encoded at zlib level `level` (0: uncompressed; at most 9).
    pub fn encode(&self, level: u32) -> Result<Encoded<'a>, String> {
        Ok(encode_all(&[self], level)?.remove(0))
    }

    /// The values of the arrays in the file's order: point data, cell data, points,
    /// connectivity, offsets, types.
    fn values(&self) -> Vec<Values<'a>> {
        self.point_data
            .iter()
            .chain(&self.cell_data)
            .chain([&self.points, &self.connectivity, &self.offsets, &self.types])
            .map(|c| c.values)
            .collect()
    }

    /// The bytes of the `.vtu` file at zlib level `level` (0: uncompressed; at most 9).
    pub fn to_bytes(&self, level: u32) -> Result<Vec<u8>, String> {
        Ok(self.encode(level)?.to_bytes())
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
        let mut arrays = |s: &mut String, list: &[&Column]| {
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
                    a.values.vtk_type(),
                    a.name,
                    off.next().copied().unwrap_or(0)
                );
            }
        };
        let active = |key: &str, name: Option<&str>| {
            name.map_or(String::new(), |n| format!(" {key}=\"{n}\""))
        };
        let _ = writeln!(
            s,
            "      <PointData{}>",
            active("Vectors", self.active_vectors)
        );
        arrays(&mut s, &self.point_data.iter().collect::<Vec<_>>());
        s.push_str("      </PointData>\n");
        let _ = writeln!(
            s,
            "      <CellData{}>",
            active("Tensors", self.active_tensors)
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

/// The grids `grids` encoded at zlib level `level` (0: uncompressed; at most 9), their
/// blocks compressed together (one parallel pass, no pause between the files).
pub fn encode_all<'a>(grids: &[&Grid<'a>], level: u32) -> Result<Vec<Encoded<'a>>, String> {
    if level > 9 {
        return Err(format!("zlib level {level} is above 9"));
    }
    let values: Vec<Vec<Values<'a>>> = grids.iter().map(|g| g.values()).collect();
    let flat: Vec<Values<'a>> = values.iter().flatten().copied().collect();
    let mut encoded = encode_arrays(&flat, level)?.into_iter();
    let mut out = Vec::with_capacity(grids.len());
    for (g, v) in grids.iter().zip(&values) {
        let mut offsets = Vec::with_capacity(v.len());
        let mut parts = Vec::new();
        let mut at = 0usize;
        for e in encoded.by_ref().take(v.len()) {
            offsets.push(at);
            at += e.iter().map(Part::len).sum::<usize>();
            parts.extend(e);
        }
        out.push(Encoded {
            head: g.xml(&offsets, level),
            parts,
        });
    }
    Ok(out)
}

/// Writes the grids `files` (each with its path) at zlib level `level`, each whole or not at
/// all; their blocks compressed together ([`encode_all`]) and the files written at the same
/// time ([`write_encoded`]). On failure, the first file that failed, in order, and the
/// message.
pub fn write_files(files: &[(&Grid, &Path)], level: u32) -> Result<(), (PathBuf, String)> {
    let grids: Vec<&Grid> = files.iter().map(|(g, _)| *g).collect();
    let first = files
        .first()
        .map_or_else(PathBuf::new, |(_, p)| p.to_path_buf());
    let encoded = encode_all(&grids, level).map_err(|e| (first, e))?;
    let paths: Vec<&Path> = files.iter().map(|(_, p)| *p).collect();
    write_encoded(&encoded.iter().zip(paths).collect::<Vec<_>>())
}

/// Writes each encoded grid to its path, whole or not at all, the files at the same time
/// (one thread each); on failure, the first file that failed, in order, and the message.
pub fn write_encoded(files: &[(&Encoded, &Path)]) -> Result<(), (PathBuf, String)> {
    let write = |e: &Encoded, path: &Path| {
        write_atomic_with(path, &mut |w| e.write_to(w))
            .map_err(|e| (path.to_path_buf(), e.to_string()))
    };
    let results: Vec<Result<(), (PathBuf, String)>> = std::thread::scope(|s| {
        let rest: Vec<_> = files
            .iter()
            .skip(1)
            .map(|&(e, p)| s.spawn(move || write(e, p)))
            .collect();
        let head = files.first().map_or(Ok(()), |&(e, p)| write(e, p));
        std::iter::once(head)
            .chain(rest.into_iter().map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err((PathBuf::new(), "the file writer panicked".into())))
            }))
            .collect()
    });
    results.into_iter().collect()
}

/// Each array's appended data as a list of parts (header, then blocks). Level 0: the byte
/// count and the raw bytes; else the zlib block header and the blocks, each block's bytes
/// produced and compressed in parallel (the bytes do not depend on the number of threads).
fn encode_arrays<'a>(arrays: &[Values<'a>], level: u32) -> Result<Vec<Vec<Part<'a>>>, String> {
    if level == 0 {
        return Ok(arrays
            .iter()
            .map(|a| {
                let n = (a.byte_len() as u64).to_le_bytes().to_vec();
                vec![Part::Owned(n), Part::Raw(*a)]
            })
            .collect());
    }
    // (array, first byte, bytes) of every block
    let blocks: Vec<(usize, usize, usize)> = arrays
        .iter()
        .enumerate()
        .flat_map(|(i, a)| {
            let n = a.byte_len();
            (0..n.div_ceil(BLOCK)).map(move |b| (i, b * BLOCK, BLOCK.min(n - b * BLOCK)))
        })
        .collect();
    let compressed: Vec<Result<Vec<u8>, String>> = blocks
        .par_iter()
        .map_init(
            || {
                (
                    Compress::new(Compression::new(level), true),
                    vec![0u8; BLOCK],
                )
            },
            |(z, buf), &(i, at, n)| {
                arrays[i].fill(at, &mut buf[..n]);
                compress_block(z, &buf[..n])
            },
        )
        .collect();
    let mut out: Vec<Vec<Part<'a>>> = arrays
        .iter()
        .map(|_| vec![Part::Owned(Vec::new())])
        .collect();
    let mut sizes: Vec<Vec<u64>> = arrays.iter().map(|_| Vec::new()).collect();
    for ((i, _, _), c) in blocks.iter().zip(compressed) {
        let c = c?;
        sizes[*i].push(c.len() as u64);
        out[*i].push(Part::Owned(c));
    }
    for ((a, parts), sizes) in arrays.iter().zip(&mut out).zip(sizes) {
        let partial = a.byte_len() % BLOCK;
        let mut head = Vec::with_capacity(8 * (3 + sizes.len()));
        for v in [sizes.len() as u64, BLOCK as u64, partial as u64]
            .into_iter()
            .chain(sizes)
        {
            head.extend_from_slice(&v.to_le_bytes());
        }
        parts[0] = Part::Owned(head);
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

/// The grid of a frame's triangles with the arrays of `arrays` (in the order of
/// [`super::arrays`]), borrowed from `frame`.
pub fn frame_grid<'a>(frame: &'a FrameData, arrays: &ArraySet) -> Grid<'a> {
    let mut grid = Grid::new(
        &frame.points,
        Values::Triangles(&frame.triangles),
        frame.triangles.len(),
        3,
        VTK_TRIANGLE,
    );
    let point = [
        ("displacement", &frame.displacement),
        ("velocity", &frame.velocity),
        ("force", &frame.force),
        ("reaction", &frame.reaction),
    ];
    let extra_points = frame
        .extra_point_vectors
        .iter()
        .map(|(n, v)| (n.as_str(), v));
    for (name, v) in point.into_iter().chain(extra_points) {
        if arrays.has(name) {
            grid.point_data.push(Column::new(name, 3, Values::Vec3(v)));
        }
    }
    let nodal = [
        Column::new("nodal_stress", 9, Values::Tensor(&frame.nodal_stress)),
        Column::new(
            "nodal_principal_stress",
            2,
            Values::Pair(&frame.nodal_principal),
        ),
        Column::new("nodal_von_mises", 1, Values::F64(&frame.nodal_von_mises)),
    ];
    grid.point_data
        .extend(nodal.into_iter().filter(|c| arrays.has(c.name)));
    let cells = [
        Column::new("stress", 9, Values::Tensor(&frame.stress)),
        Column::new("principal_stress", 2, Values::Pair(&frame.principal)),
        Column::new("von_mises", 1, Values::F64(&frame.von_mises)),
        Column::new(
            "strain_energy_density",
            1,
            Values::F64(&frame.energy_density),
        ),
        Column::new("material", 1, Values::I32(&frame.material)),
        Column::new("body", 1, Values::I32(&frame.body)),
    ];
    let extra_cells = frame
        .extra_cell_scalars
        .iter()
        .map(|(n, v)| Column::new(n, 1, Values::F64(v)));
    grid.cell_data = cells
        .into_iter()
        .chain(extra_cells)
        .filter(|c| arrays.has(c.name))
        .collect();
    grid.active_vectors = arrays.has("displacement").then_some("displacement");
    grid.active_tensors = arrays.has("stress").then_some("stress");
    grid
}

/// Encodes a frame with every array as the bytes of a `.vtu` file (zlib level `level`,
/// 0 = uncompressed).
pub fn encode(frame: &FrameData, level: u32) -> Result<Vec<u8>, String> {
    frame_grid(frame, &ArraySet::all()).to_bytes(level)
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
