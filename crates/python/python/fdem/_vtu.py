"""Reader of the ``.vtu`` files fdem writes (``frame_NNNN.vtu``, ``joints_NNNN.vtu``).

Pure Python (the standard library's ``xml`` and ``zlib``, and numpy): it needs neither the
compiled extension nor meshio. It reads exactly the layout of fdem's writer: an XML
``UnstructuredGrid`` of one piece, little endian, ``header_type="UInt64"``, every
``<DataArray>`` ``format="appended"`` with its ``offset`` into ``<AppendedData
encoding="raw">``. With ``compressor="vtkZLibDataCompressor"`` (``output.compression`` 1 to 9)
each array is ``[blocks, block size, size of the last block if partial else 0, compressed size
of each block]`` (``UInt64``) followed by the zlib blocks; without a compressor
(``output.compression`` 0) it is its byte count (``UInt64``) followed by the raw bytes. Every
cell has the same number of vertices (triangles in frames, lines in joint frames).

A file of another layout (ASCII or base64 data, another header type, several pieces, mixed
cells, a file cut short) raises :class:`VtuFormatError` naming the file and what differs; read
such files with meshio (``meshio.read(path)``).

The arrays come back as they are in the file: ``Float64`` as float64, ``Int64`` as int64,
``Int32`` as int32, ``UInt8`` as uint8; an array of one component has shape ``(n,)``, of
``k > 1`` components ``(n, k)`` (as meshio gives them). fdem's 2D vectors are 3 components
(z = 0) and its stresses the full 3x3 tensor in 9 components, row major; :mod:`fdem._output`
turns them back into fdem's 2D arrays.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
import zlib
from dataclasses import dataclass, field
from typing import Callable, Dict, List, NoReturn, Union

import numpy as np

from ._named import Named

__all__ = ["VtuData", "VtuFormatError", "read_vtu"]

PathLike = Union[str, "os.PathLike[str]"]

_TYPES: Dict[str, np.dtype] = {
    "Float64": np.dtype("<f8"),
    "Float32": np.dtype("<f4"),
    "Int64": np.dtype("<i8"),
    "Int32": np.dtype("<i4"),
    "UInt8": np.dtype("u1"),
}

_APPENDED = b'<AppendedData encoding="raw">'


class VtuFormatError(ValueError):
    """A file that is not a ``.vtu`` file of fdem's layout (or is damaged).

    ``str(e)`` names the file, what differs and the fix; ``e.file`` is the file's path.
    """

    def __init__(self, file: str, what: str) -> None:
        self.file = file
        self.what = what
        super().__init__(
            f"{file}: {what}: not a .vtu file as fdem writes it (raw appended data, UInt64 "
            "headers, zlib blocks or uncompressed); read other .vtu files with meshio "
            "(meshio.read(path))"
        )


@dataclass
class VtuData:
    """The contents of one ``.vtu`` file.

    Attributes:
        path: the file read.
        points: point coordinates, float64, shape ``(n, 3)`` (z = 0 in fdem's files).
        cells: the cells' point indices, int64, shape ``(m, k)`` (k = 3 for triangles, 2 for
            the joints' lines).
        cell_type: the VTK cell type of every cell (5 triangle, 3 line).
        point_data: the point arrays by name, in the file's order (a missing name raises a
            KeyError listing the arrays there).
        cell_data: the cell arrays by name, in the file's order (the same).
    """

    path: str
    points: np.ndarray
    cells: np.ndarray
    cell_type: int
    point_data: Dict[str, np.ndarray] = field(
        default_factory=lambda: Named(what="point array")
    )
    cell_data: Dict[str, np.ndarray] = field(default_factory=lambda: Named(what="cell array"))


def _u64(data: memoryview, at: int, count: int, fail: Callable[[str], NoReturn]) -> np.ndarray:
    end = at + 8 * count
    if at < 0 or end > len(data):
        fail("the appended data ends early")
    return np.frombuffer(data[at:end], dtype="<u8").astype(np.int64)


def _decode(
    data: memoryview, offset: int, zlib_blocks: bool, name: str, fail: Callable[[str], NoReturn]
) -> bytearray:
    """The bytes of the array at ``offset`` of the appended data (a fresh buffer)."""
    if zlib_blocks:
        n, block, partial = (int(v) for v in _u64(data, offset, 3, fail))
        sizes = _u64(data, offset + 24, n, fail)
        pos = offset + 24 + 8 * n
        out = bytearray()
        for b, size in enumerate(sizes):
            size = int(size)
            if pos + size > len(data):
                fail(f"array {name}: the appended data ends early")
            try:
                chunk = zlib.decompress(data[pos : pos + size])
            except zlib.error as e:
                fail(f"array {name}, block {b}: zlib: {e}")
            want = partial if (b + 1 == n and partial != 0) else block
            if len(chunk) != want:
                fail(f"array {name}: block {b} is {len(chunk)} bytes, not {want}")
            out += chunk
            pos += size
        return out
    (n,) = (int(v) for v in _u64(data, offset, 1, fail))
    if offset + 8 + n > len(data):
        fail(f"array {name}: the appended data ends early")
    return bytearray(data[offset + 8 : offset + 8 + n])


def read_vtu(path: PathLike) -> VtuData:
    """Reads a ``.vtu`` file written by fdem.

    Args:
        path: the file (``frame_NNNN.vtu`` or ``joints_NNNN.vtu`` of a run folder).

    Returns:
        The points, cells and arrays, equal bit for bit to what the solver wrote.

    Raises:
        FileNotFoundError: no such file.
        VtuFormatError: the file is not of fdem's layout, or is damaged.
    """
    path = os.fspath(path)
    with open(path, "rb") as f:
        raw = f.read()

    def fail(what: str) -> NoReturn:
        raise VtuFormatError(path, what)

    at = raw.find(_APPENDED)
    if at < 0:
        fail('no <AppendedData encoding="raw">')
    marker = raw.find(b"_", at + len(_APPENDED))
    if marker < 0 or raw[at + len(_APPENDED) : marker].strip() != b"":
        fail("no '_' marker at the start of the appended data")
    data = memoryview(raw)[marker + 1 :]
    try:
        root = ET.fromstring(raw[:at] + b"</VTKFile>")
    except ET.ParseError as e:
        fail(f"the XML header does not parse ({e})")
    if root.tag != "VTKFile" or root.get("type") != "UnstructuredGrid":
        fail("not a VTKFile of type UnstructuredGrid")
    if root.get("byte_order") != "LittleEndian":
        fail(f"byte_order is {root.get('byte_order')!r}, not LittleEndian")
    if root.get("header_type") != "UInt64":
        fail(f"header_type is {root.get('header_type')!r}, not UInt64")
    compressor = root.get("compressor")
    if compressor not in (None, "vtkZLibDataCompressor"):
        fail(f"compressor {compressor!r}")
    pieces = root.findall("./UnstructuredGrid/Piece")
    if len(pieces) != 1:
        fail(f"{len(pieces)} pieces, not one")
    piece = pieces[0]
    try:
        n_points = int(piece.get("NumberOfPoints", ""))
        n_cells = int(piece.get("NumberOfCells", ""))
    except ValueError:
        fail("the Piece has no NumberOfPoints or NumberOfCells")

    def array(e: ET.Element, tuples: int) -> np.ndarray:
        name = e.get("Name", "?")
        if e.get("format") != "appended":
            fail(f"array {name} is format={e.get('format')!r}, not appended")
        ty = _TYPES.get(e.get("type", ""))
        if ty is None:
            fail(f"array {name} has type {e.get('type')!r}")
        try:
            comps = int(e.get("NumberOfComponents", "1"))
            offset = int(e.get("offset", ""))
        except ValueError:
            fail(f"array {name}: no valid offset or NumberOfComponents")
        b = _decode(data, offset, compressor is not None, name, fail)
        if len(b) != tuples * comps * ty.itemsize:
            fail(
                f"array {name} has {len(b)} bytes, not {tuples} x {comps} x {ty.itemsize}"
            )
        # a view of the fresh buffer (writable), in the machine's byte order
        a = np.frombuffer(b, dtype=ty).astype(ty.newbyteorder("="), copy=False)
        return a.reshape(tuples, comps) if comps > 1 else a

    def section(tag: str, tuples: int, what: str) -> Dict[str, np.ndarray]:
        out: Dict[str, np.ndarray] = Named(what=what)
        for s in piece.findall(tag):
            for e in s.findall("DataArray"):
                name = e.get("Name", "")
                if name in out:
                    fail(f"{tag} has two arrays named {name}")
                out[name] = array(e, tuples)
        return out

    def named(parent: str, name: str, tuples: int) -> np.ndarray:
        found: List[ET.Element] = [
            e for e in piece.findall(f"./{parent}/DataArray") if e.get("Name") == name
        ]
        if len(found) != 1:
            fail(f"no single <DataArray Name=\"{name}\"> in <{parent}>")
        return array(found[0], tuples)

    point_data = section("PointData", n_points, "point array")
    cell_data = section("CellData", n_cells, "cell array")
    pts = piece.findall("./Points/DataArray")
    if len(pts) != 1:
        fail("no single <DataArray> in <Points>")
    points = array(pts[0], n_points)
    if points.ndim != 2 or points.shape[1] != 3 or points.dtype != np.float64:
        fail("the points are not 3 Float64 components")
    offsets = named("Cells", "offsets", n_cells)
    types = named("Cells", "types", n_cells)
    if offsets.dtype != np.int64 or types.dtype != np.uint8:
        fail("the cell offsets are not Int64 or the types not UInt8")
    verts = int(offsets[0]) if n_cells else 0
    if n_cells and (verts <= 0 or not np.array_equal(offsets, verts * np.arange(1, n_cells + 1))):
        fail("the cells do not all have the same number of points")
    if n_cells and not (types == types[0]).all():
        fail("the cells are not all of one type")
    conn_e = [e for e in piece.findall("./Cells/DataArray") if e.get("Name") == "connectivity"]
    if len(conn_e) != 1:
        fail('no single <DataArray Name="connectivity"> in <Cells>')
    conn = array(conn_e[0], n_cells * verts)
    if conn.dtype != np.int64:
        fail("the connectivity is not Int64")
    if n_cells and (conn.min() < 0 or conn.max() >= n_points):
        fail("the connectivity indexes a point that does not exist")
    return VtuData(
        path=path,
        points=points,
        cells=conn.reshape(n_cells, verts),
        cell_type=int(types[0]) if n_cells else 0,
        point_data=point_data,
        cell_data=cell_data,
    )
