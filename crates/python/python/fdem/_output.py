"""Lazy reading of a run folder (the ``--out`` of ``fdem run``, or the folder of ``fdem.run``).

Pure Python: needs neither the compiled extension nor meshio. Every file is read on first
access and cached. ``read(out)`` (or ``Output(out)``) gives:

- ``summary`` (``summary.json`` as a dict), ``energy`` (its ``"energy"`` ledger),
  ``accuracy`` (its accuracy indicators by name) and ``warnings`` (theirs, one line each);
- ``frames``: the frames listed in ``results.pvd``, a sequence of :class:`Frame` (time,
  points, triangles, arrays), each ``.vtu`` read when its data is first used;
  ``joint_frames``: the same for ``joints.pvd`` (fracturing runs), else ``None``;
- ``histories`` (``histories.csv``), ``walls`` (``walls.csv``): dicts of float64 arrays by
  column, ``None`` when the run has no such file; ``histories_frame()``, ``walls_frame()``:
  the same as pandas DataFrames;
- ``fractures`` (``fractures.csv``: one row per broken joint): dict of arrays (``time``, ``x``,
  ``y``, ``mode_mix``, ``energy_released`` float64, ``joint`` int64, ``mode`` str);
- ``load_displacement()``: the curve ``fdem plot load-displacement`` draws; ``failure``
  (whether the specimen failed, and how), ``failed``, ``peak_load`` (None unless it failed)
  and ``largest_load``;
- the last frame's arrays as fdem's 2D arrays: ``positions``, ``displacements``,
  ``velocities``, ``forces``, ``reactions``, ``cell_stress``, ``principal_stress``,
  ``von_mises``, ``nodal_stress``, ``triangles``, ``material``, ``body`` (None when the run
  wrote no frames, or the frames do not carry that array: ``output.arrays``), and ``joints``
  (the last joint frame's arrays).

Every dict of names (``summary``, ``energy``, ``histories``, ``walls``, ``fractures``,
``joints``, a frame's ``point_data`` and ``cell_data``) is a :class:`fdem._named.Named`: a
plain dict whose missing key raises a KeyError naming the key and listing the keys there.

How the 3D arrays of the ``.vtu`` files map back to fdem's 2D arrays (the convenience
properties of :class:`Frame`): a point vector (``displacement``, ``velocity``, ``force``,
``reaction``, ``contact_force``) is written as ``(x, y, 0)``; the property is the first two
columns, shape ``(n, 2)``. A stress (``stress`` per triangle, ``nodal_stress`` per node) is
written as the 3x3 tensor row major ``[sxx, sxy, 0, sxy, syy, 0, 0, 0, szz]``; the property
is fdem's ``(sxx, syy, sxy, szz)``, shape ``(m, 4)``, i.e. the tensor's components 0, 4, 1
and 8. Points are ``(n, 2)`` (x, y). The conversion checks that the dropped components are
the zeros (and the tensor symmetric) the writer puts there, so that a file of another origin
raises an error rather than losing data. ``point_data`` and ``cell_data`` keep the file's
arrays unchanged (as meshio reads them).
"""

from __future__ import annotations

import json
import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import (
    Any,
    Callable,
    Dict,
    Iterator,
    List,
    Optional,
    Sequence,
    Tuple,
    TypeVar,
    Union,
    cast,
    overload,
)

import numpy as np

_T = TypeVar("_T")

from ._named import Named
from ._vtu import VtuData, VtuFormatError, read_vtu

__all__ = [
    "CurveError",
    "Frame",
    "Frames",
    "JointFrame",
    "Output",
    "read",
    "vector2",
    "stress4",
]

PathLike = Union[str, "os.PathLike[str]"]

#: The files whose presence marks a run folder (at least one of them).
RUN_FILES = ("summary.json", "results.pvd", "histories.csv", "walls.csv", "joints.pvd")

_PANDAS_FIX = "install pandas: pip install pandas (or pip install 'fdem[pandas]')"


class CurveError(ValueError):
    """A run folder without load-displacement data (the error of ``fdem plot
    load-displacement``, same message)."""


def vector2(a: np.ndarray, name: str = "array") -> np.ndarray:
    """fdem's 2D vectors ``(n, 2)`` from the file's 3-component array ``(n, 3)``.

    Raises ValueError when the array is not 3 components or its z is not 0.
    """
    a = np.asarray(a)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name}: shape {a.shape}, not (n, 3): not an fdem vector array")
    if np.any(a[:, 2] != 0):
        raise ValueError(f"{name}: a z component is not 0: not an fdem 2D vector array")
    return np.ascontiguousarray(a[:, :2], dtype=np.float64)


def stress4(a: np.ndarray, name: str = "stress") -> np.ndarray:
    """fdem's stresses ``(m, 4)``: ``(sxx, syy, sxy, szz)`` from the file's 3x3 tensors
    ``(m, 9)``, row major ``[sxx, sxy, 0, sxy, syy, 0, 0, 0, szz]``.

    Raises ValueError when the array is not 9 components, not symmetric, or has a nonzero
    out-of-plane shear.
    """
    a = np.asarray(a)
    if a.ndim != 2 or a.shape[1] != 9:
        raise ValueError(f"{name}: shape {a.shape}, not (m, 9): not an fdem stress tensor")
    if np.any(a[:, [2, 5, 6, 7]] != 0) or not np.array_equal(a[:, 1], a[:, 3]):
        raise ValueError(
            f"{name}: not an in-plane symmetric tensor [sxx, sxy, 0, sxy, syy, 0, 0, 0, szz]"
        )
    return np.ascontiguousarray(a[:, [0, 4, 1, 8]], dtype=np.float64)


def summary_dict(data: Any, where: str) -> Dict[str, Any]:
    """``summary.json`` (``where``) as read by ``json``, with the summary and its energy ledger
    as :class:`Named` dicts (a missing entry raises a KeyError listing the entries there)."""
    if not isinstance(data, dict):
        raise ValueError(
            f"{where}: holds a JSON {type(data).__name__}, not an object: not a summary fdem "
            "writes (re-run the scene to write it again)"
        )
    summary: Dict[str, Any] = Named(data, what="summary entry", plural="summary entries")
    if isinstance(summary.get("energy"), dict):
        summary["energy"] = Named(summary["energy"], what="energy term")
    return summary


class Frame:
    """One frame of a run (one ``frame_NNNN.vtu``), read on first access.

    Attributes:
        index: its position in ``results.pvd``.
        time: its time [s], as listed in ``results.pvd``.
        file: the ``.vtu`` file.
    """

    def __init__(self, index: int, time: float, file: Path) -> None:
        self.index = index
        self.time = time
        self.file = file
        self._data: Optional[VtuData] = None

    def __repr__(self) -> str:
        return f"{type(self).__name__}(index={self.index}, time={self.time!r}, file='{self.file}')"

    @property
    def vtu(self) -> VtuData:
        """The file's contents as read (:class:`fdem._vtu.VtuData`, 3D points)."""
        if self._data is None:
            self._data = read_vtu(self.file)
        return self._data

    @property
    def points(self) -> np.ndarray:
        """Point positions (current configuration) [m], float64 ``(n, 2)``."""
        return vector2(self.vtu.points, f"{self.file}: points")

    @property
    def cells(self) -> np.ndarray:
        """The cells' point indices, int64 ``(m, k)``."""
        return self.vtu.cells

    @property
    def triangles(self) -> np.ndarray:
        """The triangles' node indices, int64 ``(m, 3)``."""
        return self.vtu.cells

    @property
    def point_data(self) -> Dict[str, np.ndarray]:
        """The point arrays as in the file (vectors ``(n, 3)``, tensors ``(n, 9)``)."""
        return self.vtu.point_data

    @property
    def cell_data(self) -> Dict[str, np.ndarray]:
        """The cell arrays as in the file (tensors ``(m, 9)``, pairs ``(m, 2)``, scalars
        ``(m,)``)."""
        return self.vtu.cell_data

    def _vector(self, name: str) -> Optional[np.ndarray]:
        a = self.vtu.point_data.get(name)
        return None if a is None else vector2(a, f"{self.file}: {name}")

    @property
    def displacement(self) -> Optional[np.ndarray]:
        """Nodal displacements [m] ``(n, 2)``; None when the frame does not carry them."""
        return self._vector("displacement")

    @property
    def velocity(self) -> Optional[np.ndarray]:
        """Nodal velocities [m/s] ``(n, 2)``; None when absent."""
        return self._vector("velocity")

    @property
    def force(self) -> Optional[np.ndarray]:
        """Total nodal forces [N] ``(n, 2)``; None when absent."""
        return self._vector("force")

    @property
    def reaction(self) -> Optional[np.ndarray]:
        """Support reactions at constrained DOFs [N] ``(n, 2)``; None when absent."""
        return self._vector("reaction")

    @property
    def stress(self) -> Optional[np.ndarray]:
        """Cell stresses ``(sxx, syy, sxy, szz)`` [Pa] ``(m, 4)``; None when absent."""
        a = self.vtu.cell_data.get("stress")
        return None if a is None else stress4(a, f"{self.file}: stress")

    @property
    def nodal_stress(self) -> Optional[np.ndarray]:
        """Recovered nodal stresses ``(sxx, syy, sxy, szz)`` [Pa] ``(n, 4)``; None when
        absent."""
        a = self.vtu.point_data.get("nodal_stress")
        return None if a is None else stress4(a, f"{self.file}: nodal_stress")

    @property
    def principal_stress(self) -> Optional[np.ndarray]:
        """Cell principal stresses ``(s1, s2)`` [Pa] ``(m, 2)``; None when absent."""
        return self.vtu.cell_data.get("principal_stress")

    @property
    def von_mises(self) -> Optional[np.ndarray]:
        """Cell von Mises stress [Pa] ``(m,)``; None when absent."""
        return self.vtu.cell_data.get("von_mises")

    @property
    def material(self) -> Optional[np.ndarray]:
        """Each triangle's material index, int32 ``(m,)``; None when absent."""
        return self.vtu.cell_data.get("material")

    @property
    def body(self) -> Optional[np.ndarray]:
        """Each triangle's body index, int32 ``(m,)``; None when absent."""
        return self.vtu.cell_data.get("body")


class JointFrame(Frame):
    """One frame of the joints (one ``joints_NNNN.vtu``): one line cell per joint along its
    mid-surface (joint ``j`` from ``points[2j]`` to ``points[2j + 1]``), with the joint arrays
    as ``cell_data`` (``damage``, ``mode``, ``broken``, ``time_of_failure``, ...)."""

    @property
    def lines(self) -> np.ndarray:
        """Each joint's two point indices, int64 ``(n, 2)``."""
        return self.vtu.cells

    @property
    def triangles(self) -> np.ndarray:
        """Joint frames have no triangles: raises AttributeError (use ``lines``)."""
        raise AttributeError("a joint frame has lines, not triangles: use .lines")


def _pvd_entries(path: Path) -> List[Tuple[float, str]]:
    """(time, file) of each ``DataSet`` of a ``.pvd`` collection, in order."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        raise ValueError(f"{path}: not a ParaView collection ({e})") from None
    out = []
    for d in root.iter("DataSet"):
        t, f = d.get("timestep"), d.get("file")
        if t is None or f is None:
            raise ValueError(f"{path}: a DataSet without timestep or file")
        out.append((float(t), f))
    return out


class Frames(Sequence[Frame]):
    """The frames of a ``.pvd`` collection: ``len``, indexing (negative too, slices give a
    list), iteration; a frame's file is read when its data is first used. Empty when the
    collection does not exist (a run with ``output.frames`` 0)."""

    def __init__(self, pvd: Path, kind: type = Frame) -> None:
        self.pvd = pvd
        self._kind = kind
        self._frames: Optional[List[Frame]] = None

    def _list(self) -> List[Frame]:
        if self._frames is None:
            entries = _pvd_entries(self.pvd) if self.pvd.exists() else []
            self._frames = [
                self._kind(i, t, self.pvd.parent / f) for i, (t, f) in enumerate(entries)
            ]
        return self._frames

    @property
    def times(self) -> np.ndarray:
        """The frames' times [s], float64."""
        return np.array([f.time for f in self._list()], dtype=np.float64)

    def __len__(self) -> int:
        return len(self._list())

    @overload
    def __getitem__(self, i: int) -> Frame: ...

    @overload
    def __getitem__(self, i: slice) -> List[Frame]: ...

    def __getitem__(self, i: Union[int, slice]) -> Union[Frame, List[Frame]]:
        return self._list()[i]

    def __iter__(self) -> Iterator[Frame]:
        return iter(self._list())

    def __repr__(self) -> str:
        return f"Frames('{self.pvd}', {len(self)} frames)"


class _Table:
    """A CSV file of a run read as ``fdem plot`` reads it: the header's names (trimmed) and
    rows of numbers; empty lines skipped; a field that is not a number is an error naming the
    line."""

    def __init__(self, path: Path) -> None:
        self.path = path
        with open(path, encoding="utf-8") as f:
            text = f.read()
        lines = text.split("\n")
        if lines and lines[-1] == "":
            lines.pop()
        lines = [line[:-1] if line.endswith("\r") else line for line in lines]
        self.head = [s.strip() for s in (lines[0] if lines else "").split(",")]
        self.rows: List[List[float]] = []
        for i, line in enumerate(lines[1:]):
            if not line.strip():
                continue
            try:
                self.rows.append([_number(s) for s in line.split(",")])
            except ValueError:
                raise ValueError(f"{path} line {i + 2}: not a number") from None

    def col(self, name: str) -> Optional[int]:
        """The index of column ``name``, None if absent; an error when it appears twice."""
        hits = [i for i, h in enumerate(self.head) if h == name]
        if len(hits) > 1:
            raise ValueError(
                f"{self.path}: the column {name} appears more than once (columns {hits[0] + 1} "
                f"and {hits[1] + 1}), so it is not clear which one is meant; columns: "
                f"{','.join(self.head)} (re-run the scene: runs now name such columns "
                "body/group, e.g. v_x[disc/center])"
            )
        return hits[0] if hits else None

    def values(self, c: int) -> np.ndarray:
        """Column ``c`` as float64 (NaN where a row is short)."""
        return np.array(
            [r[c] if c < len(r) else float("nan") for r in self.rows], dtype=np.float64
        )

    def columns(self, what: str, plural: str) -> Dict[str, np.ndarray]:
        """Every column by name (a missing name raises a KeyError listing them, ``what`` and
        ``plural`` naming a column in its message); an error for a repeated name or a row of
        another length."""
        for h in self.head:
            self.col(h)
        for i, r in enumerate(self.rows):
            if len(r) != len(self.head):
                raise ValueError(
                    f"{self.path}: row {i + 1} has {len(r)} values for {len(self.head)} columns"
                )
        return Named(
            ((h, self.values(c)) for c, h in enumerate(self.head)), what=what, plural=plural
        )


_NUMBER = re.compile(
    r"[+-]?(\d+\.?\d*([eE][+-]?\d+)?|\.\d+([eE][+-]?\d+)?|inf|infinity|nan)$", re.IGNORECASE
)


def _number(s: str) -> float:
    """A CSV field as Rust's ``str::parse::<f64>`` reads it (trimmed): Python's ``float``
    for the same spellings, so both round alike (correctly); others (``1_0``) refused."""
    s = s.strip()
    if not _NUMBER.match(s):
        raise ValueError(s)
    return float(s)


def _pandas() -> Any:
    try:
        import pandas  # type: ignore[import-untyped,unused-ignore]
    except ImportError:
        raise ImportError(f"this needs pandas, which is not installed: {_PANDAS_FIX}") from None
    return pandas


class Output:
    """A run folder, read lazily (each file on first access, then cached).

    Args:
        out: the folder (the ``--out`` of ``fdem run``).

    Raises:
        FileNotFoundError: no such folder, or none of the files a run writes is in it.
    """

    def __init__(self, out: PathLike) -> None:
        self.out = Path(out)
        if not self.out.is_dir():
            raise FileNotFoundError(
                f"{self.out}: no such folder: give the folder of a run (the --out of fdem run)"
            )
        if not any((self.out / f).exists() for f in RUN_FILES):
            raise FileNotFoundError(
                f"{self.out}: not a run folder: none of {', '.join(RUN_FILES)} is in it (give "
                "the folder of a run: the --out of fdem run)"
            )
        self._cache: Dict[str, Any] = {}

    def __repr__(self) -> str:
        return f"{type(self).__name__}('{self.out}')"

    def _cached(self, key: str, make: Callable[[], _T]) -> _T:
        if key not in self._cache:
            self._cache[key] = make()
        return cast(_T, self._cache[key])

    @property
    def summary(self) -> Dict[str, Any]:
        """``summary.json`` as a dict.

        Raises FileNotFoundError when the run has not written it (still running, or killed).
        """

        def make() -> Dict[str, Any]:
            p = self.out / "summary.json"
            if not p.exists():
                raise FileNotFoundError(
                    f"{p}: no summary: the run has not finished (it is still running or was "
                    "killed); an interrupted run writes one, a finished one too"
                )
            with open(p, encoding="utf-8") as f:
                return summary_dict(json.load(f), str(p))

        return self._cached("summary", make)

    @property
    def energy(self) -> Optional[Dict[str, float]]:
        """The energy ledger (``summary["energy"]``, J), None if the summary has none."""
        return self.summary.get("energy")

    @property
    def accuracy(self) -> Dict[str, Dict[str, Any]]:
        """The accuracy indicators (``summary["accuracy"]``, docs/accuracy.md) by name, each a
        dict: ``subject``, ``measure``, ``value``, ``threshold``, ``good`` (``"at_least"`` or
        ``"at_most"``), ``meaning``, ``warning`` (present when it warns: the problem and its
        fix), ``details``. An indicator given per joint material is keyed ``name[subject]``
        (``process_zone_i[fracture.material]``). Empty for a summary without the section.
        """
        section = self.summary.get("accuracy") or {}
        indicators: List[Dict[str, Any]] = section.get("indicators", [])
        names = [i["name"] for i in indicators]
        out: Dict[str, Dict[str, Any]] = Named(what="accuracy indicator")
        for i in indicators:
            key = i["name"] if names.count(i["name"]) == 1 else f"{i['name']}[{i['subject']}]"
            out[key] = i
        return out

    @property
    def warnings(self) -> List[str]:
        """The accuracy indicators' warnings, one line each (``name: warning``); empty when
        every indicator passes."""
        return [f"{k}: {i['warning']}" for k, i in self.accuracy.items() if "warning" in i]

    @property
    def frames(self) -> Frames:
        """The frames of ``results.pvd`` (empty when the run wrote none)."""
        return self._cached("frames", lambda: Frames(self.out / "results.pvd", Frame))

    @property
    def joint_frames(self) -> Optional[Frames]:
        """The frames of ``joints.pvd`` (a fracturing run), else None."""

        def make() -> Optional[Frames]:
            p = self.out / "joints.pvd"
            return Frames(p, JointFrame) if p.exists() else None

        return self._cached("joint_frames", make)

    @property
    def last_frame(self) -> Optional[Frame]:
        """The last frame of ``results.pvd``, None when the run wrote no frames."""
        frames = self.frames
        return frames[-1] if len(frames) else None

    def _last(self, name: str) -> Optional[np.ndarray]:
        f = self.last_frame
        return None if f is None else cast(Optional[np.ndarray], getattr(f, name))

    @property
    def positions(self) -> Optional[np.ndarray]:
        """Last frame: node positions [m] ``(n, 2)`` (None without frames, as the others)."""
        return self._last("points")

    @property
    def displacements(self) -> Optional[np.ndarray]:
        """Last frame: nodal displacements [m] ``(n, 2)``."""
        return self._last("displacement")

    @property
    def velocities(self) -> Optional[np.ndarray]:
        """Last frame: nodal velocities [m/s] ``(n, 2)``."""
        return self._last("velocity")

    @property
    def forces(self) -> Optional[np.ndarray]:
        """Last frame: total nodal forces [N] ``(n, 2)``."""
        return self._last("force")

    @property
    def reactions(self) -> Optional[np.ndarray]:
        """Last frame: support reactions [N] ``(n, 2)``."""
        return self._last("reaction")

    @property
    def cell_stress(self) -> Optional[np.ndarray]:
        """Last frame: cell stresses ``(sxx, syy, sxy, szz)`` [Pa] ``(m, 4)``."""
        return self._last("stress")

    @property
    def principal_stress(self) -> Optional[np.ndarray]:
        """Last frame: cell principal stresses ``(s1, s2)`` [Pa] ``(m, 2)``."""
        return self._last("principal_stress")

    @property
    def von_mises(self) -> Optional[np.ndarray]:
        """Last frame: cell von Mises stress [Pa] ``(m,)``."""
        return self._last("von_mises")

    @property
    def nodal_stress(self) -> Optional[np.ndarray]:
        """Last frame: recovered nodal stresses ``(sxx, syy, sxy, szz)`` [Pa] ``(n, 4)``."""
        return self._last("nodal_stress")

    @property
    def triangles(self) -> Optional[np.ndarray]:
        """The triangles' node indices, int64 ``(m, 3)``."""
        return self._last("triangles")

    @property
    def material(self) -> Optional[np.ndarray]:
        """Last frame: each triangle's material index, int32 ``(m,)``."""
        return self._last("material")

    @property
    def body(self) -> Optional[np.ndarray]:
        """Last frame: each triangle's body index, int32 ``(m,)``."""
        return self._last("body")

    @property
    def joints(self) -> Optional[Dict[str, np.ndarray]]:
        """The joints' arrays of the last joint frame (``damage``, ``broken``, ...: one value
        per joint) and ``points`` ``(2 n, 2)`` (joint ``j`` from ``points[2j]`` to
        ``points[2j + 1]``); None when the run has no joint frames."""
        jf = self.joint_frames
        if jf is None or not len(jf):
            return None
        last = jf[-1]
        return Named({"points": last.points, **last.cell_data}, what="joint array")

    def _table(self, name: str) -> Optional[_Table]:
        def make() -> Optional[_Table]:
            p = self.out / name
            return _Table(p) if p.exists() else None

        return self._cached("table:" + name, make)

    @property
    def histories(self) -> Optional[Dict[str, np.ndarray]]:
        """``histories.csv`` as float64 arrays by column (``time`` first), None if absent."""
        t = self._table("histories.csv")
        return (
            None
            if t is None
            else self._cached("histories", lambda: t.columns("history", "histories"))
        )

    @property
    def walls(self) -> Optional[Dict[str, np.ndarray]]:
        """``walls.csv`` as float64 arrays by column, None if absent."""
        t = self._table("walls.csv")
        return (
            None
            if t is None
            else self._cached(
                "walls", lambda: t.columns("column of walls.csv", "columns of walls.csv")
            )
        )

    @property
    def fractures(self) -> Optional[Dict[str, np.ndarray]]:
        """``fractures.csv`` (one row per broken joint, in order of failure) as arrays by
        column: ``time``, ``x``, ``y``, ``mode_mix``, ``energy_released`` float64, ``joint``
        int64, ``mode`` str (``I``, ``II``, ``mixed``); None if the run has no fracture
        section."""
        return self._cached("fractures", self._read_fractures)

    def _read_fractures(self) -> Optional[Dict[str, np.ndarray]]:
        p = self.out / "fractures.csv"
        if not p.exists():
            return None
        with open(p, encoding="utf-8") as f:
            lines = [line.rstrip("\r") for line in f.read().split("\n") if line.strip()]
        head = [h.strip() for h in lines[0].split(",")] if lines else []
        rows = [[s.strip() for s in line.split(",")] for line in lines[1:]]
        for i, r in enumerate(rows):
            if len(r) != len(head):
                raise ValueError(f"{p} line {i + 2}: {len(r)} values for {len(head)} columns")
        out: Dict[str, np.ndarray] = Named(
            what="column of fractures.csv", plural="columns of fractures.csv"
        )
        for c, h in enumerate(head):
            col = [r[c] for r in rows]
            try:
                if h == "mode":
                    out[h] = np.array(col, dtype=str)
                elif h == "joint":
                    out[h] = np.array([int(v) for v in col], dtype=np.int64)
                else:
                    out[h] = np.array([_number(v) for v in col], dtype=np.float64)
            except ValueError:
                raise ValueError(f"{p}: column {h}: a value is not a number") from None
        return out

    def histories_frame(self) -> Any:
        """``histories.csv`` as a pandas DataFrame (ImportError with the fix when pandas is
        not installed); None if the run has no histories."""
        return self._frame(self.histories)

    def walls_frame(self) -> Any:
        """``walls.csv`` as a pandas DataFrame; None if the run has no walls."""
        return self._frame(self.walls)

    def fractures_frame(self) -> Any:
        """``fractures.csv`` as a pandas DataFrame; None if absent."""
        return self._frame(self.fractures)

    @staticmethod
    def _frame(d: Optional[Dict[str, np.ndarray]]) -> Any:
        pd = _pandas()
        return None if d is None else pd.DataFrame(d)

    def load_displacement(
        self, load: Optional[str] = None, displacement: Optional[str] = None
    ) -> Tuple[np.ndarray, np.ndarray]:
        """The load-displacement curve ``fdem plot load-displacement`` draws for this run, in
        SI units (m, N; the plot shows mm and kN): ``(displacement, load)``, float64, absolute
        values, one point per row of the CSV file.

        Without arguments, as the CLI: ``walls.csv`` with moving walls gives the force of the
        first moving wall along its motion against the sum of the moving walls' displacements
        (the platen closure); else ``histories.csv``'s first group with both
        ``reaction_y[G]`` and ``u_y[G]`` (then ``x``). ``load`` and ``displacement`` name the
        two columns of one file instead (both, or neither). A column the file repeats is
        refused (ValueError listing the columns), never taken first.

        Raises:
            CurveError: the folder has no such data (the CLI's message, with the fix).
            ValueError: a repeated column, a missing named column, a damaged file.
        """
        walls = self._table("walls.csv")
        hist = self._table("histories.csv")
        tables = [t for t in (walls, hist) if t is not None]
        d = self.out
        if not tables:
            raise CurveError(
                f"{d}: neither walls.csv nor histories.csv: is this an fdem run folder? (a "
                'scene needs moving walls in "contact" or a "reaction" probe in "histories")'
            )
        if load is not None or displacement is not None:
            if load is None or displacement is None:
                raise ValueError("give both load and displacement")
            for t in tables:
                cl, cd = t.col(load), t.col(displacement)
                if cl is not None and cd is not None:
                    return np.abs(t.values(cd)), np.abs(t.values(cl))
            cols = "; ".join(f"{t.path}: {','.join(t.head)}" for t in tables)
            raise ValueError(
                f"{d}: no file has both columns {load} and {displacement} (columns: {cols})"
            )
        if walls is not None:
            w = walls
            moving: List[Tuple[str, str]] = []
            for i, h in enumerate(w.head):
                if not (h.startswith("u_x[") and h[4:].endswith("]")):
                    continue
                name = h[4:-1]
                w.col(h)
                iy = w.col(f"u_y[{name}]")
                if iy is None:
                    continue

                def last(c: int) -> float:
                    r = w.rows[-1] if w.rows else []
                    return abs(r[c]) if c < len(r) else 0.0

                ux, uy = last(i), last(iy)
                if float(np.fmax(ux, uy)) > 0.0:
                    moving.append((name, "y" if uy >= ux else "x"))
            if moving:
                first, axis = moving[0]
                f = w.col(f"force_{axis}[{first}]")
                if f is None:
                    raise ValueError(f"{w.path}: no force_{axis}[{first}]")
                u = np.zeros(len(w.rows), dtype=np.float64)
                for name, ax in moving:
                    if ax != axis:
                        continue
                    c = w.col(f"u_{ax}[{name}]")
                    if c is not None:
                        u += np.abs(w.values(c))
                return np.abs(u), np.abs(w.values(f))
        if hist is not None:
            for axis in ("y", "x"):
                prefix = f"reaction_{axis}["
                for i, col in enumerate(hist.head):
                    if not (col.startswith(prefix) and col[len(prefix) :].endswith("]")):
                        continue
                    group = col[len(prefix) : -1]
                    hist.col(col)
                    cu = hist.col(f"u_{axis}[{group}]")
                    if cu is not None:
                        return np.abs(hist.values(cu)), np.abs(hist.values(i))
        raise CurveError(
            f"{d}: no load-displacement data: no moving wall in walls.csv, and histories.csv "
            'has no group with both a "reaction" and a "displacement" probe (add them to the '
            "scene, or name the columns with load= and displacement=)"
        )

    @property
    def largest_load(self) -> Optional[float]:
        """The largest load of :meth:`load_displacement` [N], whether or not the specimen
        failed; None when the run has no such curve (or it has no rows). A repeated column or
        damaged file still raises."""
        try:
            _, p = self.load_displacement()
        except CurveError:
            return None
        return float(np.max(p)) if len(p) else None

    @property
    def result(self) -> Optional[Dict[str, Any]]:
        """The run's result block (``summary["result"]``, docs/accuracy.md): what the run
        found, from its own files: ``curve`` (its file and columns), ``failed``,
        ``criterion``, ``largest_load``, ``final_load``, ``peak_load``,
        ``displacement_at_peak``, ``stiffness`` (the loading branch's slope [N/m]),
        ``specimen`` (between platens: ``shape``, ``width``, ``height``, ``thickness``,
        ``stress_measure``, ``peak_stress`` [Pa], ``strain_at_peak``, ``modulus`` [Pa] of a
        rectangle), ``broken_joints``, ``broken_by_mode``, ``crack_extent``. None for a run
        without a load-displacement curve or broken joints, a static solve or an interrupted
        run."""
        r = self.summary.get("result")
        if not isinstance(r, dict):
            return None
        out: Dict[str, Any] = Named(r, what="result entry", plural="result entries")
        if isinstance(out.get("specimen"), dict):
            out["specimen"] = Named(out["specimen"], what="specimen entry", plural="specimen entries")
        return out

    @property
    def failure(self) -> Dict[str, Any]:
        """Whether the specimen failed, and how: a dict with ``failed`` (True, False, or None
        without a load-displacement curve), ``criterion`` (the rule, in words), ``peak_load``
        [N] and ``displacement_at_peak`` [m] (the curve's largest load and where; None when
        it did not fail), ``largest_load`` [N], ``final_load`` [N], ``broken_joints``, their
        count by mode ``broken_by_mode`` (``{"I": .., "II": .., "mixed": ..}``) and the crack
        pattern's extent ``crack_extent`` (``{"x": [min, max], "y": [min, max]}`` [m] of the
        broken joints' midpoints; None when none broke).

        The rule: a joint broke and, after the largest load, the load fell to
        ``FAILURE_DROP`` (0.8) of it or below. A run that ends while the load still rises, or
        without a broken joint, did not fail: its largest load is not a peak.

        These entries of the run's :attr:`result` block when it has one; else (an interrupted
        run) computed from the run's files by the same rule.
        """
        keys = (
            "failed",
            "criterion",
            "peak_load",
            "displacement_at_peak",
            "largest_load",
            "final_load",
            "broken_joints",
            "broken_by_mode",
            "crack_extent",
        )
        r = self.result
        if r is not None:
            out: Dict[str, Any] = Named(what="failure entry", plural="failure entries")
            out.update({k: r.get(k) for k in keys})
            return out
        return self.failure_from_files()

    def failure_from_files(self) -> Dict[str, Any]:
        """:attr:`failure` computed from the run's files (``walls.csv`` or ``histories.csv``,
        and ``fractures.csv``), whether or not the summary has a result block."""
        fr = self.fractures
        broken = 0 if fr is None else len(next(iter(fr.values()), []))
        by_mode = {m: 0 for m in ("I", "II", "mixed")}
        extent: Optional[Dict[str, List[float]]] = None
        if fr is not None and broken:
            for m in fr["mode"]:
                by_mode[str(m)] = by_mode.get(str(m), 0) + 1
            x, y = fr["x"], fr["y"]
            extent = {
                "x": [float(np.min(x)), float(np.max(x))],
                "y": [float(np.min(y)), float(np.max(y))],
            }
        out: Dict[str, Any] = Named(what="failure entry", plural="failure entries")
        out.update(
            failed=None,
            criterion=f"a joint broke and the load then fell to {FAILURE_DROP} of its largest value or below",
            peak_load=None,
            displacement_at_peak=None,
            largest_load=None,
            final_load=None,
            broken_joints=broken,
            broken_by_mode=by_mode,
            crack_extent=extent,
        )
        try:
            u, p = self.load_displacement()
        except CurveError:
            return out
        if not len(p):
            return out
        k = int(np.argmax(p))
        failed = broken > 0 and float(np.min(p[k:])) <= FAILURE_DROP * float(p[k])
        out.update(failed=bool(failed), largest_load=float(p[k]), final_load=float(p[-1]))
        if failed:
            out.update(peak_load=float(p[k]), displacement_at_peak=float(u[k]))
        return out

    @property
    def failed(self) -> Optional[bool]:
        """Whether the specimen failed (:attr:`failure`); None without a load-displacement
        curve."""
        failed: Optional[bool] = self.failure["failed"]
        return failed

    @property
    def peak_load(self) -> Optional[float]:
        """The peak load [N] of a specimen that failed (:attr:`failure`): the largest load of
        :meth:`load_displacement`. None when it did not fail within the run (no joint broke,
        or the load never fell after its largest value: see :attr:`largest_load`) or the run
        has no such curve."""
        peak: Optional[float] = self.failure["peak_load"]
        return peak


#: The load drop after the largest load that, with a broken joint, marks a failed specimen
#: (:attr:`Output.failure`): the load falls to this fraction of its largest value or below.
FAILURE_DROP = 0.8


def read(out: PathLike) -> Output:
    """Reads a run folder lazily (see :class:`Output`).

    Raises:
        FileNotFoundError: no such folder, or not a run folder (the message names it and the
            files looked for).
    """
    return Output(out)


# Re-exported for callers that catch the reader's error.
__all__ += ["VtuFormatError"]
